"""Lane under each object (issue 12 A3): the lane polygon the box centre lies in, the lane type the
object's category uses, then continuity with the previous frame's lane, then heading agreement.

Two hand-built maps:

* *side by side*: an eastbound vehicle lane ``CAR`` (y 0..3.5, centre line y = 1.75) beside an
  eastbound bike lane (y -1.5..0, centre y = -0.75), and further on (x 100..200) a vehicle lane
  ``CAR2`` (y 0..3.5) overlapped by a bike lane ``BIKE2`` (y -1.5..1, centre y = -0.25) over 1 m;
* *intersection*: an approach lane ``P`` (x 0..20, y -1.75..1.75) continues straight into
  ``S`` (x 20..40) and, bearing 10 degrees left, into ``S2`` (from (20, 0) to (40, 3.5)); a lane
  ``Q`` of another approach, not a successor of ``P``, runs from (20, -2.8) to (40, -2.1) (2
  degrees left of east, within the 3 degree heading tolerance) and overlaps ``S``; a lane ``R``
  from (20, -10) to (40, 10) (45 degrees) overlaps them. All lanes are 3.5 m wide.
"""

from __future__ import annotations

import numpy as np
from mining_scenes import Obj, const, make_log

from scenariominer.data.adapters.av2.map import Av2Map, LaneSegment, LaneType
from scenariominer.geometry import wrap_angle
from scenariominer.mine import dsl as P
from scenariominer.mine.context import LogContext, MapIndex
from scenariominer.mine.lanes import LANE_HEADING_TOLERANCE_DEG

CAR, BIKE, CAR2, BIKE2 = 10, 11, 12, 13
PA, S, Q, R, S2 = 20, 21, 22, 23, 24
T = np.round(np.arange(31) * 0.1, 6)


def _pts(*xy: tuple[float, float]) -> np.ndarray:
    return np.array([[x, y, 0.0] for x, y in xy])


def _lane(
    lane_id: int,
    kind: LaneType,
    left: np.ndarray,
    right: np.ndarray,
    *,
    intersection: bool = False,
    successors: tuple[int, ...] = (),
    predecessors: tuple[int, ...] = (),
) -> LaneSegment:
    return LaneSegment(
        id=lane_id,
        lane_type=kind,
        is_intersection=intersection,
        left_boundary_m=left,
        right_boundary_m=right,
        successors=successors,
        predecessors=predecessors,
    )


def side_by_side_map() -> Av2Map:
    return Av2Map(
        lane_segments=(
            _lane(CAR, LaneType.VEHICLE, _pts((0, 3.5), (100, 3.5)), _pts((0, 0), (100, 0))),
            _lane(BIKE, LaneType.BIKE, _pts((0, 0), (100, 0)), _pts((0, -1.5), (100, -1.5))),
            _lane(CAR2, LaneType.VEHICLE, _pts((100, 3.5), (200, 3.5)), _pts((100, 0), (200, 0))),
            _lane(BIKE2, LaneType.BIKE, _pts((100, 1), (200, 1)), _pts((100, -1.5), (200, -1.5))),
        )
    )


def intersection_map() -> Av2Map:
    def straight(lane_id: int, x0: float, y0: float, x1: float, y1: float, **kw: object) -> LaneSegment:
        d = np.array([x1 - x0, y1 - y0]) / np.hypot(x1 - x0, y1 - y0)
        n = 1.75 * np.array([-d[1], d[0]])  # to the left of the direction of travel
        left = _pts((x0 + n[0], y0 + n[1]), (x1 + n[0], y1 + n[1]))
        right = _pts((x0 - n[0], y0 - n[1]), (x1 - n[0], y1 - n[1]))
        return _lane(lane_id, LaneType.VEHICLE, left, right, **kw)  # type: ignore[arg-type]

    return Av2Map(
        lane_segments=(
            straight(PA, 0, 0, 20, 0, successors=(S, S2)),
            straight(S, 20, 0, 40, 0, intersection=True, predecessors=(PA,)),
            straight(S2, 20, 0, 40, 20 * np.tan(np.radians(10)), intersection=True, predecessors=(PA,)),
            straight(Q, 20, -2.8, 40, -2.1, intersection=True),
            straight(R, 20, -10, 40, 10, intersection=True),
        )
    )


