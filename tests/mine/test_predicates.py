"""Atomic mining predicates on hand-built scenes with known answers, plus their config thresholds.

Most tests use the street scene of ``mining_scenes`` (see its docstring for every track's path);
small dedicated scenes isolate single thresholds.
"""

from __future__ import annotations

import inspect
import math
import re

import numpy as np
import pytest
from mining_scenes import T_S, Obj, const, idx, make_log, street_map, street_objects, street_scene

from scenariominer.config.mining import MiningConfig, SandboxConfig
from scenariominer.mine import dsl as P
from scenariominer.mine.context import LogContext, MapRequiredError
from scenariominer.mine.scenario import Scenario


def _times(ctx: LogContext, s: Scenario, track: str) -> list[float]:
    return [round(float(t), 1) for t in ctx.t_s[s.referred[idx(ctx, track)]]]


def _span(ctx: LogContext, s: Scenario, track: str) -> tuple[float, float] | None:
    ts = _times(ctx, s, track)
    return (ts[0], ts[-1]) if ts else None


def _tracks(ctx: LogContext, s: Scenario) -> set[str]:
    return {str(ctx.log.track_ids[i]) for i in s.referred_tracks}


def _related(ctx: LogContext, s: Scenario, track: str) -> set[str]:
    i = idx(ctx, track)
    return {str(ctx.log.track_ids[j]) for j in s.relations[s.relations[:, 0] == i, 2]}


@pytest.fixture(scope="module")
def street() -> LogContext:
    return street_scene()


@pytest.fixture(scope="module")
def street_nomap() -> LogContext:
    return street_scene(with_map=False)


def _cat(ctx: LogContext, category: str) -> Scenario:
    return P.get_objects_of_category(ctx, category)


def _with_config(config: MiningConfig, with_map: bool = True, objs: list[Obj] | None = None) -> LogContext:
    log = make_log(objs or street_objects(), log_id="street")
    return LogContext(log, config, street_map() if with_map else None)


# ====================================================================== geometry


def test_relative_position_is_in_the_subjects_frame(street: LogContext) -> None:
    ego, bike = idx(street, "ego"), idx(street, "bike")
    x, y = street.relative_position(np.array([ego]), np.array([bike]))
    assert x[0, 0, 10] == pytest.approx(0.0) and y[0, 0, 10] == pytest.approx(-3.6)
    assert street.box_distance(np.array([ego]), np.array([bike]))[0, 0, 10] == pytest.approx(3.6 - 1.0 - 0.3)


def test_positions_are_box_centres_whatever_the_dataset() -> None:
    # The AV2 reader moves the ego to its box centre; the mining context takes positions as they are.
    objs = street_objects()
    plain = LogContext(make_log(objs, log_id="s", dataset="synthetic"))
    av2 = LogContext(make_log(objs, log_id="s", dataset="av2"))
    np.testing.assert_array_equal(av2.cx_m, plain.cx_m)
    assert plain.cx_m[0, 0] == pytest.approx(0.0)


# ====================================================================== selection


def test_categories_and_groups(street: LogContext) -> None:
    assert _tracks(street, _cat(street, "EGO_VEHICLE")) == {"ego"}
    vehicles = _tracks(street, _cat(street, "VEHICLE"))
    assert {"ego", "lead", "bus", "turner"} <= vehicles and "bike" not in vehicles and "ped" not in vehicles
    assert len(_tracks(street, _cat(street, "ANY"))) == street.n_tracks
    assert _tracks(street, _cat(street, "pedestrian")) == {"ped", "ped2", "pedA", "pedB"}
    buses = P.is_category(_cat(street, "VEHICLE"), street, category="BUS")
    assert _tracks(street, buses) == {"bus"}


def test_unknown_category_lists_the_valid_names(street: LogContext) -> None:
    with pytest.raises(ValueError, match="unknown category 'CARS'.*REGULAR_VEHICLE"):
        _cat(street, "CARS")


# ====================================================================== motion


def test_stationary_is_the_whole_log_and_has_velocity_skips_parked_objects(street: LogContext) -> None:
    vehicles = _cat(street, "VEHICLE")
    assert _tracks(street, P.stationary(vehicles, street)) == {"parked"}
    stopped = P.has_velocity(vehicles, street, min_velocity=0, max_velocity=0.5)
    assert "parked" not in _tracks(street, stopped)
    fast = P.has_velocity(vehicles, street, min_velocity=11.5)
    assert _tracks(street, fast) >= {"oncoming", "overtaker"} and "ego" not in _tracks(street, fast)


