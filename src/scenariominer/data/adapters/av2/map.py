"""Argoverse 2 vector maps: a typed reader/writer and vectorised spatial look-ups.

An Argoverse 2 log ships its local vector map as ``map/log_map_archive_<log_id>____<CITY>_city_<n>.json``
with three layers, all in the city frame (metres):

* ``lane_segments``: lanes with left/right boundary polylines, lane type (VEHICLE, BIKE, BUS),
  whether the lane lies inside an intersection, left/right neighbours and the lane graph
  (successors/predecessors);
* ``pedestrian_crossings``: crosswalks given by two roughly parallel edges (``edge1``, ``edge2``);
* ``drivable_areas``: polygons (``area_boundary``) covering the drivable surface.

:class:`Av2Map` keeps the records for round-tripping (:func:`write_av2_map`) and builds shapely
geometry once (lane polygons between the two boundaries, centre lines, crosswalk and drivable
polygons) plus an :class:`shapely.STRtree` over the lanes, so the queries used by mining predicates
(:meth:`Av2Map.lane_candidates`, :meth:`Av2Map.lane_index_at`, :meth:`Av2Map.in_drivable_area`,
:meth:`Av2Map.in_crosswalk`, :meth:`Av2Map.distance_to_intersection`) run on whole ``(K, 2)``
point arrays at once.
"""

from __future__ import annotations

import json
from collections.abc import Sequence
from dataclasses import dataclass, field
from enum import StrEnum
from pathlib import Path
from typing import Any

import numpy as np
import orjson
import shapely
from numpy.typing import ArrayLike, NDArray

from scenariominer.data.log import MAX_COORDINATE_M, LogFormatError

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]
BoolArray = NDArray[np.bool_]

#: File-name pattern of the vector map inside a log's ``map/`` folder.
MAP_FILE_GLOB = "log_map_archive_*.json"

#: Weight (metres) of a heading mismatch when several lanes contain a point: a lane pointing the
#: opposite way costs ``2 *`` this, a perpendicular one ``1 *`` this, on top of the distance (metres)
#: from the point to the lane's centre line.
LANE_HEADING_WEIGHT_M = 4.0


class LaneType(StrEnum):
    """Kind of traffic a lane segment carries (Argoverse 2 vocabulary)."""

    VEHICLE = "VEHICLE"
    BIKE = "BIKE"
    BUS = "BUS"


def _polyline_to_json(points_m: FloatArray) -> list[dict[str, float]]:
    return [
        {"x": round(float(p[0]), 4), "y": round(float(p[1]), 4), "z": round(float(p[2]), 4)} for p in points_m
    ]


def _resample(polyline_m: FloatArray, n_points: int) -> FloatArray:
    """Resample a ``(P, D)`` polyline to ``n_points`` points equally spaced in arc length."""
    seg = np.linalg.norm(np.diff(polyline_m, axis=0), axis=1)
    s = np.concatenate([[0.0], np.cumsum(seg)])
    if s[-1] <= 0.0:
        return np.repeat(polyline_m[:1], n_points, axis=0)
    targets = np.linspace(0.0, s[-1], n_points)
    return np.stack([np.interp(targets, s, polyline_m[:, d]) for d in range(polyline_m.shape[1])], axis=1)


