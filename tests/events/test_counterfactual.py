"""Counterfactual key objects: early smooth yields the collision and overlap tags never see."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from yield_scenarios import left_turn_yield, pedestrian_yield

from scenariominer.config import load_config
from scenariominer.config.tags import CounterfactualConfig, KeyIdentConfig
from scenariominer.data.log import Log
from scenariominer.events.counterfactual import (
    braking_segments,
    counterfactual_key_objects,
    identify_key_objects,
)
from scenariominer.tags import tag_log
from scenariominer.testing import LogBuilder, braking_speed, times


def _keys(log: Log, method: str) -> list[str]:
    return [ev.track_id for ev in identify_key_objects(log, tag_log(log), KeyIdentConfig(method=method))]


@pytest.fixture(scope="module")
def ped_log() -> Log:
    return pedestrian_yield().build(smooth=True)


def test_early_yield_to_pedestrian_found_only_by_counterfactual(ped_log: Log) -> None:
    # The ego stops 6 m short: the boxes never come close, so the tags name nobody.
    assert _keys(ped_log, "tags") == []
    assert _keys(ped_log, "counterfactual") == ["ped"]
    assert _keys(ped_log, "combined") == ["ped"]


def test_pedestrian_event_window_and_conflict_time(ped_log: Log) -> None:
    (event,) = identify_key_objects(ped_log, tag_log(ped_log), KeyIdentConfig(method="counterfactual"))
    assert event.method == "counterfactual"
    # Braking starts at 1 s; had it not, the ego would reach the crosswalk about 5.7 s later.
    assert event.start_ns * 1e-9 == pytest.approx(1.0, abs=0.25)
    assert 4.5 <= event.conflict_s <= 6.5
    assert event.min_distance_m > 5.0  # the actual boxes stay metres apart


def test_left_turn_yield_to_oncoming_car() -> None:
    log = left_turn_yield()
    assert _keys(log, "tags") == []
    assert _keys(log, "counterfactual") == ["oncoming"]


def test_distractors_are_not_candidates(ped_log: Log) -> None:
    cfg = KeyIdentConfig(counterfactual=CounterfactualConfig(max_per_segment=10))
    ((_, events),) = counterfactual_key_objects(ped_log, tag_log(ped_log), cfg)
    assert [ev.track_id for ev in events] == ["ped"]  # neither the parked nor the oncoming car


def test_pedestrian_already_past_is_no_conflict() -> None:
    # Same ego, but the pedestrian crossed long before the ego could get there: no key object.
    t = times(14.0)
    log = (
        LogBuilder(t)
        .ego(speed_mps=braking_speed(t, 10.0, 1.0, 1.0), x0_m=-30.0)
        .add(
            "ped",
            "PEDESTRIAN",
            speed_mps=1.4,
            x0_m=40.0,
            y0_m=2.0,
            yaw0_rad=np.pi / 2,
            length_m=0.6,
            width_m=0.6,
        )
        .build(smooth=True)
    )
    assert _keys(log, "counterfactual") == []


def test_lead_vehicle_braking_is_a_conflict() -> None:
    t = times(10.0)
    log = (
        LogBuilder(t)
        .ego(speed_mps=braking_speed(t, 10.0, 3.0, 4.0))
        .add("lead", "REGULAR_VEHICLE", speed_mps=braking_speed(t, 10.0, 2.5, 5.0), x0_m=18.0)
        .add("follower", "REGULAR_VEHICLE", speed_mps=braking_speed(t, 10.0, 3.5, 4.0), x0_m=-16.0)
        .build(smooth=True)
    )
    assert _keys(log, "counterfactual") == ["lead"]  # the follower reaches the ego's region after it


def test_no_braking_no_segment() -> None:
    t = times(6.0)
    log = (
        LogBuilder(t)
        .ego(speed_mps=8.0)
        .add("car", "REGULAR_VEHICLE", speed_mps=8.0, x0_m=20.0)
        .build(smooth=True)
    )
    assert braking_segments(log, tag_log(log), CounterfactualConfig(), 1.0) == []
    assert _keys(log, "combined") == []


def test_slow_onset_is_not_searched(ped_log: Log) -> None:
    cfg = CounterfactualConfig(min_onset_speed_mps=12.0)  # faster than the ego ever drives
    assert braking_segments(ped_log, tag_log(ped_log), cfg, 1.0) == []


def test_combined_keeps_tag_events_and_adds_unexplained_segments() -> None:
    t = times(10.0)
    log = (
        LogBuilder(t)
        .ego(speed_mps=braking_speed(t, 10.0, 3.0, 5.0))
        .add("lead", "REGULAR_VEHICLE", speed_mps=braking_speed(t, 10.0, 2.0, 6.0), x0_m=15.0)
        .build(smooth=True)
    )
    tags = tag_log(log)
    tag_events = identify_key_objects(log, tags, KeyIdentConfig(method="tags"))
    combined = identify_key_objects(log, tags, KeyIdentConfig(method="combined"))
    assert tag_events and all(ev.method == "tags" for ev in tag_events)
    assert combined == tag_events  # the segment is explained by a tag event: nothing added


def test_method_is_configurable_and_checked(tmp_path) -> None:  # type: ignore[no-untyped-def]
    cfg_file = tmp_path / "c.toml"
    cfg_file.write_text('[tags.keyident]\nmethod = "tags"\n[tags.keyident.counterfactual]\nhorizon_s = 4.0\n')
    cfg = load_config(cfg_file, environ={})
    assert cfg.tags.keyident.method == "tags"
    assert cfg.tags.keyident.counterfactual.horizon_s == 4.0
    assert load_config(environ={}).tags.keyident.method == "combined"
    with pytest.raises(ValueError, match="method"):
        KeyIdentConfig(method="magic")
    with pytest.raises(ValueError, match="step_s"):
        dataclasses.replace(CounterfactualConfig(), step_s=0.0)