def test_stationary_threshold_from_config() -> None:
    # a car creeping 2.5 m over the log
    objs = [
        Obj("ego", "EGO_VEHICLE", 10 * T_S, const(0.0), const(0.0)),
        Obj("creep", "REGULAR_VEHICLE", 2.5 * T_S / 6, const(9.0), const(0.0)),
    ]
    default = LogContext(make_log(objs))
    assert _tracks(default, P.stationary(_cat(default, "ANY"), default)) == {"creep"}
    strict = LogContext(make_log(objs), MiningConfig(stationary_max_displacement_m=2.0))
    assert _tracks(strict, P.stationary(_cat(strict, "ANY"), strict)) == set()


def test_accelerating_and_braking(street: LogContext) -> None:
    vehicles = _cat(street, "VEHICLE")
    acc = P.accelerating(vehicles, street, min_accel=1.0)
    assert "bus" in _tracks(street, acc) and _span(street, acc, "bus") == (0.1, 5.9)
    assert "lead" not in _tracks(street, acc)
    assert "bus" not in _tracks(street, P.accelerating(vehicles, street, min_accel=-math.inf, max_accel=-1.0))


def test_lateral_acceleration_sign_follows_the_lane_change(street: LogContext) -> None:
    changer = P.is_category(_cat(street, "VEHICLE"), street, "REGULAR_VEHICLE")
    left = P.has_lateral_acceleration(changer, street, min_accel=2)
    right = P.has_lateral_acceleration(changer, street, max_accel=-2)
    # a move to the left starts with a push to the left and ends with a push to the right
    assert _times(street, left, "changer")[0] < _times(street, right, "changer")[0]
    assert max(_times(street, left, "changer")) < 3.0 < min(_times(street, right, "changer"))


def test_turning_right_and_not_left(street: LogContext) -> None:
    vehicles = _cat(street, "VEHICLE")
    right = P.turning(vehicles, street, direction="right")
    assert _tracks(street, right) == {"turner"}
    lo, hi = _span(street, right, "turner")  # type: ignore[misc]
    assert 0.9 <= lo <= 1.2 and 3.8 <= hi <= 4.1
    assert P.turning(vehicles, street, direction="left").is_empty
    assert _tracks(street, P.turning(vehicles, street)) == {"turner"}


def _turn_scene(rate_deg_s: float, start_s: float, stop_s: float) -> list[Obj]:
    """A car turning left at ``rate_deg_s`` between ``start_s`` and ``stop_s`` (at 5 m/s)."""
    t = T_S
    rate = np.where((t >= start_s) & (t < stop_s), np.radians(rate_deg_s), 0.0)
    yaw = np.concatenate([[0.0], np.cumsum(rate[:-1] * 0.1)])
    x = np.concatenate([[0.0], np.cumsum(5 * np.cos(yaw[:-1]) * 0.1)])
    y = np.concatenate([[0.0], np.cumsum(5 * np.sin(yaw[:-1]) * 0.1)])
    return [
        Obj("ego", "EGO_VEHICLE", 10 * T_S, const(-30.0), const(0.0)),
        Obj("car", "REGULAR_VEHICLE", x, y, yaw),
    ]


def test_turn_angle_threshold_from_config() -> None:
    objs = _turn_scene(20.0, 2.0, 4.0)  # 40 degrees in the middle of the log
    default = LogContext(make_log(objs))
    assert P.turning(_cat(default, "ANY"), default, "left").is_empty
    loose = LogContext(make_log(objs), MiningConfig(turn_min_heading_change_deg=30))
    assert _tracks(loose, P.turning(_cat(loose, "ANY"), loose, "left")) == {"car"}


