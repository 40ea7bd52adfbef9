"""Argoverse 2 sensor-dataset logs: discovery, reading into a :class:`Log`, and writing.

An Argoverse 2 log folder (``<root>/<split>/<log_id>/``) holds

* ``annotations_with_ego.feather`` (or the original ``annotations.feather`` without the ego rows):
  one row per (``timestamp_ns``, ``track_uuid``) with ``category``, box size ``length_m``,
  ``width_m``, ``height_m``, rotation quaternion ``qw qx qy qz`` and translation ``tx_m ty_m tz_m``
  **in the ego-vehicle frame of that timestamp**, plus ``num_interior_pts`` (lidar returns);
* ``city_SE3_egovehicle.feather``: the ego pose in the city frame (``timestamp_ns``, ``qw qx qy qz``,
  ``tx_m ty_m tz_m``) at about 170 Hz, a superset of the annotation timestamps;
* ``map/``: the vector map (see :mod:`scenariominer.data.adapters.av2.map`).

Boxes are moved to the city frame with the ego pose *of the same timestamp*
(``p_city = R_city_ego @ p_ego + t_city_ego``, ``R_city_box = R_city_ego @ R_ego_box``); a timestamp
missing from the poses is interpolated (positions linearly, rotation by spherical linear
interpolation) and noted. Headings are the yaw of the composed rotation.

The ego pose (``city_SE3_egovehicle``) is the origin of the ego-vehicle frame, the rear axle of the
data-collection vehicle; the ``EGO_VEHICLE`` row sits at that origin. The ``Log`` contract is box
centres, so the reader moves the ego :data:`AV2_EGO_CENTER_OFFSET_M` forward along its heading to the
centre of its 4.877 m box and records the offset in ``Log.ego_pose_offset_m``; the writer moves it
back. The scenario-mining ground truth's ``ego_translation_m`` is the pose (rear axle), not the box
centre: it equals ``city_SE3_egovehicle``'s translation at every evaluated timestamp of the shared log
(checked in tests/data/test_av2.py), so exports give ``Log.ego_pose_xy_m()`` there.
"""

from __future__ import annotations

import uuid
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np
import pyarrow as pa
import pyarrow.compute as pc
import pyarrow.feather as feather
from numpy.typing import NDArray

from scenariominer.config import Config
from scenariominer.data.categories import EGO_CATEGORY
from scenariominer.data.log import FloatArray, Log, LogFormatError, build_log
from scenariominer.data.sources import LogSource
from scenariominer.geometry import quaternion_matrix, quaternion_x_axis, to_local, wrap_angle

ANNOTATIONS_WITH_EGO_FILE = "annotations_with_ego.feather"
ANNOTATIONS_FILE = "annotations.feather"
POSES_FILE = "city_SE3_egovehicle.feather"
MAP_FOLDER = "map"
MAP_FILE_GLOB = "log_map_archive_*.json"

#: Size (length, width, height) in metres of the Argoverse 2 ego vehicle's box (a Ford Fusion).
AV2_EGO_SIZE_M: tuple[float, float, float] = (4.877, 2.0, 1.473)

#: Distance in metres from the ego pose (rear axle) forward to the centre of the ego's box.
AV2_EGO_CENTER_OFFSET_M = 1.422

#: Columns every annotation feather must have (``num_interior_pts`` is optional when reading).
ANNOTATION_COLUMNS: tuple[str, ...] = (
    "timestamp_ns",
    "track_uuid",
    "category",
    "length_m",
    "width_m",
    "height_m",
    "qw",
    "qx",
    "qy",
    "qz",
    "tx_m",
    "ty_m",
    "tz_m",
)

#: Columns of the ego-pose feather.
POSE_COLUMNS: tuple[str, ...] = ("timestamp_ns", "qw", "qx", "qy", "qz", "tx_m", "ty_m", "tz_m")

_STRING_COLUMNS = frozenset({"track_uuid", "category"})

#: How many folder levels below a given path discovery looks for log folders
#: (``root/split/log_id`` is 2; a little slack for wrapper folders).
MAX_DISCOVERY_DEPTH = 4

#: Namespace of the track id given to an ego track synthesised from the poses.
_EGO_NAMESPACE = uuid.UUID("5d0a3c52-6a8e-4c0b-9a8f-2f3b8f1e0a01")