@dataclass(frozen=True, eq=False)
class LaneSegment:
    """One lane segment of an Argoverse 2 vector map.

    Attributes:
        id: lane segment id (unique within the map).
        lane_type: traffic the lane carries.
        is_intersection: whether the segment lies inside an intersection.
        left_boundary_m: ``(P, 3)`` left boundary polyline (x, y, z) in the direction of travel.
        right_boundary_m: ``(Q, 3)`` right boundary polyline (x, y, z) in the direction of travel.
        left_mark_type: paint of the left boundary (e.g. ``SOLID_YELLOW``, ``DASHED_WHITE``, ``NONE``).
        right_mark_type: paint of the right boundary.
        successors: ids of the segments this one leads into.
        predecessors: ids of the segments leading into this one.
        left_neighbor_id: id of the segment to the left, if any.
        right_neighbor_id: id of the segment to the right, if any.
    """

    id: int
    lane_type: LaneType
    is_intersection: bool
    left_boundary_m: FloatArray
    right_boundary_m: FloatArray
    left_mark_type: str = "NONE"
    right_mark_type: str = "NONE"
    successors: tuple[int, ...] = ()
    predecessors: tuple[int, ...] = ()
    left_neighbor_id: int | None = None
    right_neighbor_id: int | None = None

    @property
    def polygon(self) -> shapely.Geometry:
        """Area between the two boundaries (repaired with ``make_valid`` if self-intersecting)."""
        ring = np.vstack([self.left_boundary_m[:, :2], self.right_boundary_m[::-1, :2]])
        poly = shapely.Polygon(ring)
        return poly if poly.is_valid else shapely.make_valid(poly)

    def centerline_m(self, n_points: int | None = None) -> FloatArray:
        """``(n_points, 3)`` centre line: the mean of both boundaries resampled by arc length.

        Args:
            n_points: number of points; defaults to the larger boundary's point count (at least 2).
        """
        n = n_points or max(len(self.left_boundary_m), len(self.right_boundary_m), 2)
        return 0.5 * (_resample(self.left_boundary_m, n) + _resample(self.right_boundary_m, n))

    def to_json(self) -> dict[str, Any]:
        """Return the segment as an Argoverse 2 map JSON object."""
        return {
            "id": int(self.id),
            "is_intersection": bool(self.is_intersection),
            "lane_type": self.lane_type.value,
            "left_lane_boundary": _polyline_to_json(self.left_boundary_m),
            "left_lane_mark_type": self.left_mark_type,
            "right_lane_boundary": _polyline_to_json(self.right_boundary_m),
            "right_lane_mark_type": self.right_mark_type,
            "successors": [int(i) for i in self.successors],
            "predecessors": [int(i) for i in self.predecessors],
            "right_neighbor_id": None if self.right_neighbor_id is None else int(self.right_neighbor_id),
            "left_neighbor_id": None if self.left_neighbor_id is None else int(self.left_neighbor_id),
        }


@dataclass(frozen=True, eq=False)
class PedestrianCrossing:
    """A crosswalk: the area between two roughly parallel edges.

    Attributes:
        id: crossing id.
        edge1_m: ``(2, 3)`` first edge (x, y, z).
        edge2_m: ``(2, 3)`` second edge, running the same way as ``edge1_m``.
    """

    id: int
    edge1_m: FloatArray
    edge2_m: FloatArray

    @property
    def polygon(self) -> shapely.Geometry:
        """Quadrilateral spanned by the two edges."""
        ring = np.vstack([self.edge1_m[:, :2], self.edge2_m[::-1, :2]])
        poly = shapely.Polygon(ring)
        return poly if poly.is_valid else shapely.make_valid(poly)

    def to_json(self) -> dict[str, Any]:
        """Return the crossing as an Argoverse 2 map JSON object."""
        return {
            "edge1": _polyline_to_json(self.edge1_m),
            "edge2": _polyline_to_json(self.edge2_m),
            "id": int(self.id),
        }


@dataclass(frozen=True, eq=False)
class DrivableArea:
    """A drivable-area polygon.

    Attributes:
        id: area id.
        boundary_m: ``(P, 3)`` closed boundary (x, y, z); the first point is not repeated.
    """

    id: int
    boundary_m: FloatArray

    @property
    def polygon(self) -> shapely.Geometry:
        """The area as a shapely polygon."""
        poly = shapely.Polygon(self.boundary_m[:, :2])
        return poly if poly.is_valid else shapely.make_valid(poly)

    def to_json(self) -> dict[str, Any]:
        """Return the area as an Argoverse 2 map JSON object."""
        return {"area_boundary": _polyline_to_json(self.boundary_m), "id": int(self.id)}


