"""Synthetic, labelled braking scenarios written as Argoverse 2 sensor logs with a vector map.

Each generated log lasts 15 s at 10 Hz and contains the ego, one labelled *guest* whose behaviour
makes the ego brake (or, for ``not_relevant``, traffic that does not), and several background
objects (moving traffic, parked cars, pedestrians on the sidewalks). Every log comes with a small
vector map (a straight four-lane road, or a four-way intersection with crosswalks) in the
Argoverse 2 JSON format, so map-aware features work on synthetic data as on real data.

How a scenario is made (all in closed form with numpy, never a per-frame simulation loop):

1. Actors follow *paths* (dense polylines along the map's lane centre lines, crosswalks or
   sidewalks) with piecewise-linear *speed profiles*; position along the path is the exact
   integral of the profile.
2. The guest's timing is drawn first. The ego's braking is then *derived* from it, so it is
   physically consistent: for a leader (cut-in, braking lead, stopped object) the gentlest
   deceleration at or above a drawn preference that keeps a gap is found by checking candidate
   profiles on a fine time grid; for a crossing actor (pedestrian, crossing vehicle, oncoming
   vehicle in a left turn) the ego brakes to stop a drawn margin before the swept corridor of
   the guest, timed so that it would otherwise arrive while the guest is in that corridor, and
   drives on once the guest has cleared it.
3. Background actors are drawn at random and kept only if their boxes never come near the ego's
   within a 3 s look-ahead (so they cannot explain the braking) nor overlap the guest.
4. Annotation noise is added: position jitter (0.05-0.1 m), heading jitter, random missing
   frames, occlusion gaps, and a visibility range.
5. The scene is placed in the city frame by a random rotation and translation.

Labels follow the braking paper's annotation scheme (``log_id``, ``guest_id``,
``scenario_category``) plus the time window of the interaction: from the guest's triggering
action (or the ego's braking onset, whichever is earlier) until the ego drives on again after
yielding or following to a stop, or, where it does not (a cut-in, a stopped object ahead), until
it has reached its lowest speed. For ``not_relevant`` it is the time the guest spends within
40 m of the ego.

The in-memory logs (:func:`generate_log`) carry the ego's box centre (``dataset="synthetic"``).
Written logs follow the Argoverse 2 convention (the writer moves the ego pose to the rear axle,
:data:`~scenariominer.data.adapters.av2.AV2_EGO_CENTER_OFFSET_M` behind the box centre, and the reader back).
"""

from __future__ import annotations

import csv
import uuid
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from enum import StrEnum
from pathlib import Path

import numpy as np
import shapely
from numpy.typing import NDArray

from scenariominer.data.adapters.av2 import AV2_EGO_SIZE_M, write_av2_log
from scenariominer.data.adapters.av2.map import (
    Av2Map,
    DrivableArea,
    LaneSegment,
    LaneType,
    PedestrianCrossing,
    write_av2_map,
)
from scenariominer.data.log import FloatArray, Log, build_log
from scenariominer.geometry import OrientedBoxes, boxes_overlap, rotate_xy, wrap_angle

BoolArray = NDArray[np.bool_]

# ---------------------------------------------------------------------- public vocabulary


class ScenarioCategory(StrEnum):
    """Scenario categories of the braking paper (Table III) that the generator produces."""

    CUT_IN = "cut_in"
    LEAD_BRAKE = "lead_brake"
    APPROACH_STOP = "approach_stop"
    PED_CROSSING = "ped_crossing"
    OBJ_CROSSING = "obj_crossing"
    LEFT_OPPO = "left_oppo"
    RIGHT_PED = "right_ped"
    NOT_RELEVANT = "not_relevant"


class MapLayout(StrEnum):
    """Road layouts of the synthetic vector maps."""

    STRAIGHT = "straight"
    INTERSECTION = "intersection"


#: Columns of ``labels.csv``.
LABEL_COLUMNS: tuple[str, ...] = ("log_id", "guest_id", "scenario_category", "start_ns", "end_ns")

#: Frame period (s) and number of frames of a generated log (15 s at 10 Hz).
FRAME_PERIOD_S = 0.1
N_FRAMES = 150

#: Road geometry (metres): lane width, half-width of a road (two lanes each way), half-size of the
#: intersection box, length of each arm from the centre, crosswalk near/far distance from the centre.
LANE_WIDTH_M = 3.5
ROAD_HALF_WIDTH_M = 7.0
BOX_HALF_M = 12.0
ARM_M = 300.0
CROSSWALK_NEAR_M = 13.0
CROSSWALK_FAR_M = 16.0

#: Guests within this distance (m) of the ego define a ``not_relevant`` label's window.
NOT_RELEVANT_RANGE_M = 40.0


@dataclass(frozen=True)
class ScenarioLabel:
    """One row of ``labels.csv``.

    Attributes:
        log_id: the log's id (its folder name).
        guest_id: track id of the labelled guest object.
        scenario_category: what the guest does to the ego.
        start_ns: first timestamp of the interaction window (a timestamp of the log).
        end_ns: last timestamp of the interaction window.
    """

    log_id: str
    guest_id: str
    scenario_category: ScenarioCategory
    start_ns: int
    end_ns: int


@dataclass(frozen=True, eq=False)
class SynthLog:
    """One generated scenario in memory.

    Attributes:
        log: the log, ego at its box centre, ``dataset="synthetic"``.
        av2_map: its vector map (city frame).
        label: the labelled guest and window.
        layout: the road layout of the map.
    """

    log: Log
    av2_map: Av2Map
    label: ScenarioLabel
    layout: MapLayout


@dataclass(frozen=True)
class SynthResult:
    """What :func:`generate` wrote.

    Attributes:
        out_dir: the output folder (holds one folder per log and ``labels.csv``).
        labels_csv: path of ``labels.csv``.
        log_dirs: ``(n,)`` Argoverse 2 log folders, in generation order.
        labels: ``(n,)`` label rows, in the same order.
        n_tracks: ``(n,)`` tracks per log, the ego included (what a reader returns).
    """

    out_dir: Path
    labels_csv: Path
    log_dirs: tuple[Path, ...]
    labels: tuple[ScenarioLabel, ...]
    n_tracks: tuple[int, ...]


# ---------------------------------------------------------------------- geometry helpers