def test_turn_cut_by_the_log_start_uses_the_partial_thresholds() -> None:
    objs = _turn_scene(10.0, 0.0, 2.5)  # 25 degrees at 10 deg/s from the first frame
    default = LogContext(make_log(objs))
    assert _tracks(default, P.turning(_cat(default, "ANY"), default, "left")) == {"car"}
    for cfg in (
        MiningConfig(turn_partial_min_heading_change_deg=30),
        MiningConfig(turn_min_yaw_rate_deg_s=12),
        MiningConfig(turn_yaw_rate_deadband_deg_s=12),
    ):
        ctx = LogContext(make_log(objs), cfg)
        assert P.turning(_cat(ctx, "ANY"), ctx, "left").is_empty, cfg


def test_changing_lanes_left(street: LogContext) -> None:
    vehicles = _cat(street, "VEHICLE")
    left = P.changing_lanes(vehicles, street, direction="left")
    assert _tracks(street, left) == {"changer"} and _span(street, left, "changer") == (2.0, 4.0)
    assert P.changing_lanes(vehicles, street, direction="right").is_empty


@pytest.mark.parametrize(
    "config",
    [
        MiningConfig(lane_change_min_lateral_speed_mps=3.0),
        MiningConfig(lane_change_max_heading_deg=10.0),
        MiningConfig(lane_change_min_lateral_m=4.0),
    ],
)
def test_lane_change_thresholds_from_config(config: MiningConfig) -> None:
    ctx = _with_config(config)
    assert P.changing_lanes(_cat(ctx, "VEHICLE"), ctx, direction="left").is_empty


# ====================================================================== relations


def test_bicycle_to_the_right_of_the_ego_only(street: LogContext) -> None:
    vehicles, bikes = _cat(street, "VEHICLE"), _cat(street, "BICYCLE")
    beside = {"within_distance": 4, "lateral_thresh": 1}
    s = P.has_objects_in_relative_direction(vehicles, bikes, street, direction="right", **beside)
    assert _tracks(street, s) == {"ego"} and _span(street, s, "ego") == (0.0, 6.0)
    assert _related(street, s, "ego") == {"bike"}
    assert P.has_objects_in_relative_direction(vehicles, bikes, street, direction="left", **beside).is_empty


def test_direction_defaults_and_arguments(street: LogContext) -> None:
    vehicles = _cat(street, "VEHICLE")
    ego = _cat(street, "EGO_VEHICLE")
    lane = {"within_distance": 25, "lateral_thresh": 1}
    ahead = P.has_objects_in_relative_direction(ego, vehicles, street, direction="forward", **lane)
    assert _related(street, ahead, "ego") == {"lead"}  # 10.5 m gap, same lane
    assert P.has_objects_in_relative_direction(
        ego, vehicles, street, direction="front", within_distance=10, lateral_thresh=1
    ).is_empty
    behind = P.has_objects_in_relative_direction(ego, vehicles, street, direction="backward", **lane)
    # the changer, until its centre is more than 1 m beyond the ego's left side (y > 2 m at t > 3.07 s)
    assert _span(street, behind, "ego") == (0.0, 3.0)
    wide = P.has_objects_in_relative_direction(
        ego, vehicles, street, direction="left", within_distance=50, lateral_thresh=math.inf
    )
    assert {"overtaker", "parked", "oncoming"} <= _related(street, wide, "ego")
    many = P.has_objects_in_relative_direction(
        ego, vehicles, street, "left", min_number=4, within_distance=50, lateral_thresh=math.inf
    )
    one = P.has_objects_in_relative_direction(
        ego, vehicles, street, "left", max_number=1, within_distance=50, lateral_thresh=math.inf
    )
    assert 0 < many.n_referred_cells < wide.n_referred_cells
    t = int(np.argmax(many.referred[0]))
    assert (one.relations[:, 1] == t).sum() == 1 and (wide.relations[:, 1] == t).sum() >= 2


def test_direction_defaults_are_refavs_half_plane_up_to_50_m(street: LogContext) -> None:
    # RefAV: within_distance=50, lateral_thresh=inf for both functions
    for func in (P.has_objects_in_relative_direction, P.get_objects_in_relative_direction):
        params = inspect.signature(func).parameters
        assert params["within_distance"].default == 50 and params["lateral_thresh"].default == math.inf
    ego, vehicles = _cat(street, "EGO_VEHICLE"), _cat(street, "VEHICLE")
    default = P.has_objects_in_relative_direction(ego, vehicles, street, direction="left")
    wide = P.has_objects_in_relative_direction(
        ego, vehicles, street, direction="left", within_distance=50, lateral_thresh=math.inf
    )
    assert np.array_equal(default.referred, wide.referred)
    assert np.array_equal(default.relations, wide.relations)
    # the overtaker (lane 2) and the parked and oncoming cars (westbound lane) are all left of the ego
    assert {"overtaker", "parked", "oncoming"} <= _related(street, default, "ego")


