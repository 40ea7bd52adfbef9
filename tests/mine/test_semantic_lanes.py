"""Semantic lanes are RefAV's directed chains: a split or a merge never joins two lanes side by side.

The split map: lane A (x 0..50) continues straight into B (x 50..100) and D (x 100..150); at
x = 50 a second lane C branches off A to the right, veering 3.6 m south over 50 m, and continues
into E (x 100..150) beside D. B/C and D/E are left/right neighbours.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from mining_scenes import Obj, const, make_log

from scenariominer.data.adapters.av2.map import Av2Map, LaneSegment, LaneType, read_av2_map
from scenariominer.mine import dsl as P
from scenariominer.mine.context import LogContext, MapIndex

A, B, C, D, E = 1, 2, 3, 4, 5
T = np.round(np.arange(5) * 0.1, 6)


def _pts(*xy: tuple[float, float]) -> np.ndarray:
    return np.array([[x, y, 0.0] for x, y in xy])


def _lane(
    lane_id: int,
    left: np.ndarray,
    right: np.ndarray,
    successors: tuple[int, ...] = (),
    predecessors: tuple[int, ...] = (),
    left_neighbor_id: int | None = None,
    right_neighbor_id: int | None = None,
) -> LaneSegment:
    return LaneSegment(
        id=lane_id,
        lane_type=LaneType.VEHICLE,
        is_intersection=False,
        left_boundary_m=left,
        right_boundary_m=right,
        successors=successors,
        predecessors=predecessors,
        left_neighbor_id=left_neighbor_id,
        right_neighbor_id=right_neighbor_id,
    )


def split_map() -> Av2Map:
    lanes = (
        _lane(A, _pts((0, 1.8), (50, 1.8)), _pts((0, -1.8), (50, -1.8)), successors=(B, C)),
        _lane(
            B,
            _pts((50, 1.8), (100, 1.8)),
            _pts((50, -1.8), (100, -1.8)),
            predecessors=(A,),
            successors=(D,),
            right_neighbor_id=C,
        ),
        _lane(
            C,
            _pts((50, 1.8), (100, -1.8)),
            _pts((50, -1.8), (100, -5.4)),
            predecessors=(A,),
            successors=(E,),
            left_neighbor_id=B,
        ),
        _lane(
            D,
            _pts((100, 1.8), (150, 1.8)),
            _pts((100, -1.8), (150, -1.8)),
            predecessors=(B,),
            right_neighbor_id=E,
        ),
        _lane(
            E,
            _pts((100, -1.8), (150, -1.8)),
            _pts((100, -5.4), (150, -5.4)),
            predecessors=(C,),
            left_neighbor_id=D,
        ),
    )
    return Av2Map(lane_segments=lanes, pedestrian_crossings=(), drivable_areas=())


def _ids(hd: MapIndex, lanes: np.ndarray) -> set[int]:
    return {int(hd.lane_ids[i]) for i in lanes}


def test_chains_follow_one_branch_and_never_hold_neighbours() -> None:
    hd = MapIndex(split_map())
    pos = {int(lid): i for i, lid in enumerate(hd.lane_ids)}
    chains = {lid: _ids(hd, hd.semantic_lanes[pos[lid]]) for lid in (A, B, C, D, E)}
    assert chains[A] == {A, B, D}  # the straighter branch
    assert chains[B] == {A, B, D} and chains[D] == {A, B, D}
    assert chains[C] == {A, C, E} and chains[E] == {A, C, E}
    for left, right in ((B, C), (D, E)):
        assert right not in chains[left] and left not in chains[right]
    m = hd.in_semantic_lane
    assert m.shape == (6, 6) and not m[-1].any() and not m[:, -1].any()
    assert m[pos[C], pos[A]] and not m[pos[A], pos[C]]


def _split_scene() -> LogContext:
    zero = const(0.0, T)
    objs = [
        Obj("ego", "EGO_VEHICLE", const(30.0, T), zero, zero),  # on A
        Obj("on_b", "REGULAR_VEHICLE", const(90.0, T), const(0.5, T), zero),
        Obj("on_c", "REGULAR_VEHICLE", const(90.0, T), const(-3.0, T), const(-0.07, T)),
    ]
    return LogContext(make_log(objs, T, log_id="split"), hd_map=split_map())


def test_in_same_lane_keeps_neighbours_apart_and_is_directed() -> None:
    ctx = _split_scene()
    lane = ctx.lane_index("test")
    assert [int(ctx.require_map("test").lane_ids[lane[i, 0]]) for i in range(3)] == [A, B, C]
    cars = P.get_objects_of_category(ctx, "VEHICLE")

    def related(subject: str) -> set[str]:
        s = P.in_same_lane(cars.restrict(ctx.log.track_ids[:, None] == subject), cars, ctx)
        return {str(ctx.log.track_ids[j]) for j in s.relations[:, 2]}

    # the car on the branch C shares the lane of the ego on A, not of the car beside it on B
    assert related("on_c") == {"ego"}
    assert related("on_b") == {"ego"}
    # directed as RefAV's: the ego's lane A continues into B only
    assert related("ego") == {"on_b"}


def test_semantic_lanes_of_the_real_map_match_refav(av2_log_dir: Path) -> None:
    hd = MapIndex(read_av2_map(av2_log_dir))
    sizes = np.array([c.size for c in hd.semantic_lanes])
    # RefAV's get_semantic_lane on this map: 5.5 lanes on average (our former connected
    # components: 11.9, with 11 pairs of left/right neighbours in one group)
    assert sizes.mean() == pytest.approx(5.5, abs=0.05)
    m = hd.in_semantic_lane
    for i in range(hd.n_lanes):
        for j in (hd.left_neighbor[i], hd.right_neighbor[i]):
            if j >= 0:
                assert not m[i, j] and not m[j, i]