def _arc(center: tuple[float, float], radius: float, a0: float, a1: float, n: int = 24) -> FloatArray:
    ang = np.linspace(a0, a1, n)
    return np.stack([center[0] + radius * np.cos(ang), center[1] + radius * np.sin(ang)], axis=1)


@dataclass(frozen=True, eq=False)
class _Path:
    """A dense polyline with arc length and heading; poses beyond its ends are extrapolated straight."""

    xy: FloatArray  # (M, 2)
    s: FloatArray  # (M,)
    heading: FloatArray  # (M,) unwrapped

    @classmethod
    def through(cls, points: FloatArray, spacing_m: float = 0.5) -> _Path:
        pts = np.asarray(points, dtype=np.float64)
        seg = np.linalg.norm(np.diff(pts, axis=0), axis=1)
        pts = pts[np.concatenate([[True], seg > 1e-9])]
        cum = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(pts, axis=0), axis=1))])
        s = np.append(np.arange(0.0, cum[-1], spacing_m), cum[-1])
        xy = np.stack([np.interp(s, cum, pts[:, 0]), np.interp(s, cum, pts[:, 1])], axis=1)
        d = np.diff(xy, axis=0)
        seg_heading = np.arctan2(d[:, 1], d[:, 0])
        heading = np.unwrap(np.append(seg_heading, seg_heading[-1]))
        return cls(xy=xy, s=s, heading=heading)

    @property
    def length_m(self) -> float:
        return float(self.s[-1])

    def pose(self, s_m: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
        """``x, y, yaw`` at arc lengths ``s_m`` (any shape)."""
        s = np.asarray(s_m, dtype=np.float64)
        sc = np.clip(s, 0.0, self.length_m)
        yaw = np.interp(sc, self.s, self.heading)
        over = s - sc
        x = np.interp(sc, self.s, self.xy[:, 0]) + over * np.cos(yaw)
        y = np.interp(sc, self.s, self.xy[:, 1]) + over * np.sin(yaw)
        return x, y, wrap_angle(yaw)

    def rotated(self, theta: float) -> _Path:
        return _Path(xy=rotate_xy(self.xy, theta), s=self.s, heading=self.heading + theta)


@dataclass(frozen=True, eq=False)
class _Profile:
    """Piecewise-linear speed over time (knots), constant beyond the first and last knot."""

    t_s: FloatArray  # (K,) strictly increasing
    v_mps: FloatArray  # (K,) >= 0
    s0_m: float  # distance travelled at t_s[0]

    @classmethod
    def of(cls, knots: Sequence[tuple[float, float]], s0_m: float = 0.0) -> _Profile:
        t = [float(knots[0][0])]
        v = [max(float(knots[0][1]), 0.0)]
        for tk, vk in knots[1:]:
            if tk > t[-1] + 1e-9:
                t.append(float(tk))
                v.append(max(float(vk), 0.0))
            else:
                v[-1] = max(float(vk), 0.0)
        return cls(t_s=np.asarray(t), v_mps=np.asarray(v), s0_m=s0_m)

    def speed(self, t: FloatArray) -> FloatArray:
        return np.interp(t, self.t_s, self.v_mps)

    def distance(self, t: FloatArray) -> FloatArray:
        """Distance travelled at times ``t`` (exact integral of the piecewise-linear speed)."""
        t = np.asarray(t, dtype=np.float64)
        dt = np.diff(self.t_s)
        s_knot = self.s0_m + np.concatenate([[0.0], np.cumsum(0.5 * (self.v_mps[:-1] + self.v_mps[1:]) * dt)])
        acc = np.append(np.diff(self.v_mps) / dt, 0.0)  # constant speed after the last knot
        k = np.clip(np.searchsorted(self.t_s, t, side="right") - 1, 0, self.t_s.size - 1)
        tau = t - self.t_s[k]
        a = np.where(tau < 0.0, 0.0, acc[k])  # constant speed before the first knot
        return np.asarray(s_knot[k] + self.v_mps[k] * tau + 0.5 * a * tau**2, dtype=np.float64)

    def time_at(self, s_m: float, t_max_s: float = 60.0) -> float:
        """First time the distance reaches ``s_m`` (``inf`` if not before ``t_max_s``)."""
        grid = np.arange(min(self.t_s[0], 0.0) - 30.0, t_max_s, 0.005)
        dist = self.distance(grid)
        i = int(np.searchsorted(np.maximum.accumulate(dist), s_m))
        return float(grid[i]) if i < grid.size else float("inf")


def _boxes(x: FloatArray, y: FloatArray, yaw: FloatArray, length: float, width: float) -> NDArray[np.object_]:
    """Shapely rectangles of boxes centred at ``x, y`` with heading ``yaw`` (all ``(K,)``)."""
    local = np.array([[0.5, 0.5], [-0.5, 0.5], [-0.5, -0.5], [0.5, -0.5]]) * [length, width]
    c, s = np.cos(yaw)[:, None], np.sin(yaw)[:, None]
    cx = x[:, None] + c * local[:, 0] - s * local[:, 1]
    cy = y[:, None] + s * local[:, 0] + c * local[:, 1]
    return np.asarray(shapely.polygons(np.stack([cx, cy], axis=2)), dtype=object)


def _first_run_on(
    path: _Path, length: float, width: float, region: shapely.Geometry, step_m: float = 0.25
) -> tuple[float, float] | None:
    """Arc lengths where a box moving along ``path`` first enters and then leaves ``region``."""
    s = np.arange(0.0, path.length_m, step_m)
    x, y, yaw = path.pose(s)
    hit = np.asarray(shapely.intersects(_boxes(x, y, yaw, length, width), region), dtype=bool)
    if not hit.any():
        return None
    i0 = int(np.argmax(hit))
    rest = hit[i0:]
    i1 = i0 + (int(np.argmin(rest)) - 1 if not rest.all() else rest.size - 1)
    return float(s[i0]), float(s[i1])


# ---------------------------------------------------------------------- actors


@dataclass(eq=False)
class _Track:
    """One actor's noise-free states on the log's frame grid (canonical frame)."""

    category: str
    length: float
    width: float
    height: float
    x: FloatArray
    y: FloatArray
    yaw: FloatArray
    valid: BoolArray
    track_id: str = ""

    @classmethod
    def along(
        cls, path: _Path, profile: _Profile, t: FloatArray, category: str, size: tuple[float, float, float]
    ) -> _Track:
        x, y, yaw = path.pose(profile.distance(t))
        return cls(category, *size, x=x, y=y, yaw=yaw, valid=np.ones(t.size, dtype=bool))

    @property
    def box(self) -> tuple[FloatArray, FloatArray, FloatArray, float, float]:
        return self.x, self.y, self.yaw, self.length, self.width


def _conflicts(a: _Track, b: _Track, horizon_frames: int, margin_m: float) -> bool:
    """Whether ``a`` at frame i and ``b`` at frame j overlap for some ``|i - j| <= horizon_frames``."""
    n = a.x.size
    i, j = np.nonzero(np.abs(np.arange(n)[:, None] - np.arange(n)[None, :]) <= horizon_frames)
    ok = a.valid[i] & b.valid[j]
    i, j = i[ok], j[ok]
    return bool(
        boxes_overlap(
            OrientedBoxes(
                a.x[i],
                a.y[i],
                a.yaw[i],
                np.asarray(a.length, dtype=np.float64),
                np.asarray(a.width, dtype=np.float64),
            ),
            OrientedBoxes(
                b.x[j],
                b.y[j],
                b.yaw[j],
                np.asarray(b.length, dtype=np.float64),
                np.asarray(b.width, dtype=np.float64),
            ),
            margin_m,
        ).any()
    )


_SIZES_M: dict[str, tuple[tuple[float, float], tuple[float, float], tuple[float, float]]] = {
    "REGULAR_VEHICLE": ((4.2, 5.1), (1.75, 2.05), (1.4, 1.9)),
    "LARGE_VEHICLE": ((5.5, 6.5), (2.0, 2.3), (2.0, 2.8)),
    "BOX_TRUCK": ((6.5, 8.5), (2.3, 2.6), (3.0, 3.6)),
    "TRUCK": ((7.0, 9.5), (2.4, 2.6), (3.0, 3.8)),
    "BUS": ((11.5, 13.0), (2.5, 2.6), (3.0, 3.4)),
    "PEDESTRIAN": ((0.45, 0.8), (0.45, 0.8), (1.5, 1.9)),
    "BICYCLIST": ((1.6, 1.9), (0.6, 0.8), (1.6, 1.9)),
    "MOTORCYCLIST": ((2.0, 2.3), (0.8, 1.0), (1.5, 1.7)),
}

_VEHICLE_MIX = (
    ("REGULAR_VEHICLE", 0.76),
    ("LARGE_VEHICLE", 0.08),
    ("BOX_TRUCK", 0.07),
    ("TRUCK", 0.04),
    ("BUS", 0.05),
)


def _size(rng: np.random.Generator, category: str) -> tuple[float, float, float]:
    (l0, l1), (w0, w1), (h0, h1) = _SIZES_M[category]
    return float(rng.uniform(l0, l1)), float(rng.uniform(w0, w1)), float(rng.uniform(h0, h1))


def _pick(rng: np.random.Generator, mix: Sequence[tuple[str, float]]) -> str:
    names = [m[0] for m in mix]
    weights = np.asarray([m[1] for m in mix])
    return str(names[int(rng.choice(len(names), p=weights / weights.sum()))])


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


# ---------------------------------------------------------------------- ego speed plans


class _Retry(Exception):
    """The drawn parameters do not give a valid scenario; draw again."""


def _stop_and_go(
    v0: float, t_b: float, a_brake: float, t_go: float, a_acc: float, v_resume: float, v_floor: float = 0.0
) -> list[tuple[float, float]]:
    """Knots: cruise at ``v0``, brake from ``t_b`` towards ``v_floor``, hold, accelerate from ``t_go``."""
    t_floor = t_b + (v0 - v_floor) / a_brake
    knots = [(0.0, v0), (t_b, v0)]
    if t_go < t_floor:
        v_go = v0 - a_brake * max(t_go - t_b, 0.0)
        knots.append((max(t_go, t_b), v_go))
    else:
        knots += [(t_floor, v_floor), (t_go, v_floor)]
        v_go = v_floor
    knots.append((max(t_go, t_b) + abs(v_resume - v_go) / a_acc, v_resume))
    return knots


def _gentlest_brake(
    build: Callable[[float], _Profile],
    t_fine: FloatArray,
    front_limit_m: FloatArray,
    a_pref: float,
    a_max: float = 8.0,
) -> tuple[float, _Profile]:
    """Smallest deceleration ``>= a_pref`` whose profile keeps ``distance <= front_limit_m`` throughout."""
    for a in a_pref * 1.06 ** np.arange(80):
        if a > a_max:
            break
        profile = build(float(a))
        if np.all(profile.distance(t_fine) <= front_limit_m):
            return float(a), profile
    raise _Retry


def _with_turn_exit(
    knots: list[tuple[float, float]], s0: float, arc_end_s: float, v_exit: float, a_acc: float
) -> _Profile:
    """Append an acceleration to ``v_exit`` once the ego has left the turn at ``arc_end_s``."""
    profile = _Profile.of(knots, s0)
    t_exit = max(profile.time_at(arc_end_s), knots[-1][0])
    if not np.isfinite(t_exit):
        return profile
    v_turn = knots[-1][1]
    return _Profile.of([*knots, (t_exit, v_turn), (t_exit + max(v_exit - v_turn, 0.0) / a_acc, v_exit)], s0)


# ---------------------------------------------------------------------- scenarios (canonical frame)


@dataclass(eq=False)
class _Scene:
    layout: MapLayout
    ego: _Track
    guest: _Track
    start_s: float
    end_s: float


_T: FloatArray = np.arange(N_FRAMES, dtype=np.float64) * FRAME_PERIOD_S
_T_FINE: FloatArray = np.arange(0.0, N_FRAMES * FRAME_PERIOD_S, 0.02, dtype=np.float64)


def _ego_track(path: _Path, profile: _Profile) -> _Track:
    return _Track.along(path, profile, _T, "EGO_VEHICLE", AV2_EGO_SIZE_M)


def _scene_cut_in(rng: np.random.Generator) -> _Scene:
    lane_e = int(rng.integers(1, 3))
    y_e, y_g = _LANE_Y[lane_e], _LANE_Y[3 - lane_e]
    le, we, _ = AV2_EGO_SIZE_M
    v0 = rng.uniform(9.0, 15.0)
    v_g = max(v0 - rng.uniform(2.0, 5.5), 3.0)
    t_c, dur, gap, tau = (
        rng.uniform(3.0, 7.0),
        rng.uniform(2.0, 3.5),
        rng.uniform(4.0, 12.0),
        rng.uniform(0.3, 1.0),
    )
    category = _pick(rng, (("REGULAR_VEHICLE", 0.8), ("LARGE_VEHICLE", 0.1), ("MOTORCYCLIST", 0.1)))
    size = _size(rng, category)
    x_e0 = rng.uniform(-270.0, -230.0)
    x_gc = x_e0 + v0 * t_c + le / 2 + gap + size[0] / 2
    xs = np.arange(-ARM_M, ARM_M, 0.5)
    u = np.clip((xs - x_gc) / (v_g * dur), 0.0, 1.0)
    guest_path = _Path.through(np.column_stack([xs, y_g + (y_e - y_g) * u * u * (3 - 2 * u)]))
    guest_profile = _Profile.of([(0.0, v_g)], s0_m=(x_gc + ARM_M) - v_g * t_c)
    gx, gy, gyaw = guest_path.pose(guest_profile.distance(_T_FINE))
    in_lane = np.abs(gy - y_e) < (we + size[1]) / 2 + 0.2
    rear = gx - 0.5 * size[0] * np.abs(np.cos(gyaw)) - 0.5 * size[1] * np.abs(np.sin(gyaw))
    limit = np.where(in_lane, rear - 1.0 - le / 2 + ARM_M, np.inf)
    t_b = t_c + tau
    v_t = v_g * rng.uniform(0.85, 1.0)
    a, profile = _gentlest_brake(
        lambda a: _Profile.of([(0.0, v0), (t_b, v0), (t_b + (v0 - v_t) / a, v_t)], x_e0 + ARM_M),
        _T_FINE,
        limit,
        rng.uniform(1.5, 3.5),
    )
    ego_path = _route(0, "straight", lane_e)
    guest = _Track.along(guest_path, guest_profile, _T, category, size)
    return _Scene(
        MapLayout.STRAIGHT, _ego_track(ego_path, profile), guest, t_c, max(t_c + dur, t_b + (v0 - v_t) / a)
    )


def _scene_lead_brake(rng: np.random.Generator) -> _Scene:
    lane = int(rng.integers(1, 3))
    le = AV2_EGO_SIZE_M[0]
    v0 = rng.uniform(8.0, 16.0)
    category = _pick(rng, _VEHICLE_MIX)
    size = _size(rng, category)
    gap0 = v0 * rng.uniform(0.9, 2.0) + 2.0
    t_lb, a_l = rng.uniform(3.5, 7.0), rng.uniform(3.0, 7.0)
    v_end = 0.0 if rng.random() < 0.4 else v0 * rng.uniform(0.1, 0.5)
    hold, a_acc_l, v_res = rng.uniform(1.5, 4.0), rng.uniform(1.0, 2.5), v0 * rng.uniform(0.6, 1.0)
    t_lstop = t_lb + (v0 - v_end) / a_l
    t_lgo = t_lstop + hold
    x_e0 = rng.uniform(-270.0, -230.0)
    lead_profile = _Profile.of(
        [(0.0, v0), (t_lb, v0), (t_lstop, v_end), (t_lgo, v_end), (t_lgo + (v_res - v_end) / a_acc_l, v_res)],
        s0_m=x_e0 + ARM_M + le / 2 + gap0 + size[0] / 2,
    )
    # The ego keeps at least this gap (m) to the lead's rear; its braking is the gentlest that does.
    limit = lead_profile.distance(_T_FINE) - size[0] / 2 - rng.uniform(2.0, 4.0) - le / 2
    t_b = t_lb + rng.uniform(0.5, 1.2)
    t_go = t_lgo + rng.uniform(0.8, 1.5)
    a_acc = a_acc_l * rng.uniform(0.7, 1.0)
    _, profile = _gentlest_brake(
        lambda a: _Profile.of(_stop_and_go(v0, t_b, a, t_go, a_acc, v_res, v_end), x_e0 + ARM_M),
        _T_FINE,
        limit,
        rng.uniform(1.0, 2.0),
    )
    path = _route(0, "straight", lane)
    guest = _Track.along(path, lead_profile, _T, category, size)
    # The interaction lasts until the ego drives on again behind the lead.
    return _Scene(MapLayout.STRAIGHT, _ego_track(path, profile), guest, t_lb, t_go)


def _scene_approach_stop(rng: np.random.Generator) -> _Scene:
    lane = int(rng.integers(1, 3))
    le = AV2_EGO_SIZE_M[0]
    v0 = rng.uniform(7.0, 14.0)
    category = _pick(
        rng, (("REGULAR_VEHICLE", 0.6), ("BOX_TRUCK", 0.15), ("BUS", 0.1), ("LARGE_VEHICLE", 0.15))
    )
    size = _size(rng, category)
    v_g = 0.0 if rng.random() < 0.6 else rng.uniform(1.0, 3.5)
    t_b = rng.uniform(3.0, 7.0)
    a = max(rng.uniform(1.5, 3.0), v0 / 5.0)
    gap_final = rng.uniform(2.5, 6.0)
    x_e0 = rng.uniform(-270.0, -230.0)
    s_front_b = x_e0 + ARM_M + v0 * t_b + le / 2
    rear_at_b = s_front_b + gap_final + (v0 - v_g) ** 2 / (2 * a)
    guest_profile = _Profile.of([(0.0, v_g)], s0_m=rear_at_b + size[0] / 2 - v_g * t_b)
    t_end = t_b + (v0 - v_g) / a
    profile = _Profile.of([(0.0, v0), (t_b, v0), (t_end, v_g)], x_e0 + ARM_M)
    path = _route(0, "straight", lane)
    guest = _Track.along(path, guest_profile, _T, category, size)
    return _Scene(MapLayout.STRAIGHT, _ego_track(path, profile), guest, t_b, t_end)


@dataclass(frozen=True)
class _Crossing:
    """Parameters of a scenario where the guest crosses the ego's path."""

    ego_path: _Path
    guest_path: _Path
    guest_category: str
    guest_speed_mps: float
    walks_from_curb: bool
    v0_mps: float
    margin_m: tuple[float, float]
    turn: str = "straight"
    v_turn_mps: float = 0.0
    v_exit_mps: float = 0.0


def _scene_crossing(rng: np.random.Generator, spec: _Crossing) -> tuple[_Track, _Track, float, float]:
    le, we, _ = AV2_EGO_SIZE_M
    size = _size(rng, spec.guest_category)
    ego_corridor = shapely.buffer(shapely.LineString(spec.ego_path.xy), we / 2 + 0.3)
    guest_corridor = shapely.buffer(shapely.LineString(spec.guest_path.xy), size[1] / 2 + 0.3)
    span_g = _first_run_on(spec.guest_path, size[0], size[1], ego_corridor)
    span_e = _first_run_on(spec.ego_path, le, we, guest_corridor)
    if span_g is None or span_e is None:
        raise _Retry
    s_in, s_out = span_g
    s_conf = span_e[0]
    t_in = rng.uniform(5.0, 8.5)
    v_g = spec.guest_speed_mps
    if spec.walks_from_curb:
        t_walk = t_in - s_in / v_g - 0.4
        guest_profile = _Profile.of([(t_walk, 0.0), (t_walk + 0.8, v_g)], 0.0)
    else:
        guest_profile = _Profile.of([(0.0, v_g)], s_in - v_g * t_in)
    t_out = guest_profile.time_at(s_out)

    v0 = spec.v0_mps
    a = max(rng.uniform(1.8, 3.5), v0 / 5.5)
    s_stop = s_conf - rng.uniform(*spec.margin_m)
    s_b = s_stop - v0**2 / (2 * a)
    t_b = t_in + rng.uniform(-0.5, 1.0) - (s_conf - s_b) / v0
    s_e0 = s_b - v0 * t_b
    t_go = t_out + rng.uniform(0.4, 1.2)
    if t_b < 1.0 or s_e0 < 0.0 or t_go > 13.5:
        raise _Retry
    a_acc = rng.uniform(1.2, 2.5)
    if spec.turn == "straight":
        profile = _Profile.of(_stop_and_go(v0, t_b, a, t_go, a_acc, v0 * rng.uniform(0.8, 1.0)), s_e0)
    else:
        knots = _stop_and_go(v0, t_b, a, t_go, a_acc, spec.v_turn_mps)
        profile = _with_turn_exit(knots, s_e0, _arc_end_s(spec.turn), spec.v_exit_mps, a_acc)
    # By construction the ego's centre stays behind s_stop until the guest has left the corridor.
    ego = _ego_track(spec.ego_path, profile)
    guest = _Track.along(spec.guest_path, guest_profile, _T, spec.guest_category, size)
    # The interaction lasts until the ego drives on (it has come to its lowest speed by then).
    return ego, guest, min(t_b, t_in), t_go


def _ped_path(rng: np.random.Generator, k: int, across_x: float) -> _Path:
    """Walk across arm ``k``'s crosswalk, from a curb 3 m off the road, in a random direction."""
    x = across_x + rng.uniform(-0.8, 0.8)
    y0 = ROAD_HALF_WIDTH_M + 3.0
    ys = np.array([-y0, y0 + 40.0]) if rng.random() < 0.5 else np.array([y0, -y0 - 40.0])
    return _Path.through(np.column_stack([[x, x], ys])).rotated(k * np.pi / 2)


def _scene_ped_crossing(rng: np.random.Generator) -> _Scene:
    far_side = rng.random() < 0.5
    across_x = (1 if far_side else -1) * 0.5 * (CROSSWALK_NEAR_M + CROSSWALK_FAR_M)
    spec = _Crossing(
        ego_path=_route(0, "straight", int(rng.integers(1, 3))),
        guest_path=_ped_path(rng, 0, across_x),
        guest_category="PEDESTRIAN",
        guest_speed_mps=rng.uniform(1.0, 1.8),
        walks_from_curb=True,
        v0_mps=rng.uniform(7.0, 13.0),
        margin_m=(1.0, 3.5),
    )
    ego, guest, t0, t1 = _scene_crossing(rng, spec)
    return _Scene(MapLayout.INTERSECTION, ego, guest, t0, t1)


def _scene_obj_crossing(rng: np.random.Generator) -> _Scene:
    category = _pick(rng, (("REGULAR_VEHICLE", 0.6), ("BICYCLIST", 0.25), ("MOTORCYCLIST", 0.15)))
    speed = {"REGULAR_VEHICLE": (6.0, 12.0), "BICYCLIST": (3.0, 6.0), "MOTORCYCLIST": (7.0, 12.0)}[category]
    spec = _Crossing(
        ego_path=_route(0, "straight", int(rng.integers(1, 3))),
        guest_path=_route(int(rng.choice([1, 3])), "straight", int(rng.integers(1, 3))),
        guest_category=category,
        guest_speed_mps=rng.uniform(*speed),
        walks_from_curb=False,
        v0_mps=rng.uniform(8.0, 13.0),
        margin_m=(2.0, 8.0),
    )
    ego, guest, t0, t1 = _scene_crossing(rng, spec)
    return _Scene(MapLayout.INTERSECTION, ego, guest, t0, t1)


def _scene_left_oppo(rng: np.random.Generator) -> _Scene:
    category = _pick(
        rng, (("REGULAR_VEHICLE", 0.75), ("LARGE_VEHICLE", 0.1), ("BOX_TRUCK", 0.05), ("MOTORCYCLIST", 0.1))
    )
    spec = _Crossing(
        ego_path=_route(0, "left", 1),
        guest_path=_route(2, "straight", int(rng.integers(1, 3))),
        guest_category=category,
        guest_speed_mps=rng.uniform(7.0, 13.0),
        walks_from_curb=False,
        v0_mps=rng.uniform(6.0, 10.0),
        margin_m=(0.8, 2.5),
        turn="left",
        v_turn_mps=rng.uniform(4.0, 6.0),
        v_exit_mps=rng.uniform(8.0, 12.0),
    )
    ego, guest, t0, t1 = _scene_crossing(rng, spec)
    return _Scene(MapLayout.INTERSECTION, ego, guest, t0, t1)


def _scene_right_ped(rng: np.random.Generator) -> _Scene:
    # The south arm's crosswalk is the west arm's turned a quarter counter-clockwise.
    spec = _Crossing(
        ego_path=_route(0, "right", 2),
        guest_path=_ped_path(rng, 1, -0.5 * (CROSSWALK_NEAR_M + CROSSWALK_FAR_M)),
        guest_category="PEDESTRIAN",
        guest_speed_mps=rng.uniform(1.0, 1.8),
        walks_from_curb=True,
        v0_mps=rng.uniform(5.0, 8.0),
        margin_m=(1.0, 3.0),
        turn="right",
        v_turn_mps=rng.uniform(3.0, 4.5),
        v_exit_mps=rng.uniform(7.0, 11.0),
    )
    ego, guest, t0, t1 = _scene_crossing(rng, spec)
    return _Scene(MapLayout.INTERSECTION, ego, guest, t0, t1)


def _scene_not_relevant(rng: np.random.Generator) -> _Scene:
    variant = str(rng.choice(["oncoming", "overtaking", "far_lead", "cross_before", "sidewalk"]))
    layout = MapLayout.INTERSECTION if variant == "cross_before" else MapLayout.STRAIGHT
    lane = int(rng.integers(1, 3))
    v0 = rng.uniform(8.0, 14.0)
    x_e0 = rng.uniform(-270.0, -200.0)
    knots = [(0.0, v0)]
    if rng.random() < 0.5:  # a gentle acceleration, never a deceleration
        t_a = rng.uniform(2.0, 8.0)
        knots += [(t_a, v0), (t_a + rng.uniform(2.0, 4.0), v0 + rng.uniform(0.5, 1.5))]
    ego_path = _route(0, "straight", lane)
    ego_profile = _Profile.of(knots, x_e0 + ARM_M)
    ego = _ego_track(ego_path, ego_profile)
    t_pass = rng.uniform(4.0, 10.0)
    x_pass = float(ego_profile.distance(np.array([t_pass]))[0]) - ARM_M  # the ego's x when the guest passes
    if variant == "oncoming":
        category = _pick(rng, _VEHICLE_MIX)
        v_g = rng.uniform(6.0, 14.0)
        path = _route(2, "straight", int(rng.integers(1, 3)))  # runs from x = +ARM towards -ARM
        profile = _Profile.of([(0.0, v_g)], (ARM_M - x_pass) - v_g * t_pass)
    elif variant == "overtaking":
        category = _pick(rng, _VEHICLE_MIX)
        v_g = v0 + rng.uniform(2.0, 5.0)
        path = _route(0, "straight", 3 - lane)
        profile = _Profile.of([(0.0, v_g)], x_pass + ARM_M - v_g * t_pass)
    elif variant == "far_lead":
        category = _pick(rng, _VEHICLE_MIX)
        v_g = v0 + rng.uniform(1.0, 3.0)
        path = ego_path
        profile = _Profile.of([(0.0, v_g)], x_e0 + ARM_M + rng.uniform(45.0, 60.0))
    elif variant == "cross_before":
        category = _pick(rng, (("REGULAR_VEHICLE", 0.8), ("BICYCLIST", 0.2)))
        v_g = rng.uniform(6.0, 12.0) if category == "REGULAR_VEHICLE" else rng.uniform(3.0, 6.0)
        path = _route(int(rng.choice([1, 3])), "straight", int(rng.integers(1, 3)))
        t_ego_at_box = ego_profile.time_at(ARM_M - BOX_HALF_M)
        t_cross = t_ego_at_box - rng.uniform(4.5, 7.0)
        profile = _Profile.of([(0.0, v_g)], ARM_M - v_g * t_cross)
    else:  # sidewalk
        category = "PEDESTRIAN"
        v_g = rng.uniform(0.8, 1.6)
        side = rng.choice([-1.0, 1.0])
        y_walk = side * rng.uniform(8.5, 11.0)
        heading_sign = rng.choice([-1.0, 1.0])
        path = _Path.through(np.array([[-heading_sign * ARM_M, y_walk], [heading_sign * ARM_M, y_walk]]))
        s_pass = heading_sign * x_pass + ARM_M
        profile = _Profile.of([(0.0, v_g)], s_pass - v_g * t_pass)
    guest = _Track.along(path, profile, _T, category, _size(rng, category))
    if _conflicts(ego, guest, horizon_frames=30, margin_m=0.5):
        raise _Retry
    near = np.hypot(guest.x - ego.x, guest.y - ego.y) <= NOT_RELEVANT_RANGE_M
    if near.sum() < 10:
        raise _Retry
    frames = np.flatnonzero(near)
    return _Scene(layout, ego, guest, float(_T[frames[0]]), float(_T[frames[-1]]))


_SCENES: dict[ScenarioCategory, Callable[[np.random.Generator], _Scene]] = {
    ScenarioCategory.CUT_IN: _scene_cut_in,
    ScenarioCategory.LEAD_BRAKE: _scene_lead_brake,
    ScenarioCategory.APPROACH_STOP: _scene_approach_stop,
    ScenarioCategory.PED_CROSSING: _scene_ped_crossing,
    ScenarioCategory.OBJ_CROSSING: _scene_obj_crossing,
    ScenarioCategory.LEFT_OPPO: _scene_left_oppo,
    ScenarioCategory.RIGHT_PED: _scene_right_ped,
    ScenarioCategory.NOT_RELEVANT: _scene_not_relevant,
}


# ---------------------------------------------------------------------- background traffic


def _background_candidate(rng: np.random.Generator, layout: MapLayout, ego: _Track) -> _Track:
    x_e0 = float(ego.x[0])  # every ego route enters from the west arm heading +x
    kind = str(rng.choice(["same_dir", "oncoming", "cross", "parked", "pedestrian", "pedestrian"]))
    if kind == "cross" and layout is MapLayout.STRAIGHT:
        kind = "oncoming"
    if kind in ("same_dir", "oncoming", "cross"):
        category = _pick(rng, _VEHICLE_MIX)
        v = rng.uniform(5.0, 15.0)
        if kind == "same_dir":
            path = _route(0, "straight", int(rng.integers(1, 3)))
            s0 = x_e0 + ARM_M + rng.uniform(-60.0, 120.0)
        elif kind == "oncoming":
            path = _route(2, "straight", int(rng.integers(1, 3)))
            s0 = ARM_M - x_e0 - rng.uniform(0.0, 250.0)
        else:
            movement = str(rng.choice(["straight", "straight", "left", "right"]))
            path = _route(
                int(rng.integers(1, 4)),
                movement,
                1 if movement == "left" else 2 if movement == "right" else int(rng.integers(1, 3)),
            )
            s0 = ARM_M - BOX_HALF_M - v * rng.uniform(-3.0, 14.0)
        return _Track.along(path, _Profile.of([(0.0, v)], s0), _T, category, _size(rng, category))
    if kind == "parked":
        category = _pick(rng, (("REGULAR_VEHICLE", 0.85), ("LARGE_VEHICLE", 0.1), ("BOX_TRUCK", 0.05)))
        side = rng.choice([-1.0, 1.0])
        x = x_e0 + rng.uniform(-20.0, 220.0)
        if layout is MapLayout.INTERSECTION and abs(x) < CROSSWALK_FAR_M + 8.0:
            x += np.sign(x or 1.0) * 30.0
        size = _size(rng, category)
        y = side * (ROAD_HALF_WIDTH_M + 0.3 + size[1] / 2 + rng.uniform(0.0, 0.4))
        yaw = (0.0 if side < 0 else np.pi) + rng.normal(0.0, 0.03)
        n = _T.size
        return _Track(
            category,
            *size,
            x=np.full(n, x),
            y=np.full(n, y),
            yaw=np.full(n, yaw),
            valid=np.ones(n, dtype=bool),
        )
    side = rng.choice([-1.0, 1.0])
    y = side * rng.uniform(8.5, 11.0)
    direction = rng.choice([-1.0, 1.0])
    v = 0.0 if rng.random() < 0.3 else rng.uniform(0.8, 1.6)
    path = _Path.through(np.array([[-direction * ARM_M, y], [direction * ARM_M, y]]))
    x0 = x_e0 + rng.uniform(0.0, 200.0)
    return _Track.along(
        path, _Profile.of([(0.0, v)], direction * x0 + ARM_M), _T, "PEDESTRIAN", _size(rng, "PEDESTRIAN")
    )


def _background(rng: np.random.Generator, scene: _Scene, n_wanted: int, visible_m: float) -> list[_Track]:
    kept: list[_Track] = []
    for _ in range(8 * n_wanted):
        if len(kept) == n_wanted:
            break
        cand = _background_candidate(rng, scene.layout, scene.ego)
        seen = np.hypot(cand.x - scene.ego.x, cand.y - scene.ego.y) <= visible_m
        if seen.sum() < 10:
            continue
        if _conflicts(scene.ego, cand, horizon_frames=30, margin_m=0.5):
            continue
        if _conflicts(scene.guest, cand, horizon_frames=0, margin_m=0.5):
            continue
        if any(_conflicts(other, cand, horizon_frames=0, margin_m=0.3) for other in kept):
            continue
        kept.append(cand)
    return kept


# ---------------------------------------------------------------------- assembly


def _uuid(rng: np.random.Generator) -> str:
    return str(uuid.UUID(bytes=rng.bytes(16), version=4))


def _observe(
    rng: np.random.Generator, track: _Track, ego: _Track, visible_m: float, *, is_guest: bool
) -> BoolArray:
    """Visibility mask: within range, minus random dropped frames and (background only) an occlusion gap."""
    valid = np.hypot(track.x - ego.x, track.y - ego.y) <= visible_m
    p_drop = rng.uniform(0.0, 0.02 if is_guest else 0.05)
    valid &= rng.random(valid.size) >= p_drop
    if not is_guest and rng.random() < 0.3:
        start = int(rng.integers(0, valid.size))
        valid[start : start + int(rng.integers(3, 11))] = False
    return valid


def _scene_for(category: ScenarioCategory, rng: np.random.Generator) -> _Scene:
    for _ in range(200):
        try:
            scene = _SCENES[category](rng)
        except _Retry:
            continue
        if _conflicts(scene.ego, scene.guest, horizon_frames=0, margin_m=0.2):
            continue
        if category is not ScenarioCategory.NOT_RELEVANT:
            i0, i1 = np.searchsorted(_T, [scene.start_s, scene.end_s])
            speed = np.hypot(np.gradient(scene.ego.x, _T), np.gradient(scene.ego.y, _T))
            if speed[min(i1, N_FRAMES - 1)] > speed[min(i0, N_FRAMES - 1)] - 1.0:
                continue
        return scene
    raise RuntimeError(
        f"could not draw a valid {category.value} scenario in 200 attempts"
    )  # pragma: no cover


def generate_log(category: ScenarioCategory | str, rng: np.random.Generator) -> SynthLog:
    """Generate one labelled scenario in memory.

    Args:
        category: the scenario category to generate.
        rng: source of every random draw (the result is a pure function of its state).

    Returns:
        The log (ego at its box centre, ``dataset="synthetic"``), its map, label and layout.
    """
    category = ScenarioCategory(category)
    log_id = _uuid(rng)
    scene = _scene_for(category, rng)
    visible_m = rng.uniform(60.0, 90.0)
    background = _background(rng, scene, int(rng.integers(4, 11)), visible_m)

    # Noise-free canonical tracks → observed, noisy, city-frame rows.
    theta = rng.uniform(-np.pi, np.pi)
    offset = rng.uniform(-2000.0, 2000.0, size=2) + np.array([3000.0, 3000.0])
    z0 = rng.uniform(-30.0, 30.0)

    def tf(xy: FloatArray) -> FloatArray:
        return np.asarray(rotate_xy(np.asarray(xy, dtype=np.float64), theta) + offset, dtype=np.float64)

    sigma_pos = rng.uniform(0.05, 0.1)
    sigma_yaw = rng.uniform(0.01, 0.03)
    tracks = [scene.ego, scene.guest, *background]
    for i, track in enumerate(tracks):
        track.track_id = _uuid(rng)
        if i == 0:
            continue
        track.valid = _observe(rng, track, scene.ego, visible_m, is_guest=i == 1)
    tracks = [tr for i, tr in enumerate(tracks) if i < 2 or tr.valid.sum() >= 5]

    n_t = _T.size
    t0_ns = 315_966_000_000_000_000 + int(rng.integers(0, 10**9)) * 1_000_000
    jitter = rng.integers(-300_000, 300_001, size=n_t)
    jitter[0] = 0
    timestamps = t0_ns + np.arange(n_t, dtype=np.int64) * 100_000_000 + jitter

    ids: list[NDArray[np.str_]] = []
    cats: list[NDArray[np.str_]] = []
    ts: list[NDArray[np.int64]] = []
    cols: dict[str, list[FloatArray]] = {
        k: [] for k in ("x_m", "y_m", "z_m", "yaw_rad", "length_m", "width_m", "height_m")
    }
    for i, tr in enumerate(tracks):
        k = np.flatnonzero(tr.valid)
        pos_sigma, yaw_sigma = (
            (0.01, 0.002)
            if i == 0
            else (sigma_pos, sigma_yaw * (3.0 if tr.category == "PEDESTRIAN" else 1.0))
        )
        xy = tf(np.column_stack([tr.x[k], tr.y[k]])) + rng.normal(0.0, pos_sigma, size=(k.size, 2))
        ids.append(np.full(k.size, tr.track_id))
        cats.append(np.full(k.size, tr.category))
        ts.append(timestamps[k])
        cols["x_m"].append(xy[:, 0])
        cols["y_m"].append(xy[:, 1])
        cols["z_m"].append(z0 + tr.height / 2 + rng.normal(0.0, pos_sigma / 4, size=k.size))
        cols["yaw_rad"].append(wrap_angle(tr.yaw[k] + theta + rng.normal(0.0, yaw_sigma, size=k.size)))
        cols["length_m"].append(np.full(k.size, tr.length))
        cols["width_m"].append(np.full(k.size, tr.width))
        cols["height_m"].append(np.full(k.size, tr.height))
    log = build_log(
        log_id=log_id,
        track_id=np.concatenate(ids),
        category=np.concatenate(cats),
        timestamp_ns=np.concatenate(ts),
        fields={k: np.concatenate(v) for k, v in cols.items()},
        ego_track_id=scene.ego.track_id,
        source="<synthetic>",
        dataset="synthetic",
    )
    i0 = int(np.clip(np.round(scene.start_s / FRAME_PERIOD_S), 0, n_t - 1))
    i1 = int(np.clip(np.round(scene.end_s / FRAME_PERIOD_S), i0, n_t - 1))
    label = ScenarioLabel(log_id, scene.guest.track_id, category, int(timestamps[i0]), int(timestamps[i1]))
    return SynthLog(log=log, av2_map=_build_map(scene.layout, tf, z0), label=label, layout=scene.layout)


def write_labels(labels: Sequence[ScenarioLabel], path: Path) -> Path:
    """Write label rows as CSV with the columns :data:`LABEL_COLUMNS`."""
    path.parent.mkdir(parents=True, exist_ok=True)
    with path.open("w", newline="", encoding="utf-8") as fh:
        writer = csv.writer(fh)
        writer.writerow(LABEL_COLUMNS)
        for lab in labels:
            writer.writerow([lab.log_id, lab.guest_id, lab.scenario_category.value, lab.start_ns, lab.end_ns])
    return path


def read_labels(path: Path) -> tuple[ScenarioLabel, ...]:
    """Read a labels CSV written by :func:`write_labels` (or annotated by hand in the same layout).

    Raises:
        ValueError: a column is missing, or a row has an unknown category or non-integer times.
    """
    with Path(path).open(newline="", encoding="utf-8") as fh:
        reader = csv.DictReader(fh)
        missing = [c for c in LABEL_COLUMNS if c not in (reader.fieldnames or [])]
        if missing:
            raise ValueError(f"{path}: missing label column(s) {missing}; expected {list(LABEL_COLUMNS)}")
        out = []
        for line, row in enumerate(reader, start=2):
            try:
                out.append(
                    ScenarioLabel(
                        row["log_id"],
                        row["guest_id"],
                        ScenarioCategory(row["scenario_category"]),
                        int(row["start_ns"]),
                        int(row["end_ns"]),
                    )
                )
            except ValueError as exc:
                raise ValueError(f"{path}:{line}: {exc}") from None
    return tuple(out)


def generate(
    out_dir: Path,
    n: int,
    seed: int = 0,
    categories: Sequence[str] | None = None,
    progress: Callable[[int], None] | None = None,
) -> SynthResult:
    """Generate ``n`` labelled scenarios as Argoverse 2 logs with vector maps, plus ``labels.csv``.

    Log ``i`` has category ``categories[i % len(categories)]`` and depends only on ``(seed, i)``,
    so a larger ``n`` extends a smaller run with the same seed.

    Args:
        out_dir: output folder; receives ``<log_id>/`` folders (annotations, poses, ``map/``) and
            ``labels.csv``.
        n: number of logs.
        seed: random seed.
        categories: scenario category names to cycle through; all of :class:`ScenarioCategory`
            by default.
        progress: called with the number of logs written so far after each log.

    Returns:
        Paths, labels and per-log track counts.

    Raises:
        ValueError: ``n`` is negative or a category name is unknown.
    """
    if n < 0:
        raise ValueError(f"n must be >= 0, got {n}")
    try:
        cycle = (
            [ScenarioCategory(c) for c in categories] if categories is not None else list(ScenarioCategory)
        )
    except ValueError:
        known = [c.value for c in ScenarioCategory]
        raise ValueError(f"unknown scenario category in {list(categories or [])}; known: {known}") from None
    if not cycle:
        raise ValueError("categories must not be empty")
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    log_dirs, labels, n_tracks = [], [], []
    for i in range(n):
        synth = generate_log(cycle[i % len(cycle)], np.random.default_rng([seed, i]))
        log_dir = write_av2_log(synth.log, out_dir)
        write_av2_map(
            synth.av2_map, log_dir / "map" / f"log_map_archive_{synth.log.log_id}____SYN_city_{i:05d}.json"
        )
        log_dirs.append(log_dir)
        labels.append(synth.label)
        n_tracks.append(synth.log.n_tracks)
        if progress is not None:
            progress(i + 1)
    labels_csv = write_labels(labels, out_dir / "labels.csv")
    return SynthResult(out_dir, labels_csv, tuple(log_dirs), tuple(labels), tuple(n_tracks))


__all__ = [
    "LABEL_COLUMNS",
    "MapLayout",
    "ScenarioCategory",
    "ScenarioLabel",
    "SynthLog",
    "SynthResult",
    "generate",
    "generate_log",
    "read_labels",
    "write_labels",
]