# ---------------------------------------------------------------------- discovery


def _annotation_file(log_dir: Path) -> Path | None:
    for name in (ANNOTATIONS_WITH_EGO_FILE, ANNOTATIONS_FILE):
        candidate = log_dir / name
        if candidate.is_file():
            return candidate
    return None


def is_av2_log_dir(path: Path) -> bool:
    """Whether ``path`` is a folder holding an Argoverse 2 annotation feather."""
    return path.is_dir() and _annotation_file(path) is not None


def av2_source(log_dir: Path) -> LogSource:
    """Build the :class:`LogSource` of one log folder: annotations, poses and vector-map JSON files."""
    log_dir = log_dir.resolve()
    annotations = _annotation_file(log_dir)
    files: list[Path] = [] if annotations is None else [annotations]
    files.append(log_dir / POSES_FILE)
    map_dir = log_dir / MAP_FOLDER
    if map_dir.is_dir():
        files.extend(sorted(map_dir.glob(MAP_FILE_GLOB)))
    return LogSource(key=str(log_dir), format=Av2Reader.format, path=log_dir, files=tuple(files))


class Av2Reader:
    """Reads Argoverse 2 sensor-dataset logs (:class:`~scenariominer.data.sources.LogReader`)."""

    format = "av2"

    def discover(self, path: Path) -> list[LogSource]:
        """Log folders at or below ``path`` (a log folder, split folder or dataset root).

        A log folder is one with ``annotations_with_ego.feather`` or ``annotations.feather``;
        folders are searched at most :data:`MAX_DISCOVERY_DEPTH` levels deep. An annotation
        file given directly stands for its folder.
        """
        path = Path(path).expanduser()
        if path.is_file():
            return (
                [av2_source(path.parent)]
                if path.name in (ANNOTATIONS_WITH_EGO_FILE, ANNOTATIONS_FILE)
                else []
            )
        if not path.is_dir():
            return []
        if is_av2_log_dir(path):
            return [av2_source(path)]
        found: set[Path] = set()
        for depth in range(1, MAX_DISCOVERY_DEPTH + 1):
            pattern = "/".join(["*"] * depth)
            for name in (ANNOTATIONS_WITH_EGO_FILE, ANNOTATIONS_FILE):
                found.update(hit.parent for hit in path.glob(f"{pattern}/{name}") if hit.is_file())
        # A log folder nested inside another log folder is not a separate log.
        # Each folder's ancestors are looked up in the set: linear in the number of logs.
        return [av2_source(d) for d in sorted(found) if found.isdisjoint(d.parents)]

    def read(self, source: LogSource, config: Config) -> Iterator[Log]:
        """Yield the one log of an Argoverse 2 log folder (see :func:`read_av2_log`)."""
        yield read_av2_log(source.path, min_track_frames=config.ingest.min_track_frames, source=source)


# ---------------------------------------------------------------------- reading helpers


def _read_table(path: Path, columns: tuple[str, ...]) -> pa.Table:
    """Read a feather file and check that ``columns`` exist with usable types and rows."""
    if not path.is_file():
        raise LogFormatError(path, "missing file")
    try:
        table = feather.read_table(path)
    except (OSError, pa.ArrowException, ValueError) as exc:
        raise LogFormatError(path, f"not a readable Feather file ({exc})") from None
    missing = [c for c in columns if c not in table.column_names]
    if missing:
        raise LogFormatError(path, f"missing column(s) {missing}; expected {list(columns)}")
    for name in columns:
        typ = table.schema.field(name).type
        if name in _STRING_COLUMNS:
            ok = pa.types.is_string(typ) or pa.types.is_large_string(typ) or pa.types.is_dictionary(typ)
            expected = "strings"
        elif name == "timestamp_ns":
            ok = pa.types.is_integer(typ)
            expected = "integer nanoseconds"
        else:
            ok = pa.types.is_integer(typ) or pa.types.is_floating(typ)
            expected = "numbers"
        if not ok:
            raise LogFormatError(path, f"column {name!r} has type {typ}, expected {expected}")
        if table.column(name).null_count:
            raise LogFormatError(
                path, f"column {name!r} has {table.column(name).null_count} missing value(s)"
            )
    if table.num_rows == 0:
        raise LogFormatError(path, "the table has no rows")
    return table


