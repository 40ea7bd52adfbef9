"""Mining outputs: per-log matches, the store tables, and the Argoverse 2 submission pickle.

* :class:`LogMatches` is what one program found in one log: the referred (track, timestamp)
  cells and the related objects, columnar, identified by track id and timestamp (not by row
  index, so it survives re-reading the log).
* :func:`matches_table` / :func:`runs_table` are the store tables ``mining_results`` (one row
  per referred cell) and ``mining_runs`` (one row per log and description).
* :func:`av2_frames` builds the frames of the Argoverse 2 scenario-mining submission for one
  (log, description); :func:`write_av2_submission` and :func:`read_av2_submission` save and
  load the pickle ``{(log_id, description): [frame, ...]}``.

Submission frames (one per evaluation timestamp, in time order, for every evaluation timestamp
of the log, also when nothing matched) hold every object observed at that timestamp, with

* ``translation_m`` ``(N, 3)`` float64, ``size`` ``(N, 3)`` float32 (length, width, height),
  ``yaw`` ``(N,)`` float32, ``velocity_m_per_s`` ``(N, 3)`` float64, all in the city frame from
  the RAW boxes (the ground truth uses the unsmoothed annotation boxes; the Argoverse 2 ego box
  sits at the pose origin, the rear axle);
* ``label`` ``(N,)`` int32: 0 referred object, 1 related object, 2 other object (including a
  referred track's frames where it is not referred, since HOTA-Track follows whole tracks), and
  ``name`` ``(N,)`` the matching ``REFERRED_OBJECT``/``RELATED_OBJECT``/``OTHER_OBJECT``;
* ``track_id`` ``(N,)`` int32 (the track's row in the log), ``score`` ``(N,)`` float32 (1.0:
  programs make hard decisions);
* ``timestamp_ns``, ``ego_translation_m`` (three floats), ``description`` and ``seq_id``.

The official evaluator matches frames by position, so the evaluation timestamps must be the
ground truth's: by default every ``round(0.5 s / dt)``-th timestamp of the log from the first
(the 2 Hz subsampling of the 10 Hz Argoverse 2 annotations), or the timestamps given.
"""

from __future__ import annotations

import hashlib
import pickle
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from enum import IntEnum
from pathlib import Path
from typing import Any

import numpy as np
import pyarrow as pa
from numpy.typing import NDArray

from scenariominer import errors as _errors
from scenariominer.data.log import BoolArray, FloatArray, Log
from scenariominer.mine.context import IntArray
from scenariominer.mine.scenario import Scenario

__all__ = [
    "EVALUATION_RATE_HZ",
    "MATCHES_TABLE",
    "RUNS_TABLE",
    "LogMatches",
    "ObjectLabel",
    "SubmissionFormatError",
    "av2_frames",
    "evaluation_timestamps",
    "matches_table",
    "program_sha256",
    "read_av2_submission",
    "runs_table",
    "write_av2_submission",
]

#: Store table with one row per referred (track, timestamp) cell.
MATCHES_TABLE = "mining_results"
#: Store table with one row per (log, description) that was mined.
RUNS_TABLE = "mining_runs"
#: Rate of the scenario-mining evaluation timestamps (Argoverse 2 evaluates at 2 Hz).
EVALUATION_RATE_HZ = 2.0

Submission = dict[tuple[str, str], list[dict[str, Any]]]


class ObjectLabel(IntEnum):
    """Role of a box in a scenario-mining frame (values of the ``label`` array)."""

    REFERRED = 0
    """An object the description refers to, at a timestamp where it holds."""
    RELATED = 1
    """An object a referred object is related to at that timestamp (e.g. the bicycle)."""
    OTHER = 2
    """Any other object, and referred tracks where the description does not hold."""

    @property
    def av2_name(self) -> str:
        """The ``name`` the Argoverse 2 format gives boxes with this label."""
        return f"{self.name}_OBJECT"


_LABEL_NAMES = np.array([label.av2_name for label in ObjectLabel], dtype="<U31")


class SubmissionFormatError(_errors.MiningError, ValueError):
    """A submission or ground-truth pickle does not have the Argoverse 2 scenario-mining layout."""


def program_sha256(program: str) -> str:
    """SHA-256 (hex) of a program's text with surrounding whitespace stripped."""
    return hashlib.sha256(program.strip().encode("utf-8")).hexdigest()