def _as_xy(xy: ArrayLike) -> FloatArray:
    arr = np.asarray(xy, dtype=np.float64)
    if arr.ndim == 1 and arr.shape[0] == 2:
        arr = arr[None, :]
    if arr.ndim != 2 or arr.shape[1] != 2:
        raise ValueError(f"expected points of shape (K, 2), got {arr.shape}")
    return arr


def _union(geoms: Sequence[shapely.Geometry]) -> shapely.Geometry | None:
    if len(geoms) == 0:
        return None
    union = shapely.union_all(np.asarray(geoms, dtype=object))
    shapely.prepare(union)
    return union


@dataclass(frozen=True, eq=False)
class Av2Map:
    """An Argoverse 2 vector map with prebuilt geometry for vectorised look-ups.

    Build with :func:`read_av2_map` or ``Av2Map(lane_segments, pedestrian_crossings, drivable_areas)``;
    the derived attributes are computed once at construction. Lane *indices* (positions in
    :attr:`lane_segments`) are what the queries return; ``-1`` means "no lane".

    Attributes:
        lane_segments: the lanes, in file order.
        pedestrian_crossings: the crosswalks.
        drivable_areas: the drivable-area polygons.
        source_path: the JSON file the map was read from, if any.
        lane_ids: ``(L,)`` lane segment ids.
        lane_polygons: ``(L,)`` shapely polygons between each lane's boundaries.
        lane_centerlines: ``(L,)`` shapely line strings (2-D centre lines).
        lane_is_intersection: ``(L,)`` whether each lane lies inside an intersection.
        lane_types: ``(L,)`` lane type names (``VEHICLE``, ``BIKE``, ``BUS``).
        crosswalk_polygons: ``(C,)`` shapely polygons of the crosswalks.
        drivable_polygons: ``(D,)`` shapely polygons of the drivable areas.
        lane_tree: STRtree over :attr:`lane_polygons`.
    """

    lane_segments: tuple[LaneSegment, ...]
    pedestrian_crossings: tuple[PedestrianCrossing, ...] = ()
    drivable_areas: tuple[DrivableArea, ...] = ()
    source_path: Path | None = None
    lane_ids: IntArray = field(init=False, repr=False)
    lane_polygons: NDArray[np.object_] = field(init=False, repr=False)
    lane_centerlines: NDArray[np.object_] = field(init=False, repr=False)
    lane_is_intersection: BoolArray = field(init=False, repr=False)
    lane_types: NDArray[np.str_] = field(init=False, repr=False)
    crosswalk_polygons: NDArray[np.object_] = field(init=False, repr=False)
    drivable_polygons: NDArray[np.object_] = field(init=False, repr=False)
    lane_tree: shapely.STRtree = field(init=False, repr=False)
    _drivable_union: shapely.Geometry | None = field(init=False, repr=False)
    _crosswalk_union: shapely.Geometry | None = field(init=False, repr=False)
    _intersection_union: shapely.Geometry | None = field(init=False, repr=False)

    def __post_init__(self) -> None:
        lanes = self.lane_segments
        derived: dict[str, Any] = {
            "lane_ids": np.asarray([ls.id for ls in lanes], dtype=np.int64),
            "lane_polygons": np.asarray([ls.polygon for ls in lanes] or [], dtype=object),
            "lane_centerlines": np.asarray(
                [shapely.LineString(ls.centerline_m()[:, :2]) for ls in lanes] or [], dtype=object
            ),
            "lane_is_intersection": np.asarray([ls.is_intersection for ls in lanes], dtype=bool),
            "lane_types": np.asarray([ls.lane_type.value for ls in lanes], dtype=str),
            "crosswalk_polygons": np.asarray(
                [pc.polygon for pc in self.pedestrian_crossings] or [], dtype=object
            ),
            "drivable_polygons": np.asarray([da.polygon for da in self.drivable_areas] or [], dtype=object),
        }
        derived["lane_tree"] = shapely.STRtree(derived["lane_polygons"])
        derived["_drivable_union"] = _union(list(derived["drivable_polygons"]))
        derived["_crosswalk_union"] = _union(list(derived["crosswalk_polygons"]))
        derived["_intersection_union"] = _union(
            list(derived["lane_polygons"][derived["lane_is_intersection"]])
        )
        for name, value in derived.items():
            object.__setattr__(self, name, value)

    # ------------------------------------------------------------------ basic look-ups
    @property
    def n_lanes(self) -> int:
        """Number of lane segments ``L``."""
        return len(self.lane_segments)

    def lane_index(self, lane_id: int) -> int:
        """Index of the lane with id ``lane_id``; raises ``KeyError`` when absent."""
        hits = np.flatnonzero(self.lane_ids == lane_id)
        if hits.size == 0:
            raise KeyError(f"lane segment {lane_id} is not in the map")
        return int(hits[0])

    # ------------------------------------------------------------------ vectorised queries
    def lane_candidates(
        self, xy: ArrayLike, yaw_rad: ArrayLike | None = None
    ) -> tuple[IntArray, IntArray, FloatArray, FloatArray]:
        """Every (point, lane) pair with the point in (or on the edge of) the lane's polygon.

        Args:
            xy: ``(K, 2)`` points in the city frame, metres (rows with NaN are in no lane).
            yaw_rad: optional ``(K,)`` headings of the objects at those points.

        Returns:
            ``(point, lane, cost, lane_yaw)`` arrays of one entry per pair, sorted by point then
            lane: the point's row in ``xy``, the lane index, the pair's cost in metres (distance
            from the point to the lane's centre line plus, with ``yaw_rad``, the heading mismatch
            ``LANE_HEADING_WEIGHT_M * (1 - cos(dyaw))``; a NaN heading adds nothing) and the lane's
            local direction (radians) at the centre-line point nearest the point.
        """
        pts_xy = _as_xy(xy)
        k = pts_xy.shape[0]
        finite = np.flatnonzero(np.all(np.isfinite(pts_xy), axis=1))
        if finite.size == 0 or self.n_lanes == 0:
            empty = np.zeros(0, dtype=np.int64)
            return empty, empty.copy(), np.zeros(0), np.zeros(0)
        points = shapely.points(pts_xy[finite])
        inp, lane = self.lane_tree.query(points, predicate="intersects")
        order = np.lexsort((lane, inp))
        inp, lane = inp[order], lane[order].astype(np.int64)
        lines = self.lane_centerlines[lane]
        cost = np.asarray(shapely.distance(points[inp], lines), dtype=np.float64)
        s = shapely.line_locate_point(lines, points[inp])
        p0 = shapely.get_coordinates(shapely.line_interpolate_point(lines, np.maximum(s - 0.5, 0.0)))
        p1 = shapely.get_coordinates(shapely.line_interpolate_point(lines, s + 0.5))
        lane_yaw = np.arctan2(p1[:, 1] - p0[:, 1], p1[:, 0] - p0[:, 0])
        if yaw_rad is not None:
            yaw = np.broadcast_to(np.asarray(yaw_rad, dtype=np.float64), (k,))[finite][inp]
            penalty = LANE_HEADING_WEIGHT_M * (1.0 - np.cos(yaw - lane_yaw))
            cost = cost + np.where(np.isfinite(penalty), penalty, 0.0)
        return finite[inp].astype(np.int64), lane, cost, lane_yaw

    def lane_index_at(self, xy: ArrayLike, yaw_rad: ArrayLike | None = None) -> IntArray:
        """Index of the lane containing each point, ``-1`` where no lane does.

        Where lanes overlap (intersections, merges) the lane of lowest
        :meth:`lane_candidates` cost wins: the closest centre line, with ``yaw_rad`` plus a
        heading mismatch of ``LANE_HEADING_WEIGHT_M * (1 - cos(dyaw))`` metres. Each point is
        looked at alone; the mining context's lane per track and frame
        (:func:`scenariominer.mine.lanes.assign_lanes`) also weighs lane type and continuity.

        Args:
            xy: ``(K, 2)`` points in the city frame, metres (rows with NaN give ``-1``).
            yaw_rad: optional ``(K,)`` headings of the objects at those points.

        Returns:
            ``(K,)`` int64 lane indices into :attr:`lane_segments`.
        """
        pts_xy = _as_xy(xy)
        out = np.full(pts_xy.shape[0], -1, dtype=np.int64)
        point, lane, cost, _ = self.lane_candidates(pts_xy, yaw_rad)
        if point.size == 0:
            return out
        order = np.lexsort((cost, point))
        first_point, first_pos = np.unique(point[order], return_index=True)
        out[first_point] = lane[order][first_pos]
        return out

    def in_drivable_area(self, xy: ArrayLike) -> BoolArray:
        """``(K,)`` whether each point lies in (or on the edge of) a drivable area."""
        pts = _as_xy(xy)
        if self._drivable_union is None:
            return np.zeros(pts.shape[0], dtype=bool)
        return np.asarray(shapely.intersects_xy(self._drivable_union, pts[:, 0], pts[:, 1]), dtype=bool)

    def in_crosswalk(self, xy: ArrayLike) -> BoolArray:
        """``(K,)`` whether each point lies in (or on the edge of) a pedestrian crossing."""
        pts = _as_xy(xy)
        if self._crosswalk_union is None:
            return np.zeros(pts.shape[0], dtype=bool)
        return np.asarray(shapely.intersects_xy(self._crosswalk_union, pts[:, 0], pts[:, 1]), dtype=bool)

    def distance_to_intersection(self, xy: ArrayLike) -> FloatArray:
        """``(K,)`` distance in metres to the nearest intersection lane (0 inside one).

        ``inf`` when the map has no intersection lanes; ``NaN`` for non-finite points.
        """
        pts = _as_xy(xy)
        out = np.full(pts.shape[0], np.inf)
        finite = np.all(np.isfinite(pts), axis=1)
        out[~finite] = np.nan
        if self._intersection_union is None or not finite.any():
            return out
        out[finite] = shapely.distance(self._intersection_union, shapely.points(pts[finite]))
        return out

    def is_intersection(self, lane_idx: ArrayLike) -> BoolArray:
        """Whether each lane index is an intersection lane (``False`` for ``-1``), same shape as input."""
        idx = np.asarray(lane_idx, dtype=np.int64)
        flat = idx.reshape(-1)
        out = np.zeros(flat.shape, dtype=bool)
        ok = flat >= 0
        out[ok] = self.lane_is_intersection[flat[ok]]
        return out.reshape(idx.shape)

    def lane_type(self, lane_idx: ArrayLike) -> NDArray[np.str_]:
        """Lane type name of each lane index (``""`` for ``-1``), same shape as input."""
        idx = np.asarray(lane_idx, dtype=np.int64)
        flat = idx.reshape(-1)
        out = np.full(flat.shape, "", dtype="<U7")
        ok = flat >= 0
        out[ok] = self.lane_types[flat[ok]]
        return out.reshape(idx.shape)

    # ------------------------------------------------------------------ serialisation
    def to_json(self) -> dict[str, Any]:
        """Return the map as an Argoverse 2 ``log_map_archive_*.json`` document."""
        return {
            "pedestrian_crossings": {str(pc.id): pc.to_json() for pc in self.pedestrian_crossings},
            "lane_segments": {str(ls.id): ls.to_json() for ls in self.lane_segments},
            "drivable_areas": {str(da.id): da.to_json() for da in self.drivable_areas},
        }