def _floats(table: pa.Table, *names: str) -> FloatArray:
    """``(M, len(names))`` float64 copy of numeric columns (writable, as scipy requires)."""
    return np.stack([np.array(table.column(n).to_numpy(), dtype=np.float64) for n in names], axis=1)


def _strings(table: pa.Table, name: str) -> pa.Array:
    """A text column as one Arrow string array (kept in Arrow: build_log encodes it without copies)."""
    col = table.column(name)
    if pa.types.is_dictionary(col.type):
        col = col.cast(pa.string())  # chunks may hold different dictionaries
    return col.combine_chunks()  # nulls were refused by _read_table


def _is(column: pa.Array, text: str) -> NDArray[np.bool_]:
    """``(M,)`` whether each row of a text column equals ``text``."""
    return np.asarray(pc.equal(column, text).to_numpy(zero_copy_only=False), dtype=bool)


def _check_quaternions(quat: FloatArray, path: Path, timestamps: NDArray[np.int64], what: str) -> None:
    with np.errstate(over="ignore", invalid="ignore"):
        norm = np.linalg.norm(quat, axis=1)  # inf when a component overflows its square
    bad = ~np.all(np.isfinite(quat), axis=1) | ~(norm > 1e-9) | ~np.isfinite(norm)
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        raise LogFormatError(
            path,
            f"{int(bad.sum())} {what} row(s) have a non-finite, zero or overflowing rotation quaternion "
            f"(first at timestamp_ns={int(timestamps[i])}: qw,qx,qy,qz={quat[i].tolist()})",
        )


class _EgoPoses:
    """City-frame ego poses, sorted by time, with look-up (and interpolation) at given timestamps."""

    def __init__(self, path: Path) -> None:
        table = _read_table(path, POSE_COLUMNS)
        t_ns = np.asarray(table.column("timestamp_ns").to_numpy(), dtype=np.int64)
        quat = _floats(table, "qw", "qx", "qy", "qz")
        xyz = _floats(table, "tx_m", "ty_m", "tz_m")
        _check_quaternions(quat, path, t_ns, "pose")
        if not np.all(np.isfinite(xyz)):
            i = int(np.flatnonzero(~np.all(np.isfinite(xyz), axis=1))[0])
            raise LogFormatError(path, f"non-finite pose translation at timestamp_ns={int(t_ns[i])}")
        order = np.argsort(t_ns, kind="stable")
        t_ns, quat, xyz = t_ns[order], quat[order], xyz[order]
        dup = np.flatnonzero(np.diff(t_ns) == 0)
        if dup.size:
            raise LogFormatError(path, f"{dup.size} duplicate pose timestamp(s), e.g. {int(t_ns[dup[0]])}")
        self.path = path
        self.t_ns = t_ns
        self.quat_wxyz = quat / np.linalg.norm(quat, axis=1, keepdims=True)
        self.xyz = xyz

    def at(self, t_ns: NDArray[np.int64]) -> tuple[FloatArray, FloatArray, int]:
        """Poses at ``t_ns`` ``(U,)``.

        Returns:
            Rotations ``(U, 3, 3)``, translations ``(U, 3)``, and how many poses were interpolated.
        """
        lo, hi = int(self.t_ns[0]), int(self.t_ns[-1])
        outside = (t_ns < lo) | (t_ns > hi)
        if outside.any():
            i = int(np.flatnonzero(outside)[0])
            raise LogFormatError(
                self.path,
                f"{int(outside.sum())} annotation timestamp(s) outside the pose range [{lo}, {hi}] "
                f"(e.g. {int(t_ns[i])}); the ego pose cannot be extrapolated",
            )
        pos = np.searchsorted(self.t_ns, t_ns)
        exact = self.t_ns[np.minimum(pos, self.t_ns.size - 1)] == t_ns
        quat = np.empty((t_ns.size, 4))
        xyz = np.empty((t_ns.size, 3))
        quat[exact] = self.quat_wxyz[pos[exact]]
        xyz[exact] = self.xyz[pos[exact]]
        n_interp = int((~exact).sum())
        if n_interp:
            # Relative times keep float64 precision (absolute ns timestamps do not fit a double exactly).
            t0 = self.t_ns[0]
            rel = (self.t_ns - t0).astype(np.float64)
            query = (t_ns[~exact] - t0).astype(np.float64)
            # scipy only here (a pose missing at an annotation time is rare; it costs 0.4 s to import)
            from scipy.spatial.transform import Rotation, Slerp

            rotations = Rotation.from_quat(self.quat_wxyz, scalar_first=True)
            quat[~exact] = Slerp(rel, rotations)(query).as_quat(scalar_first=True)
            for d in range(3):
                xyz[~exact, d] = np.interp(query, rel, self.xyz[:, d])
        return quaternion_matrix(quat), xyz, n_interp


