"""What the store records about logs (metadata, sources, summaries) and how a log becomes a table and back."""

from __future__ import annotations

import functools
import hashlib
import json
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

import numpy as np
import pyarrow as pa
import pyarrow.compute as pc

from scenariominer.data.log import STATE_FIELDS, Log, LogFormatError
from scenariominer.store.errors import (
    InvalidLogError,
    StoreError,
)
from scenariominer.store.layout import (
    SCHEMA_VERSION,
    TRACKS_TABLE,
)


@dataclass(frozen=True)
class LogMeta:
    """What the store knows about one log without reading its tracks.

    Attributes:
        log_id: the log's identifier.
        source_key: key of the source the log was ingested from.
        dataset: source format name (``av2``, ``highd``, ``tabular``, ``synthetic``).
        source_hash: content hash of the source files at ingestion.
        source_path: file or folder the log was read from, if any.
        map_dir: Argoverse 2 vector map folder, if any.
        n_tracks: number of tracks, the ego included.
        n_timestamps: number of timestamps.
        n_frames: number of valid (track, timestamp) cells.
        duration_s: time between the first and last timestamp, seconds.
        start_timestamp_ns: first timestamp, nanoseconds.
        end_timestamp_ns: last timestamp, nanoseconds.
        categories: number of tracks per category.
        notes: repairs applied while reading the log.
        ingested_at: when the log was last ingested (UTC).
        ego_pose_offset_m: see :attr:`Log.ego_pose_offset_m`.
    """

    log_id: str
    source_key: str
    dataset: str
    source_hash: str
    source_path: str | None
    map_dir: str | None
    n_tracks: int
    n_timestamps: int
    n_frames: int
    duration_s: float
    start_timestamp_ns: int
    end_timestamp_ns: int
    categories: Mapping[str, int]
    notes: tuple[str, ...]
    ingested_at: datetime
    ego_pose_offset_m: float = 0.0

    @classmethod
    def of_log(cls, log: Log, source_key: str, ingested_at: datetime) -> LogMeta:
        """Metadata of ``log`` as ingested from ``source_key`` at ``ingested_at``."""
        return cls(
            log_id=log.log_id,
            source_key=source_key,
            dataset=log.dataset,
            source_hash=log.source_hash,
            source_path=str(log.source_path) if log.source_path is not None else None,
            map_dir=str(log.map_dir) if log.map_dir is not None else None,
            n_tracks=log.n_tracks,
            n_timestamps=log.n_timestamps,
            n_frames=log.n_frames,
            duration_s=log.duration_s,
            start_timestamp_ns=int(log.timestamps_ns[0]),
            end_timestamp_ns=int(log.timestamps_ns[-1]),
            categories=log.category_counts(),
            notes=tuple(log.notes),
            ingested_at=ingested_at,
            ego_pose_offset_m=float(log.ego_pose_offset_m),
        )

    def to_json_dict(self) -> dict[str, Any]:
        """JSON-serialisable form (``ingested_at`` as ISO 8601)."""
        out = {name: getattr(self, name) for name in self.__dataclass_fields__}
        out["categories"] = dict(self.categories)
        out["notes"] = list(self.notes)
        out["ingested_at"] = self.ingested_at.isoformat()
        return out

    @classmethod
    def from_json_dict(cls, data: Mapping[str, Any]) -> LogMeta:
        """Inverse of :meth:`to_json_dict`."""
        fields = {name: data[name] for name in cls.__dataclass_fields__ if name in data}
        fields["categories"] = {str(k): int(v) for k, v in data["categories"].items()}
        fields["notes"] = tuple(data["notes"])
        fields["ingested_at"] = datetime.fromisoformat(data["ingested_at"])
        return cls(**fields)


@dataclass(frozen=True)
class SourceRecord:
    """One ingested source.

    Attributes:
        source_key: stable identifier of the source (see :class:`~scenariominer.data.sources.LogSource`).
        content_hash: hash the source had when it was last ingested.
        log_ids: logs the source yielded, sorted.
        ingested_at: when it was last ingested (UTC).
    """

    source_key: str
    content_hash: str
    log_ids: tuple[str, ...]
    ingested_at: datetime


