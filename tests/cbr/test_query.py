"""From our own logs: event -> query (risk-type mapping, caption) and log -> rollout scene."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from scenariominer.cbr.query import query_from_event, risk_type_of
from scenariominer.cbr.rollout import RECORDED, rollout, scene_from_log
from scenariominer.cbr.vocab import load_manoeuvres
from scenariominer.config.cbr import CbrConfig
from scenariominer.explain.records import EventRecord
from scenariominer.testing.builders import LogBuilder, times


def _record(**changes: object) -> EventRecord:
    blank = {
        f.name: ("" if f.type == "str" else 0 if f.type == "int" else math.nan)
        for f in dataclasses.fields(EventRecord)
    }
    blank.update(
        event_id="log:g:1", log_id="log", guest_id="g", guest_category="REGULAR_VEHICLE", category="cut_in"
    )
    blank.update(changes)
    return EventRecord(**blank)  # type: ignore[arg-type]


@pytest.mark.parametrize(
    ("category", "guest", "expected"),
    [
        ("cut_in", "REGULAR_VEHICLE", "merging_vehicle"),
        ("lead_brake", "BUS", "vehicle_ahead"),
        ("left_oppo", "REGULAR_VEHICLE", "opposite_turning_vehicle"),
        ("obj_crossing", "BICYCLIST", "pedestrian"),  # a vulnerable guest overrides the category
        ("not_relevant", "REGULAR_VEHICLE", "vehicle_ahead"),  # unmapped: the default
    ],
)
def test_risk_type_mapping(category: str, guest: str, expected: str) -> None:
    assert risk_type_of(_record(category=category, guest_category=guest), CbrConfig()) == expected


def test_caption_is_facts_then_description_and_capped() -> None:
    r = _record(
        facts="guest: bus\nsmallest gap:  12.0 m\n",
        llm_description="",
        tag_description="Overview: a bus. Initial tags: x" * 1,
    )
    q = query_from_event(r, CbrConfig())
    # the facts' lines were run together ("guest: bus smallest gap: 12.0 m Overview: ...")
    assert q.caption == "guest: bus; smallest gap: 12.0 m. Overview: a bus."
    assert query_from_event(_record(facts="", llm_description="A bus."), CbrConfig()).caption == "A bus."
    long = query_from_event(_record(llm_description="word " * 400), CbrConfig())
    assert len(long.caption) <= 700 and long.caption.endswith("...")


def test_scene_from_log_stopped_car_braking_avoids() -> None:
    t = times(10.0)
    log = (
        LogBuilder(t)
        .ego(speed_mps=15.0)
        .add("stopped", "REGULAR_VEHICLE", x0_m=100.0)
        .add("far", "REGULAR_VEHICLE", x0_m=-300.0, present=t < 1.0)  # gone before the window
        .build()
    )
    # The ego front reaches the stopped car's rear (100 - 2.25 - 2.44 = 95.3 m) at 6.35 s.
    conflict_ns = int(log.timestamps_ns[0] + 6.35e9)
    scene = scene_from_log(log, conflict_ns, lead_s=2.5, horizon_s=5.0)
    assert scene.other_ids == ("stopped",)
    assert scene.t_s[0] == 0.0 and scene.t_s[-1] == pytest.approx(5.0, abs=0.11)
    assert scene.ego_speed_mps == pytest.approx(15.0, abs=0.2)
    out = rollout(scene, load_manoeuvres().manoeuvres)
    # 2.5 s before contact the gap is 37.5 m; braking needs ~15.6 m.
    assert out[RECORDED].collision
    assert out["emergency_braking"].avoided
    assert np.all(np.isfinite(out["emergency_braking"].x_m))
