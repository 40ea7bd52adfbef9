"""Routes and the vector map of the generated road layouts (straight road, four-way junction)."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np
import shapely
from numpy.typing import NDArray

from scenariominer.data.adapters.av2.map import (
    Av2Map,
    DrivableArea,
    LaneSegment,
    LaneType,
    PedestrianCrossing,
)
from scenariominer.data.log import FloatArray
from scenariominer.geometry import rotate_xy
from scenariominer.synth.actors import (
    _arc,
    _Path,
)
from scenariominer.synth.vocab import (
    ARM_M,
    BOX_HALF_M,
    CROSSWALK_FAR_M,
    CROSSWALK_NEAR_M,
    LANE_WIDTH_M,
    ROAD_HALF_WIDTH_M,
    MapLayout,
)

BoolArray = NDArray[np.bool_]


# ---------------------------------------------------------------------- routes and map (canonical frame)

_LANE_Y = {1: -0.5 * LANE_WIDTH_M, 2: -1.5 * LANE_WIDTH_M}  # centre lines of the inner/outer lane heading +x


def _route(k: int, movement: str, lane: int) -> _Path:
    """Centre line of a route entering from arm ``k`` (0 = west, heading east; CCW quarter turns)."""
    y = _LANE_Y[lane]
    b = BOX_HALF_M
    if movement == "straight":
        pts = np.array([[-ARM_M, y], [ARM_M, y]])
    elif movement == "left":
        r = b - _LANE_Y[1]
        pts = np.vstack(
            [
                [[-ARM_M, _LANE_Y[1]], [-b, _LANE_Y[1]]],
                _arc((-b, b), r, -np.pi / 2, 0.0),
                [[-_LANE_Y[1], ARM_M]],
            ]
        )
    elif movement == "right":
        r = b + _LANE_Y[2]
        pts = np.vstack(
            [
                [[-ARM_M, _LANE_Y[2]], [-b, _LANE_Y[2]]],
                _arc((-b, -b), r, np.pi / 2, 0.0),
                [[_LANE_Y[2], -ARM_M]],
            ]
        )
    else:  # pragma: no cover - internal vocabulary
        raise ValueError(movement)
    return _Path.through(pts).rotated(k * np.pi / 2)


def _arc_end_s(movement: str) -> float:
    """Arc length (along :func:`_route`) at which a turn ends."""
    if movement == "left":
        return ARM_M - BOX_HALF_M + (BOX_HALF_M - _LANE_Y[1]) * np.pi / 2
    if movement == "right":
        return ARM_M - BOX_HALF_M + (BOX_HALF_M + _LANE_Y[2]) * np.pi / 2
    return ARM_M + BOX_HALF_M


@dataclass(eq=False)
class _LaneDraft:
    """A lane segment under construction (canonical frame), linked before it is frozen."""

    id: int
    left: FloatArray
    right: FloatArray
    intersection: bool
    marks: tuple[str, str]
    succ: list[int] = field(default_factory=list)
    pred: list[int] = field(default_factory=list)
    left_neighbor: int | None = None
    right_neighbor: int | None = None


class _MapBuilder:
    """Collects lane segments in the canonical frame, then links and transforms them."""

    first_id = 40_000_001

    def __init__(self) -> None:
        self.lanes: list[_LaneDraft] = []

    def straight(
        self, k: int, x0: float, x1: float, lane: int, *, intersection: bool, marks: tuple[str, str]
    ) -> list[int]:
        """Segments (at most 60 m) along +x from ``x0`` to ``x1`` in lane ``lane``, rotated by arm ``k``."""
        y = _LANE_Y[lane]
        n = max(1, int(np.ceil((x1 - x0) / 60.0)))
        edges = np.linspace(x0, x1, n + 1)
        ids = []
        for a, b in zip(edges[:-1], edges[1:], strict=True):
            left = rotate_xy(np.array([[a, y + LANE_WIDTH_M / 2], [b, y + LANE_WIDTH_M / 2]]), k * np.pi / 2)
            right = rotate_xy(np.array([[a, y - LANE_WIDTH_M / 2], [b, y - LANE_WIDTH_M / 2]]), k * np.pi / 2)
            ids.append(self.add(left, right, intersection=intersection, marks=marks))
        for a_id, b_id in zip(ids[:-1], ids[1:], strict=True):
            self.link(a_id, b_id)
        return ids

    def turn(self, k: int, movement: str) -> int:
        """Add the left (inner lane) or right (outer lane) turn connector of arm ``k``."""
        b = BOX_HALF_M
        if movement == "left":
            r = b - _LANE_Y[1]
            left = _arc((-b, b), r - LANE_WIDTH_M / 2, -np.pi / 2, 0.0, 12)
            right = _arc((-b, b), r + LANE_WIDTH_M / 2, -np.pi / 2, 0.0, 12)
        else:
            r = b + _LANE_Y[2]
            left = _arc((-b, -b), r + LANE_WIDTH_M / 2, np.pi / 2, 0.0, 12)
            right = _arc((-b, -b), r - LANE_WIDTH_M / 2, np.pi / 2, 0.0, 12)
        return self.add(
            rotate_xy(left, k * np.pi / 2),
            rotate_xy(right, k * np.pi / 2),
            intersection=True,
            marks=("NONE", "NONE"),
        )

    def add(self, left: FloatArray, right: FloatArray, *, intersection: bool, marks: tuple[str, str]) -> int:
        draft = _LaneDraft(self.first_id + len(self.lanes), left, right, intersection, marks)
        self.lanes.append(draft)
        return draft.id

    def link(self, a: int, b: int) -> None:
        self.lanes[a - self.first_id].succ.append(b)
        self.lanes[b - self.first_id].pred.append(a)

    def neighbours(self, inner: Sequence[int], outer: Sequence[int]) -> None:
        for i, o in zip(inner, outer, strict=True):
            self.lanes[i - self.first_id].right_neighbor = o
            self.lanes[o - self.first_id].left_neighbor = i

    def segments(self, tf: Callable[[FloatArray], FloatArray], z_m: float) -> tuple[LaneSegment, ...]:
        def xyz(xy: FloatArray) -> FloatArray:
            return np.column_stack([tf(xy), np.full(len(xy), z_m)])

        return tuple(
            LaneSegment(
                id=d.id,
                lane_type=LaneType.VEHICLE,
                is_intersection=d.intersection,
                left_boundary_m=xyz(d.left),
                right_boundary_m=xyz(d.right),
                left_mark_type=d.marks[0],
                right_mark_type=d.marks[1],
                successors=tuple(d.succ),
                predecessors=tuple(d.pred),
                left_neighbor_id=d.left_neighbor,
                right_neighbor_id=d.right_neighbor,
            )
            for d in self.lanes
        )


_MARKS_INNER = ("SOLID_YELLOW", "DASHED_WHITE")
_MARKS_OUTER = ("DASHED_WHITE", "SOLID_WHITE")


def _build_map(layout: MapLayout, tf: Callable[[FloatArray], FloatArray], z_m: float) -> Av2Map:
    """Build the vector map of ``layout`` with every point passed through ``tf`` (canonical → city)."""
    mb = _MapBuilder()
    crossings: list[PedestrianCrossing] = []
    if layout is MapLayout.STRAIGHT:
        for k in (0, 2):
            inner = mb.straight(k, -ARM_M, ARM_M, 1, intersection=False, marks=_MARKS_INNER)
            outer = mb.straight(k, -ARM_M, ARM_M, 2, intersection=False, marks=_MARKS_OUTER)
            mb.neighbours(inner, outer)
        area = shapely.box(-ARM_M, -ROAD_HALF_WIDTH_M, ARM_M, ROAD_HALF_WIDTH_M)
    else:
        b = BOX_HALF_M
        inbound: dict[tuple[int, int], list[int]] = {}
        outbound: dict[tuple[int, int], list[int]] = {}
        through: dict[tuple[int, int], int] = {}
        for k in range(4):
            for lane, marks in ((1, _MARKS_INNER), (2, _MARKS_OUTER)):
                inbound[k, lane] = mb.straight(k, -ARM_M, -b, lane, intersection=False, marks=marks)
                outbound[k, lane] = mb.straight(k, b, ARM_M, lane, intersection=False, marks=marks)
                through[k, lane] = mb.straight(k, -b, b, lane, intersection=True, marks=("NONE", "NONE"))[0]
            mb.neighbours(inbound[k, 1], inbound[k, 2])
            mb.neighbours(outbound[k, 1], outbound[k, 2])
            mb.neighbours([through[k, 1]], [through[k, 2]])
            edge1 = rotate_xy(
                np.array([[-CROSSWALK_FAR_M, -ROAD_HALF_WIDTH_M], [-CROSSWALK_FAR_M, ROAD_HALF_WIDTH_M]]),
                k * np.pi / 2,
            )
            edge2 = rotate_xy(
                np.array([[-CROSSWALK_NEAR_M, -ROAD_HALF_WIDTH_M], [-CROSSWALK_NEAR_M, ROAD_HALF_WIDTH_M]]),
                k * np.pi / 2,
            )
            crossings.append(
                PedestrianCrossing(
                    id=30_000_001 + k,
                    edge1_m=np.column_stack([tf(edge1), np.full(2, z_m)]),
                    edge2_m=np.column_stack([tf(edge2), np.full(2, z_m)]),
                )
            )
        for k in range(4):
            left, right = mb.turn(k, "left"), mb.turn(k, "right")
            for lane in (1, 2):
                mb.link(inbound[k, lane][-1], through[k, lane])
                mb.link(through[k, lane], outbound[k, lane][0])
            mb.link(inbound[k, 1][-1], left)
            mb.link(left, outbound[(k + 1) % 4, 1][0])
            mb.link(inbound[k, 2][-1], right)
            mb.link(right, outbound[(k + 3) % 4, 2][0])
        area = shapely.union_all(
            [
                shapely.box(-ARM_M, -ROAD_HALF_WIDTH_M, ARM_M, ROAD_HALF_WIDTH_M),
                shapely.box(-ROAD_HALF_WIDTH_M, -ARM_M, ROAD_HALF_WIDTH_M, ARM_M),
                shapely.box(-b, -b, b, b),
            ]
        )
    ring = np.asarray(shapely.get_coordinates(area.exterior))[:-1]
    drivable = DrivableArea(id=20_000_001, boundary_m=np.column_stack([tf(ring), np.full(len(ring), z_m)]))
    return Av2Map(
        lane_segments=mb.segments(tf, z_m), pedestrian_crossings=tuple(crossings), drivable_areas=(drivable,)
    )