# ---------------------------------------------------------------------- reading


def _points(raw: Any, path: Path, what: str, min_points: int) -> FloatArray:
    if not isinstance(raw, list):
        raise LogFormatError(path, f"{what} is not a list of points")
    try:
        pts = np.asarray([[p["x"], p["y"], p.get("z", 0.0)] for p in raw], dtype=np.float64)
    except (KeyError, TypeError, ValueError, AttributeError, OverflowError) as exc:
        raise LogFormatError(path, f"{what} has a malformed point ({exc!r}); expected {{x, y, z}}") from None
    if pts.shape[0] < min_points:
        raise LogFormatError(path, f"{what} has {pts.shape[0]} point(s), at least {min_points} needed")
    if not np.all(np.isfinite(pts)):
        raise LogFormatError(path, f"{what} has non-finite coordinates")
    if np.any(np.abs(pts[:, :2]) > MAX_COORDINATE_M):
        raise LogFormatError(path, f"{what} has a coordinate beyond {MAX_COORDINATE_M:.0e} m")
    return pts


def _id(value: Any) -> int:
    """A record id or reference: an integer that fits 64 bits (ids are stored as int64)."""
    out = int(value)
    if not -(2**63) <= out < 2**63:
        raise OverflowError(f"id {out} does not fit 64 bits")
    return out


