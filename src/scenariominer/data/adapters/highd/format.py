"""highD file format: column sets, metadata, and reading and validating the three CSV files."""

from __future__ import annotations

import csv
import math
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from enum import IntEnum
from pathlib import Path
from typing import Any

import numpy as np
import pyarrow as pa
import pyarrow.csv as pacsv
from numpy.typing import NDArray

from scenariominer.data.adapters.highd.consistency import (
    META_SPAN_COLUMNS,
    check_frame_rate,
    meta_span_mismatch,
)
from scenariominer.data.categories import UnknownCategoryError, canonical_category
from scenariominer.data.log import MAX_COORDINATE_M, FloatArray, LogFormatError
from scenariominer.data.sources import check_delimiter

IntArray = NDArray[np.int64]

#: Columns of ``NN_tracks.csv`` in the order of the published format.
TRACKS_COLUMNS: tuple[str, ...] = (
    "frame",
    "id",
    "x",
    "y",
    "width",
    "height",
    "xVelocity",
    "yVelocity",
    "xAcceleration",
    "yAcceleration",
    "frontSightDistance",
    "backSightDistance",
    "dhw",
    "thw",
    "ttc",
    "precedingXVelocity",
    "precedingId",
    "followingId",
    "leftPrecedingId",
    "leftAlongsideId",
    "leftFollowingId",
    "rightPrecedingId",
    "rightAlongsideId",
    "rightFollowingId",
    "laneId",
)

#: Columns of ``NN_tracksMeta.csv``.
TRACKS_META_COLUMNS: tuple[str, ...] = (
    "id",
    "width",
    "height",
    "initialFrame",
    "finalFrame",
    "numFrames",
    "class",
    "drivingDirection",
    "traveledDistance",
    "minXVelocity",
    "maxXVelocity",
    "meanXVelocity",
    "minDHW",
    "minTHW",
    "minTTC",
    "numLaneChanges",
)

#: Columns of ``NN_recordingMeta.csv``.
RECORDING_META_COLUMNS: tuple[str, ...] = (
    "id",
    "frameRate",
    "locationId",
    "speedLimit",
    "month",
    "weekDay",
    "startTime",
    "duration",
    "totalDrivenDistance",
    "totalDrivenTime",
    "numVehicles",
    "numCars",
    "numTrucks",
    "upperLaneMarkings",
    "lowerLaneMarkings",
)

# Columns the reader needs; the others are read by nobody and may be absent.
_TRACKS_REQUIRED = ("frame", "id", "x", "y", "width", "height", "xVelocity", "yVelocity")
_TRACKS_OPTIONAL = ("xAcceleration", "yAcceleration", "laneId")
_TRACKS_META_REQUIRED = ("id", "class", "drivingDirection")
_RECORDING_META_REQUIRED = ("id", "frameRate")

#: Default sensor-like range around the ego, metres: other vehicles appear in a window's log while
#: their box centre is within this distance of the ego's (Argoverse 2 annotates to about 150 m).
DEFAULT_RADIUS_M = 150.0

#: highD gives no vehicle heights; these typical values fill ``height_m`` (metres).
ASSUMED_HEIGHT_M: Mapping[str, float] = {"REGULAR_VEHICLE": 1.6, "TRUCK": 3.8}
_FALLBACK_HEIGHT_M = 1.6

#: Below this speed the heading is taken from the driving direction, not the (noisy) velocity.
STOPPED_SPEED_MPS = 0.5

_NAME_RE = re.compile(r"^(\d+)_(tracks|tracksMeta|recordingMeta)\.csv$")
_NS_PER_S = 1_000_000_000


class HighDDirection(IntEnum):
    """highD ``drivingDirection`` codes."""

    #: Driving towards -x (the upper carriageway in the image); canonical yaw pi.
    LEFT = 1
    #: Driving towards +x (the lower carriageway in the image); canonical yaw 0.
    RIGHT = 2


# ---------------------------------------------------------------------------------------- files