def test_direction_lateral_threshold_narrows_the_half_plane() -> None:
    # the bike rides 3.5 m ahead of the ego's centre: its centre is 1.25 m past the ego's front
    objs = street_objects()
    bike = next(o for o in objs if o.track_id == "bike")
    bike.x_m = bike.x_m + 3.5
    ctx = _with_config(MiningConfig(), objs=objs)
    ego, bikes = _cat(ctx, "EGO_VEHICLE"), _cat(ctx, "BICYCLE")
    assert not P.has_objects_in_relative_direction(ego, bikes, ctx, "right").is_empty
    assert P.has_objects_in_relative_direction(ego, bikes, ctx, "right", lateral_thresh=1).is_empty
    assert not P.has_objects_in_relative_direction(ego, bikes, ctx, "right", lateral_thresh=2).is_empty
    # the bike box is 2.3 m from the ego's box
    assert P.has_objects_in_relative_direction(ego, bikes, ctx, "right", within_distance=2).is_empty


def test_get_objects_in_relative_direction_returns_the_related_side(street: LogContext) -> None:
    s = P.get_objects_in_relative_direction(
        _cat(street, "EGO_VEHICLE"),
        _cat(street, "PEDESTRIAN"),
        street,
        "forward",
        within_distance=20,
        lateral_thresh=1,
    )
    assert _tracks(street, s) == {"ped"} and _related(street, s, "ped") == {"ego"}
    assert _span(street, s, "ped") == (2.8, 3.9)


def test_facing_toward_uses_the_subjects_heading(street: LogContext) -> None:
    s = P.facing_toward(
        _cat(street, "PEDESTRIAN"), _cat(street, "EGO_VEHICLE"), street, within_angle=30, max_distance=20
    )
    assert _tracks(street, s) == {"pedA"}  # pedB stands next to it facing away
    assert _span(street, s, "pedA") == (1.6, 2.4)


def test_heading_toward_needs_a_closing_distance(street: LogContext) -> None:
    others = P.scenario_not(P.is_category)(_cat(street, "VEHICLE"), street, category="EGO_VEHICLE")
    s = P.heading_toward(others, _cat(street, "EGO_VEHICLE"), street, max_distance=30)
    # the changer drives behind the ego at the same speed: pointed at it but not closing in
    assert _tracks(street, s) == {"oncoming", "overtaker"}
    assert _span(street, s, "oncoming") == (3.0, 3.7)


def test_pedestrian_crossing_in_front_of_the_lead(street: LogContext) -> None:
    vehicles, peds = _cat(street, "VEHICLE"), _cat(street, "PEDESTRIAN")
    s = P.being_crossed_by(vehicles, peds, street)
    # the pedestrian walks through the lead's front midplane at t = 3 s, 2.75 m ahead; the ego is
    # 17.75 m away then (beyond forward_thresh = 10 m); the standing ped2 crosses nobody
    assert _tracks(street, s) == {"lead"} and _related(street, s, "lead") == {"ped"}
    assert _span(street, s, "lead") == (2.3, 3.2)
    # northward = from the lead's right to its left = counterclockwise seen from above
    assert not P.being_crossed_by(vehicles, peds, street, in_direction="counterclockwise").is_empty
    assert P.being_crossed_by(vehicles, peds, street, in_direction="clockwise").is_empty
    assert P.being_crossed_by(vehicles, peds, street, forward_thresh=1).is_empty


def test_overtaking_on_the_left_is_a_clockwise_crossing(street: LogContext) -> None:
    ego, vehicles = _cat(street, "EGO_VEHICLE"), _cat(street, "VEHICLE")
    s = P.being_crossed_by(
        ego, vehicles, street, direction="left", in_direction="clockwise", forward_thresh=4
    )
    # the overtaker is 5t - 20 m ahead of the ego's centre: tracked from 5 m behind the ego's rear
    # (7.25 m behind its centre, t = 2.55 s) until 5 m ahead of its centre (t = 5 s, excluded)
    assert _related(street, s, "ego") == {"overtaker"} and _span(street, s, "ego") == (2.6, 4.9)
    assert P.being_crossed_by(
        ego, vehicles, street, direction="left", in_direction="counterclockwise", forward_thresh=4
    ).is_empty