def _opt_int(value: Any) -> int | None:
    return None if value is None else _id(value)


def _parse_lane(raw: Any, path: Path) -> LaneSegment:
    what = f"lane segment {raw.get('id', '?') if isinstance(raw, dict) else '?'}"
    if not isinstance(raw, dict):
        raise LogFormatError(path, f"{what} is not an object")
    try:
        lane_type = LaneType(str(raw["lane_type"]))
    except ValueError:
        raise LogFormatError(
            path, f"{what} has unknown lane_type {raw['lane_type']!r} (expected VEHICLE, BIKE or BUS)"
        ) from None
    except KeyError as exc:
        raise LogFormatError(path, f"{what} lacks the key {exc.args[0]!r}") from None
    try:
        return LaneSegment(
            id=_id(raw["id"]),
            lane_type=lane_type,
            is_intersection=bool(raw["is_intersection"]),
            left_boundary_m=_points(raw["left_lane_boundary"], path, f"{what} left_lane_boundary", 2),
            right_boundary_m=_points(raw["right_lane_boundary"], path, f"{what} right_lane_boundary", 2),
            left_mark_type=str(raw.get("left_lane_mark_type", "NONE")),
            right_mark_type=str(raw.get("right_lane_mark_type", "NONE")),
            successors=tuple(_id(i) for i in raw.get("successors") or ()),
            predecessors=tuple(_id(i) for i in raw.get("predecessors") or ()),
            left_neighbor_id=_opt_int(raw.get("left_neighbor_id")),
            right_neighbor_id=_opt_int(raw.get("right_neighbor_id")),
        )
    except LogFormatError:
        raise
    except KeyError as exc:
        raise LogFormatError(path, f"{what} lacks the key {exc.args[0]!r}") from None
    except (TypeError, ValueError, OverflowError) as exc:
        raise LogFormatError(path, f"{what} has a malformed field ({exc})") from None