@dataclass(frozen=True)
class StoreInfo:
    """Summary of a store's content.

    Attributes:
        root: the store directory.
        schema_version: layout version of the store.
        n_sources: ingested sources.
        n_logs: logs.
        n_tracks: tracks over all logs, egos included.
        n_timestamps: timestamps over all logs.
        n_frames: valid (track, timestamp) cells over all logs.
        total_duration_s: summed log durations, seconds.
        categories: tracks per category over all logs.
        datasets: logs per dataset name.
        tables: derived table names present (``tracks`` excluded), sorted.
        table_logs: number of logs holding each derived table.
        size_bytes: bytes on disk under the root.
    """

    root: Path
    schema_version: int
    n_sources: int
    n_logs: int
    n_tracks: int
    n_timestamps: int
    n_frames: int
    total_duration_s: float
    categories: Mapping[str, int] = field(default_factory=dict)
    datasets: Mapping[str, int] = field(default_factory=dict)
    tables: tuple[str, ...] = ()
    table_logs: Mapping[str, int] = field(default_factory=dict)
    size_bytes: int = 0


@dataclass(frozen=True)
class StoreCheck:
    """Result of :meth:`ScenarioStore.check`.

    Attributes:
        root: the store directory.
        n_logs: logs in the catalog.
        orphaned_files: files and folders under ``logs/`` that no catalog entry references (leftovers
            of a killed writer; :meth:`ScenarioStore.vacuum` removes them).
        missing_files: files the catalog references that are gone (damage: re-ingest those logs).
        stale_staging: staging folders of writers that are gone (removed by ``vacuum``).
        corpus_tables: names of the corpus-level tables.
    """

    root: str
    n_logs: int
    orphaned_files: tuple[str, ...]
    missing_files: tuple[str, ...]
    stale_staging: tuple[str, ...]
    corpus_tables: tuple[str, ...]

    @property
    def ok(self) -> bool:
        """True when nothing is missing (orphans and stale staging are harmless leftovers)."""
        return not self.missing_files


@dataclass(frozen=True)
class _LogRow:
    log_id: str
    source_key: str
    dir: str
    digest: str
    meta_json: str = "{}"

    @functools.cached_property
    def meta(self) -> LogMeta:
        return LogMeta.from_json_dict(json.loads(self.meta_json))


@dataclass(frozen=True)
class _Snapshot:
    """One consistent read of the catalog (``tables`` possibly restricted to some names)."""

    generation: int
    n_sources: int
    logs: dict[str, _LogRow]
    tables: dict[str, dict[str, str]]  # table name -> log id -> file (relative to the root)
    table_names: tuple[str, ...]  # every table name present, ``tracks`` included


def _now() -> datetime:
    return datetime.now(UTC)


def _meta_file(meta: LogMeta, digest: str) -> dict[str, Any]:
    return {**meta.to_json_dict(), "content_digest": digest, "schema_version": SCHEMA_VERSION}


def _meta_table(rows: Sequence[_LogRow], snap: _Snapshot) -> pa.Table:
    """Build the ``meta`` view: one row per log."""
    metas = [r.meta for r in rows]
    has: dict[str, list[str]] = {}
    for name in sorted(snap.tables):
        if name != TRACKS_TABLE:
            for log_id in snap.tables[name]:
                has.setdefault(log_id, []).append(name)

    def col(name: str) -> list[Any]:
        return [getattr(m, name) for m in metas]

    return pa.table(
        {
            "log_id": pa.array(col("log_id"), pa.string()),
            "source_key": pa.array(col("source_key"), pa.string()),
            "dataset": pa.array(col("dataset"), pa.string()),
            "source_hash": pa.array(col("source_hash"), pa.string()),
            "source_path": pa.array(col("source_path"), pa.string()),
            "map_dir": pa.array(col("map_dir"), pa.string()),
            "n_tracks": pa.array(col("n_tracks"), pa.int64()),
            "n_timestamps": pa.array(col("n_timestamps"), pa.int64()),
            "n_frames": pa.array(col("n_frames"), pa.int64()),
            "duration_s": pa.array(col("duration_s"), pa.float64()),
            "start_timestamp_ns": pa.array(col("start_timestamp_ns"), pa.int64()),
            "end_timestamp_ns": pa.array(col("end_timestamp_ns"), pa.int64()),
            "categories": pa.array(
                [list(m.categories.items()) for m in metas], pa.map_(pa.string(), pa.int64())
            ),
            "notes": pa.array([list(m.notes) for m in metas], pa.list_(pa.string())),
            "tables": pa.array([has.get(m.log_id, []) for m in metas], pa.list_(pa.string())),
            "ingested_at": pa.array(col("ingested_at"), pa.timestamp("us", tz="UTC")),
            "ego_pose_offset_m": pa.array(col("ego_pose_offset_m"), pa.float64()),
        }
    )