@dataclass(frozen=True)
class HighDFiles:
    """The three files of one highD recording.

    Attributes:
        recording_id: the ``NN`` prefix of the file names.
        tracks: ``NN_tracks.csv``.
        tracks_meta: ``NN_tracksMeta.csv``.
        recording_meta: ``NN_recordingMeta.csv``.
    """

    recording_id: int
    tracks: Path
    tracks_meta: Path
    recording_meta: Path

    @property
    def all(self) -> tuple[Path, Path, Path]:
        """The three paths (tracks, tracks meta, recording meta)."""
        return (self.tracks, self.tracks_meta, self.recording_meta)

    @classmethod
    def for_recording(cls, folder: Path, recording_id: int) -> HighDFiles:
        """Paths of recording ``recording_id`` in ``folder`` (the files need not exist)."""
        stem = f"{recording_id:02d}"
        return cls(
            recording_id=recording_id,
            tracks=folder / f"{stem}_tracks.csv",
            tracks_meta=folder / f"{stem}_tracksMeta.csv",
            recording_meta=folder / f"{stem}_recordingMeta.csv",
        )

    @classmethod
    def from_path(cls, path: Path) -> HighDFiles | None:
        """Return the recording a highD-named file belongs to (``None`` if the name is not highD's).

        Raises:
            LogFormatError: the recording's tracks file or one of its meta files is missing.
        """
        match = _NAME_RE.match(path.name)
        if match is None:
            return None
        prefix = match.group(1)
        folder = path.parent
        files = cls(
            recording_id=int(prefix),
            tracks=folder / f"{prefix}_tracks.csv",
            tracks_meta=folder / f"{prefix}_tracksMeta.csv",
            recording_meta=folder / f"{prefix}_recordingMeta.csv",
        )
        for f in files.all:
            if not f.is_file():
                what = "not a regular file" if f.exists() else "missing"
                raise LogFormatError(
                    f, f"highD recording {prefix} is incomplete: {f.name} is {what} next to {path.name}"
                )
        return files


# ---------------------------------------------------------------------------------------- recording


@dataclass(frozen=True)
class HighDRecordingMeta:
    """The fields of ``NN_recordingMeta.csv`` the adapter uses.

    Attributes:
        recording_id: the recording's ``id``.
        frame_rate_hz: frames per second (25 in the published data).
        location_id: highD location (1 to 6), 0 when absent.
        speed_limit_mps: posted limit in metres per second; ``None`` when unlimited (highD ``-1``).
        upper_lane_markings_m: image-y of the upper carriageway's lane markings, metres, top to
            bottom; the canonical y of a marking is its negative.
        lower_lane_markings_m: image-y of the lower carriageway's lane markings, metres.
        duration_s: length of the recording in seconds, ``None`` when absent.
    """

    recording_id: int
    frame_rate_hz: float
    location_id: int = 0
    speed_limit_mps: float | None = None
    upper_lane_markings_m: tuple[float, ...] = ()
    lower_lane_markings_m: tuple[float, ...] = ()
    duration_s: float | None = None