def test_crossing_ends_lateral_thresh_past_the_centre_line() -> None:
    # a pedestrian walks north at 1 m/s across the front of a parked car (centre at the origin,
    # facing east, 2 m wide), 4 m ahead of its centre: y = t - 8 m over 16 s
    t = np.round(np.arange(161) * 0.1, 6)
    objs = [
        Obj("ego", "EGO_VEHICLE", const(-100.0, t), const(50.0, t), const(0.0, t)),
        Obj("car", "REGULAR_VEHICLE", const(0.0, t), const(0.0, t), const(0.0, t)),
        Obj("ped", "PEDESTRIAN", const(4.0, t), t - 8.0, const(np.pi / 2, t), 0.6, 0.6),
    ]
    ctx = LogContext(make_log(objs, t, log_id="crossing"))
    car = _cat(ctx, "REGULAR_VEHICLE")
    peds = _cat(ctx, "PEDESTRIAN")
    # RefAV: the crossing ends lateral_thresh past the car's centre line (y < 5 m), not past its
    # left side (y <= 6 m); the approach starts lateral_thresh before its right side (y >= -6 m)
    assert _span(ctx, P.being_crossed_by(car, peds, ctx), "car") == (2.0, 12.9)
    assert _span(ctx, P.being_crossed_by(car, peds, ctx, lateral_thresh=3), "car") == (4.0, 10.9)
    # with lateral_thresh = 0 the pass through the centre line still counts
    assert _span(ctx, P.being_crossed_by(car, peds, ctx, lateral_thresh=0), "car") == (7.0, 8.0)


def test_crossing_speed_threshold_from_config() -> None:
    ctx = _with_config(MiningConfig(crossing_min_speed_mps=2.5))  # the pedestrian walks at 2 m/s
    assert P.being_crossed_by(_cat(ctx, "VEHICLE"), _cat(ctx, "PEDESTRIAN"), ctx).is_empty


def test_near_objects_counts_related_objects(street: LogContext) -> None:
    peds = _cat(street, "PEDESTRIAN")
    pair = P.near_objects(peds, peds, street, distance_thresh=2)
    assert _tracks(street, pair) == {"pedA", "pedB"} and _related(street, pair, "pedA") == {"pedB"}
    assert P.near_objects(peds, peds, street, distance_thresh=2, min_objects=2).is_empty
    with_self = P.near_objects(peds, peds, street, distance_thresh=2, min_objects=2, include_self=True)
    assert _tracks(street, with_self) == {"pedA", "pedB"}
    group = _cat(street, "PEDESTRIAN").restrict(np.isin(street.log.track_ids, ["pedA", "pedB"])[:, None])
    assert _tracks(street, P.near_objects(peds, group, street, distance_thresh=2, min_objects=None)) == set()


def test_following_in_lane_with_and_without_map(street: LogContext, street_nomap: LogContext) -> None:
    for ctx in (street, street_nomap):
        vehicles = _cat(ctx, "VEHICLE")
        s = P.following(vehicles, vehicles, ctx)
        assert _related(ctx, s, "ego") == {"lead"} and _span(ctx, s, "ego") == (0.0, 6.0)
        assert "oncoming" not in _tracks(ctx, s)  # the parked car ahead of it does not move
    changer = P.following(_cat(street, "VEHICLE"), _cat(street, "VEHICLE"), street)
    assert _related(street, changer, "changer") == {"ego", "overtaker"}