def _parse_crossing(raw: Any, path: Path) -> PedestrianCrossing:
    what = f"pedestrian crossing {raw.get('id', '?') if isinstance(raw, dict) else '?'}"
    if not isinstance(raw, dict):
        raise LogFormatError(path, f"{what} is not an object")
    try:
        return PedestrianCrossing(
            id=_id(raw["id"]),
            edge1_m=_points(raw["edge1"], path, f"{what} edge1", 2),
            edge2_m=_points(raw["edge2"], path, f"{what} edge2", 2),
        )
    except LogFormatError:
        raise
    except KeyError as exc:
        raise LogFormatError(path, f"{what} lacks the key {exc.args[0]!r}") from None
    except (TypeError, ValueError, OverflowError) as exc:
        raise LogFormatError(path, f"{what} has a malformed field ({exc})") from None


def _parse_area(raw: Any, path: Path) -> DrivableArea:
    what = f"drivable area {raw.get('id', '?') if isinstance(raw, dict) else '?'}"
    if not isinstance(raw, dict):
        raise LogFormatError(path, f"{what} is not an object")
    try:
        return DrivableArea(id=_id(raw["id"]), boundary_m=_points(raw["area_boundary"], path, f"{what}", 3))
    except LogFormatError:
        raise
    except KeyError as exc:
        raise LogFormatError(path, f"{what} lacks the key {exc.args[0]!r}") from None
    except (TypeError, ValueError, OverflowError) as exc:
        raise LogFormatError(path, f"{what} has a malformed field ({exc})") from None


