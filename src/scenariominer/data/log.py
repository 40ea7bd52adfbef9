"""The canonical driving-log model: one ego track plus object tracks as dense columnar arrays.

Every adapter (Argoverse 2, highD, tabular) produces a :class:`Log`; every later stage
(preprocessing, tags, events, mining, clustering) consumes one. Arrays are dense over
``tracks × timestamps`` so that stages vectorise with numpy instead of looping per frame:

* ``N`` tracks, the ego always at index :attr:`Log.ego_index` (= 0),
* ``T`` timestamps shared by all tracks (the log's annotation clock),
* per-track, per-timestamp float arrays of shape ``(N, T)``, ``NaN`` where the track does
  not exist at that timestamp, with :attr:`Log.valid` the matching boolean mask.

Positions are in the log's world ("city") frame in metres, yaw in radians counter-clockwise
from the world x axis, time in integer nanoseconds.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import pyarrow as pa
import pyarrow.compute as pc
from numpy.typing import NDArray

from scenariominer import errors as _errors
from scenariominer.data.categories import EGO_CATEGORY, UnknownCategoryError, canonical_category
from scenariominer.data.clocks import align_track_clocks
from scenariominer.geometry import wrap_angle

FloatArray = NDArray[np.float64]
BoolArray = NDArray[np.bool_]

#: The per-track, per-timestamp float fields of a :class:`Log`, all shaped ``(N, T)``.
#: Version of what a stored log means; part of the ingestion fingerprint, so a change re-ingests
#: every stored log. 2: the Argoverse 2 ego is stored at its box centre (was: the rear axle).
LOG_SCHEMA_VERSION = 2

STATE_FIELDS: tuple[str, ...] = (
    "x_m",
    "y_m",
    "z_m",
    "yaw_rad",
    "length_m",
    "width_m",
    "height_m",
    "vx_mps",
    "vy_mps",
    "ax_mps2",
    "ay_mps2",
)

#: Fields an adapter must supply; velocities and accelerations are derived when absent.
REQUIRED_FIELDS: tuple[str, ...] = ("x_m", "y_m", "yaw_rad", "length_m", "width_m")

#: Largest plausible |x| or |y| (metres; 10,000 km): rows beyond are dropped as corrupt.
MAX_COORDINATE_M = 1e7
#: A zero or negative box length or width (no extent recorded, or a sign error) becomes this (metres).
MIN_BOX_SIZE_M = 0.1
#: Largest plausible box length or width (metres; a road train is about 50 m): rows beyond are dropped.
MAX_BOX_SIZE_M = 100.0
#: Largest ``tracks x timestamps`` grid a log may have (each state field is one float64 per cell).
MAX_LOG_CELLS = 20_000_000


class LogFormatError(_errors.DataError):
    """A log cannot be read or is malformed; the message names the source and the problem.

    Attributes:
        source: file or folder the problem was found in.
        problem: one-line description of what is wrong.
    """

    def __init__(self, source: str | Path, problem: str) -> None:
        self.source = str(source)
        self.problem = problem
        super().__init__(f"{self.source}: {problem}")


@dataclass(frozen=True, eq=False)
class Log:
    """One driving log as dense ``tracks × timestamps`` arrays.

    Attributes:
        log_id: unique identifier of the log (Argoverse 2 log UUID, ``<recording>_<ego>_<window>``
            for highD windows, or the user's id for tabular data).
        timestamps_ns: ``(T,)`` int64, strictly increasing.
        track_ids: ``(N,)`` str, unique; ``track_ids[ego_index]`` is the ego.
        categories: ``(N,)`` str, Argoverse 2 category names (the ego is ``EGO_VEHICLE``).
        valid: ``(N, T)`` bool, True where the track is observed (or interpolated inside its lifespan).
        x_m, y_m, z_m: ``(N, T)`` box centre in the world frame, metres.
        yaw_rad: ``(N, T)`` heading, radians, counter-clockwise from world +x, wrapped to
            ``[-pi, pi)`` (:func:`scenariominer.geometry.wrap_angle`).
        length_m, width_m, height_m: ``(N, T)`` box size, metres.
        vx_mps, vy_mps: ``(N, T)`` world-frame velocity, metres per second.
        ax_mps2, ay_mps2: ``(N, T)`` world-frame acceleration, metres per second squared.
        dataset: name of the source format (``av2``, ``highd``, ``tabular``, ``synthetic``).
        source_path: the file or folder the log was read from, if any.
        map_dir: folder with an Argoverse 2 vector map for this log, if one exists.
        source_hash: content hash of the source files (drives incremental ingestion).
        notes: human-readable repairs applied while reading (e.g. dropped one-frame tracks).
        ego_index: index of the ego track; always 0 for logs built by this package.
        ego_pose_offset_m: distance, metres, from the ego's box centre BACK along its heading to the
            point the source format reports as the ego pose (the origin of its vehicle frame).
            Positions in the log are always box centres; this only lets a writer or an exporter
            give the pose back in the source's convention. Argoverse 2 reports the rear axle,
            1.422 m behind the box centre; 0 for formats that report box centres.
    """

    log_id: str
    timestamps_ns: NDArray[np.int64]
    track_ids: NDArray[np.str_]
    categories: NDArray[np.str_]
    valid: BoolArray
    x_m: FloatArray
    y_m: FloatArray
    z_m: FloatArray
    yaw_rad: FloatArray
    length_m: FloatArray
    width_m: FloatArray
    height_m: FloatArray
    vx_mps: FloatArray
    vy_mps: FloatArray
    ax_mps2: FloatArray
    ay_mps2: FloatArray
    dataset: str = "unknown"
    source_path: Path | None = None
    map_dir: Path | None = None
    source_hash: str = ""
    notes: tuple[str, ...] = field(default_factory=tuple)
    ego_index: int = 0
    ego_pose_offset_m: float = 0.0

    # ------------------------------------------------------------------ basic properties
    @property
    def n_tracks(self) -> int:
        """Number of tracks ``N``, the ego included."""
        return int(self.track_ids.shape[0])

    @property
    def n_timestamps(self) -> int:
        """Number of timestamps ``T``."""
        return int(self.timestamps_ns.shape[0])

    @property
    def t_s(self) -> FloatArray:
        """``(T,)`` seconds since the first timestamp."""
        t: FloatArray = (self.timestamps_ns - self.timestamps_ns[0]).astype(np.float64) * 1e-9
        return t

    @property
    def duration_s(self) -> float:
        """Time between first and last timestamp, seconds."""
        if self.n_timestamps < 2:
            return 0.0
        return float((self.timestamps_ns[-1] - self.timestamps_ns[0]) * 1e-9)

    @property
    def n_frames(self) -> int:
        """Number of valid (track, timestamp) cells, i.e. object observations."""
        return int(self.valid.sum())

    @property
    def speed_mps(self) -> FloatArray:
        """``(N, T)`` ground speed, metres per second."""
        speed: FloatArray = np.hypot(self.vx_mps, self.vy_mps)
        return speed

    @property
    def has_map(self) -> bool:
        """Whether an Argoverse 2 vector map folder is attached."""
        return self.map_dir is not None

    def track_index(self, track_id: str) -> int:
        """Row index of ``track_id``; raises ``KeyError`` naming the log when absent."""
        hits = np.flatnonzero(self.track_ids == track_id)
        if hits.size == 0:
            raise KeyError(f"track {track_id!r} is not in log {self.log_id}")
        return int(hits[0])

    def category_counts(self) -> dict[str, int]:
        """Number of tracks per category (the ego included)."""
        names, counts = np.unique(self.categories, return_counts=True)
        return {str(n): int(c) for n, c in zip(names, counts, strict=True)}

    # ------------------------------------------------------------------ derived copies
    def replace(self, **changes: Any) -> Log:
        """Return a copy with some fields replaced (see :func:`dataclasses.replace`)."""
        return dataclasses.replace(self, **changes)

    def ego_pose_xy_m(self) -> tuple[FloatArray, FloatArray]:
        """``(T,)`` x and y of the ego pose in the source's convention (see :attr:`ego_pose_offset_m`)."""
        e = self.ego_index
        x: FloatArray = self.x_m[e] - self.ego_pose_offset_m * np.cos(self.yaw_rad[e])
        y: FloatArray = self.y_m[e] - self.ego_pose_offset_m * np.sin(self.yaw_rad[e])
        return x, y

    def select_tracks(self, mask_or_index: BoolArray | NDArray[np.int64]) -> Log:
        """Return a log with a subset of tracks; the ego must remain at row 0."""
        idx = np.arange(self.n_tracks)[mask_or_index]
        if idx.size == 0 or idx[0] != self.ego_index:
            raise ValueError("select_tracks must keep the ego track as the first row")
        changes: dict[str, Any] = {name: getattr(self, name)[idx] for name in STATE_FIELDS}
        changes.update(track_ids=self.track_ids[idx], categories=self.categories[idx], valid=self.valid[idx])
        return self.replace(**changes)

    def slice_time(self, start: int, stop: int, log_id: str | None = None) -> Log:
        """Return the timestamps ``[start, stop)``; tracks absent from the slice are dropped."""
        sl = slice(start, stop)
        valid = self.valid[:, sl]
        keep: BoolArray = np.asarray(valid.any(axis=1), dtype=bool)
        keep[self.ego_index] = True
        changes: dict[str, Any] = {name: getattr(self, name)[keep, sl] for name in STATE_FIELDS}
        changes.update(
            timestamps_ns=self.timestamps_ns[sl],
            track_ids=self.track_ids[keep],
            categories=self.categories[keep],
            valid=valid[keep],
            log_id=log_id or self.log_id,
        )
        return self.replace(**changes)

    # ------------------------------------------------------------------ long-table round trip
    def to_arrow(self) -> pa.Table:
        """Long table with one row per valid (track, timestamp) cell; see :func:`Log.from_arrow`."""
        rows, cols = np.nonzero(self.valid)
        # one Arrow string per track, gathered per row in Arrow (encoding every row's text costs more)
        row_index = pa.array(rows)
        data: dict[str, Any] = {
            "track_id": pa.array(self.track_ids.tolist(), type=pa.string()).take(row_index),
            "category": pa.array(self.categories.tolist(), type=pa.string()).take(row_index),
            "timestamp_ns": pa.array(self.timestamps_ns[cols], type=pa.int64()),
            "is_ego": pa.array(rows == self.ego_index),
        }
        for name in STATE_FIELDS:
            data[name] = pa.array(getattr(self, name)[rows, cols], type=pa.float64())
        return pa.table(data)

    @classmethod
    def from_arrow(
        cls,
        table: pa.Table,
        *,
        log_id: str,
        source: str | Path = "<table>",
        **kwargs: Any,
    ) -> Log:
        """Build a log from a long table as written by :meth:`to_arrow` (the store's format)."""
        ego_id = None
        if "is_ego" in table.column_names:
            ego_rows = np.flatnonzero(table.column("is_ego").to_numpy(zero_copy_only=False))
            if ego_rows.size:
                ego_id = str(table.column("track_id")[int(ego_rows[0])].as_py())
        fields = {
            k: table.column(k).to_numpy(zero_copy_only=False) for k in table.column_names if k in STATE_FIELDS
        }
        return build_log(
            log_id=log_id,
            track_id=table.column("track_id"),
            category=table.column("category"),
            timestamp_ns=table.column("timestamp_ns").to_numpy(zero_copy_only=False),
            fields=fields,
            ego_track_id=ego_id,
            source=source,
            **kwargs,
        )


# ---------------------------------------------------------------------- builder


def build_log(
    *,
    log_id: str,
    track_id: Sequence[Any] | NDArray[Any] | pa.Array | pa.ChunkedArray,
    category: Sequence[Any] | NDArray[Any] | pa.Array | pa.ChunkedArray,
    timestamp_ns: Sequence[int] | NDArray[np.int64],
    fields: Mapping[str, NDArray[np.float64] | Sequence[float]],
    ego_track_id: str | None,
    source: str | Path,
    dataset: str = "unknown",
    map_dir: Path | None = None,
    source_hash: str = "",
    category_aliases: Mapping[str, str] | None = None,
    min_track_frames: int = 2,
    max_cells: int = MAX_LOG_CELLS,
) -> Log:
    """Build a :class:`Log` from long-format columns (one entry per observation).

    This is the single place where every adapter's rows become a validated log, so every
    format gets the same checks and the same documented repairs:

    * missing required fields, non-finite timestamps, and conflicting duplicate rows
      (same track and timestamp, different values) are errors naming ``source``;
    * unsorted rows are sorted (no information is lost);
    * exact duplicate rows are collapsed;
    * rows with NaN/inf position, yaw or size, a coordinate beyond :data:`MAX_COORDINATE_M`, or a
      length or width beyond :data:`MAX_BOX_SIZE_M`, are dropped (preprocessing interpolates the
      gap; an ego with no row left is an error); a zero or negative length or width becomes
      :data:`MIN_BOX_SIZE_M`;
    * timestamps outside the int64 range (e.g. a wrapped unsigned value) are an error;
    * tracks stamped by their own clocks (timestamps a few µs apart) are snapped onto one clock, and
      a log whose clocks are too far apart to snap, or whose grid would exceed ``max_cells``, is an
      error (see :mod:`scenariominer.data.clocks`);
    * a NUL character in a track id (cut off by Arrow when stored) becomes U+FFFD;
    * tracks with fewer than ``min_track_frames`` observations are dropped (a one-frame track
      has no motion; the ego is never dropped, a one-frame ego is an error);
    * unknown categories are an error unless ``category_aliases`` maps them.

    Each repair adds a line to :attr:`Log.notes`.

    Args:
        log_id: identifier of the resulting log.
        track_id: ``(M,)`` track identifier per row (a sequence, numpy or Arrow array).
        category: ``(M,)`` category name per row (Argoverse 2 name or alias).
        timestamp_ns: ``(M,)`` integer nanoseconds per row.
        fields: state columns named as in :data:`STATE_FIELDS`, each ``(M,)``; at least
            :data:`REQUIRED_FIELDS`. Missing ``z_m``/``height_m`` default to 0 / 1.5 m;
            missing velocities and accelerations are derived by finite differences.
        ego_track_id: the ego's track id; ``None`` means the rows whose category is ``EGO_VEHICLE``.
        source: file or folder named in error messages.
        dataset: name of the source format.
        map_dir: Argoverse 2 vector map folder, if any.
        source_hash: content hash of the source files.
        category_aliases: extra lower-case alias → Argoverse 2 name mapping.
        min_track_frames: tracks with fewer observations are dropped (with a note).
        max_cells: largest ``tracks x timestamps`` grid accepted (:data:`MAX_LOG_CELLS`).
    """
    notes: list[str] = []
    m = len(track_id)
    if m == 0:
        raise LogFormatError(source, "the log has no rows")
    # Texts become integer codes once (track ids repeat on every row; comparing, sorting and
    # gathering strings per row cost most of a real log's build time); codes follow text order.
    texts, rows = _encode(track_id)
    names, tcode = _sorted_codes(_replace_nul(texts, source, notes), rows)
    missing = [f for f in REQUIRED_FIELDS if f not in fields]
    if missing:
        raise LogFormatError(source, f"missing required column(s) {missing}")
    try:
        ts = np.asarray(timestamp_ns, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise LogFormatError(source, f"timestamps are not numeric ({exc})") from None
    if not np.all(np.isfinite(ts)):
        raise LogFormatError(source, f"{int((~np.isfinite(ts)).sum())} row(s) have a missing/NaN timestamp")
    if np.any(np.abs(ts) >= 2.0**63):
        bad = float(ts[np.abs(ts) >= 2.0**63][0])
        raise LogFormatError(
            source, f"timestamp {bad:.0f} ns is outside the int64 range (an unsigned value that wrapped?)"
        )
    ts_i = np.asarray(timestamp_ns).astype(np.int64)
    cols: dict[str, NDArray[np.float64]] = {}
    for name, values in fields.items():
        if name not in STATE_FIELDS:
            continue
        try:
            arr = np.asarray(values, dtype=np.float64)
        except (TypeError, ValueError) as exc:
            raise LogFormatError(source, f"column {name!r} is not numeric ({exc})") from None
        if arr.shape != (m,):
            raise LogFormatError(source, f"column {name!r} has {arr.shape[0]} rows, expected {m}")
        cols[name] = arr
    if len({m, len(category), ts_i.shape[0]}) != 1:
        raise LogFormatError(source, "track_id, category and timestamp columns differ in length")

    # Categories: canonicalise each distinct name once (aliases may merge names).
    raw_names, raw_code = _encode(category)
    mapped = []
    for name in raw_names:
        try:
            mapped.append(canonical_category(str(name), category_aliases))
        except UnknownCategoryError as exc:
            raise LogFormatError(source, str(exc)) from None
    cat_names, canon_of_raw = np.unique(np.asarray(mapped + [EGO_CATEGORY], dtype=str), return_inverse=True)
    ccode = canon_of_raw[:-1][raw_code]
    ego_cat = int(canon_of_raw[-1])

    if ego_track_id is None:
        ego_codes = np.unique(tcode[ccode == ego_cat])
        if ego_codes.size == 0:
            raise LogFormatError(
                source, "no ego track: no row has category EGO_VEHICLE and no ego id was given"
            )
        if ego_codes.size > 1:
            raise LogFormatError(
                source, f"several tracks have category EGO_VEHICLE: {names[ego_codes[:5]].tolist()}"
            )
        ego_code = int(ego_codes[0])
        ego_track_id = str(names[ego_code])
    else:
        hit = np.flatnonzero(names == ego_track_id)
        if hit.size == 0 or not np.any(tcode == hit[0]):
            raise LogFormatError(source, f"ego track {ego_track_id!r} does not occur in the data")
        ego_code = int(hit[0])
    ccode = np.where(tcode == ego_code, ego_cat, ccode)

    # Drop rows whose geometry is unusable (documented repair; preprocessing interpolates the gap).
    finite = np.ones(m, dtype=bool)
    for name in ("x_m", "y_m", "yaw_rad", "length_m", "width_m"):
        finite &= np.isfinite(cols[name])
    with np.errstate(invalid="ignore"):
        far = finite & ((np.abs(cols["x_m"]) > MAX_COORDINATE_M) | (np.abs(cols["y_m"]) > MAX_COORDINATE_M))
        huge = finite & ~far & ((cols["length_m"] > MAX_BOX_SIZE_M) | (cols["width_m"] > MAX_BOX_SIZE_M))
        for name in ("length_m", "width_m"):
            flat = finite & (cols[name] <= 0)
            if flat.any():
                notes.append(
                    f"set {name} of {int(flat.sum())} row(s) from zero or negative to {MIN_BOX_SIZE_M} m"
                )
                cols[name] = np.where(flat, MIN_BOX_SIZE_M, cols[name])
    geom = finite & ~far & ~huge
    if not geom.all():
        for count, what in (
            (int((~finite).sum()), "NaN/inf position, yaw or size"),
            (int(far.sum()), f"a coordinate beyond {MAX_COORDINATE_M:.0e} m"),
            (int(huge.sum()), f"a length or width beyond {MAX_BOX_SIZE_M:g} m"),
        ):
            if count:
                notes.append(f"dropped {count} row(s) with {what} (gaps are interpolated)")
        tcode, ccode, ts_i = tcode[geom], ccode[geom], ts_i[geom]
        cols = {k: v[geom] for k, v in cols.items()}
        if tcode.size == 0:
            raise LogFormatError(source, "no row has a usable position, yaw and size")
        if not np.any(tcode == ego_code):
            raise LogFormatError(
                source, f"the ego track {ego_track_id!r} has no row with a usable position, yaw and size"
            )

    # Sort by (track, time); detect duplicates.
    order = np.lexsort((ts_i, tcode))
    if not np.all(order[1:] > order[:-1]):
        tcode, ccode, ts_i = tcode[order], ccode[order], ts_i[order]
        cols = {k: v[order] for k, v in cols.items()}
    dup = (tcode[1:] == tcode[:-1]) & (ts_i[1:] == ts_i[:-1])
    if dup.any():
        stacked = np.stack([np.nan_to_num(v, nan=np.inf) for v in cols.values()], axis=1)
        conflicting = dup & np.any(stacked[1:] != stacked[:-1], axis=1)
        if conflicting.any():
            i = int(np.flatnonzero(conflicting)[0])
            raise LogFormatError(
                source,
                f"{int(conflicting.sum())} duplicate (track, timestamp) row(s) with different values, "
                f"e.g. track {str(names[tcode[i]])!r} at timestamp_ns={int(ts_i[i])}",
            )
        keep = np.concatenate([[True], ~dup])
        notes.append(f"collapsed {int(dup.sum())} exact duplicate row(s)")
        tcode, ccode, ts_i = tcode[keep], ccode[keep], ts_i[keep]
        cols = {k: v[keep] for k, v in cols.items()}

    # Category must be constant per track.
    first = np.concatenate([[True], tcode[1:] != tcode[:-1]])
    track_codes = tcode[first]
    track_start = np.flatnonzero(first)
    track_of_row = np.cumsum(first) - 1
    track_ccode = ccode[first]
    changed = ccode != track_ccode[track_of_row]
    if np.any(changed):
        i = int(np.flatnonzero(changed)[0])
        raise LogFormatError(
            source,
            f"track {str(names[tcode[i]])!r} changes category "
            f"({cat_names[track_ccode[track_of_row[i]]]} → {cat_names[ccode[i]]})",
        )

    # One-frame tracks.
    counts = np.diff(np.append(track_start, tcode.size))
    short = counts < min_track_frames
    ego_pos = int(np.flatnonzero(track_codes == ego_code)[0])
    if short[ego_pos]:
        raise LogFormatError(source, f"the ego track has only {int(counts[ego_pos])} frame(s)")
    if short.any():
        notes.append(
            f"dropped {int(short.sum())} track(s) with fewer than {min_track_frames} frames "
            f"(e.g. {names[track_codes[short][:3]].tolist()})"
        )
        keep_rows = ~short[track_of_row]
        tcode, ts_i = tcode[keep_rows], ts_i[keep_rows]
        cols = {k: v[keep_rows] for k, v in cols.items()}
        track_codes = track_codes[~short]
        track_ccode = track_ccode[~short]
        first = np.concatenate([[True], tcode[1:] != tcode[:-1]])
        track_of_row = np.cumsum(first) - 1
    track_names = names[track_codes]
    track_cat = cat_names[track_ccode]

    # Tracks on their own clocks (µs offsets, per-row float rounding): one clock, or refused.
    clocks = align_track_clocks(ts_i, first, tcode == ego_code)
    if clocks.problem:
        raise LogFormatError(source, clocks.problem)
    if clocks.note:
        notes.append(clocks.note)
        ts_i = clocks.timestamps_ns

    # Put the ego first.
    ego_pos = int(np.flatnonzero(track_codes == ego_code)[0])
    perm = np.concatenate([[ego_pos], np.delete(np.arange(track_names.size), ego_pos)])
    rank = np.empty_like(perm)
    rank[perm] = np.arange(perm.size)
    row_track = rank[track_of_row]
    track_names = track_names[perm]
    track_cat = track_cat[perm]

    timestamps, col_t = np.unique(ts_i, return_inverse=True)
    n, t = track_names.size, timestamps.size
    if n * t > max_cells:
        raise LogFormatError(
            source,
            f"the log would be {n} tracks x {t} timestamps = {n * t:,} cells, over the limit of "
            f"{max_cells:,}; split it into shorter logs",
        )
    valid = np.zeros((n, t), dtype=bool)
    valid[row_track, col_t] = True

    def dense(values: NDArray[np.float64] | None, default: float) -> FloatArray:
        out = np.full((n, t), np.nan)
        if values is None:
            out[row_track, col_t] = default
        else:
            out[row_track, col_t] = values
        return out

    state: dict[str, FloatArray] = {
        "x_m": dense(cols["x_m"], 0.0),
        "y_m": dense(cols["y_m"], 0.0),
        "z_m": dense(cols.get("z_m"), 0.0),
        "yaw_rad": dense(wrap_angle(cols["yaw_rad"]), 0.0),
        "length_m": dense(cols["length_m"], 0.0),
        "width_m": dense(cols["width_m"], 0.0),
        "height_m": dense(cols.get("height_m"), 1.5),
    }
    t_s = (timestamps - timestamps[0]).astype(np.float64) * 1e-9
    have_v = "vx_mps" in cols and "vy_mps" in cols and np.all(np.isfinite(cols["vx_mps"]))
    if have_v:
        state["vx_mps"] = dense(cols["vx_mps"], 0.0)
        state["vy_mps"] = dense(cols["vy_mps"], 0.0)
    else:
        state["vx_mps"] = time_derivative(state["x_m"], t_s)
        state["vy_mps"] = time_derivative(state["y_m"], t_s)
    have_a = "ax_mps2" in cols and "ay_mps2" in cols and np.all(np.isfinite(cols["ax_mps2"]))
    if have_a:
        state["ax_mps2"] = dense(cols["ax_mps2"], 0.0)
        state["ay_mps2"] = dense(cols["ay_mps2"], 0.0)
    else:
        state["ax_mps2"] = time_derivative(state["vx_mps"], t_s)
        state["ay_mps2"] = time_derivative(state["vy_mps"], t_s)

    return Log(
        log_id=log_id,
        timestamps_ns=timestamps.astype(np.int64),
        track_ids=track_names.astype(str),
        categories=track_cat.astype(str),
        valid=valid,
        dataset=dataset,
        source_path=Path(source) if not str(source).startswith("<") else None,
        map_dir=map_dir,
        source_hash=source_hash,
        notes=tuple(notes),
        **state,  # type: ignore[arg-type]  # exactly the float state fields
    )


def _encode(values: Any) -> tuple[list[str], NDArray[np.intp]]:
    """The distinct texts of ``values`` ``(M,)`` (``K``, in order of appearance) and each row's index.

    ``values`` is a sequence, a numpy array or an Arrow array (a dictionary-encoded one is used as
    it is). Arrow hashes the texts once: several times faster than sorting ``M`` numpy strings.
    """
    if isinstance(values, pa.ChunkedArray):
        values = values.combine_chunks()
    if not isinstance(values, pa.Array):
        # through Python strings: Arrow would cut a numpy string at its first NUL character
        arr = np.asarray(values)
        values = pa.array((arr if arr.dtype.kind == "U" else arr.astype(str)).tolist(), type=pa.string())
    elif not pa.types.is_dictionary(values.type) and not pa.types.is_string(values.type):
        values = values.cast(pa.string())
    if values.null_count:
        values = values.fill_null("None")
    encoded = values if pa.types.is_dictionary(values.type) else pc.dictionary_encode(values)
    texts = [str(t) for t in encoded.dictionary.to_pylist()]
    rows = encoded.indices.to_numpy(zero_copy_only=False).astype(np.intp)
    if len(set(texts)) != len(texts):  # a dictionary-encoded input may repeat a text
        uniq = list(dict.fromkeys(texts))
        index = {t: i for i, t in enumerate(uniq)}
        rows = np.asarray([index[t] for t in texts], dtype=np.intp)[rows]
        texts = uniq
    return texts, rows


def _sorted_codes(texts: list[str], rows: NDArray[np.intp]) -> tuple[NDArray[np.str_], NDArray[np.intp]]:
    """``texts`` sorted ``(K,)`` and each row's index into the sorted array ``(M,)``.

    A text that occurs in no row is kept (it is never referred to).
    """
    order = sorted(range(len(texts)), key=texts.__getitem__)
    rank = np.empty(len(texts), dtype=np.intp)
    rank[order] = np.arange(len(texts))
    return np.asarray([texts[i] for i in order], dtype=str), rank[rows]


def _replace_nul(texts: list[str], source: str | Path, notes: list[str]) -> list[str]:
    """Track ids with a NUL character, which Arrow cuts off when storing, get U+FFFD instead.

    ``texts`` are the distinct ids; the result keeps their order and must stay distinct.
    """
    bad = [t for t in texts if "\x00" in t]
    if not bad:
        return texts
    fixed = ["\ufffd".join(t.split("\x00")) for t in texts]
    if len(set(fixed)) != len(fixed):
        raise LogFormatError(source, "track ids differ only by NUL characters (cannot be stored apart)")
    notes.append(
        f"replaced NUL characters with U+FFFD in {len(bad)} track id(s) "
        f"(e.g. {bad[0]!r}; a NUL would cut the id short when stored)"
    )
    return fixed


def time_derivative(values: FloatArray, t_s: FloatArray) -> FloatArray:
    """Finite-difference time derivative along axis 1 of ``values`` ``(N, T)``, NaN-aware.

    Uses central differences between valid neighbours and one-sided differences at the ends of
    each track's observed span; cells that are NaN in ``values`` stay NaN. Vectorised over tracks.
    """
    n, t = values.shape
    out = np.full((n, t), np.nan)
    if t < 2:
        out[np.isfinite(values)] = 0.0
        return out
    finite = np.isfinite(values)
    dt = np.diff(t_s)
    fwd = np.full((n, t), np.nan)
    fwd[:, :-1] = np.diff(values, axis=1) / dt
    bwd = np.full((n, t), np.nan)
    bwd[:, 1:] = fwd[:, :-1]
    central = np.full((n, t), np.nan)
    if t >= 3:
        span = t_s[2:] - t_s[:-2]
        central[:, 1:-1] = (values[:, 2:] - values[:, :-2]) / span
    out = np.where(np.isfinite(central), central, np.where(np.isfinite(fwd), fwd, bwd))
    out[~finite] = np.nan
    # An isolated observation (no finite neighbour) has no measurable motion.
    out[finite & ~np.isfinite(out)] = 0.0
    return out