def _checked_map_dir(map_dir: Path) -> tuple[Path | None, str]:
    """``map_dir`` if it holds one vector map that reads, else ``None`` and a note naming the cause.

    The check parses the JSON and its records (:func:`~.map.validate_av2_map`, about 2.5 ms for a
    130 kB map) so that a broken map is found at ingestion, not when a mining program first asks
    for a lane; the log itself is still usable, so it loads without its map.
    """
    if not map_dir.is_dir():
        return None, ""
    from scenariominer.data.adapters.av2.map import validate_av2_map

    try:
        validate_av2_map(map_dir)
    except LogFormatError as exc:
        where = Path(exc.source).name
        return None, f"loaded without its vector map: {where}: {exc.problem}"
    return map_dir, ""


# ---------------------------------------------------------------------- reading


def read_av2_log(
    log_dir: Path,
    *,
    min_track_frames: int = 2,
    source: LogSource | None = None,
) -> Log:
    """Read one Argoverse 2 log folder into a :class:`Log` in the city frame.

    Args:
        log_dir: the log folder (named by its log id).
        min_track_frames: tracks with fewer observations are dropped (noted on the log).
        source: the folder's :class:`LogSource`; built with :func:`av2_source` when omitted.
            Its content hash becomes :attr:`Log.source_hash`.

    Returns:
        The log (``dataset="av2"``, ego at its box centre, ``map_dir`` set when the ``map/``
        folder holds one vector map that reads; a broken or ambiguous map leaves ``map_dir`` unset
        with a note naming the cause).

    Raises:
        LogFormatError: missing files or columns, wrong column types, missing values, non-finite
            or zero quaternions, empty tables, annotation timestamps outside the pose range, or
            any check of :func:`~scenariominer.data.log.build_log`; the message names the file.
    """
    log_dir = Path(log_dir)
    if not log_dir.is_dir():
        raise LogFormatError(log_dir, "not a folder")
    ann_path = _annotation_file(log_dir)
    if ann_path is None:
        raise LogFormatError(
            log_dir / ANNOTATIONS_WITH_EGO_FILE, f"missing file (nor is there an {ANNOTATIONS_FILE})"
        )
    pose_path = log_dir / POSES_FILE
    if not pose_path.is_file():
        raise LogFormatError(
            pose_path, "missing file (the ego poses are needed to place the boxes in the city)"
        )
    source = source or av2_source(log_dir)
    source_hash = source.content_hash()

    table = _read_table(ann_path, ANNOTATION_COLUMNS)
    t_ns = np.asarray(table.column("timestamp_ns").to_numpy(), dtype=np.int64)
    track = _strings(table, "track_uuid")
    category = _strings(table, "category")
    quat = _floats(table, "qw", "qx", "qy", "qz")
    t_ego = _floats(table, "tx_m", "ty_m", "tz_m")
    size = _floats(table, "length_m", "width_m", "height_m")
    _check_quaternions(quat, ann_path, t_ns, "annotation")

    poses = _EgoPoses(pose_path)
    notes: list[str] = []
    is_ego = _is(category, EGO_CATEGORY)
    ego_id: str | None = None
    if not is_ego.any():
        # annotations.feather has no ego rows: synthesise the ego track from the poses.
        ego_id = str(uuid.uuid5(_EGO_NAMESPACE, log_dir.name))
        uniq_t = np.unique(t_ns)
        k = uniq_t.size
        t_ns = np.concatenate([t_ns, uniq_t])
        track = pa.concat_arrays([track.cast(pa.string()), pa.array([ego_id] * k, type=pa.string())])
        category = pa.concat_arrays(
            [category.cast(pa.string()), pa.array([EGO_CATEGORY] * k, type=pa.string())]
        )
        is_ego = np.concatenate([is_ego, np.ones(k, dtype=bool)])
        quat = np.concatenate([quat, np.tile([1.0, 0.0, 0.0, 0.0], (k, 1))])
        t_ego = np.concatenate([t_ego, np.zeros((k, 3))])
        size = np.concatenate([size, np.tile(AV2_EGO_SIZE_M, (k, 1))])
        notes.append(f"ego track synthesised from {POSES_FILE} at {k} annotation timestamp(s)")

    uniq_t, inverse = np.unique(t_ns, return_inverse=True)
    mat_pose, xyz_pose, n_interp = poses.at(uniq_t)
    if n_interp:
        notes.append(
            f"interpolated the ego pose at {n_interp} annotation timestamp(s) missing from {POSES_FILE}"
        )
    # One 3x3 matrix per distinct timestamp, gathered per row; a box's heading is the image of
    # its own x axis (the first column of its rotation).
    mat_rows = mat_pose[inverse]
    xyz_city = np.einsum("nij,nj->ni", mat_rows, t_ego) + xyz_pose[inverse]
    heading = np.einsum("nij,nj->ni", mat_rows, quaternion_x_axis(quat))
    yaw_city = np.arctan2(heading[:, 1], heading[:, 0])
    # The ego's box centre lies AV2_EGO_CENTER_OFFSET_M ahead of the pose (rear axle) along its heading
    # (in the ground plane, so Log.ego_pose_xy_m gives the pose back exactly; z stays the pose's).
    xyz_city[is_ego, 0] += AV2_EGO_CENTER_OFFSET_M * np.cos(yaw_city[is_ego])
    xyz_city[is_ego, 1] += AV2_EGO_CENTER_OFFSET_M * np.sin(yaw_city[is_ego])

    fields: dict[str, Any] = {
        "x_m": xyz_city[:, 0],
        "y_m": xyz_city[:, 1],
        "z_m": xyz_city[:, 2],
        "yaw_rad": yaw_city,
        "length_m": size[:, 0],
        "width_m": size[:, 1],
        "height_m": size[:, 2],
    }
    map_dir, map_note = _checked_map_dir(log_dir / MAP_FOLDER)
    if map_note:
        notes.append(map_note)
    log = build_log(
        log_id=log_dir.name,
        track_id=track,
        category=category,
        timestamp_ns=t_ns,
        fields=fields,
        ego_track_id=ego_id,
        source=ann_path,
        dataset="av2",
        map_dir=map_dir,
        source_hash=source_hash,
        min_track_frames=min_track_frames,
    )
    return log.replace(
        source_path=log_dir, notes=(*notes, *log.notes), ego_pose_offset_m=AV2_EGO_CENTER_OFFSET_M
    )


