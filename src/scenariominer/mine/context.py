"""Per-log arrays shared by every mining predicate, computed once and cached.

A :class:`LogContext` wraps one :class:`~scenariominer.data.log.Log` and derives, lazily and at
most once, everything the atomic predicates need: box centres (with the Argoverse 2 ego's
rear-axle offset corrected), headings, body-frame velocities and accelerations, yaw rates,
pairwise relative positions of one set of tracks in the frames of another, pairwise box-to-box
distances, and the HD-map look-ups (lane per observation, drivable area, crossings). Predicates
therefore never loop over frames in Python; a program that calls ten predicates on the same
vehicles pays for the vehicles' geometry once.

Frames and units: world ("city") frame in metres; a track's *box frame* has its origin at the box
centre, ``x`` forward along the heading and ``y`` to the left. Angles are radians unless the name
says ``_deg``. Arrays are ``(N, T)`` over tracks × timestamps, ``NaN`` where a track is absent.
"""

from __future__ import annotations

from collections import OrderedDict
from collections.abc import Callable
from functools import cached_property
from typing import Any

import numpy as np
import shapely
from numpy.typing import ArrayLike, NDArray
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

from scenariominer import errors as _errors
from scenariominer.config.mining import MiningConfig
from scenariominer.data.adapters.av2.map import Av2Map, read_av2_map
from scenariominer.data.categories import expand_categories
from scenariominer.data.log import BoolArray, FloatArray, Log
from scenariominer.geometry import OrientedBoxes, box_distance_m, to_local, wrap_angle, yaw_rate_radps
from scenariominer.mine import lanes as lane_rules

__all__ = [
    "AGENT_CATEGORIES",
    "IntArray",
    "LogContext",
    "MapIndex",
    "MapRequiredError",
]

IntArray = NDArray[np.int64]

#: Categories that choose their own direction of travel (RefAV's "free will" objects): their box
#: heading is meaningful even while they stand still.
AGENT_CATEGORIES: frozenset[str] = frozenset(
    {
        "ANIMAL",
        "OFFICIAL_SIGNALER",
        "RAILED_VEHICLE",
        "ARTICULATED_BUS",
        "WHEELED_RIDER",
        "SCHOOL_BUS",
        "MOTORCYCLIST",
        "TRUCK_CAB",
        "VEHICULAR_TRAILER",
        "BICYCLIST",
        "MOTORCYCLE",
        "TRUCK",
        "BOX_TRUCK",
        "BUS",
        "LARGE_VEHICLE",
        "PEDESTRIAN",
        "REGULAR_VEHICLE",
        "EGO_VEHICLE",
    }
)

#: Map-free predicates suggested to a program that called a map predicate on a log without a map.
MAP_FREE_PREDICATES: tuple[str, ...] = (
    "has_objects_in_relative_direction",
    "near_objects",
    "facing_toward",
    "heading_toward",
    "being_crossed_by",
    "following",
    "has_velocity",
    "accelerating",
    "turning",
    "stationary",
)

_PAIR_CACHE_ENTRIES = 32
_CHUNK_CELLS = 1_000_000


class MapRequiredError(_errors.MiningError, RuntimeError):
    """A map-aware predicate was called on a log without an HD map.

    The message is written for the program-repair loop: it names the predicate and lists
    map-free predicates the program can use instead.

    Attributes:
        predicate: name of the predicate that needs the map.
        log_id: the log without a map.
    """

    def __init__(self, predicate: str, log_id: str) -> None:
        self.predicate = predicate
        self.log_id = log_id
        super().__init__(
            f"predicate {predicate}() needs an HD map; log {log_id} has none. Rewrite the program with "
            f"map-free predicates such as {', '.join(MAP_FREE_PREDICATES)}."
        )