def test_following_thresholds_from_config() -> None:
    for cfg in (MiningConfig(following_max_gap_m=10.0), MiningConfig(moving_min_speed_mps=15.0)):
        ctx = _with_config(cfg)
        assert "ego" not in _tracks(ctx, P.following(_cat(ctx, "VEHICLE"), _cat(ctx, "VEHICLE"), ctx))
    # without a map: a lead 1.5 m to the side, and a lead driving at 50 degrees to the follower
    side = [
        Obj("ego", "EGO_VEHICLE", 10 * T_S, const(0.0), const(0.0)),
        Obj("lead", "REGULAR_VEHICLE", 10 * T_S + 12, const(1.5), const(0.0)),
    ]
    for cfg, expected in ((MiningConfig(), True), (MiningConfig(following_max_lateral_m=1.0), False)):
        ctx = LogContext(make_log(side), cfg)
        assert (not P.following(_cat(ctx, "ANY"), _cat(ctx, "ANY"), ctx).is_empty) is expected
    yaw = math.radians(50)
    skew = [
        Obj("ego", "EGO_VEHICLE", 10 * T_S, const(0.0), const(0.0)),
        Obj(
            "lead",
            "REGULAR_VEHICLE",
            12 + 10 * math.cos(yaw) * T_S,
            10 * math.sin(yaw) * (T_S - 0.3),
            const(yaw),
        ),
    ]
    for cfg, expected in ((MiningConfig(), True), (MiningConfig(following_min_heading_cos=0.7), False)):
        ctx = LogContext(make_log(skew), cfg)
        assert (not P.following(_cat(ctx, "ANY"), _cat(ctx, "ANY"), ctx).is_empty) is expected


def test_heading_in_relative_direction_to(street: LogContext) -> None:
    vehicles, ego = _cat(street, "VEHICLE"), _cat(street, "EGO_VEHICLE")
    opposite = P.heading_in_relative_direction_to(vehicles, ego, street, direction="opposite")
    assert _tracks(street, opposite) == {"oncoming", "parked"}  # parked: its heading, the ego moves
    same = P.heading_in_relative_direction_to(vehicles, ego, street, direction="same")
    assert {"lead", "overtaker", "changer", "bus"} <= _tracks(street, same)
    perp = P.heading_in_relative_direction_to(
        _cat(street, "PEDESTRIAN"), ego, street, direction="perpendicular"
    )
    assert {"ped", "pedA", "pedB"} <= _tracks(street, perp)


def test_direction_angle_and_speed_thresholds_from_config() -> None:
    yaw = math.radians(60)
    objs = [
        Obj("ego", "EGO_VEHICLE", 10 * T_S, const(0.0), const(0.0)),
        Obj("car", "REGULAR_VEHICLE", 5 * math.cos(yaw) * T_S, 20 + 5 * math.sin(yaw) * T_S, const(yaw)),
    ]
    for cfg, expected in (
        (MiningConfig(), "perpendicular"),
        (MiningConfig(same_direction_max_deg=70), "same"),
    ):
        ctx = LogContext(make_log(objs), cfg)
        car = P.is_category(_cat(ctx, "ANY"), ctx, "REGULAR_VEHICLE")
        assert not P.heading_in_relative_direction_to(car, _cat(ctx, "EGO_VEHICLE"), ctx, expected).is_empty
    reverse = [
        objs[0],
        Obj(
            "car",
            "REGULAR_VEHICLE",
            50 - 10 * math.cos(0.6) * T_S,
            10 * math.sin(0.6) * T_S,
            const(math.pi - 0.6),
        ),
    ]
    for cfg, expected in ((MiningConfig(), True), (MiningConfig(opposite_direction_min_deg=150), False)):
        ctx = LogContext(make_log(reverse), cfg)  # 180 - 34.4 = 145.6 degrees apart
        car = P.is_category(_cat(ctx, "ANY"), ctx, "REGULAR_VEHICLE")
        assert (
            not P.heading_in_relative_direction_to(car, _cat(ctx, "EGO_VEHICLE"), ctx, "opposite").is_empty
        ) is expected
    # a rolling bicycle (not an agent) at 0.6 m/s has a travel direction only below heading_min_speed_mps
    slow = [objs[0], Obj("bike", "BICYCLE", 20 + 0.6 * T_S, const(3.0), const(0.0), 1.8, 0.6)]
    for cfg, expected in ((MiningConfig(), False), (MiningConfig(heading_min_speed_mps=0.5), True)):
        ctx = LogContext(make_log(slow), cfg)
        bike = _cat(ctx, "BICYCLE")
        assert (
            not P.heading_in_relative_direction_to(bike, _cat(ctx, "EGO_VEHICLE"), ctx, "same").is_empty
        ) is expected