# ---------------------------------------------------------------------- writing


def estimate_interior_points(
    range_m: FloatArray, length_m: FloatArray, width_m: FloatArray, height_m: FloatArray
) -> NDArray[np.int64]:
    """Rough lidar return count of boxes at ``range_m`` (inverse-square in range, capped at 5000).

    Calibrated on the shared Argoverse 2 log (a car has about 1500 returns at 7 m, 150 at 30 m,
    a dozen at 60 m). All arguments are broadcastable float arrays; returns int64 counts.
    """
    area = (length_m + width_m) * height_m
    r2 = np.maximum(range_m, 1.0) ** 2
    return np.asarray(np.round(np.minimum(5000.0, 7000.0 * area / r2)), dtype=np.int64)


def write_av2_log(log: Log, out_dir: Path) -> Path:
    """Write ``log`` as an Argoverse 2 log folder ``out_dir/<log_id>/`` (inverse of :func:`read_av2_log`).

    Writes ``annotations_with_ego.feather`` (every valid cell, the ego as ``EGO_VEHICLE`` at the
    origin, boxes in the ego frame of their timestamp, ``num_interior_pts`` estimated with
    :func:`estimate_interior_points`) and ``city_SE3_egovehicle.feather`` (the ego track as the
    pose at each annotation timestamp; rotation about the vertical axis only). The log's ego is at
    its box centre (the ``Log`` contract); the written pose is the rear axle,
    :data:`AV2_EGO_CENTER_OFFSET_M` behind it, so :func:`read_av2_log` gives the same centre back.

    Args:
        log: the log; its ego must be valid at every timestamp where any track is.
        out_dir: parent folder (e.g. a split folder); created if needed.

    Returns:
        The log folder.

    Raises:
        ValueError: the ego is missing at a timestamp that has other observations.
    """
    ego = log.ego_index
    ego_valid = log.valid[ego]
    used = log.valid.any(axis=0)
    if np.any(used & ~ego_valid):
        t = int(log.timestamps_ns[np.flatnonzero(used & ~ego_valid)[0]])
        raise ValueError(
            f"log {log.log_id}: the ego is not observed at timestamp_ns={t}; cannot write ego-frame boxes"
        )
    cols = np.flatnonzero(ego_valid)
    # The pose (and the frame of every box) is the rear axle, behind the ego's box centre.
    eyaw = log.yaw_rad[ego]
    ex = log.x_m[ego] - AV2_EGO_CENTER_OFFSET_M * np.cos(eyaw)
    ey = log.y_m[ego] - AV2_EGO_CENTER_OFFSET_M * np.sin(eyaw)
    ez = np.nan_to_num(log.z_m[ego])

    # Cells in AV2 order: by timestamp, the ego first at each timestamp.
    rows, tcols = np.nonzero(log.valid)
    order = np.lexsort((rows != ego, tcols))
    rows, tcols = rows[order], tcols[order]
    tx, ty = to_local(log.x_m[rows, tcols] - ex[tcols], log.y_m[rows, tcols] - ey[tcols], eyaw[tcols])
    tz = np.nan_to_num(log.z_m[rows, tcols]) - ez[tcols]
    rel_yaw = wrap_angle(log.yaw_rad[rows, tcols] - eyaw[tcols])
    is_ego = rows == ego
    tx[is_ego], ty[is_ego], tz[is_ego], rel_yaw[is_ego] = 0.0, 0.0, 0.0, 0.0  # AV2 puts the ego at the origin
    length = log.length_m[rows, tcols]
    width = log.width_m[rows, tcols]
    height = np.nan_to_num(log.height_m[rows, tcols], nan=1.5)
    points = estimate_interior_points(np.hypot(tx, ty), length, width, height)
    points[is_ego] = 1

    annotations = pa.table(
        {
            "timestamp_ns": pa.array(log.timestamps_ns[tcols], type=pa.int64()),
            "track_uuid": pa.array(log.track_ids[rows].astype(str)),
            "category": pa.array(log.categories[rows].astype(str)),
            "length_m": pa.array(length, type=pa.float64()),
            "width_m": pa.array(width, type=pa.float64()),
            "height_m": pa.array(height, type=pa.float64()),
            "qw": pa.array(np.cos(rel_yaw / 2.0), type=pa.float64()),
            "qx": pa.array(np.zeros(rows.size), type=pa.float64()),
            "qy": pa.array(np.zeros(rows.size), type=pa.float64()),
            "qz": pa.array(np.sin(rel_yaw / 2.0), type=pa.float64()),
            "tx_m": pa.array(tx, type=pa.float64()),
            "ty_m": pa.array(ty, type=pa.float64()),
            "tz_m": pa.array(tz, type=pa.float64()),
            "num_interior_pts": pa.array(points, type=pa.int64()),
        }
    )
    poses = pa.table(
        {
            "timestamp_ns": pa.array(log.timestamps_ns[cols], type=pa.int64()),
            "qw": pa.array(np.cos(eyaw[cols] / 2.0), type=pa.float64()),
            "qx": pa.array(np.zeros(cols.size), type=pa.float64()),
            "qy": pa.array(np.zeros(cols.size), type=pa.float64()),
            "qz": pa.array(np.sin(eyaw[cols] / 2.0), type=pa.float64()),
            "tx_m": pa.array(ex[cols], type=pa.float64()),
            "ty_m": pa.array(ey[cols], type=pa.float64()),
            "tz_m": pa.array(ez[cols], type=pa.float64()),
        }
    )
    log_dir = Path(out_dir) / log.log_id
    log_dir.mkdir(parents=True, exist_ok=True)
    feather.write_feather(annotations, log_dir / ANNOTATIONS_WITH_EGO_FILE)
    feather.write_feather(poses, log_dir / POSES_FILE)
    return log_dir