class MapIndex:
    """Mining look-ups over an Argoverse 2 vector map, built once per map.

    Wraps an :class:`~scenariominer.data.adapters.av2.map.Av2Map` (its lane polygons, centre lines,
    types, intersection flags, crossings, drivable areas and lane graph) and derives the lane
    groupings RefAV's predicates use:

    * *semantic lane* of a segment (:attr:`semantic_lanes`, :attr:`in_semantic_lane`): the
      chain of segments continuing it straight backwards and forwards, one best-aligned
      predecessor/successor at a time, as RefAV's ``get_semantic_lane`` (turning lanes inside
      intersections stay alone); ``in_same_lane``, ``following``, ``at_stop_sign`` and
      ``changing_lanes`` use it;
    * *road side*: segments joined by their semantic-lane links and with their same-direction
      neighbours (connected components); ``on_relative_side_of_road`` compares these, and the
      opposite side is the road side of an opposite-direction neighbour.

    Args:
        hd_map: the vector map.
    """

    def __init__(self, hd_map: Av2Map) -> None:
        self.map = hd_map
        self.lane_ids: IntArray = hd_map.lane_ids
        self.lane_polygons: NDArray[np.object_] = hd_map.lane_polygons
        self.lane_centerlines: NDArray[np.object_] = hd_map.lane_centerlines
        self.lane_types: NDArray[np.str_] = hd_map.lane_types
        self.lane_is_intersection: BoolArray = hd_map.lane_is_intersection
        pos = {int(lid): i for i, lid in enumerate(self.lane_ids)}

        def idx(lid: int | None) -> int:
            return pos.get(int(lid), -1) if lid is not None else -1

        lanes = hd_map.lane_segments
        self.successors: list[list[int]] = [[idx(j) for j in ls.successors if idx(j) >= 0] for ls in lanes]
        self.predecessors: list[list[int]] = [
            [idx(j) for j in ls.predecessors if idx(j) >= 0] for ls in lanes
        ]
        self.left_neighbor: IntArray = np.asarray([idx(ls.left_neighbor_id) for ls in lanes], dtype=np.int64)
        self.right_neighbor: IntArray = np.asarray(
            [idx(ls.right_neighbor_id) for ls in lanes], dtype=np.int64
        )

    @classmethod
    def from_map(cls, hd_map: Any) -> MapIndex:
        """A :class:`MapIndex` for ``hd_map`` (an :class:`Av2Map`, or a :class:`MapIndex` itself)."""
        if isinstance(hd_map, MapIndex):
            return hd_map
        if isinstance(hd_map, Av2Map):
            return cls(hd_map)
        raise TypeError(f"expected an Av2Map or MapIndex as HD map, got {type(hd_map).__name__}")

    # ------------------------------------------------------------------ lane geometry
    @property
    def n_lanes(self) -> int:
        """Number of lane segments ``L``."""
        return int(self.lane_ids.shape[0])

    @cached_property
    def lane_direction_rad(self) -> FloatArray:
        """``(L,)`` overall direction of each lane, start to end of its centre line (radians)."""
        if self.n_lanes == 0:
            return np.empty(0)
        start = shapely.get_coordinates(shapely.get_point(self.lane_centerlines, 0))
        end = shapely.get_coordinates(shapely.get_point(self.lane_centerlines, -1))
        return np.asarray(np.arctan2(end[:, 1] - start[:, 1], end[:, 0] - start[:, 0]), dtype=np.float64)

    @cached_property
    def lane_turn(self) -> NDArray[np.str_]:
        """``(L,)`` ``left``/``right``/``straight`` for intersection lanes, ``""`` for others.

        The heading change between the first and the last centre-line segment decides; more than
        30 degrees is a turn.
        """
        out = np.full(self.n_lanes, "", dtype="<U8")
        for i in np.flatnonzero(self.lane_is_intersection):
            xy = shapely.get_coordinates(self.lane_centerlines[i])
            if xy.shape[0] < 2:
                out[i] = "straight"
                continue
            h0 = np.arctan2(*(xy[1] - xy[0])[::-1])
            h1 = np.arctan2(*(xy[-1] - xy[-2])[::-1])
            change = float(wrap_angle(h1 - h0))
            out[i] = "left" if change > np.pi / 6 else "right" if change < -np.pi / 6 else "straight"
        return out

    def _straight_link(self, i: int, links: list[int]) -> int:
        """The link of lane ``i`` best aligned with it among non-turning lanes (or -1).

        Candidates are ``links`` (successors or predecessors of ``i``) that are not turning
        lanes of an intersection and whose direction is within 90 degrees of lane ``i``'s; the
        one with the largest cosine wins (the first listed on a tie).
        """
        best, best_cos = -1, 0.0
        for j in links:
            if self.lane_turn[j] in ("left", "right"):
                continue
            cos = float(np.cos(self.lane_direction_rad[j] - self.lane_direction_rad[i]))
            if cos > best_cos:
                best, best_cos = j, cos
        return best

    def _chain(self, start: int, links: list[list[int]], members: list[int], beside: set[int]) -> None:
        """Extend ``members`` from lane ``start`` along its straightest ``links``, one lane at a time.

        Stops at a lane without a straight link, at a lane already in the chain (a loop) and at
        a lane that is a left/right neighbour of a chain member (``beside``, updated here), so
        two lanes side by side never join one semantic lane.
        """
        cur = start
        while True:
            nxt = self._straight_link(cur, links[cur])
            if nxt < 0 or nxt in members or nxt in beside:
                return
            members.append(nxt)
            beside.update(int(j) for j in (self.left_neighbor[nxt], self.right_neighbor[nxt]) if j >= 0)
            cur = nxt

    @cached_property
    def semantic_lanes(self) -> tuple[IntArray, ...]:
        """Per lane segment, the segments of its *semantic lane* (RefAV's ``get_semantic_lane``).

        For lane ``i``: ``i`` itself, then its best-aligned non-turning predecessor, that lane's,
        and so on backwards, then its best-aligned non-turning successor chain forwards (see
        :meth:`_straight_link`). A turning lane inside an intersection is a semantic lane of its
        own. The relation is directed: where two lanes merge, both chains continue into the
        merged lane, but the merged lane's chain goes back along one of them only; where a lane
        splits, its chain follows one branch. Left/right neighbours never share a chain.
        """
        out: list[IntArray] = []
        for i in range(self.n_lanes):
            members = [i]
            if self.lane_turn[i] not in ("left", "right"):
                beside = {int(j) for j in (self.left_neighbor[i], self.right_neighbor[i]) if j >= 0}
                self._chain(i, self.predecessors, members, beside)
                self._chain(i, self.successors, members, beside)
            out.append(np.asarray(members, dtype=np.int64))
        return tuple(out)

    @cached_property
    def in_semantic_lane(self) -> BoolArray:
        """``(L + 1, L + 1)`` bool: ``[i, j]`` is True when lane ``j`` is in lane ``i``'s semantic lane.

        Row and column ``L`` (index ``-1``) are all False, so lane arrays that use -1 for "no
        lane" index it directly: ``in_semantic_lane[lane_a, lane_b]``.
        """
        n = self.n_lanes
        out = np.zeros((n + 1, n + 1), dtype=bool)
        for i, members in enumerate(self.semantic_lanes):
            out[i, members] = True
        return out

    def _groups(self, pairs: list[tuple[int, int]]) -> IntArray:
        n = self.n_lanes
        if not pairs:
            return np.arange(n, dtype=np.int64)
        a = np.asarray(pairs, dtype=np.int64)
        graph = coo_matrix((np.ones(len(a)), (a[:, 0], a[:, 1])), shape=(n, n))
        _, labels = connected_components(graph, directed=False)
        return np.asarray(labels, dtype=np.int64)

    def _same_direction(self, i: int, j: int) -> bool:
        return bool(np.cos(self.lane_direction_rad[i] - self.lane_direction_rad[j]) > 0)

    @cached_property
    def road_side(self) -> IntArray:
        """``(L,)`` group id of the side of the road each segment is on (see class doc)."""
        pairs = [(i, int(j)) for i, members in enumerate(self.semantic_lanes) for j in members[1:]]
        for i in range(self.n_lanes):
            for j in (int(self.left_neighbor[i]), int(self.right_neighbor[i])):
                if j >= 0 and self._same_direction(i, j):
                    pairs.append((i, j))
        return self._groups(pairs)

    @cached_property
    def opposite_road_side(self) -> IntArray:
        """``(L,)`` road-side id of the opposite direction of travel, -1 when the map has none."""
        side = self.road_side
        out = np.full(self.n_lanes, -1, dtype=np.int64)
        for i in range(self.n_lanes):
            for j in (int(self.left_neighbor[i]), int(self.right_neighbor[i])):
                if j >= 0 and not self._same_direction(i, j):
                    out[side == side[i]] = side[j]
        return out

    # ------------------------------------------------------------------ vectorised look-ups
    @cached_property
    def successor_codes(self) -> IntArray:
        """Sorted codes ``i * L + j`` of the lane-graph links ``i -> j`` (:func:`lanes.successor_codes`)."""
        return lane_rules.successor_codes(self.successors)

    def lanes_at(
        self, x_m: FloatArray, y_m: FloatArray, yaw_rad: FloatArray, categories: ArrayLike | None = None
    ) -> tuple[IntArray, FloatArray]:
        """Lane segment under each point and the lane's local direction there.

        The lane polygons containing the point are the candidates (none: no lane); among several,
        the lane type suited to the object's category, then continuity with the track's previous
        lane, then the closest centre line with a heading-mismatch penalty decide
        (:func:`scenariominer.mine.lanes.assign_lanes`).

        Args:
            x_m: point x. A 2-D array is tracks × timestamps (continuity along each row); any
                other shape holds independent points. NaN points get no lane.
            y_m: point y, same shape.
            yaw_rad: heading at each point (same shape); NaN counts as no preference.
            categories: category of each row of a 2-D input (``(N,)``) or of each point;
                ``None``: no lane-type preference.

        Returns:
            Lane indices (into :attr:`lane_ids`) of the input shape, -1 where no lane, and the
            local direction (radians) of the chosen lane's centre line at each point (NaN where
            no lane).
        """
        return lane_rules.assign_lanes(self.map, self.successor_codes, x_m, y_m, yaw_rad, categories)

    def near_intersection(self, x_m: FloatArray, y_m: FloatArray, threshold_m: float) -> BoolArray:
        """Whether each point lies within ``threshold_m`` of an intersection lane polygon (or on it)."""
        xy = np.stack([np.ravel(x_m), np.ravel(y_m)], axis=1)
        d = self.map.distance_to_intersection(xy)
        with np.errstate(invalid="ignore"):
            return np.asarray(d <= threshold_m).reshape(np.shape(x_m))

    def in_drivable_area(self, x_m: FloatArray, y_m: FloatArray) -> BoolArray:
        """Whether each point lies inside a drivable-area polygon."""
        xy = np.stack([np.ravel(x_m), np.ravel(y_m)], axis=1)
        out = np.zeros(xy.shape[0], dtype=bool)
        ok = np.all(np.isfinite(xy), axis=1)
        if ok.any():
            out[ok] = self.map.in_drivable_area(xy[ok])
        return out.reshape(np.shape(x_m))

    @cached_property
    def _crosswalk_union(self) -> Any:
        polys = self.map.crosswalk_polygons
        return shapely.union_all(polys) if len(polys) else None

    def crosswalk_distance(self, boxes: NDArray[np.object_]) -> FloatArray:
        """Distance (m) from each shapely box polygon to the nearest pedestrian crossing (inf if none)."""
        if self._crosswalk_union is None:
            return np.full(np.shape(boxes), np.inf)
        return np.asarray(shapely.distance(self._crosswalk_union, boxes), dtype=np.float64)