def _lane_ids(ctx: LogContext) -> np.ndarray:
    """``(N, T)`` lane ids under each object (-1: none)."""
    lane = ctx.lane_index("test")
    ids = np.append(ctx.require_map("test").lane_ids, -1)
    return ids[lane]


def _scene(objs: list[Obj], hd: Av2Map) -> LogContext:
    ego = Obj("ego", "EGO_VEHICLE", const(-500.0, T), const(-500.0, T), const(0.0, T))  # off the map
    return LogContext(make_log([ego, *objs], T, log_id="lanes"), hd_map=hd)


# ---------------------------------------------------------------------- lane type


def test_a_car_nearest_the_bike_lane_centre_line_is_in_the_car_lane_polygon_it_lies_in() -> None:
    # centre y = 0.3: 1.05 m from the bike lane's centre line, 1.45 m from the car lane's, but
    # inside the car lane's polygon only
    car = Obj("car", "REGULAR_VEHICLE", 10.0 + 10.0 * T, const(0.3, T), const(0.0, T))
    assert set(_lane_ids(_scene([car], side_by_side_map()))[1].tolist()) == {CAR}


def test_a_car_in_a_car_lane_and_an_overlapping_bike_lane_is_in_the_car_lane() -> None:
    # centre y = 0.5 in CAR2 and BIKE2: 0.75 m from BIKE2's centre line, 1.25 m from CAR2's
    car = Obj("car", "REGULAR_VEHICLE", 110.0 + 10.0 * T, const(0.5, T), const(0.0, T))
    bus = Obj("bus", "BUS", 110.0 + 10.0 * T, const(0.5, T), const(0.0, T))
    moto = Obj("moto", "MOTORCYCLE", 110.0 + 10.0 * T, const(0.5, T), const(0.0, T))
    ctx = _scene([car, bus, moto], side_by_side_map())
    lanes = _lane_ids(ctx)
    assert set(lanes[1].tolist()) == {CAR2} and set(lanes[2].tolist()) == {CAR2}
    # a motorcycle has no lane-type preference: the nearer centre line wins
    assert set(lanes[3].tolist()) == {BIKE2}
    vehicles = P.get_objects_of_category(ctx, "REGULAR_VEHICLE")
    assert not P.on_lane_type(vehicles, ctx, "BIKE").referred.any()


def test_a_car_in_the_bike_lane_only_is_in_the_bike_lane() -> None:
    car = Obj("car", "REGULAR_VEHICLE", 10.0 + 10.0 * T, const(-0.75, T), const(0.0, T))
    assert set(_lane_ids(_scene([car], side_by_side_map()))[1].tolist()) == {BIKE}


def test_a_bicycle_in_the_overlap_prefers_the_bike_lane() -> None:
    # centre y = 0.9: 0.85 m from CAR2's centre line, 1.15 m from BIKE2's; also in plain BIKE
    bike = Obj("bike", "BICYCLIST", 110.0 + 5.0 * T, const(0.9, T), const(0.0, T), 1.8, 0.7)
    in_bike = Obj("in_bike", "BICYCLE", 10.0 + 5.0 * T, const(-0.7, T), const(0.0, T), 1.8, 0.7)
    ctx = _scene([bike, in_bike], side_by_side_map())
    lanes = _lane_ids(ctx)
    assert set(lanes[1].tolist()) == {BIKE2} and set(lanes[2].tolist()) == {BIKE}
    # off every lane polygon: no lane, and on_road agrees
    walker = Obj("walker", "PEDESTRIAN", const(50.0, T), const(6.0, T), const(0.0, T), 0.5, 0.5)
    ctx = _scene([walker], side_by_side_map())
    assert (_lane_ids(ctx)[1] == -1).all()
    assert not P.on_road(P.get_objects_of_category(ctx, "PEDESTRIAN"), ctx).referred.any()