def find_map_file(path: Path) -> Path:
    """Find the ``log_map_archive_*.json`` file at ``path`` (the file, a ``map/`` folder or a log folder).

    Raises:
        LogFormatError: no map file, or several, at that location.
    """
    path = Path(path)
    if path.is_file():
        return path
    for folder in (path, path / "map"):
        hits = sorted(folder.glob(MAP_FILE_GLOB)) if folder.is_dir() else []
        if len(hits) > 1:
            raise LogFormatError(
                folder, f"several vector maps ({', '.join(h.name for h in hits)}); expected one"
            )
        if hits:
            return hits[0]
    raise LogFormatError(
        path, f"no Argoverse 2 vector map ({MAP_FILE_GLOB}) in this folder or its map/ folder"
    )


def _load_layers(file: Path, *, fast: bool = False) -> dict[str, dict[str, Any]]:
    """Parse the JSON of a map file and return its three layers (each an object keyed by id).

    ``fast`` parses with orjson, about three times faster than :mod:`json`, for a map that is then
    checked by :func:`_quick_check`; orjson reads some bad input differently (an integer beyond 64
    bits becomes a float), so a file it refuses or a map that fails the check is parsed again by
    :mod:`json` (:func:`_valid_layers`): what is accepted and every message are :mod:`json`'s.
    """
    try:
        raw = file.read_bytes()
        try:
            doc = orjson.loads(raw) if fast else None
        except orjson.JSONDecodeError:
            doc = None
        if doc is None:
            doc = json.loads(raw.decode("utf-8"))
    except OSError as exc:
        raise LogFormatError(file, f"cannot read the vector map ({exc.strerror or exc})") from None
    except UnicodeDecodeError as exc:
        problem = f"vector map is not UTF-8 text ({exc.reason} at byte {exc.start})"
        raise LogFormatError(file, problem) from None
    except json.JSONDecodeError as exc:
        raise LogFormatError(file, f"vector map is not valid JSON ({exc})") from None
    except RecursionError:
        raise LogFormatError(file, "vector map JSON is nested too deeply to parse") from None
    if not isinstance(doc, dict):
        raise LogFormatError(file, "vector map is not a JSON object")
    layers: dict[str, dict[str, Any]] = {}
    for key in ("lane_segments", "pedestrian_crossings", "drivable_areas"):
        layer = doc.get(key)
        if not isinstance(layer, dict):
            raise LogFormatError(file, f"vector map lacks the {key!r} layer (an object keyed by id)")
        layers[key] = layer
    return layers


def _parse_layers(
    layers: dict[str, dict[str, Any]], file: Path
) -> tuple[tuple[LaneSegment, ...], tuple[PedestrianCrossing, ...], tuple[DrivableArea, ...]]:
    return (
        tuple(_parse_lane(v, file) for v in layers["lane_segments"].values()),
        tuple(_parse_crossing(v, file) for v in layers["pedestrian_crossings"].values()),
        tuple(_parse_area(v, file) for v in layers["drivable_areas"].values()),
    )


_LANE_TYPES = frozenset(t.value for t in LaneType)
_QUICK_ERRORS = (KeyError, TypeError, ValueError, AttributeError, OverflowError)