# ====================================================================== map-aware


def test_lane_types_intersection_and_road(street: LogContext) -> None:
    anything = _cat(street, "ANY")
    # the pedestrian crossing the road passes through the bike lane too
    assert _tracks(street, P.on_lane_type(anything, street, lane_type="BIKE")) == {"bike", "bus", "ped"}
    assert _tracks(street, P.on_lane_type(anything, street, lane_type="bus")) == set()
    assert _tracks(street, P.on_intersection(anything, street)) == {"turner"}
    assert _span(street, P.on_intersection(anything, street), "turner") == (0.1, 2.1)
    near = P.near_intersection(anything, street, threshold=5)
    assert "turner" in _tracks(street, near) and "ego" not in _tracks(street, near)
    assert "lead" in _tracks(street, P.near_intersection(anything, street, threshold=20))
    on_road = _tracks(street, P.on_road(anything, street))
    assert {"ego", "bike", "parked"} <= on_road and not {"pedA", "ped2", "stop"} & on_road
    drivable = _tracks(street, P.in_drivable_area(anything, street))
    assert "ped2" in drivable and "pedA" not in drivable  # ped2 stands in the intersection block


def test_pedestrian_crossing_and_jaywalking(street: LogContext) -> None:
    peds = _cat(street, "PEDESTRIAN")
    on = P.at_pedestrian_crossing(peds, street, within_distance=0)
    assert _tracks(street, on) == {"ped"} and _span(street, on, "ped") == (0.2, 6.0)
    assert _tracks(street, P.at_pedestrian_crossing(peds, street, within_distance=3)) == {"ped"}


def test_same_lane_and_side_of_road(street: LogContext) -> None:
    bikes, vehicles = _cat(street, "BICYCLE"), _cat(street, "VEHICLE")
    assert _related(street, P.in_same_lane(bikes, vehicles, street), "bike") == {"bus"}
    ego = _cat(street, "EGO_VEHICLE")
    opposite = P.on_relative_side_of_road(vehicles, ego, street, side="opposite")
    assert _tracks(street, opposite) == {"oncoming", "parked"}
    same = P.on_relative_side_of_road(vehicles, ego, street, side="same")
    assert {"lead", "overtaker", "bus"} <= _tracks(street, same) and "oncoming" not in _tracks(street, same)


def test_at_stop_sign(street: LogContext) -> None:
    s = P.at_stop_sign(_cat(street, "VEHICLE"), street)
    assert _tracks(street, s) == {"ego", "lead"} and _related(street, s, "ego") == {"stop"}
    # the sign stands at x = 46 facing west (heading -pi); the ego's centre is within 10 m before it
    # and less than 1 m past it. At 4.7 s the ego is exactly 1 m past: a floating-point tie of the
    # strict limit (the sign of sin(-pi) decides it), not counted.
    assert _span(street, s, "ego") == (3.7, 4.6)
    # forward_thresh=5: at 4.1 s the ego is exactly 5 m before the sign (a tie, counted this time)
    assert _span(street, P.at_stop_sign(_cat(street, "VEHICLE"), street, forward_thresh=5), "ego") == (
        4.1,
        4.6,
    )


@pytest.mark.parametrize(
    ("config", "span"),
    [(MiningConfig(stop_sign_min_behind_m=0.5), (3.7, 4.6)), (MiningConfig(stop_sign_max_right_m=5.0), None)],
)
def test_stop_sign_thresholds_from_config(config: MiningConfig, span: tuple[float, float] | None) -> None:
    ctx = _with_config(config)
    assert _span(ctx, P.at_stop_sign(_cat(ctx, "VEHICLE"), ctx), "ego") == span


MAP_CALLS = {
    "changing_lanes": lambda c, s: P.changing_lanes(s, c),
    "at_pedestrian_crossing": lambda c, s: P.at_pedestrian_crossing(s, c),
    "on_lane_type": lambda c, s: P.on_lane_type(s, c, "BIKE"),
    "near_intersection": lambda c, s: P.near_intersection(s, c),
    "on_intersection": lambda c, s: P.on_intersection(s, c),
    "at_stop_sign": lambda c, s: P.at_stop_sign(s, c),
    "in_drivable_area": lambda c, s: P.in_drivable_area(s, c),
    "on_road": lambda c, s: P.on_road(s, c),
    "in_same_lane": lambda c, s: P.in_same_lane(s, s, c),
    "on_relative_side_of_road": lambda c, s: P.on_relative_side_of_road(s, s, c),
}