@dataclass(frozen=True, eq=False)
class LogMatches:
    """What one program found in one log.

    Attributes:
        log_id: the log.
        description: the description mined.
        program_sha256: hash of the program that ran (:func:`program_sha256`).
        timestamps_ns: ``(T,)`` int64 timestamps of the mined log.
        track_ids: ``(N,)`` str track ids of the mined log.
        categories: ``(N,)`` str categories.
        referred: ``(N, T)`` bool, True where the track is a referred object.
        relations: ``(K, 3)`` int64 ``(referred row, timestamp index, related row)``.
        execution_s: seconds the program ran on this log.
    """

    log_id: str
    description: str
    program_sha256: str
    timestamps_ns: NDArray[np.int64]
    track_ids: NDArray[np.str_]
    categories: NDArray[np.str_]
    referred: BoolArray
    relations: IntArray
    execution_s: float = 0.0

    @classmethod
    def from_scenario(
        cls, scenario: Scenario, description: str, program: str, execution_s: float = 0.0
    ) -> LogMatches:
        """Record a program's scenario (ids and timestamps are taken from its log)."""
        log = scenario.context.log
        return cls(
            log_id=log.log_id,
            description=description,
            program_sha256=program_sha256(program),
            timestamps_ns=log.timestamps_ns,
            track_ids=log.track_ids,
            categories=log.categories,
            referred=np.asarray(scenario.referred, dtype=bool),
            relations=np.asarray(scenario.relations, dtype=np.int64),
            execution_s=execution_s,
        )

    @property
    def related(self) -> BoolArray:
        """``(N, T)`` bool, True where the track is related to some referred object."""
        out = np.zeros_like(self.referred)
        if self.relations.shape[0]:
            out[self.relations[:, 2], self.relations[:, 1]] = True
        return out

    @property
    def referred_track_ids(self) -> list[str]:
        """Ids of the tracks referred at least once, in log order."""
        return [str(t) for t in self.track_ids[self.referred.any(axis=1)]]

    @property
    def n_referred_timestamps(self) -> int:
        """Timestamps at which at least one object is referred."""
        return int(self.referred.any(axis=0).sum())

    def timestamps_of(self, track_id: str) -> NDArray[np.int64]:
        """``(k,)`` timestamps at which ``track_id`` is referred (empty if never)."""
        rows = np.flatnonzero(self.track_ids == track_id)
        if rows.size == 0:
            return np.zeros(0, dtype=np.int64)
        return np.asarray(self.timestamps_ns[self.referred[rows[0]]], dtype=np.int64)

    def restrict_timestamps(self, keep: BoolArray) -> LogMatches:
        """A copy whose referred cells and relations are limited to timestamps where ``keep`` ``(T,)``."""
        referred = self.referred & np.asarray(keep, dtype=bool)[None, :]
        rel = self.relations
        if rel.shape[0]:
            rel = rel[referred[rel[:, 0], rel[:, 1]]]
        return LogMatches(
            self.log_id,
            self.description,
            self.program_sha256,
            self.timestamps_ns,
            self.track_ids,
            self.categories,
            referred,
            rel,
            self.execution_s,
        )


def matches_table(matches: LogMatches) -> pa.Table:
    """The ``mining_results`` rows of one log: one per referred (track, timestamp) cell.

    Columns: ``description``, ``program_sha256``, ``track_id``, ``category``, ``timestamp_ns``,
    ``related_track_ids`` (list of str, the related objects at that cell).
    """
    rows, cols = np.nonzero(matches.referred)
    n = int(rows.size)
    rel = matches.relations
    shape = matches.referred.shape
    # every relation starts at a referred cell: find that cell's row in (rows, cols) order
    cell_of_rel = np.searchsorted(
        np.ravel_multi_index((rows, cols), shape) if n else np.zeros(0, dtype=np.int64),
        np.ravel_multi_index((rel[:, 0], rel[:, 1]), shape) if rel.shape[0] else np.zeros(0, dtype=np.int64),
    )
    order = np.argsort(cell_of_rel, kind="stable")
    offsets = np.searchsorted(cell_of_rel[order], np.arange(n + 1)).astype(np.int32)
    related = pa.ListArray.from_arrays(
        pa.array(offsets, type=pa.int32()),
        pa.array(matches.track_ids[rel[order, 2]].astype(str), type=pa.string()),
    )
    return pa.table(
        {
            "description": pa.array([matches.description] * n, type=pa.string()),
            "program_sha256": pa.array([matches.program_sha256] * n, type=pa.string()),
            "track_id": pa.array(matches.track_ids[rows].astype(str), type=pa.string()),
            "category": pa.array(matches.categories[rows].astype(str), type=pa.string()),
            "timestamp_ns": pa.array(matches.timestamps_ns[cols], type=pa.int64()),
            "related_track_ids": related,
        }
    )