# ---------------------------------------------------------------------- continuity


def test_continuity_keeps_a_car_on_the_successor_of_its_previous_lane() -> None:
    # eastbound at y = -1.4 from x = 5 (on P) through the intersection: from x = 20 it lies in S
    # (1.4 m from its centre line) and in Q (1.4 - 0.035 (x - 20) m from its centre line, 2
    # degrees off: lower cost everywhere past x = 20, 0.88 m at x = 35); S continues P, so S wins.
    car = Obj("car", "REGULAR_VEHICLE", 5.0 + 10.0 * T, const(-1.4, T), const(0.0, T))
    # the same car seen first inside the overlap at x = 34: no previous lane, the lower cost (Q) wins
    late = Obj("late", "REGULAR_VEHICLE", const(34.0, T), const(-1.4, T), const(0.0, T))
    ctx = _scene([car, late], intersection_map())
    lanes = _lane_ids(ctx)
    x = ctx.log.x_m[1]
    assert (lanes[1][x < 19.9] == PA).all()
    assert (lanes[1][x > 20.1] == S).all() and (x > 20.1).sum() >= 14
    assert set(lanes[2].tolist()) == {Q}
    # the lane direction is S's (east), not Q's
    np.testing.assert_allclose(ctx.lane_direction_rad("test")[1][x > 20.1], 0.0, atol=1e-9)


def test_a_car_waiting_where_two_successors_overlap_stays_on_one() -> None:
    # at (22, y) heading 5 degrees, y jittering 0.15 / 0.25 m around the point equally far from
    # the centre lines of S (y = 0) and S2 (0.35 m at x = 22): the nearer centre line alternates,
    # the lane does not
    y = np.where(np.arange(T.size) % 2 == 0, 0.15, 0.25)
    car = Obj("car", "REGULAR_VEHICLE", const(22.0, T), y, const(np.radians(5.0), T))
    lanes = _lane_ids(_scene([car], intersection_map()))[1]
    assert len(set(lanes.tolist())) == 1 and lanes[0] in (S, S2)
    hd = MapIndex(intersection_map())
    alone, _ = hd.lanes_at(const(22.0, T), y, const(np.radians(5.0), T))  # points alone: it alternates
    assert set(hd.lane_ids[alone].tolist()) == {S, S2}


def test_continuity_yields_to_a_clear_heading_disagreement() -> None:
    # on P, then at (30, 0) in S, S2 and R heading 60 degrees left: S is 60 degrees off, S2 50,
    # R (45 degrees) 15: S and S2 are more than 3 degrees worse than R, which wins although S
    # and S2 continue P
    xs = np.where(T < 1.5, 15.0 + 2.0 * T, 30.0)
    yaw = np.where(T < 1.5, 0.0, np.radians(60.0))
    car = Obj("car", "REGULAR_VEHICLE", xs, np.where(T < 1.5, 0.0, 0.0), yaw)
    lanes = _lane_ids(_scene([car], intersection_map()))
    assert set(lanes[1][T < 1.5].tolist()) == {PA} and set(lanes[1][T >= 1.5].tolist()) == {R}


def test_heading_agreement_comes_before_the_nearer_centre_line() -> None:
    # at (30, 1.5) heading east: in S (1.5 m from its centre line, aligned) and in S2 (0.26 m from
    # its centre line, 10 degrees off, cost 0.32 m): S2 is more than 3 degrees worse aligned
    hd = MapIndex(intersection_map())
    lane, _ = hd.lanes_at(np.array([30.0, 30.0]), np.array([1.5, 1.5]), np.radians([0.0, 10.0]))
    assert hd.lane_ids[lane].tolist() == [S, S2]


def test_lanes_at_without_tracks_keeps_each_point_alone() -> None:
    hd = MapIndex(intersection_map())
    # 1-D input: independent points, no continuity (the first point on P does not pull the second into S)
    lane, direction = hd.lanes_at(np.array([10.0, 34.0]), np.array([-1.4, -1.4]), np.zeros(2))
    assert hd.lane_ids[lane].tolist() == [PA, Q]
    assert np.isfinite(direction).all()