@dataclass(frozen=True, eq=False)
class HighDRecording:
    """A whole highD recording in the canonical frame, as columns over ``M`` rows.

    Rows are sorted by (vehicle, frame); vehicle ``v``'s rows are
    ``track_start[v] : track_start[v] + track_count[v]``.

    Attributes:
        files: the three source files.
        meta: recording meta data.
        vehicle_ids: ``(V,)`` int64 highD ids, ascending.
        vehicle_categories: ``(V,)`` str, Argoverse 2 category of each vehicle.
        driving_direction: ``(V,)`` int64, :class:`HighDDirection` codes.
        track_start: ``(V,)`` int64 first row of each vehicle.
        track_count: ``(V,)`` int64 number of rows of each vehicle.
        row_vehicle: ``(M,)`` int64 index into ``vehicle_ids`` per row.
        frame: ``(M,)`` int64 highD frame number.
        t_ns: ``(M,)`` int64 ``frame / frame_rate`` in nanoseconds.
        x_m, y_m: ``(M,)`` box centre, canonical frame (y = -image y), metres.
        yaw_rad: ``(M,)`` heading, radians counter-clockwise from +x.
        length_m, width_m, height_m: ``(M,)`` box size, metres.
        vx_mps, vy_mps: ``(M,)`` velocity, canonical frame.
        ax_mps2, ay_mps2: ``(M,)`` acceleration, canonical frame (NaN when the file has none).
        lane_id: ``(M,)`` int64 highD ``laneId`` (-1 when the file has none).
        frame_order: ``(M,)`` int64 row indices sorted by frame (for window slicing).
        frame_sorted: ``(M,)`` int64 ``frame[frame_order]``.
        notes: repairs applied while reading (e.g. sorted rows).
    """

    files: HighDFiles
    meta: HighDRecordingMeta
    vehicle_ids: IntArray
    vehicle_categories: NDArray[np.str_]
    driving_direction: IntArray
    track_start: IntArray
    track_count: IntArray
    row_vehicle: IntArray
    frame: IntArray
    t_ns: IntArray
    x_m: FloatArray
    y_m: FloatArray
    yaw_rad: FloatArray
    length_m: FloatArray
    width_m: FloatArray
    height_m: FloatArray
    vx_mps: FloatArray
    vy_mps: FloatArray
    ax_mps2: FloatArray
    ay_mps2: FloatArray
    lane_id: IntArray
    frame_order: IntArray
    frame_sorted: IntArray
    notes: tuple[str, ...] = field(default_factory=tuple)

    @property
    def n_vehicles(self) -> int:
        """Number of vehicles ``V``."""
        return int(self.vehicle_ids.shape[0])

    @property
    def n_rows(self) -> int:
        """Number of (vehicle, frame) rows ``M``."""
        return int(self.frame.shape[0])

    def vehicle_index(self, vehicle_id: int) -> int:
        """Index of ``vehicle_id`` in :attr:`vehicle_ids`; ``KeyError`` when absent."""
        pos = int(np.searchsorted(self.vehicle_ids, vehicle_id))
        if pos >= self.n_vehicles or int(self.vehicle_ids[pos]) != vehicle_id:
            raise KeyError(f"vehicle {vehicle_id} is not in highD recording {self.files.recording_id:02d}")
        return pos

    def vehicle_rows(self, vehicle_id: int) -> slice:
        """Row slice of ``vehicle_id`` (rows sorted by frame)."""
        v = self.vehicle_index(vehicle_id)
        start = int(self.track_start[v])
        return slice(start, start + int(self.track_count[v]))


def _read_header(path: Path) -> list[str]:
    try:
        with path.open(encoding="utf-8-sig", newline="") as fh:
            line = fh.readline()
    except OSError as exc:
        raise LogFormatError(path, f"cannot read file ({exc.strerror or exc})") from None
    except UnicodeDecodeError:
        raise LogFormatError(path, "not a text CSV file (cannot decode as UTF-8)") from None
    if not line.strip():
        raise LogFormatError(path, "empty file: expected a CSV header line")
    check_delimiter(path, line)
    return [c.strip().strip('"') for c in line.strip().split(",")]


def _read_columns(
    path: Path,
    required: Sequence[str],
    optional: Sequence[str],
    expected: Sequence[str],
    types: Mapping[str, Any],
) -> dict[str, NDArray[Any]]:
    """Read ``required`` (error when absent) and ``optional`` columns of a CSV with pyarrow."""
    header = _read_header(path)
    missing = [c for c in required if c not in header]
    if missing:
        raise LogFormatError(
            path,
            f"missing column(s) {missing}; a highD {path.name.split('_', 1)[-1]} file has {list(expected)}",
        )
    include = [c for c in (*required, *optional) if c in header]
    try:
        table = pacsv.read_csv(
            path,
            convert_options=pacsv.ConvertOptions(
                include_columns=include, column_types={c: types[c] for c in include if c in types}
            ),
        )
    except (pa.ArrowInvalid, OSError) as exc:
        raise LogFormatError(path, f"cannot parse CSV ({exc})") from None
    if table.num_rows == 0:
        raise LogFormatError(path, "the file has a header but no rows")
    out: dict[str, NDArray[Any]] = {}
    for name in include:
        col = table.column(name)
        if col.null_count and pa.types.is_integer(col.type):
            raise LogFormatError(path, f"column {name!r} has {col.null_count} empty value(s)")
        out[name] = col.to_numpy(zero_copy_only=False)
    return out


def _parse_markings(text: str, path: Path, column: str) -> tuple[float, ...]:
    text = text.strip()
    if not text:
        return ()
    try:
        values = tuple(float(v) for v in text.split(";") if v.strip())
    except ValueError:
        raise LogFormatError(
            path, f"column {column!r} is not a ';'-separated list of numbers: {text!r}"
        ) from None
    if not all(math.isfinite(v) and abs(v) <= MAX_COORDINATE_M for v in values):
        raise LogFormatError(path, f"column {column!r} has a non-finite or out-of-range marking: {text!r}")
    return values