def runs_table(matches: LogMatches, status: str = "ok", error: str = "") -> pa.Table:
    """The ``mining_runs`` row of one (log, description): what ran and how much it found."""
    return pa.table(
        {
            "description": pa.array([matches.description], type=pa.string()),
            "program_sha256": pa.array([matches.program_sha256], type=pa.string()),
            "status": pa.array([status], type=pa.string()),
            "error": pa.array([error], type=pa.string()),
            "n_referred_tracks": pa.array([len(matches.referred_track_ids)], type=pa.int64()),
            "n_referred_timestamps": pa.array([matches.n_referred_timestamps], type=pa.int64()),
            "n_referred_cells": pa.array([int(matches.referred.sum())], type=pa.int64()),
            "execution_s": pa.array([matches.execution_s], type=pa.float64()),
        }
    )


# ---------------------------------------------------------------------- Argoverse 2 submission


def evaluation_timestamps(log: Log, rate_hz: float = EVALUATION_RATE_HZ) -> NDArray[np.int64]:
    """The timestamps a scenario-mining evaluation looks at: every ``k``-th from the first.

    ``k = round((1 / rate_hz) / median time step)``, so 10 Hz annotations give every fifth
    timestamp at 2 Hz (the Argoverse 2 ground truth's frames).

    Args:
        log: the log.
        rate_hz: evaluation rate.
    """
    if rate_hz <= 0:
        raise ValueError(f"rate_hz must be > 0, got {rate_hz}")
    ts = log.timestamps_ns
    if ts.size < 2:
        return ts.copy()
    dt_s = float(np.median(np.diff(ts))) * 1e-9
    step = max(1, int(round(1.0 / rate_hz / dt_s)))
    return np.asarray(ts[::step], dtype=np.int64)


def _cells_on(matches: LogMatches, raw: Log, columns: NDArray[np.int64]) -> tuple[BoolArray, BoolArray]:
    """Referred and related masks ``(N_raw, len(columns))`` of ``matches`` on the raw log's grid.

    Tracks are matched by id, timestamps by exact value; cells of the raw log that the mined log
    does not have stay False.
    """
    n_raw = raw.n_tracks
    referred = np.zeros((n_raw, columns.size), dtype=bool)
    related = np.zeros_like(referred)
    row_of = {str(t): i for i, t in enumerate(matches.track_ids)}
    raw_rows = np.array([row_of.get(str(t), -1) for t in raw.track_ids], dtype=np.int64)
    ts = raw.timestamps_ns[columns]
    mcol = np.searchsorted(matches.timestamps_ns, ts)
    mcol_ok = (mcol < matches.timestamps_ns.size) & (
        matches.timestamps_ns[np.minimum(mcol, matches.timestamps_ns.size - 1)] == ts
    )
    have = raw_rows >= 0
    if have.any() and mcol_ok.any():
        sub_r = raw_rows[have]
        sub_c = mcol[mcol_ok]
        referred[np.ix_(have, mcol_ok)] = matches.referred[np.ix_(sub_r, sub_c)]
        related[np.ix_(have, mcol_ok)] = matches.related[np.ix_(sub_r, sub_c)]
    return referred, related