def _check_storable(log: Log) -> None:
    """Refuse logs that the long-table format cannot restore exactly."""
    if not isinstance(log, Log):
        raise InvalidLogError(f"expected a Log, got {type(log).__name__}")
    n, t = log.n_tracks, log.n_timestamps
    if log.ego_index != 0:
        raise InvalidLogError(f"log {log.log_id}: the ego must be track 0 (build logs with build_log)")
    if t == 0 or n == 0:
        raise InvalidLogError(f"log {log.log_id}: the log is empty")
    if log.valid.shape != (n, t):
        raise InvalidLogError(f"log {log.log_id}: valid has shape {log.valid.shape}, expected {(n, t)}")
    empty_tracks = ~log.valid.any(axis=1)
    if empty_tracks.any():
        ids = log.track_ids[empty_tracks][:3].tolist()
        raise InvalidLogError(f"log {log.log_id}: track(s) {ids} have no valid cell and cannot be stored")
    empty_times = ~log.valid.any(axis=0)
    if empty_times.any():
        ts = log.timestamps_ns[empty_times][:3].tolist()
        raise InvalidLogError(f"log {log.log_id}: timestamp(s) {ts} have no valid cell and cannot be stored")
    for name in STATE_FIELDS:
        values = getattr(log, name)
        bad = log.valid & ~np.isfinite(values)
        if bad.any():
            r, c = (int(i[0]) for i in np.nonzero(bad))
            raise InvalidLogError(
                f"log {log.log_id}: {name} is not finite in {int(bad.sum())} valid cell(s), e.g. track "
                f"{str(log.track_ids[r])!r} at timestamp_ns={int(log.timestamps_ns[c])}"
            )


def _log_digest(log: Log) -> str:
    """SHA-256 over everything the tracks file stores (arrays at valid cells, ids, categories)."""
    h = hashlib.sha256()
    h.update(
        json.dumps([log.dataset, str(log.map_dir) if log.map_dir else None, log.ego_pose_offset_m]).encode()
    )
    h.update(np.ascontiguousarray(log.timestamps_ns, dtype="<i8").tobytes())
    for names in (log.track_ids, log.categories):
        h.update("\x1f".join(str(s) for s in names.tolist()).encode())
        h.update(b"\x1e")
    h.update(np.packbits(log.valid).tobytes())
    h.update(np.asarray(log.valid.shape, dtype="<i8").tobytes())
    for name in STATE_FIELDS:
        h.update(np.ascontiguousarray(getattr(log, name)[log.valid], dtype="<f8").tobytes())
    return h.hexdigest()


def _log_from_table(table: pa.Table, meta: LogMeta, path: Path) -> Log:
    """Rebuild a stored log: :meth:`Log.from_arrow`, then the stored track order and metadata."""
    if "log_id" in table.column_names:
        table = table.drop_columns(["log_id"])
    try:
        log = Log.from_arrow(
            table,
            log_id=meta.log_id,
            source=path,
            dataset=meta.dataset,
            map_dir=Path(meta.map_dir) if meta.map_dir else None,
            source_hash=meta.source_hash,
            min_track_frames=1,
        )
    except LogFormatError as exc:
        raise StoreError(f"stored log {meta.log_id} is corrupt: {exc}") from None
    stored_ids = table.column("track_id").to_numpy(zero_copy_only=False).astype(str)
    uniq, first = np.unique(stored_ids, return_index=True)
    stored_order = uniq[np.argsort(first)]
    if not np.array_equal(stored_order, log.track_ids):
        position = {str(tid): i for i, tid in enumerate(log.track_ids.tolist())}
        log = log.select_tracks(np.asarray([position[str(tid)] for tid in stored_order], dtype=np.int64))
    if (log.n_tracks, log.n_timestamps, log.n_frames) != (meta.n_tracks, meta.n_timestamps, meta.n_frames):
        raise StoreError(f"stored log {meta.log_id} is corrupt: its tracks file disagrees with its metadata")
    return log.replace(
        source_path=Path(meta.source_path) if meta.source_path else None,
        notes=tuple(meta.notes),
        ego_pose_offset_m=meta.ego_pose_offset_m,
    )


def _with_log_id(table: pa.Table, log_id: str, name: str) -> pa.Table:
    """``table`` with a leading ``log_id`` string column equal to ``log_id`` everywhere."""
    if not isinstance(table, pa.Table):
        raise ValueError(f"table {name!r} must be a pyarrow.Table, got {type(table).__name__}")
    if "log_id" in table.column_names:
        column = table.column("log_id")
        agrees = column.null_count == 0 and (
            table.num_rows == 0 or bool(pc.all(pc.equal(column.cast(pa.string()), log_id)).as_py())
        )
        if not agrees:
            raise ValueError(f"table {name!r} for log {log_id!r} has a log_id column with other values")
        table = table.drop_columns(["log_id"])
    return table.add_column(0, "log_id", pa.repeat(pa.scalar(log_id, pa.string()), table.num_rows))
