"""Planning simulated highway sets and their road layout (no SUMO needed)."""

from __future__ import annotations

import dataclasses

import pytest

from scenariominer.errors import DataError
from scenariominer.sim.highway_net import ACCEL_LANE_M, DOWNSTREAM_M, UPSTREAM_M, layout
from scenariominer.sim.highway_scenario import HighwaySettings, HighwaySimError, plan_scenarios


@pytest.mark.parametrize(
    ("changes", "named"),
    [
        ({"lanes": 5}, "lanes"),
        ({"lanes": 1}, "lanes"),
        ({"recordings": 0}, "recordings"),
        ({"recordings": 100}, "recordings"),
        ({"minutes": 0.0}, "minutes"),
        ({"minutes": float("nan")}, "minutes"),
        ({"demand_vph": -5.0}, "demand"),
        ({"speed_limit_kmh": 20.0}, "speed limit"),
        ({"truck_share": 1.5}, "truck share"),
        ({"variety": "wild"}, "variety"),
        ({"frame_rate_hz": 7.0}, "frame rate"),
        ({"section_m": 50.0}, "section length"),
        ({"seed": -1}, "seed"),
    ],
)
def test_a_bad_setting_is_refused_naming_it(changes: dict[str, object], named: str) -> None:
    with pytest.raises(HighwaySimError, match=named) as info:
        HighwaySettings(**changes)  # type: ignore[arg-type]
    assert isinstance(info.value, DataError)  # the data family: ``except ValueError`` works too


def test_a_plan_is_reproducible_and_a_recording_does_not_depend_on_the_set_size() -> None:
    six = plan_scenarios(HighwaySettings(recordings=6, seed=7))
    again = plan_scenarios(HighwaySettings(recordings=6, seed=7))
    two = plan_scenarios(HighwaySettings(recordings=2, seed=7))
    assert six == again
    assert six[:2] == two
    assert plan_scenarios(HighwaySettings(recordings=6, seed=8)) != six


def test_the_mixed_preset_varies_the_road_and_the_traffic() -> None:
    plan = plan_scenarios(HighwaySettings(recordings=12, seed=7))
    assert {s.lanes for s in plan} == {2, 3, 4}
    assert {s.on_ramp for s in plan} == {True, False}
    assert {s.lane_drop for s in plan} == {True, False}
    assert None in {s.speed_limit_kmh for s in plan}  # an unlimited section
    assert len({s.speed_limit_kmh for s in plan}) >= 3
    assert len({s.sumo_seed for s in plan}) == 12
    for s in plan:
        assert 0.05 <= s.truck_share <= 0.30
        assert (s.ramp_demand_vph > 0) == s.on_ramp
        assert len(s.demand_vph) == 6  # (120 s warm-up + 600 s) / 120 s periods
        assert len(set(s.demand_vph)) > 1  # demand changes over time
        per_lane = sum(s.demand_vph) / len(s.demand_vph) / s.lanes
        assert 900 * 0.55 <= per_lane <= 1900 * 1.45


def test_pinned_settings_replace_only_their_own_draw() -> None:
    free = plan_scenarios(HighwaySettings(recordings=4, seed=3))
    pinned = plan_scenarios(
        HighwaySettings(recordings=4, seed=3, lanes=2, speed_limit_kmh=0.0, on_ramp=False, truck_share=0.5)
    )
    for a, b in zip(free, pinned, strict=True):
        assert b.lanes == 2 and b.speed_limit_kmh is None and not b.on_ramp and b.truck_share == 0.5
        assert b.ramp_demand_vph == 0.0
        assert (a.lane_drop, a.sumo_seed, a.aggressive_share) == (
            b.lane_drop,
            b.sumo_seed,
            b.aggressive_share,
        )


def test_the_fixed_preset_gives_one_road_with_constant_demand() -> None:
    plan = plan_scenarios(HighwaySettings(recordings=3, seed=3, variety="fixed", demand_vph=4000.0))
    roads = {(s.lanes, s.speed_limit_kmh, s.truck_share, s.on_ramp, s.lane_drop) for s in plan}
    assert roads == {(3, 120.0, 0.15, False, False)}
    assert all(set(s.demand_vph) == {4000.0} for s in plan)
    assert len({s.sumo_seed for s in plan}) == 3  # the traffic itself still differs


def test_layout_adds_the_acceleration_lane_on_the_right_and_drops_the_rightmost_lane() -> None:
    base = plan_scenarios(HighwaySettings(recordings=1, lanes=3, section_m=1000.0))[0]
    both = layout(dataclasses.replace(base, on_ramp=True, lane_drop=True))
    x0 = UPSTREAM_M
    merge = x0 + 150.0  # 15 % of the section
    assert both.lanes == (3, 4, 3, 2)
    assert both.breaks_m == (0.0, merge, merge + ACCEL_LANE_M, x0 + 700.0, x0 + 1000.0 + DOWNSTREAM_M)
    assert both.merge_index == 1
    assert both.section == (x0, x0 + 1000.0)
    plain = layout(dataclasses.replace(base, on_ramp=False, lane_drop=False))
    assert plain.lanes == (3,) and plain.merge_index == -1
