"""highD adapter: drone recordings of German highways cut into ego-centred logs, and a writer.

A highD recording ``NN`` is three CSV files (see ``docs/highd.md``):

* ``NN_tracks.csv``: one row per (vehicle, frame): ``frame, id, x, y, width, height, xVelocity,
  yVelocity, xAcceleration, yAcceleration, frontSightDistance, backSightDistance, dhw, thw, ttc,
  precedingXVelocity, precedingId, followingId, leftPrecedingId, leftAlongsideId, leftFollowingId,
  rightPrecedingId, rightAlongsideId, rightFollowingId, laneId``;
* ``NN_tracksMeta.csv``: one row per vehicle (``class`` Car/Truck, ``drivingDirection`` 1 = towards
  -x ("left"), 2 = towards +x ("right"), frame span and summary statistics);
* ``NN_recordingMeta.csv``: one row (``frameRate``, location, speed limit, lane markings).

Coordinate conversion. highD positions are image-aligned: ``x`` grows to the right along the road,
``y`` grows *downwards*, and ``(x, y)`` is the **upper-left corner** of the axis-aligned box whose
extent along x is the column ``width`` (the vehicle's length) and along y the column ``height``
(the vehicle's width). The canonical frame of this package is right-handed with yaw
counter-clockwise, so the adapter uses

* ``x_m = x + width / 2`` and ``y_m = -(y + height / 2)`` (box centre, y flipped),
* ``length_m = width``, ``width_m = height``, ``vx_mps = xVelocity``, ``vy_mps = -yVelocity``,
  ``ax_mps2 = xAcceleration``, ``ay_mps2 = -yAcceleration``,
* ``yaw_rad = atan2(vy_mps, vx_mps)``; when the vehicle is (nearly) stopped or its velocity points
  against its driving direction, the yaw of the driving direction (0 for direction 2, pi for 1),
* ``height_m``: highD has no heights; :data:`ASSUMED_HEIGHT_M` per class,
* time ``t_ns = frame / frameRate`` in nanoseconds.

Windowing. Any vehicle can be the ego. Each chosen ego's visible span is cut into consecutive full
windows of ``config.ingest.highd_window_s`` (a remainder shorter than a window is not used); each
(ego, window) is one :class:`~scenariominer.data.log.Log` named
``highd-<recording:02d>-ego<id>-w<k>`` with the ego at row 0 and every vehicle observed within
``radius_m`` of the ego (like a sensor range; a vehicle appears while it is within range).
"""

from __future__ import annotations

import csv
import re
from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from enum import IntEnum
from pathlib import Path
from typing import Any

import numpy as np
import pyarrow as pa
import pyarrow.csv as pacsv
from numpy.typing import NDArray

from scenariominer.config import Config
from scenariominer.data.categories import UnknownCategoryError, canonical_category
from scenariominer.data.log import FloatArray, Log, LogFormatError, build_log
from scenariominer.data.sources import LogSource