def read_recording_meta(path: Path) -> HighDRecordingMeta:
    """Parse ``NN_recordingMeta.csv``.

    Raises:
        LogFormatError: missing file, missing ``id``/``frameRate`` columns, or bad values.
    """
    try:
        with path.open(encoding="utf-8-sig", newline="") as fh:
            rows = list(csv.DictReader(fh))
    except OSError as exc:
        raise LogFormatError(path, f"cannot read file ({exc.strerror or exc})") from None
    if not rows:
        raise LogFormatError(path, "no data row: expected one row describing the recording")
    row = {k.strip(): (v or "").strip() for k, v in rows[0].items() if k is not None}
    missing = [c for c in _RECORDING_META_REQUIRED if c not in row]
    if missing:
        raise LogFormatError(
            path,
            f"missing column(s) {missing}; a highD recordingMeta file has {list(RECORDING_META_COLUMNS)}",
        )

    def number(name: str, default: float) -> float:
        raw = row.get(name, "")
        if raw == "":
            return default
        try:
            return float(raw)
        except ValueError:
            raise LogFormatError(path, f"column {name!r} is not a number: {raw!r}") from None

    def integer(name: str) -> int:
        value = number(name, 0.0)
        if not (math.isfinite(value) and value == int(value) and abs(value) < 2**63):
            raise LogFormatError(path, f"column {name!r} is not an integer: {row[name]!r}")
        return int(value)

    frame_rate = number("frameRate", float("nan"))
    if not np.isfinite(frame_rate) or frame_rate <= 0:
        raise LogFormatError(path, f"frameRate must be a positive number, got {row['frameRate']!r}")
    speed_limit = number("speedLimit", -1.0)
    if not math.isfinite(speed_limit):
        raise LogFormatError(path, f"speedLimit must be a number (-1: none), got {row['speedLimit']!r}")
    duration = number("duration", float("nan"))
    return HighDRecordingMeta(
        recording_id=integer("id"),
        frame_rate_hz=frame_rate,
        location_id=integer("locationId"),
        speed_limit_mps=None if speed_limit < 0 else speed_limit,
        upper_lane_markings_m=_parse_markings(row.get("upperLaneMarkings", ""), path, "upperLaneMarkings"),
        lower_lane_markings_m=_parse_markings(row.get("lowerLaneMarkings", ""), path, "lowerLaneMarkings"),
        duration_s=duration if np.isfinite(duration) else None,
    )


def _vehicles(vid: IntArray) -> tuple[IntArray, IntArray, IntArray, IntArray]:
    """Per-vehicle structure of rows sorted by id: first row, ids, row counts, vehicle of each row."""
    first = np.concatenate([[True], vid[1:] != vid[:-1]])
    track_start = np.flatnonzero(first).astype(np.int64)
    track_count = np.diff(np.append(track_start, vid.size)).astype(np.int64)
    return track_start, vid[track_start], track_count, (np.cumsum(first) - 1).astype(np.int64)