def _quick_check(layers: dict[str, dict[str, Any]]) -> bool:
    """Whether every record passes the parsers' checks, tested in one pass without building records.

    The same rules as :func:`_parse_lane`, :func:`_parse_crossing` and :func:`_parse_area` (ids and
    neighbour ids are integers that fit 64 bits, lane types known, polylines long enough with finite
    x, y, z and x, y within :data:`~scenariominer.data.log.MAX_COORDINATE_M`), with
    all coordinates converted and checked at once. ``False`` says only that some record fails: the
    parsers then name it.
    """
    coords: list[Any] = []
    try:
        for lane in layers["lane_segments"].values():
            _id(lane["id"])
            lane["is_intersection"]  # noqa: B018  # required key
            if str(lane["lane_type"]) not in _LANE_TYPES:
                return False
            for key in ("left_lane_boundary", "right_lane_boundary"):
                if not _gather(lane[key], 2, coords):
                    return False
            for i in (*(lane.get("successors") or ()), *(lane.get("predecessors") or ())):
                _id(i)
            for key in ("left_neighbor_id", "right_neighbor_id"):
                _opt_int(lane.get(key))
        for crossing in layers["pedestrian_crossings"].values():
            _id(crossing["id"])
            if not (_gather(crossing["edge1"], 2, coords) and _gather(crossing["edge2"], 2, coords)):
                return False
        for area in layers["drivable_areas"].values():
            _id(area["id"])
            if not _gather(area["area_boundary"], 3, coords):
                return False
        xyz = np.asarray(coords, dtype=np.float64).reshape(-1, 3)
        return bool(np.all(np.isfinite(xyz)) and np.all(np.abs(xyz[:, :2]) <= MAX_COORDINATE_M))
    except _QUICK_ERRORS:
        return False


def _gather(raw: Any, min_points: int, coords: list[Any]) -> bool:
    """Append the x, y, z of the points of ``raw`` to ``coords``; ``False`` when too few or not a list."""
    if not isinstance(raw, list) or len(raw) < min_points:
        return False
    coords.extend([c for p in raw for c in (p["x"], p["y"], p.get("z", 0.0))])
    return True


def _valid_layers(file: Path) -> dict[str, dict[str, Any]]:
    """The layers of the map ``file``, parsed fast and checked in one pass where it is valid.

    A map that fails :func:`_quick_check` is parsed again by :mod:`json` and record by record, which
    raises naming the record at fault.
    """
    layers = _load_layers(file, fast=True)
    if _quick_check(layers):
        return layers
    layers = _load_layers(file)
    _parse_layers(layers, file)  # raises, naming the record at fault
    return layers


def validate_av2_map(path: Path) -> Path:
    """Check that :func:`read_av2_map` will read the map at ``path``, without building its geometry.

    Parses the JSON and every record with the reader's own parsers (ids, lane types, boundary
    points), so a map that passes reads later; skips the shapely polygons, centre lines and spatial
    index, which cost several times more. A map that is valid is checked in one pass over its
    records without building them (:func:`_quick_check`); only one that fails is parsed record by
    record, for the message.

    Returns:
        The map file.

    Raises:
        LogFormatError: as :func:`read_av2_map`.
    """
    file = find_map_file(path)
    _valid_layers(file)
    return file


def read_av2_map(path: Path) -> Av2Map:
    """Read an Argoverse 2 vector map.

    Args:
        path: the ``log_map_archive_*.json`` file, the log's ``map/`` folder, or the log folder.

    Raises:
        LogFormatError: missing/unreadable file, invalid JSON, missing layers or malformed records;
            the message names the file and the offending record.
    """
    file = find_map_file(path)
    lanes, crossings, areas = _parse_layers(_valid_layers(file), file)
    return Av2Map(lane_segments=lanes, pedestrian_crossings=crossings, drivable_areas=areas, source_path=file)


def write_av2_map(av2_map: Av2Map, path: Path) -> Path:
    """Write ``av2_map`` as an Argoverse 2 vector-map JSON file (see :func:`read_av2_map`).

    Args:
        av2_map: the map to write.
        path: destination file; parent folders are created. Name it
            ``log_map_archive_<log_id>____<CITY>_city_<n>.json`` inside the log's ``map/`` folder
            for readers to find it.

    Returns:
        The written path.
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(av2_map.to_json()), encoding="utf-8")
    return path