def av2_frames(
    matches: LogMatches,
    raw: Log,
    *,
    timestamps_ns: Sequence[int] | NDArray[np.int64] | None = None,
) -> list[dict[str, Any]]:
    """The submission frames of one (log, description), one per evaluation timestamp.

    Args:
        matches: what the program found (on the raw log or on a preprocessed copy of it with the
            same track ids and timestamps).
        raw: the log with the RAW boxes to report (see the module docstring).
        timestamps_ns: evaluation timestamps (e.g. the ground truth's); default
            :func:`evaluation_timestamps` of ``raw``. Each must be a timestamp of ``raw``.

    Returns:
        Frames in time order (see the module docstring for their keys).

    Raises:
        ValueError: the logs differ or a requested timestamp is not in ``raw``.
    """
    if matches.log_id != raw.log_id:
        raise ValueError(f"matches are for log {matches.log_id}, the raw log is {raw.log_id}")
    eval_ts = (
        evaluation_timestamps(raw) if timestamps_ns is None else np.asarray(timestamps_ns, dtype=np.int64)
    )
    columns = np.searchsorted(raw.timestamps_ns, eval_ts)
    bad = (columns >= raw.n_timestamps) | (
        raw.timestamps_ns[np.minimum(columns, raw.n_timestamps - 1)] != eval_ts
    )
    if bad.any():
        raise ValueError(
            f"log {raw.log_id} has no timestamp {int(eval_ts[bad][0])} (of {int(bad.sum())} requested)"
        )
    referred, related = _cells_on(matches, raw, columns)
    labels = np.full(referred.shape, int(ObjectLabel.OTHER), dtype=np.int32)
    labels[related] = int(ObjectLabel.RELATED)
    labels[referred] = int(ObjectLabel.REFERRED)
    ego = raw.ego_index
    pose_x, pose_y = raw.ego_pose_xy_m()  # the source's ego pose (AV2: rear axle), as the GT has it
    z = np.nan_to_num(raw.z_m, nan=0.0)
    height = np.nan_to_num(raw.height_m, nan=0.0)
    frames: list[dict[str, Any]] = []
    key = (raw.log_id, matches.description)
    for j, col in enumerate(columns):
        rows = np.flatnonzero(raw.valid[:, col])
        frames.append(
            {
                "seq_id": key,
                "timestamp_ns": np.int64(raw.timestamps_ns[col]),
                "ego_translation_m": [float(pose_x[col]), float(pose_y[col]), float(z[ego, col])],
                "description": matches.description,
                "translation_m": _box_positions(raw, rows, col, pose_x, pose_y, z),
                "size": np.stack(
                    [raw.length_m[rows, col], raw.width_m[rows, col], height[rows, col]], axis=1
                ).astype(np.float32),
                "yaw": raw.yaw_rad[rows, col].astype(np.float32),
                "velocity_m_per_s": np.stack(
                    [
                        np.nan_to_num(raw.vx_mps[rows, col]),
                        np.nan_to_num(raw.vy_mps[rows, col]),
                        np.zeros(rows.size),
                    ],
                    axis=1,
                ),
                "label": labels[rows, j].astype(np.int32),
                "name": _LABEL_NAMES[labels[rows, j]],
                "track_id": rows.astype(np.int32),
                "score": np.ones(rows.size, dtype=np.float32),
            }
        )
    return frames


def write_av2_submission(
    submission: Mapping[tuple[str, str], list[dict[str, Any]]], path: str | Path
) -> Path:
    """Write a scenario-mining submission pickle (``{(log_id, description): [frame, ...]}``).

    Returns:
        The path written (parent folders are created).
    """
    out = Path(path)
    out.parent.mkdir(parents=True, exist_ok=True)
    tmp = out.with_name(out.name + ".partial")
    with tmp.open("wb") as fh:
        pickle.dump(dict(submission), fh, protocol=pickle.HIGHEST_PROTOCOL)
    tmp.replace(out)
    return out


def _box_positions(
    raw: Log, rows: NDArray[np.intp], col: int, pose_x: FloatArray, pose_y: FloatArray, z: FloatArray
) -> FloatArray:
    """``(len(rows), 3)`` box positions at ``col``; the ego's at its source pose, as the AV2 GT places it."""
    xyz = np.stack([raw.x_m[rows, col], raw.y_m[rows, col], z[rows, col]], axis=1)
    ego = rows == raw.ego_index
    xyz[ego, 0], xyz[ego, 1] = pose_x[col], pose_y[col]
    return xyz


_FRAME_KEYS = ("timestamp_ns", "translation_m", "size", "yaw", "label", "track_id", "name")


def read_av2_submission(path: str | Path) -> Submission:
    """Read a scenario-mining submission or ground-truth pickle and check its layout.

    Only open files you trust: a pickle can run code when it is loaded.

    Raises:
        SubmissionFormatError: unreadable file, or not ``{(log_id, description): [frame, ...]}``
            with the per-frame keys the evaluator needs; the message names the key and frame.
    """
    p = Path(path)
    try:
        with p.open("rb") as fh:
            data = pickle.load(fh)  # noqa: S301 - the documented format of the benchmark
    except (OSError, pickle.UnpicklingError, EOFError, AttributeError, ImportError) as exc:
        raise SubmissionFormatError(f"{p}: cannot read the pickle ({type(exc).__name__}: {exc})") from None
    if not isinstance(data, dict):
        raise SubmissionFormatError(f"{p}: expected a dict {{(log_id, description): [frame, ...]}}")
    out: Submission = {}
    for key, frames in data.items():
        if not (isinstance(key, tuple) and len(key) == 2 and all(isinstance(k, str) for k in key)):
            raise SubmissionFormatError(f"{p}: key {key!r} is not a (log_id, description) pair of strings")
        if not isinstance(frames, list):
            raise SubmissionFormatError(f"{p}: {key!r} must map to a list of frames")
        for i, frame in enumerate(frames):
            if not isinstance(frame, dict):
                raise SubmissionFormatError(f"{p}: {key!r} frame {i} is not a dict")
            missing = [k for k in _FRAME_KEYS if k not in frame]
            if missing:
                raise SubmissionFormatError(f"{p}: {key!r} frame {i} lacks {missing}")
        out[key] = frames
    return out