class LogContext:
    """One log plus the derived arrays shared by all predicates (see module docstring).

    Pass a preprocessed log (:func:`scenariominer.data.preprocess.preprocess`): accelerations of
    raw annotation boxes are too noisy for ``accelerating``/``has_lateral_acceleration``.

    Args:
        log: the log to mine.
        config: predicate thresholds; defaults to :class:`MiningConfig`.
        hd_map: an HD map for the log (an :class:`~scenariominer.data.adapters.av2.map.Av2Map` or a
            :class:`MapIndex`); ``None`` reads ``log.map_dir`` on first use, if set.
    """

    def __init__(self, log: Log, config: MiningConfig | None = None, hd_map: Any = None) -> None:
        self.log = log
        self.config = config or MiningConfig()
        self._map_given = hd_map
        self._pair_cache: OrderedDict[tuple[str, bytes, bytes], Any] = OrderedDict()
        self._memo: dict[tuple[Any, ...], Any] = {}

    def __repr__(self) -> str:
        return f"LogContext({self.log.log_id!r}, {self.n_tracks} tracks, {self.n_timestamps} timestamps)"

    # ------------------------------------------------------------------ basic views
    @property
    def log_id(self) -> str:
        """Identifier of the log."""
        return self.log.log_id

    @property
    def n_tracks(self) -> int:
        """Number of tracks ``N`` (ego included)."""
        return self.log.n_tracks

    @property
    def n_timestamps(self) -> int:
        """Number of timestamps ``T``."""
        return self.log.n_timestamps

    @property
    def valid(self) -> BoolArray:
        """``(N, T)`` observation mask."""
        return self.log.valid

    @property
    def ego_index(self) -> int:
        """Row of the ego track."""
        return self.log.ego_index

    @cached_property
    def t_s(self) -> FloatArray:
        """``(T,)`` seconds since the first timestamp."""
        return self.log.t_s

    def category_mask(self, category: str) -> BoolArray:
        """``(N,)`` tracks whose category is ``category`` or belongs to the group ``category``.

        Raises:
            ValueError: unknown category name; the message lists the valid names.
        """
        from scenariominer.data.categories import AV2_CATEGORIES, CATEGORY_GROUPS

        try:
            names = expand_categories([category])
        except ValueError:
            raise ValueError(
                f"unknown category {category!r}; use one of {sorted(AV2_CATEGORIES)} or a group "
                f"{sorted(CATEGORY_GROUPS)}"
            ) from None
        return np.isin(self.log.categories, sorted(names))

    @cached_property
    def is_agent(self) -> BoolArray:
        """``(N,)`` tracks of :data:`AGENT_CATEGORIES` (their heading is meaningful at rest)."""
        return np.isin(self.log.categories, sorted(AGENT_CATEGORIES))

    # ------------------------------------------------------------------ kinematics
    @cached_property
    def yaw_rad(self) -> FloatArray:
        """``(N, T)`` box heading, radians."""
        return np.where(self.valid, self.log.yaw_rad, np.nan)

    @cached_property
    def length_m(self) -> FloatArray:
        """``(N, T)`` box length, metres."""
        return np.where(self.valid, self.log.length_m, np.nan)

    @cached_property
    def width_m(self) -> FloatArray:
        """``(N, T)`` box width, metres."""
        return np.where(self.valid, self.log.width_m, np.nan)

    @cached_property
    def center_xy_m(self) -> tuple[FloatArray, FloatArray]:
        """``(N, T)`` x and y of the box centres, world frame (NaN where not observed)."""
        x = np.where(self.valid, self.log.x_m, np.nan)
        y = np.where(self.valid, self.log.y_m, np.nan)
        return x, y

    @property
    def cx_m(self) -> FloatArray:
        """``(N, T)`` box centre x, world frame."""
        return self.center_xy_m[0]

    @property
    def cy_m(self) -> FloatArray:
        """``(N, T)`` box centre y, world frame."""
        return self.center_xy_m[1]

    @cached_property
    def speed_mps(self) -> FloatArray:
        """``(N, T)`` ground speed, m/s."""
        return np.where(self.valid, np.hypot(self.log.vx_mps, self.log.vy_mps), np.nan)

    @cached_property
    def v_body_mps(self) -> tuple[FloatArray, FloatArray]:
        """``(N, T)`` velocity in the box frame: (forward, leftward), m/s."""
        vx, vy = self.log.vx_mps, self.log.vy_mps
        return to_local(vx, vy, self.yaw_rad)

    @cached_property
    def a_body_mps2(self) -> tuple[FloatArray, FloatArray]:
        """``(N, T)`` acceleration in the box frame: (forward, leftward), m/s²."""
        ax, ay = self.log.ax_mps2, self.log.ay_mps2
        return to_local(ax, ay, self.yaw_rad)

    @cached_property
    def yaw_rate_deg_s(self) -> FloatArray:
        """``(N, T)`` heading rate, degrees per second, counter-clockwise (left) positive."""
        return np.degrees(yaw_rate_radps(self.yaw_rad, self.t_s))

    @cached_property
    def travel_direction_rad(self) -> FloatArray:
        """``(N, T)`` direction of travel (radians).

        The velocity direction when at least :attr:`MiningConfig.heading_min_speed_mps` fast,
        else the box heading for agents (:data:`AGENT_CATEGORIES`), else NaN.
        """
        moving = self.speed_mps >= self.config.heading_min_speed_mps
        vel_dir = np.arctan2(self.log.vy_mps, self.log.vx_mps)
        out = np.where(moving, vel_dir, np.where(self.is_agent[:, None], self.yaw_rad, np.nan))
        return np.where(self.valid, out, np.nan)

    @cached_property
    def displacement_extent_m(self) -> FloatArray:
        """``(N,)`` diagonal of the bounding box of each track's observed centres, metres."""
        x, y = self.center_xy_m
        has = self.valid.any(axis=1)

        def extent(a: FloatArray) -> FloatArray:
            hi = np.where(self.valid, a, -np.inf).max(axis=1, initial=-np.inf)
            lo = np.where(self.valid, a, np.inf).min(axis=1, initial=np.inf)
            return np.where(has, hi - lo, 0.0)

        dx, dy = extent(x), extent(y)
        return np.asarray(np.hypot(dx, dy))

    def memo(self, key: tuple[Any, ...], compute: Callable[[], Any]) -> Any:
        """Return ``compute()`` cached under ``key`` for the lifetime of this context.

        Predicates use it for per-log results that do not depend on the candidates (e.g. the
        turning mask of every track), so several programs on one log share them.
        """
        if key not in self._memo:
            self._memo[key] = compute()
        return self._memo[key]

    # ------------------------------------------------------------------ pairwise geometry
    def _cached(self, kind: str, rows: IntArray, cols: IntArray, compute: Callable[[], Any]) -> Any:
        key = (kind, rows.tobytes(), cols.tobytes())
        hit = self._pair_cache.get(key)
        if hit is not None:
            self._pair_cache.move_to_end(key)
            return hit
        value = compute()
        self._pair_cache[key] = value
        if len(self._pair_cache) > _PAIR_CACHE_ENTRIES:
            self._pair_cache.popitem(last=False)
        return value

    def relative_position(self, rows: IntArray, cols: IntArray) -> tuple[FloatArray, FloatArray]:
        """Centres of tracks ``cols`` in the box frames of tracks ``rows``.

        Args:
            rows: ``(R,)`` track indices whose frames are used (the subjects).
            cols: ``(C,)`` track indices whose centres are expressed (the references).

        Returns:
            ``(x_m, y_m)``, each ``(R, C, T)``: forward and leftward offset in metres; NaN where
            either track is absent.
        """
        rows = np.asarray(rows, dtype=np.int64)
        cols = np.asarray(cols, dtype=np.int64)

        def compute() -> tuple[FloatArray, FloatArray]:
            x, y = self.center_xy_m
            dx = x[cols][None, :, :] - x[rows][:, None, :]
            dy = y[cols][None, :, :] - y[rows][:, None, :]
            return to_local(dx, dy, self.yaw_rad[rows][:, None, :])

        result: tuple[FloatArray, FloatArray] = self._cached("relpos", rows, cols, compute)
        return result

    def relative_velocity(self, rows: IntArray, cols: IntArray) -> tuple[FloatArray, FloatArray]:
        """World velocities of tracks ``cols`` rotated into the box frames of ``rows``.

        Returns:
            ``(vx_mps, vy_mps)``, each ``(R, C, T)``: forward and leftward components of the
            reference track's own ground velocity (not the difference of velocities).
        """
        rows = np.asarray(rows, dtype=np.int64)
        cols = np.asarray(cols, dtype=np.int64)

        def compute() -> tuple[FloatArray, FloatArray]:
            vx = self.log.vx_mps[cols][None, :, :]
            vy = self.log.vy_mps[cols][None, :, :]
            return to_local(vx, vy, self.yaw_rad[rows][:, None, :])

        result: tuple[FloatArray, FloatArray] = self._cached("relvel", rows, cols, compute)
        return result

    def box_distance(self, rows: IntArray, cols: IntArray) -> FloatArray:
        """``(R, C, T)`` minimum footprint-to-footprint distance (m) between tracks; 0 if touching."""
        rows = np.asarray(rows, dtype=np.int64)
        cols = np.asarray(cols, dtype=np.int64)

        def compute() -> FloatArray:
            x, y = self.center_xy_m
            t = self.n_timestamps
            out = np.empty((rows.size, cols.size, t))
            step = max(1, _CHUNK_CELLS // max(1, cols.size * t))
            fields = (x, y, self.yaw_rad, self.length_m, self.width_m)
            b = OrientedBoxes(*(f[cols][None, :, :] for f in fields))
            for start in range(0, rows.size, step):
                r = rows[start : start + step]
                a = OrientedBoxes(*(f[r][:, None, :] for f in fields))
                out[start : start + step] = box_distance_m(a, b)
            return out

        result: FloatArray = self._cached("boxdist", rows, cols, compute)
        return result

    @cached_property
    def box_polygons(self) -> NDArray[np.object_]:
        """``(N, T)`` shapely footprints of every box (``None`` where the track is absent)."""
        x, y = self.center_xy_m
        corners = OrientedBoxes(x, y, self.yaw_rad, self.length_m, self.width_m).corners()  # (N, T, 4, 2)
        coords = np.concatenate([corners, corners[..., :1, :]], axis=-2)  # closed ring (N, T, 5, 2)
        out = np.full(x.shape, None, dtype=object)
        ok = np.isfinite(coords).all(axis=(-1, -2))
        if ok.any():
            out[ok] = shapely.polygons(coords[ok])
        return out

    # ------------------------------------------------------------------ HD map
    @cached_property
    def _map(self) -> MapIndex | None:
        if self._map_given is not None:
            return MapIndex.from_map(self._map_given)
        if self.log.map_dir is None:
            return None
        return MapIndex(read_av2_map(self.log.map_dir))

    @property
    def has_map(self) -> bool:
        """Whether an HD map is available (loads it on first call)."""
        return self._map is not None

    def require_map(self, predicate: str) -> MapIndex:
        """The map index, or :class:`MapRequiredError` naming ``predicate`` when there is none."""
        m = self._map
        if m is None:
            raise MapRequiredError(predicate, self.log_id)
        return m

    def lane_index(self, predicate: str) -> IntArray:
        """``(N, T)`` index of the lane segment under each box centre (-1: none), computed once.

        The lane polygons containing the centre are the candidates; where several do
        (intersections, merges, overlapping bike lanes) the lane type suited to the track's
        category wins, then the previous frame's lane or its successor, then the closest centre
        line with a heading-mismatch penalty (:mod:`scenariominer.mine.lanes`).

        Raises:
            MapRequiredError: the log has no map; names ``predicate``.
        """
        self.require_map(predicate)
        return self._lanes[0]

    def lane_direction_rad(self, predicate: str) -> FloatArray:
        """``(N, T)`` local direction (radians) of the lane under each box centre (NaN: none)."""
        self.require_map(predicate)
        return self._lanes[1]

    @cached_property
    def _lanes(self) -> tuple[IntArray, FloatArray]:
        hd = self.require_map("lane_index")
        x, y = self.center_xy_m
        return hd.lanes_at(x, y, self.yaw_rad, self.log.categories)