def read_highd_recording(files: HighDFiles) -> HighDRecording:
    """Read and validate one highD recording, converted to the canonical frame.

    Repairs (each adds a note): rows not sorted by (id, frame) are sorted; exact duplicate
    (id, frame) rows are collapsed; tracksMeta vehicles without rows are ignored; vehicles whose rows
    disagree with their tracksMeta ``initialFrame``/``finalFrame``/``numFrames`` are dropped.

    Raises:
        LogFormatError: naming the file, for missing columns, empty or non-numeric values,
            non-finite positions/sizes/velocities, conflicting duplicate (id, frame) rows, vehicle
            ids absent from the tracks meta file, a tracksMeta whose spans disagree for every
            vehicle, a ``frameRate`` or ``duration`` the tracks contradict
            (:mod:`~.consistency`), unknown classes or driving directions.
    """
    meta = read_recording_meta(files.recording_meta)
    tm = _read_columns(
        files.tracks_meta,
        _TRACKS_META_REQUIRED,
        META_SPAN_COLUMNS,
        TRACKS_META_COLUMNS,
        {
            "id": pa.int64(),
            "class": pa.string(),
            "drivingDirection": pa.int64(),
            **{c: pa.int64() for c in META_SPAN_COLUMNS},
        },
    )
    float_types = {c: pa.float64() for c in TRACKS_COLUMNS}
    float_types.update(frame=pa.int64(), id=pa.int64(), laneId=pa.int64())
    tr = _read_columns(files.tracks, _TRACKS_REQUIRED, _TRACKS_OPTIONAL, TRACKS_COLUMNS, float_types)
    path = files.tracks
    notes: list[str] = []

    vid = tr["id"].astype(np.int64)
    frame = tr["frame"].astype(np.int64)
    numeric = {c: tr[c].astype(np.float64) for c in _TRACKS_REQUIRED[2:]}
    for name in ("xAcceleration", "yAcceleration"):
        if name in tr:
            numeric[name] = tr[name].astype(np.float64)
    for name, values in numeric.items():
        bad = ~np.isfinite(values)
        if bad.any() and not name.endswith("Acceleration"):
            i = int(np.flatnonzero(bad)[0])
            raise LogFormatError(
                path,
                f"column {name!r} has {int(bad.sum())} missing/non-finite value(s) "
                f"(first at id {int(vid[i])}, frame {int(frame[i])})",
            )
    lane = tr["laneId"].astype(np.int64) if "laneId" in tr else np.full(vid.shape, -1, dtype=np.int64)

    # Sort by (id, frame); duplicates.
    in_order = bool(np.all((vid[1:] > vid[:-1]) | ((vid[1:] == vid[:-1]) & (frame[1:] > frame[:-1]))))
    if not in_order:
        order = np.lexsort((frame, vid))
        vid, frame, lane = vid[order], frame[order], lane[order]
        numeric = {k: v[order] for k, v in numeric.items()}
        dup = (vid[1:] == vid[:-1]) & (frame[1:] == frame[:-1])
        if dup.any():
            stacked = np.stack([np.nan_to_num(v, nan=np.inf) for v in numeric.values()], axis=1)
            conflicting = dup & (np.any(stacked[1:] != stacked[:-1], axis=1) | (lane[1:] != lane[:-1]))
            if conflicting.any():
                i = int(np.flatnonzero(conflicting)[0])
                raise LogFormatError(
                    path,
                    f"{int(conflicting.sum())} duplicate (id, frame) row(s) with different values, "
                    f"e.g. id {int(vid[i])} at frame {int(frame[i])}",
                )
            keep = np.concatenate([[True], ~dup])
            vid, frame, lane = vid[keep], frame[keep], lane[keep]
            numeric = {k: v[keep] for k, v in numeric.items()}
            notes.append(f"{path.name}: collapsed {int(dup.sum())} exact duplicate (id, frame) row(s)")
        else:
            notes.append(f"{path.name}: rows were not sorted by (id, frame); sorted them")

    check_frame_rate(
        meta.frame_rate_hz,
        meta.duration_s,
        vid,
        frame,
        numeric["x"],
        numeric["xVelocity"],
        files.recording_meta,
    )

    # Vehicles and their meta data.
    track_start, vehicle_ids, track_count, row_vehicle = _vehicles(vid)
    meta_ids = tm["id"].astype(np.int64)
    meta_sorted = np.argsort(meta_ids, kind="stable")
    ms_ids = meta_ids[meta_sorted]
    if ms_ids.size > 1 and np.any(ms_ids[1:] == ms_ids[:-1]):
        dups = np.unique(ms_ids[1:][ms_ids[1:] == ms_ids[:-1]])
        raise LogFormatError(
            files.tracks_meta, f"vehicle id(s) {dups[:5].tolist()} are listed more than once"
        )
    pos = np.clip(np.searchsorted(ms_ids, vehicle_ids), 0, ms_ids.size - 1)
    absent = ms_ids[pos] != vehicle_ids
    if absent.any():
        raise LogFormatError(
            path,
            f"{int(absent.sum())} vehicle id(s) of the tracks are not listed in {files.tracks_meta.name}, "
            f"e.g. {vehicle_ids[absent][:5].tolist()}",
        )
    meta_row = meta_sorted[pos]
    unused = np.isin(ms_ids, vehicle_ids, invert=True)
    if unused.any():
        notes.append(
            f"{files.tracks_meta.name}: ignored {int(unused.sum())} vehicle(s) with no rows in {path.name} "
            f"(e.g. {ms_ids[unused][:5].tolist()})"
        )
    spans = {c: tm[c].astype(np.int64)[meta_row] for c in META_SPAN_COLUMNS if c in tm}
    last_frame = frame[track_start + track_count - 1]
    bad_span, example = meta_span_mismatch(frame[track_start], last_frame, track_count, spans)
    if bad_span.all():
        raise LogFormatError(
            files.tracks_meta,
            f"does not describe {path.name}: the frame span of every vehicle disagrees "
            f"(e.g. vehicle {int(vehicle_ids[0])}: {example})",
        )
    if bad_span.any():
        i = int(np.flatnonzero(bad_span)[0])
        notes.append(
            f"dropped {int(bad_span.sum())} vehicle(s) whose rows in {path.name} disagree with "
            f"{files.tracks_meta.name} (e.g. vehicle {int(vehicle_ids[i])}: {example})"
        )
        keep = ~bad_span[row_vehicle]
        vid, frame, lane = vid[keep], frame[keep], lane[keep]
        numeric = {k: v[keep] for k, v in numeric.items()}
        meta_row = meta_row[~bad_span]
        track_start, vehicle_ids, track_count, row_vehicle = _vehicles(vid)
    classes = tm["class"].astype(str)[meta_row]
    uniq, inverse = np.unique(classes, return_inverse=True)
    mapped: list[str] = []
    for name in uniq:
        try:
            mapped.append(canonical_category(str(name)))
        except UnknownCategoryError as exc:
            raise LogFormatError(files.tracks_meta, f"column 'class': {exc}") from None
    vehicle_categories = np.asarray(mapped, dtype=object)[inverse].astype(str)
    direction = tm["drivingDirection"].astype(np.int64)[meta_row]
    bad_dir = (direction != HighDDirection.LEFT) & (direction != HighDDirection.RIGHT)
    if bad_dir.any():
        i = int(np.flatnonzero(bad_dir)[0])
        raise LogFormatError(
            files.tracks_meta,
            f"drivingDirection must be 1 (left) or 2 (right), got {int(direction[i])} for vehicle "
            f"{int(vehicle_ids[i])}",
        )

    # Canonical frame.
    length = numeric["width"]
    width = numeric["height"]
    x_m = numeric["x"] + 0.5 * length
    y_m = -(numeric["y"] + 0.5 * width)
    vx = numeric["xVelocity"]
    vy = -numeric["yVelocity"] + 0.0  # "+ 0.0" turns -0.0 into 0.0, so atan2 gives pi, not -pi
    ax = numeric.get("xAcceleration", np.full(vx.shape, np.nan))
    ay = -numeric.get("yAcceleration", np.full(vx.shape, np.nan))
    row_dir = direction[row_vehicle]
    sign = np.where(row_dir == HighDDirection.RIGHT, 1.0, -1.0)
    moving = (np.hypot(vx, vy) >= STOPPED_SPEED_MPS) & (vx * sign > 0)
    yaw = np.where(moving, np.arctan2(vy, vx), np.where(sign > 0, 0.0, np.pi))
    height_per_vehicle = np.array(
        [ASSUMED_HEIGHT_M.get(str(c), _FALLBACK_HEIGHT_M) for c in vehicle_categories]
    )
    t_ns = np.rint(frame.astype(np.float64) * (_NS_PER_S / meta.frame_rate_hz)).astype(np.int64)
    frame_order = np.argsort(frame, kind="stable").astype(np.int64)

    return HighDRecording(
        files=files,
        meta=meta,
        vehicle_ids=vehicle_ids,
        vehicle_categories=vehicle_categories,
        driving_direction=direction,
        track_start=track_start,
        track_count=track_count,
        row_vehicle=row_vehicle,
        frame=frame,
        t_ns=t_ns,
        x_m=x_m,
        y_m=y_m,
        yaw_rad=yaw,
        length_m=length,
        width_m=width,
        height_m=height_per_vehicle[row_vehicle],
        vx_mps=vx,
        vy_mps=vy,
        ax_mps2=ax,
        ay_mps2=ay,
        lane_id=lane,
        frame_order=frame_order,
        frame_sorted=frame[frame_order],
        notes=tuple(notes),
    )