@pytest.mark.parametrize("name", sorted(MAP_CALLS))
def test_map_predicates_without_a_map_raise_an_actionable_error(street_nomap: LogContext, name: str) -> None:
    with pytest.raises(
        MapRequiredError, match=rf"{name}\(\) needs an HD map.*has_objects_in_relative_direction"
    ):
        MAP_CALLS[name](street_nomap, _cat(street_nomap, "ANY"))


# ====================================================================== argument errors and docs


def test_argument_errors_say_how_to_call(street: LogContext) -> None:
    vehicles = _cat(street, "VEHICLE")
    with pytest.raises(TypeError, match=r"log_dir comes after.*turning\(vehicles, log_dir"):
        P.turning(street, "left")  # type: ignore[arg-type]
    with pytest.raises(TypeError, match="predefined variable log_dir, got str 'left'"):
        P.turning(vehicles, "left")  # type: ignore[arg-type]
    with pytest.raises(
        ValueError, match=r"direction must be one of \['forward', 'backward', 'left', 'right'\]"
    ):
        P.has_objects_in_relative_direction(vehicles, vehicles, street, direction="north")
    with pytest.raises(TypeError, match="get_objects_of_category first"):
        P.near_objects("VEHICLE", vehicles, street)  # type: ignore[arg-type]
    with pytest.raises(TypeError, match="min_velocity must be a number"):
        P.has_velocity(vehicles, street, min_velocity="fast")  # type: ignore[arg-type]


def _fmt(value: object) -> str:
    if isinstance(value, float) and math.isinf(value):
        return "-inf" if value < 0 else "inf"
    if isinstance(value, float) and value.is_integer():
        return str(int(value))
    return str(value)


PREDICATES = [name for name in P.DSL_FUNCTIONS if name != "output_scenario"]


@pytest.mark.parametrize("name", PREDICATES)
def test_docstrings_state_every_default_and_an_example(name: str) -> None:
    func = P.DSL_FUNCTIONS[name]
    doc = inspect.getdoc(func) or ""
    assert "Example:" in doc and "Returns:" in doc
    for param in inspect.signature(func).parameters.values():
        if param.default is inspect.Parameter.empty or isinstance(param.default, str):
            continue
        assert re.search(rf"{param.name}:.*?Default {re.escape(_fmt(param.default))}\b", doc, re.S), (
            name,
            param.name,
        )
    if "related_candidates" in inspect.signature(func).parameters and name not in (
        "get_objects_in_relative_direction",
    ):
        assert "SUBJECT" in doc and "REFERENCE" in doc, name


def test_library_reference_and_public_api() -> None:
    text = P.library_reference()
    for name, func in P.DSL_FUNCTIONS.items():
        assert f"def {name}(" in text and (inspect.getdoc(func) or "").splitlines()[0] in text
        assert name in P.__all__
    assert len(P.DSL_FUNCTIONS) >= 30


def test_config_rejects_inconsistent_values() -> None:
    with pytest.raises(ValueError, match="same_direction_max_deg"):
        MiningConfig(same_direction_max_deg=150, opposite_direction_min_deg=120)
    with pytest.raises(ValueError, match="following_max_gap_m"):
        MiningConfig(following_max_gap_m=0)
    with pytest.raises(ValueError, match="turn_min_yaw_rate_deg_s"):
        MiningConfig(turn_min_yaw_rate_deg_s=-1)
    with pytest.raises(ValueError, match="timeout_s"):
        SandboxConfig(timeout_s=0)


def test_category_docstring_lists_the_vehicle_group_exactly() -> None:
    from scenariominer.data.categories import CATEGORY_GROUPS

    doc = " ".join((P.get_objects_of_category.__doc__ or "").split())
    listed = re.search(r'``"VEHICLE"`` \(every motor vehicle incl\. the ego: ([A-Z_, ]+)\)', doc)
    assert listed is not None
    assert set(listed.group(1).replace(" ", "").split(",")) == set(CATEGORY_GROUPS["VEHICLE"])