def _sequential_lanes(hd: MapIndex, x: np.ndarray, y: np.ndarray, yaw: np.ndarray) -> np.ndarray:
    """Reference: the same rules frame by frame in plain Python (no lane types: one category)."""
    out = np.full(x.shape, -1)
    for i in range(x.shape[0]):
        prev = -1
        for t in range(x.shape[1]):
            _, lane, cost, lane_yaw = hd.map.lane_candidates(
                np.array([[x[i, t], y[i, t]]]), yaw[i, t : t + 1]
            )
            if lane.size == 0:
                continue
            mismatch = np.abs(wrap_angle(yaw[i, t] - lane_yaw))
            if np.isfinite(mismatch).all():
                ok = mismatch <= mismatch.min() + np.radians(LANE_HEADING_TOLERANCE_DEG)
                lane, cost = lane[ok], cost[ok]
            follows = np.array([prev >= 0 and (c == prev or c in hd.successors[prev]) for c in lane])
            prev = int(lane[np.lexsort((cost, ~follows))[0]])
            out[i, t] = prev
    return out


def fan_map() -> Av2Map:
    """Five 3.5 m lanes from (0, 0), 40 m long, at 0, 2, 4, 6 and 8 degrees: all overlap near the
    origin; links 0 -> 1, 1 -> 2, 3 -> 1 and 4 -> 0 (arbitrary, to exercise continuity)."""
    links = {0: (1,), 1: (2,), 3: (1,), 4: (0,)}
    lanes = []
    for k in range(5):
        d = np.array([np.cos(np.radians(2 * k)), np.sin(np.radians(2 * k))])
        n = 1.75 * np.array([-d[1], d[0]])
        end = 40 * d
        left = _pts((n[0], n[1]), (end[0] + n[0], end[1] + n[1]))
        right = _pts((-n[0], -n[1]), (end[0] - n[0], end[1] - n[1]))
        lanes.append(
            _lane(100 + k, LaneType.VEHICLE, left, right, successors=tuple(100 + j for j in links.get(k, ())))
        )
    return Av2Map(lane_segments=tuple(lanes))


def test_the_vectorised_continuity_matches_a_frame_by_frame_loop() -> None:
    rng = np.random.default_rng(7)
    hd = MapIndex(intersection_map())
    n, t = 40, 60
    # random walks through the overlapping lanes, headings 0..60 degrees (many within 3 degrees
    # of each other), some frames missing, some headings unknown
    x = 14.0 + np.cumsum(rng.uniform(0.0, 0.8, (n, t)), axis=1)
    y = rng.uniform(-3.0, 4.0, (n, 1)) + np.cumsum(rng.normal(0.0, 0.3, (n, t)), axis=1)
    yaw = np.radians(rng.choice([0.0, 1.0, 2.0, 5.0, 10.0, 14.0, 45.0, 60.0], (n, t)))
    x[rng.random((n, t)) < 0.05] = np.nan
    yaw[rng.random((n, t)) < 0.05] = np.nan
    lane, _ = hd.lanes_at(x, y, yaw, np.full(n, "REGULAR_VEHICLE"))
    assert (lane >= 0).sum() > 500 and len(np.unique(lane)) == 6
    np.testing.assert_array_equal(lane, _sequential_lanes(hd, x, y, yaw))
    # the fan: random points near its origin and headings of 0 to 8 degrees change the lane
    # often inside one run of ambiguous frames
    fan = MapIndex(fan_map())
    x = rng.uniform(0.0, 12.0, (n, t))
    y = rng.uniform(-1.0, 2.0, (n, t))
    yaw = np.radians(rng.uniform(0.0, 8.0, (n, t)))
    x[rng.random((n, t)) < 0.05] = np.nan
    lane, _ = fan.lanes_at(x, y, yaw)
    assert len(np.unique(lane)) == 6
    np.testing.assert_array_equal(lane, _sequential_lanes(fan, x, y, yaw))