__all__ = [
    "ASSUMED_HEIGHT_M",
    "DEFAULT_RADIUS_M",
    "RECORDING_META_COLUMNS",
    "TRACKS_COLUMNS",
    "TRACKS_META_COLUMNS",
    "HighDDirection",
    "HighDFiles",
    "HighDReader",
    "HighDRecording",
    "HighDRecordingMeta",
    "HighDVehicle",
    "HighDWindow",
    "plan_windows",
    "read_highd_recording",
    "window_log",
    "write_highd_recording",
]

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
                raise LogFormatError(
                    f, f"highD recording {prefix} is incomplete: {f.name} is missing next to {path.name}"
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
    """

    recording_id: int
    frame_rate_hz: float
    location_id: int = 0
    speed_limit_mps: float | None = None
    upper_lane_markings_m: tuple[float, ...] = ()
    lower_lane_markings_m: tuple[float, ...] = ()


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
        return tuple(float(v) for v in text.split(";") if v.strip())
    except ValueError:
        raise LogFormatError(
            path, f"column {column!r} is not a ';'-separated list of numbers: {text!r}"
        ) from None


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

    frame_rate = number("frameRate", float("nan"))
    if not np.isfinite(frame_rate) or frame_rate <= 0:
        raise LogFormatError(path, f"frameRate must be a positive number, got {row['frameRate']!r}")
    speed_limit = number("speedLimit", -1.0)
    return HighDRecordingMeta(
        recording_id=int(number("id", 0)),
        frame_rate_hz=frame_rate,
        location_id=int(number("locationId", 0)),
        speed_limit_mps=None if speed_limit < 0 else speed_limit,
        upper_lane_markings_m=_parse_markings(row.get("upperLaneMarkings", ""), path, "upperLaneMarkings"),
        lower_lane_markings_m=_parse_markings(row.get("lowerLaneMarkings", ""), path, "lowerLaneMarkings"),
    )


def read_highd_recording(files: HighDFiles) -> HighDRecording:
    """Read and validate one highD recording, converted to the canonical frame.

    Repairs (each adds a note): rows not sorted by (id, frame) are sorted; exact duplicate
    (id, frame) rows are collapsed.

    Raises:
        LogFormatError: naming the file, for missing columns, empty or non-numeric values,
            non-finite positions/sizes/velocities, conflicting duplicate (id, frame) rows, vehicle
            ids absent from the tracks meta file, unknown classes or driving directions.
    """
    meta = read_recording_meta(files.recording_meta)
    tm = _read_columns(
        files.tracks_meta,
        _TRACKS_META_REQUIRED,
        (),
        TRACKS_META_COLUMNS,
        {"id": pa.int64(), "class": pa.string(), "drivingDirection": pa.int64()},
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

    # Vehicles and their meta data.
    first = np.concatenate([[True], vid[1:] != vid[:-1]])
    track_start = np.flatnonzero(first).astype(np.int64)
    vehicle_ids = vid[track_start]
    track_count = np.diff(np.append(track_start, vid.size)).astype(np.int64)
    row_vehicle = (np.cumsum(first) - 1).astype(np.int64)

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


# ---------------------------------------------------------------------------------------- windows


@dataclass(frozen=True)
class HighDWindow:
    """One (ego, window) cut of a recording.

    Attributes:
        ego_id: highD id of the ego vehicle.
        index: window number ``k`` within the ego's span (0-based).
        first_frame: first highD frame of the window (inclusive).
        stop_frame: frame after the last one (exclusive).
    """

    ego_id: int
    index: int
    first_frame: int
    stop_frame: int

    def log_id(self, recording_id: int) -> str:
        """Return the log id ``highd-<recording:02d>-ego<id>-w<k>``."""
        return f"highd-{recording_id:02d}-ego{self.ego_id}-w{self.index}"


def plan_windows(
    recording: HighDRecording,
    window_s: float,
    ego_ids: Sequence[int] = (),
    max_egos: int = 0,
) -> list[HighDWindow]:
    """Choose egos and cut each one's visible span into full windows of ``window_s``.

    Args:
        recording: the recording.
        window_s: window length in seconds (``round(window_s * frameRate)`` frames).
        ego_ids: explicit egos; ids absent from the recording or visible for less than one window
            are skipped (so one id list can serve many recordings). Empty: every vehicle visible for
            at least one window, thinned to ``max_egos`` evenly spread over the ascending ids
            (highD ids grow with entry time, so the choice spreads over the recording).
        max_egos: cap on automatically chosen egos; 0 means no cap.

    Returns:
        Windows ordered by ego id, then window index.

    Raises:
        ValueError: ``window_s`` is not positive.
    """
    if not window_s > 0:
        raise ValueError(f"highd_window_s must be positive, got {window_s}")
    n_win_frames = max(2, round(window_s * recording.meta.frame_rate_hz))
    first = recording.frame[recording.track_start]
    last = recording.frame[recording.track_start + recording.track_count - 1]
    span = last - first + 1
    eligible = span >= n_win_frames
    if ego_ids:
        wanted = np.isin(recording.vehicle_ids, np.asarray(list(ego_ids), dtype=np.int64))
        chosen = np.flatnonzero(wanted & eligible)
    else:
        chosen = np.flatnonzero(eligible)
        if max_egos > 0 and chosen.size > max_egos:
            picks = np.unique(np.round(np.linspace(0, chosen.size - 1, max_egos)).astype(np.int64))
            chosen = chosen[picks]
    windows: list[HighDWindow] = []
    for v in chosen.tolist():
        start = int(first[v])
        for k in range(int(span[v]) // n_win_frames):
            f0 = start + k * n_win_frames
            windows.append(HighDWindow(int(recording.vehicle_ids[v]), k, f0, f0 + n_win_frames))
    return windows


def window_log(
    recording: HighDRecording,
    window: HighDWindow,
    *,
    radius_m: float | None = DEFAULT_RADIUS_M,
    source_hash: str = "",
    min_track_frames: int = 2,
) -> Log:
    """Build the :class:`Log` of one (ego, window).

    The ego is row 0 (category ``EGO_VEHICLE``); another vehicle's cell is kept when the ego is
    observed at that frame and the two box centres are at most ``radius_m`` apart (``None``: no
    limit). Vectorised: one slice of the frame-sorted rows and a distance mask.
    """
    rec = recording
    lo, hi = np.searchsorted(rec.frame_sorted, [window.first_frame, window.stop_frame])
    rows = rec.frame_order[lo:hi]
    ego_rows = rec.vehicle_rows(window.ego_id)
    ego_frames = rec.frame[ego_rows]
    idx = np.clip(np.searchsorted(ego_frames, rec.frame[rows]), 0, ego_frames.size - 1)
    keep = ego_frames[idx] == rec.frame[rows]
    if radius_m is not None:
        dist = np.hypot(rec.x_m[rows] - rec.x_m[ego_rows][idx], rec.y_m[rows] - rec.y_m[ego_rows][idx])
        keep &= dist <= radius_m
    rows = rows[keep]
    veh = rec.row_vehicle[rows]
    fields = {
        "x_m": rec.x_m[rows],
        "y_m": rec.y_m[rows],
        "z_m": np.zeros(rows.size),
        "yaw_rad": rec.yaw_rad[rows],
        "length_m": rec.length_m[rows],
        "width_m": rec.width_m[rows],
        "height_m": rec.height_m[rows],
        "vx_mps": rec.vx_mps[rows],
        "vy_mps": rec.vy_mps[rows],
        "ax_mps2": rec.ax_mps2[rows],
        "ay_mps2": rec.ay_mps2[rows],
    }
    log = build_log(
        log_id=window.log_id(rec.files.recording_id),
        track_id=rec.vehicle_ids.astype(str)[veh],
        category=rec.vehicle_categories[veh],
        timestamp_ns=rec.t_ns[rows],
        fields=fields,
        ego_track_id=str(window.ego_id),
        source=rec.files.tracks,
        dataset="highd",
        source_hash=source_hash,
        min_track_frames=min_track_frames,
    )
    return log.replace(notes=rec.notes + log.notes) if rec.notes else log


# ---------------------------------------------------------------------------------------- reader


#: Sentinel for :class:`HighDReader`: take the radius from ``config.ingest.highd_radius_m``.
RADIUS_FROM_CONFIG = -1.0


class HighDReader:
    """Reads highD recordings (``NN_tracks.csv`` + meta files) as ego-centred windowed logs.

    Args:
        radius_m: other vehicles appear in a log while within this distance of the ego (metres);
            ``None`` keeps every vehicle of the window; the default (:data:`RADIUS_FROM_CONFIG`)
            uses ``config.ingest.highd_radius_m`` at read time.
    """

    format = "highd"

    def __init__(self, radius_m: float | None = RADIUS_FROM_CONFIG) -> None:
        self.radius_m = radius_m

    def discover(self, path: Path) -> list[LogSource]:
        """Find recordings at ``path``: one highD file, or a folder (or its ``data/`` subfolder) of them.

        Raises:
            LogFormatError: a tracks file lacks one of its meta files (naming the missing file).
        """
        if path.is_file():
            found = HighDFiles.from_path(path)
            return [] if found is None else [self._source(found)]
        if not path.is_dir():
            return []
        sources: list[LogSource] = []
        for folder in (path, path / "data"):
            if not folder.is_dir():
                continue
            for tracks in sorted(folder.glob("*_tracks.csv")):
                found = HighDFiles.from_path(tracks)
                if found is not None:
                    sources.append(self._source(found))
        return sources

    def _source(self, files: HighDFiles) -> LogSource:
        tracks = files.tracks.resolve()
        return LogSource(
            key=str(tracks),
            format=self.format,
            path=tracks,
            files=tuple(f.resolve() for f in files.all),
        )

    def read(self, source: LogSource, config: Config) -> Iterator[Log]:
        """Yield one log per (ego, window) of the recording, ordered by ego id then window."""
        files = HighDFiles.from_path(source.path)
        if files is None:
            raise LogFormatError(source.path, "not a highD file name (expected NN_tracks.csv)")
        recording = read_highd_recording(files)
        ingest = config.ingest
        windows = plan_windows(
            recording, ingest.highd_window_s, ingest.highd_ego_ids, ingest.highd_max_egos_per_recording
        )
        source_hash = source.content_hash() if windows else ""
        for window in windows:
            yield window_log(
                recording,
                window,
                radius_m=ingest.highd_radius_m if self.radius_m == RADIUS_FROM_CONFIG else self.radius_m,
                source_hash=source_hash,
                min_track_frames=ingest.min_track_frames,
            )


# ---------------------------------------------------------------------------------------- writer


@dataclass(frozen=True, eq=False)
class HighDVehicle:
    """One vehicle to write, in the canonical frame (box centre, y = -image y), ``K`` frames.

    Attributes:
        vehicle_id: positive highD id, unique in the recording.
        vehicle_class: ``"Car"`` or ``"Truck"``.
        first_frame: highD frame of the first sample; the track covers ``K`` consecutive frames.
        x_m, y_m: ``(K,)`` box centre, metres (y is negative on a highD road).
        length_m, width_m: box size, metres.
        vx_mps, vy_mps: ``(K,)`` velocity; ``None`` derives it from the positions.
        ax_mps2, ay_mps2: ``(K,)`` acceleration; ``None`` derives it from the velocity.
    """

    vehicle_id: int
    vehicle_class: str
    first_frame: int
    x_m: FloatArray
    y_m: FloatArray
    length_m: float
    width_m: float
    vx_mps: FloatArray | None = None
    vy_mps: FloatArray | None = None
    ax_mps2: FloatArray | None = None
    ay_mps2: FloatArray | None = None

    @property
    def n_frames(self) -> int:
        """Number of frames ``K``."""
        return int(np.asarray(self.x_m).shape[0])


def _derivative(values: FloatArray, dt_s: float) -> FloatArray:
    if values.size < 2:
        return np.zeros_like(values)
    return np.gradient(values, dt_s)


def _neighbours(
    code: IntArray,
    query_code: IntArray,
    x: FloatArray,
    length: FloatArray,
    sign: FloatArray,
    *,
    same_lane: bool,
    reach: int = 6,
) -> tuple[IntArray, IntArray, IntArray]:
    """Row index of the preceding, alongside and following vehicle in lane group ``query_code``.

    Rows are grouped by ``code`` (frame and lane); for each row the candidates are the ``2 * reach``
    rows of group ``query_code`` nearest in x. "Alongside" means the boxes overlap along x (never
    for the own lane); "preceding" is the nearest non-overlapping one ahead in the driving direction
    ``sign``, "following" the nearest behind. -1 where there is none.
    """
    m = x.size
    x0 = float(x.min())
    scale = float(x.max() - x0) + 10.0
    key = code.astype(np.float64) * scale + (x - x0)
    order = np.argsort(key, kind="stable")
    skey, scode = key[order], code[order]
    qkey = query_code.astype(np.float64) * scale + (x - x0)
    pos = np.searchsorted(skey, qkey)
    self_rows = np.arange(m)
    out = {name: np.full(m, -1, dtype=np.int64) for name in ("prec", "along", "fol")}
    best = {name: np.full(m, np.inf) for name in ("prec", "along", "fol")}
    for offset in range(-reach, reach):
        p = pos + offset
        ok = (p >= 0) & (p < m)
        pc = np.clip(p, 0, m - 1)
        cand = order[pc]
        ok &= (scode[pc] == query_code) & (cand != self_rows)
        ahead = (x[cand] - x) * sign
        overlap = np.zeros(m, dtype=bool) if same_lane else np.abs(ahead) < 0.5 * (length + length[cand])
        for name, hit, dist in (
            ("prec", ok & ~overlap & (ahead > 0), ahead),
            ("fol", ok & ~overlap & (ahead <= 0), -ahead),
            ("along", ok & overlap, np.abs(ahead)),
        ):
            better = hit & (dist < best[name])
            best[name][better] = dist[better]
            out[name][better] = cand[better]
    return out["prec"], out["along"], out["fol"]


def _decimal_column(values: FloatArray, decimals: int) -> pa.Array:
    return pa.array(np.round(values, decimals)).cast(pa.decimal128(18, decimals), safe=False)


def _write_csv(path: Path, columns: Sequence[str], data: Mapping[str, pa.Array | NDArray[Any]]) -> None:
    table = pa.table({c: data[c] for c in columns})
    with path.open("wb") as fh:
        fh.write((",".join(columns) + "\n").encode())
        pacsv.write_csv(
            table, fh, write_options=pacsv.WriteOptions(include_header=False, quoting_style="none")
        )


def write_highd_recording(
    out_dir: str | Path,
    recording_id: int,
    vehicles: Sequence[HighDVehicle],
    *,
    upper_lane_markings_m: Sequence[float],
    lower_lane_markings_m: Sequence[float],
    frame_rate_hz: float = 25.0,
    location_id: int = 1,
    speed_limit_mps: float | None = None,
    month: str = "09.2017",
    week_day: str = "Tue",
    start_time: str = "08:00",
    road_length_m: float | None = None,
    decimals: int = 2,
) -> HighDFiles:
    """Write vehicles as the three CSV files of a highD recording, in the published format.

    Positions are converted back to highD's image frame (upper-left box corner, y down). The
    derived columns follow the format's meaning, computed from the data:

    * ``laneId`` from the box centre's image-y and the lane markings (the lane between markings
      ``i`` and ``i + 1`` of all markings top to bottom is ``i + 2``, so a 2 + 2 lane road has lanes
      2, 3 and 5, 6 as in highD);
    * ``drivingDirection`` 2 when the mean x velocity is >= 0, else 1;
    * same-lane ``precedingId``/``followingId`` and the left/right lane's preceding, alongside
      (boxes overlap along x) and following vehicle, 0 when none ("left" is relative to the driving
      direction); ``dhw`` is the bumper-to-bumper gap to the preceding vehicle, ``thw`` = dhw /
      speed, ``ttc`` = dhw / closing speed when closing, and all three (and ``precedingXVelocity``)
      are 0 without a preceding vehicle; the meta file's ``minDHW``/``minTHW``/``minTTC`` are -1
      when never defined;
    * ``frontSightDistance``/``backSightDistance`` to the ends of the road section
      ``[min(0, rear-most x), road_length_m or front-most x]``.

    Floats are written with ``decimals`` decimals (highD uses 2).

    Args:
        out_dir: folder to write ``NN_tracks.csv``, ``NN_tracksMeta.csv``, ``NN_recordingMeta.csv``.
        recording_id: ``NN``.
        vehicles: the vehicles (any order; written by ascending id).
        upper_lane_markings_m: image-y of the upper carriageway's markings (metres, ascending).
        lower_lane_markings_m: image-y of the lower carriageway's markings (metres, ascending).
        frame_rate_hz: frames per second.
        location_id: highD location id.
        speed_limit_mps: posted limit, m/s; ``None`` writes highD's ``-1`` (no limit).
        month: ``MM.YYYY`` as in highD.
        week_day: three-letter week day.
        start_time: ``HH:MM``.
        road_length_m: image length of the road section; default: the front-most box edge.
        decimals: decimals of float columns.

    Returns:
        The paths written.

    Raises:
        ValueError: no vehicles, duplicate or non-positive ids, an unknown class, mismatched
            array lengths or non-finite positions.
    """
    if not vehicles:
        raise ValueError("write_highd_recording needs at least one vehicle")
    vehicles = sorted(vehicles, key=lambda v: v.vehicle_id)
    ids = np.array([v.vehicle_id for v in vehicles], dtype=np.int64)
    if np.any(ids <= 0) or np.unique(ids).size != ids.size:
        raise ValueError(f"vehicle ids must be positive and unique, got {ids.tolist()}")
    dt_s = 1.0 / frame_rate_hz
    cols: dict[str, list[NDArray[Any]]] = {k: [] for k in ("vid", "frame", "x", "y", "vx", "vy", "ax", "ay")}
    lengths, widths, classes = [], [], []
    for v in vehicles:
        if v.vehicle_class not in ("Car", "Truck"):
            raise ValueError(
                f"vehicle {v.vehicle_id}: class must be 'Car' or 'Truck', got {v.vehicle_class!r}"
            )
        x = np.asarray(v.x_m, dtype=np.float64)
        y = np.asarray(v.y_m, dtype=np.float64)
        k = x.size
        if k == 0 or y.shape != (k,) or not (np.all(np.isfinite(x)) and np.all(np.isfinite(y))):
            raise ValueError(
                f"vehicle {v.vehicle_id}: x_m and y_m must be equal-length, non-empty and finite"
            )
        vx = _derivative(x, dt_s) if v.vx_mps is None else np.asarray(v.vx_mps, dtype=np.float64)
        vy = _derivative(y, dt_s) if v.vy_mps is None else np.asarray(v.vy_mps, dtype=np.float64)
        ax = _derivative(vx, dt_s) if v.ax_mps2 is None else np.asarray(v.ax_mps2, dtype=np.float64)
        ay = _derivative(vy, dt_s) if v.ay_mps2 is None else np.asarray(v.ay_mps2, dtype=np.float64)
        for name, arr in (("vx_mps", vx), ("vy_mps", vy), ("ax_mps2", ax), ("ay_mps2", ay)):
            if arr.shape != (k,):
                raise ValueError(f"vehicle {v.vehicle_id}: {name} has shape {arr.shape}, expected ({k},)")
        cols["vid"].append(np.full(k, v.vehicle_id, dtype=np.int64))
        cols["frame"].append(v.first_frame + np.arange(k, dtype=np.int64))
        for name, arr in (("x", x), ("y", y), ("vx", vx), ("vy", vy), ("ax", ax), ("ay", ay)):
            cols[name].append(arr)
        lengths.append(float(v.length_m))
        widths.append(float(v.width_m))
        classes.append(v.vehicle_class)
    c = {name: np.concatenate(parts) for name, parts in cols.items()}
    counts = np.array([v.n_frames for v in vehicles], dtype=np.int64)
    starts = np.concatenate([[0], np.cumsum(counts)[:-1]]).astype(np.int64)
    row_v = np.repeat(np.arange(len(vehicles)), counts)
    length = np.asarray(lengths)[row_v]
    width = np.asarray(widths)[row_v]
    mean_vx = np.add.reduceat(c["vx"], starts) / counts
    direction = np.where(mean_vx >= 0, int(HighDDirection.RIGHT), int(HighDDirection.LEFT)).astype(np.int64)
    sign = np.where(direction[row_v] == HighDDirection.RIGHT, 1.0, -1.0)

    # Image frame.
    img_y_centre = -c["y"]
    markings = np.sort(np.concatenate([np.asarray(upper_lane_markings_m), np.asarray(lower_lane_markings_m)]))
    lane = (np.searchsorted(markings, img_y_centre, side="right") + 1).astype(np.int64)

    # Surrounding vehicles.
    lane_span = int(markings.size) + 4
    code = c["frame"] * lane_span + lane
    step = np.where(sign > 0, -1, 1).astype(np.int64)  # lane id of the left neighbour is lane + step
    prec, _, fol = _neighbours(code, code, c["x"], length, sign, same_lane=True)
    lp, la, lf = _neighbours(code, code + step, c["x"], length, sign, same_lane=False)
    rp, ra, rf = _neighbours(code, code - step, c["x"], length, sign, same_lane=False)

    def ids_of(rows: IntArray) -> IntArray:
        return np.where(rows >= 0, c["vid"][np.clip(rows, 0, None)], 0).astype(np.int64)

    has_prec = prec >= 0
    pc = np.clip(prec, 0, None)
    speed = np.abs(c["vx"])
    dhw = np.where(has_prec, (c["x"][pc] - c["x"]) * sign - 0.5 * (length + length[pc]), 0.0)
    thw = np.where(has_prec & (speed > 0), dhw / np.where(speed > 0, speed, 1.0), 0.0)
    closing = speed - np.abs(c["vx"][pc])
    ttc_ok = has_prec & (closing > 0)
    ttc = np.where(ttc_ok, dhw / np.where(closing > 0, closing, 1.0), 0.0)
    prec_vx = np.where(has_prec, c["vx"][pc], 0.0)
    rear = c["x"] - 0.5 * length
    front = c["x"] + 0.5 * length
    road_start = min(0.0, float(rear.min()))
    road_end = float(front.max()) if road_length_m is None else float(road_length_m)
    front_sight = np.where(sign > 0, road_end - front, rear - road_start)
    back_sight = np.where(sign > 0, rear - road_start, road_end - front)

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    files = HighDFiles.for_recording(out, recording_id)

    def dec(a: FloatArray) -> pa.Array:
        return _decimal_column(a, decimals)

    tracks: dict[str, pa.Array | NDArray[Any]] = {
        "frame": c["frame"],
        "id": c["vid"],
        "x": dec(rear),
        "y": dec(img_y_centre - 0.5 * width),
        "width": dec(length),
        "height": dec(width),
        "xVelocity": dec(c["vx"]),
        "yVelocity": dec(-c["vy"]),
        "xAcceleration": dec(c["ax"]),
        "yAcceleration": dec(-c["ay"]),
        "frontSightDistance": dec(front_sight),
        "backSightDistance": dec(back_sight),
        "dhw": dec(dhw),
        "thw": dec(thw),
        "ttc": dec(ttc),
        "precedingXVelocity": dec(prec_vx),
        "precedingId": ids_of(prec),
        "followingId": ids_of(fol),
        "leftPrecedingId": ids_of(lp),
        "leftAlongsideId": ids_of(la),
        "leftFollowingId": ids_of(lf),
        "rightPrecedingId": ids_of(rp),
        "rightAlongsideId": ids_of(ra),
        "rightFollowingId": ids_of(rf),
        "laneId": lane,
    }
    _write_csv(files.tracks, TRACKS_COLUMNS, tracks)

    # Per-vehicle statistics (reduceat over each vehicle's contiguous rows).
    def seg_min(values: FloatArray, valid: NDArray[np.bool_]) -> FloatArray:
        mins = np.minimum.reduceat(np.where(valid, values, np.inf), starts)
        return np.where(np.isfinite(mins), mins, -1.0)

    step_len = np.hypot(np.diff(c["x"], prepend=c["x"][0]), np.diff(c["y"], prepend=c["y"][0]))
    step_len[starts] = 0.0
    lane_change = np.concatenate([[0], (lane[1:] != lane[:-1]).astype(np.int64)])
    lane_change[starts] = 0
    traveled = np.add.reduceat(step_len, starts)
    tracks_meta: dict[str, pa.Array | NDArray[Any]] = {
        "id": ids,
        "width": dec(np.asarray(lengths)),
        "height": dec(np.asarray(widths)),
        "initialFrame": c["frame"][starts],
        "finalFrame": c["frame"][starts + counts - 1],
        "numFrames": counts,
        "class": pa.array(classes, type=pa.string()),
        "drivingDirection": direction,
        "traveledDistance": dec(traveled),
        "minXVelocity": dec(np.minimum.reduceat(speed, starts)),
        "maxXVelocity": dec(np.maximum.reduceat(speed, starts)),
        "meanXVelocity": dec(np.add.reduceat(speed, starts) / counts),
        "minDHW": dec(seg_min(dhw, has_prec)),
        "minTHW": dec(seg_min(thw, has_prec & (thw > 0))),
        "minTTC": dec(seg_min(ttc, ttc_ok)),
        "numLaneChanges": np.add.reduceat(lane_change, starts).astype(np.int64),
    }
    _write_csv(files.tracks_meta, TRACKS_META_COLUMNS, tracks_meta)

    def num(value: float) -> str:
        return str(int(value)) if float(value).is_integer() else f"{value:.{decimals}f}"

    n_trucks = sum(1 for cls in classes if cls == "Truck")
    frames_all = c["frame"]
    recording_meta = {
        "id": str(recording_id),
        "frameRate": num(frame_rate_hz),
        "locationId": str(location_id),
        "speedLimit": f"{-1.0 if speed_limit_mps is None else speed_limit_mps:.2f}",
        "month": month,
        "weekDay": week_day,
        "startTime": start_time,
        "duration": f"{(int(frames_all.max()) - int(frames_all.min()) + 1) * dt_s:.2f}",
        "totalDrivenDistance": f"{float(traveled.sum()):.2f}",
        "totalDrivenTime": f"{float(counts.sum()) * dt_s:.2f}",
        "numVehicles": str(len(vehicles)),
        "numCars": str(len(vehicles) - n_trucks),
        "numTrucks": str(n_trucks),
        "upperLaneMarkings": ";".join(f"{m:.2f}" for m in upper_lane_markings_m),
        "lowerLaneMarkings": ";".join(f"{m:.2f}" for m in lower_lane_markings_m),
    }
    files.recording_meta.write_text(
        ",".join(RECORDING_META_COLUMNS)
        + "\n"
        + ",".join(recording_meta[k] for k in RECORDING_META_COLUMNS)
        + "\n",
        encoding="utf-8",
    )
    return files
