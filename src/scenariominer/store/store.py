"""The scenario store: a directory of Parquet files, a SQLite catalog, and DuckDB for queries.

Layout under the store root::

    store.json                              format marker and schema version (written first)
    catalog.sqlite                          which files are current: sources, logs, tables
    logs/<log dir>/<version>/tracks.parquet Log.to_arrow() long table plus a log_id column
    logs/<log dir>/<version>/meta.json      the log's metadata (a human-readable copy)
    logs/<log dir>/<version>/<table>.<token>.parquet   derived tables (tags, events, embeddings, ...)
    .staging/                               files being written; never referenced by the catalog

Every data file is immutable once written: an update writes new files, then switches the
catalog to them in one SQLite transaction, then deletes the files it replaced. That commit is
the only moment a change becomes visible, so

* a failure at any point before it (an exception, a full disk, a killed process) leaves the
  previous state intact and no partial rows visible; leftovers are cleaned up on the spot, or
  by :meth:`ScenarioStore.vacuum` after a hard crash;
* every read (``sql``, ``read_table``, ``load_log``, ``info``) works on one consistent catalog
  snapshot, so a reader in another thread or process sees a whole source before or after a
  re-ingest, never a mix; if a writer deletes a file the reader was about to open, the read is
  retried on the new snapshot;
* writers are serialised by SQLite's write lock (held only for the short commit step, never
  while Parquet is being encoded); readers take no lock beyond SQLite's brief shared lock.

``<log dir>`` is the log id with every character outside ``[A-Za-z0-9_.-]`` percent-encoded
(and a leading dot encoded), so any log id is a safe, glob-free directory name.
"""

from __future__ import annotations

import contextlib
import functools
import hashlib
import json
import os
import re
import shutil
import sqlite3
import threading
import time
import uuid
from collections import Counter
from collections.abc import Collection, Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from datetime import UTC, datetime
from pathlib import Path
from typing import Any
from urllib.parse import quote

import duckdb
import numpy as np
import pyarrow as pa
import pyarrow.compute as pc
import pyarrow.parquet as pq

from scenariominer import errors as _errors
from scenariominer.data.log import STATE_FIELDS, Log, LogFormatError
from scenariominer.store.corpus import CorpusTable, CorpusTableInfo, list_corpus_tables

#: Value of ``format`` in ``store.json``.
STORE_FORMAT = "scenariominer-store"
#: Layout version written by this code; a store with a higher version is refused.
SCHEMA_VERSION = 1
#: Environment variable naming the store directory (see :func:`resolve_store_path`).
STORE_ENV_VAR = "SCENARIOMINER_STORE"
#: Name of the per-observation table of every log.
TRACKS_TABLE = "tracks"
#: Name of the one-row-per-log metadata view available in :meth:`ScenarioStore.sql`.
META_TABLE = "meta"
#: Table names a caller cannot write.
RESERVED_TABLES = frozenset({TRACKS_TABLE, META_TABLE})

_MARKER = "store.json"
_CATALOG = "catalog.sqlite"
_LOGS_DIR = "logs"
_STAGING_DIR = ".staging"
_TABLE_NAME_RE = re.compile(r"^[a-z][a-z0-9_]{0,62}$")
_MAX_DIR_NAME = 200
_READ_ATTEMPTS = 5
_BUSY_TIMEOUT_S = 60.0
#: Staging folders older than this are stale even when their writer's pid is alive (pid reuse).
_STAGING_MAX_AGE_S = 24 * 3600.0
_PARQUET_COMPRESSION = "zstd"

_CATALOG_SCHEMA = """
CREATE TABLE IF NOT EXISTS state (key TEXT PRIMARY KEY, value INTEGER NOT NULL);
INSERT OR IGNORE INTO state (key, value) VALUES ('generation', 0);
CREATE TABLE IF NOT EXISTS sources (
    source_key TEXT PRIMARY KEY,
    content_hash TEXT NOT NULL,
    ingested_at TEXT NOT NULL
);
CREATE TABLE IF NOT EXISTS logs (
    log_id TEXT PRIMARY KEY,
    source_key TEXT NOT NULL,
    dir TEXT NOT NULL,
    digest TEXT NOT NULL,
    meta TEXT NOT NULL
);
CREATE INDEX IF NOT EXISTS logs_by_source ON logs (source_key);
CREATE TABLE IF NOT EXISTS log_tables (
    log_id TEXT NOT NULL,
    name TEXT NOT NULL,
    file TEXT NOT NULL,
    n_rows INTEGER NOT NULL,
    PRIMARY KEY (log_id, name)
);
CREATE INDEX IF NOT EXISTS log_tables_by_name ON log_tables (name);
"""


# ---------------------------------------------------------------------- errors


class StoreError(_errors.StoreError):
    """Base class of every error raised by the store."""


class NotAStoreError(StoreError):
    """A directory cannot be opened as a store; the message names the path and the reason.

    Attributes:
        path: the directory that was to be opened.
        problem: one-line description of what is wrong.
    """

    def __init__(self, path: str | Path, problem: str) -> None:
        self.path = str(path)
        self.problem = problem
        super().__init__(f"{self.path}: {problem}")


class StoreVersionError(StoreError):
    """The store was written by a newer scenariominer with an unknown layout version."""


class UnknownLogError(StoreError, LookupError):
    """A log id is not in the store."""

    def __init__(self, log_id: str) -> None:
        self.log_id = log_id
        super().__init__(f"log {log_id!r} is not in the store")

    def __str__(self) -> str:
        return str(self.args[0])


class UnknownTableError(StoreError, LookupError):
    """A table name is not present in the store; the message lists the tables that are."""

    def __init__(self, name: str, available: Sequence[str]) -> None:
        self.name = name
        self.available = tuple(available)
        super().__init__(f"no table {name!r} in the store; available: {', '.join(self.available) or 'none'}")

    def __str__(self) -> str:
        return str(self.args[0])


class InvalidNameError(StoreError, ValueError):
    """A table name or log id cannot be used (the message says why)."""


class InvalidLogError(StoreError, ValueError):
    """A log cannot be stored without losing information (the message names the log and the cell)."""


class LogConflictError(StoreError, ValueError):
    """A source tried to write a log id that another source already owns."""


class QueryError(StoreError):
    """A SQL query failed; the message carries DuckDB's explanation and the available tables."""


# ---------------------------------------------------------------------- records


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


# ---------------------------------------------------------------------- locations


def default_store_path() -> Path:
    """Return the per-user default store, ``platformdirs.user_data_dir("scenariominer")/store``."""
    from platformdirs import user_data_dir

    return Path(user_data_dir("scenariominer")) / "store"


def resolve_store_path(
    path: str | Path | None = None,
    config_path: str | Path | None = None,
    *,
    environ: Mapping[str, str] | None = None,
) -> Path:
    """Where the store lives, by precedence: ``path`` > ``$SCENARIOMINER_STORE`` > config > default.

    Args:
        path: an explicit directory (e.g. the ``--store`` option); wins when given.
        config_path: ``config.store.path``; empty or ``None`` means unset.
        environ: environment mapping (defaults to ``os.environ``).

    Returns:
        The store directory, ``~`` expanded (it may not exist yet).
    """
    env = os.environ if environ is None else environ
    for candidate in (path, env.get(STORE_ENV_VAR), config_path):
        if candidate is not None and str(candidate).strip():
            return Path(candidate).expanduser()
    return default_store_path()


def log_dir_name(log_id: str) -> str:
    """Directory name of a log: the id with unsafe characters percent-encoded.

    Raises:
        InvalidNameError: the id is empty, has control characters, or encodes to over 200 characters.
    """
    if not isinstance(log_id, str) or not log_id:
        raise InvalidNameError(f"log id must be a non-empty string, got {log_id!r}")
    if any(ord(ch) < 32 or ord(ch) == 127 for ch in log_id):
        raise InvalidNameError(f"log id {log_id!r} contains control characters")
    encoded = quote(log_id, safe="-_")
    encoded = encoded.replace("~", "%7E")
    if encoded.startswith("."):
        encoded = "%2E" + encoded[1:]
    if len(encoded) > _MAX_DIR_NAME:
        raise InvalidNameError(
            f"log id {log_id[:40]!r} is too long ({len(encoded)} > {_MAX_DIR_NAME} encoded)"
        )
    return encoded


def check_table_name(name: str) -> str:
    """Validate a derived table name and return it.

    A table name must be a lower-case SQL identifier (``[a-z][a-z0-9_]*``, at most 63
    characters), not a reserved SQL keyword, and not ``tracks`` or ``meta``.

    Raises:
        InvalidNameError: the name breaks one of these rules.
    """
    if not isinstance(name, str) or not _TABLE_NAME_RE.match(name):
        raise InvalidNameError(
            f"table name {name!r} is not a lower-case identifier ([a-z][a-z0-9_]*, at most 63 characters)"
        )
    if name in RESERVED_TABLES:
        raise InvalidNameError(f"table name {name!r} is reserved by the store")
    if name in _reserved_sql_keywords():
        raise InvalidNameError(f"table name {name!r} is a reserved SQL keyword")
    return name


_KEYWORDS: frozenset[str] | None = None


def _reserved_sql_keywords() -> frozenset[str]:
    global _KEYWORDS
    if _KEYWORDS is None:
        with duckdb.connect(":memory:") as con:
            rows = con.execute(
                "SELECT keyword_name FROM duckdb_keywords() WHERE keyword_category = 'reserved'"
            ).fetchall()
        _KEYWORDS = frozenset(str(r[0]).lower() for r in rows)
    return _KEYWORDS


# ---------------------------------------------------------------------- the store


class ScenarioStore:
    """A scenario store rooted at a directory (see the module docstring for the layout).

    Open with :meth:`open` (or the constructor). Every method is safe to call from several
    threads and processes at once: each call opens its own short-lived SQLite connection, and
    queries run on a private cursor of one in-memory DuckDB database per store object, so no
    file lock is held between calls. Do not share a store object across ``fork``; open it again.
    """

    def __init__(self, root: str | Path, *, create: bool = True) -> None:
        """Open the store at ``root``, creating it when ``create`` and the directory is absent or empty.

        Raises:
            NotAStoreError: ``root`` is a file, a non-empty directory without ``store.json``
                (the store never writes into an arbitrary directory), or absent with ``create=False``.
            StoreVersionError: the store was written by a newer, incompatible version.
        """
        self._root = Path(root).expanduser().absolute()
        self._duckdb: duckdb.DuckDBPyConnection | None = None
        self._duckdb_lock = threading.Lock()
        marker = self._root / _MARKER
        if self._root.exists() and not self._root.is_dir():
            raise NotAStoreError(self._root, "is a file, not a store directory")
        if marker.is_file():
            self._check_marker(marker)
        elif self._root.is_dir() and any(self._root.iterdir()):
            raise NotAStoreError(
                self._root,
                f"directory is not empty and has no {_MARKER}; refusing to use it as a store "
                "(choose an empty or new directory)",
            )
        elif not create:
            raise NotAStoreError(self._root, "no store here")
        else:
            self._root.mkdir(parents=True, exist_ok=True)
            _write_json_atomic(
                marker,
                {"format": STORE_FORMAT, "schema_version": SCHEMA_VERSION, "created_at": _now().isoformat()},
            )
        if not (self._root / _CATALOG).exists():
            with contextlib.closing(self._connect()) as con:
                con.executescript(_CATALOG_SCHEMA)

    @classmethod
    def open(cls, root: str | Path, *, create: bool = True) -> ScenarioStore:
        """Open the store at ``root`` (see :meth:`__init__`)."""
        return cls(root, create=create)

    @property
    def root(self) -> Path:
        """The store directory (absolute)."""
        return self._root

    def __repr__(self) -> str:
        return f"ScenarioStore({str(self._root)!r})"

    # ------------------------------------------------------------------ catalog reads
    def log_ids(self) -> list[str]:
        """Every log id in the store, sorted."""
        with contextlib.closing(self._connect()) as con:
            return [r[0] for r in con.execute("SELECT log_id FROM logs ORDER BY log_id")]

    def logs_of_source(self, source_key: str) -> list[str]:
        """Log ids the source yielded when it was last ingested, sorted (empty if unknown)."""
        with contextlib.closing(self._connect()) as con:
            rows = con.execute("SELECT log_id FROM logs WHERE source_key = ? ORDER BY log_id", (source_key,))
            return [r[0] for r in rows]

    def needs_ingest(self, source_key: str, content_hash: str) -> bool:
        """Whether ``source_key`` is absent or was ingested with a different ``content_hash``."""
        with contextlib.closing(self._connect()) as con:
            row = con.execute(
                "SELECT content_hash FROM sources WHERE source_key = ?", (source_key,)
            ).fetchone()
        return row is None or row[0] != content_hash

    def sources(self) -> list[SourceRecord]:
        """Every ingested source, sorted by key."""
        with contextlib.closing(self._connect()) as con:
            con.execute("BEGIN")
            src = con.execute("SELECT source_key, content_hash, ingested_at FROM sources ORDER BY source_key")
            rows = src.fetchall()
            by_source: dict[str, list[str]] = {}
            for log_id, key in con.execute("SELECT log_id, source_key FROM logs ORDER BY log_id"):
                by_source.setdefault(key, []).append(log_id)
            con.execute("COMMIT")
        return [
            SourceRecord(key, h, tuple(by_source.get(key, ())), datetime.fromisoformat(at))
            for key, h, at in rows
        ]

    def log_meta(self, log_id: str) -> LogMeta:
        """Metadata of one log (no track data is read).

        Raises:
            UnknownLogError: the log is not in the store.
        """
        with contextlib.closing(self._connect()) as con:
            row = con.execute("SELECT meta FROM logs WHERE log_id = ?", (log_id,)).fetchone()
        if row is None:
            raise UnknownLogError(log_id)
        return LogMeta.from_json_dict(json.loads(row[0]))

    def table_names(self) -> list[str]:
        """List the derived table names present in at least one log, sorted (``tracks`` excluded)."""
        with contextlib.closing(self._connect()) as con:
            rows = con.execute(
                "SELECT DISTINCT name FROM log_tables WHERE name != ? ORDER BY name", (TRACKS_TABLE,)
            )
            return [r[0] for r in rows]

    # ------------------------------------------------------------------ ingestion
    def corpus(self, name: str, schema_version: int = 1) -> CorpusTable:
        """The corpus-level table ``name`` (created on first write; see :mod:`scenariominer.store.corpus`).

        Raises:
            InvalidNameError: ``name`` is not a valid table name.
            CorpusSchemaError: the table was written with another ``schema_version``.
        """
        return CorpusTable(self._root / _CATALOG, check_table_name(name), schema_version)

    def corpus_tables(self) -> list[CorpusTableInfo]:
        """Every corpus-level table with its schema version, version and row count."""
        return list_corpus_tables(self._root / _CATALOG)

    def replace_source(self, source_key: str, content_hash: str, logs: Sequence[Log]) -> list[str]:
        """Make ``logs`` the complete, current content of source ``source_key``, atomically.

        New and changed logs are written to staging first; then one catalog transaction
        switches to them, drops the logs the source no longer yields, and records
        ``content_hash``. Readers see the whole source before or after, never a mix.
        A log whose content (arrays, track ids, categories, dataset, map folder) is unchanged
        keeps its files and its derived tables; a changed log loses its derived tables,
        which were computed from the old data.

        Args:
            source_key: stable identifier of the source.
            content_hash: content hash of the source files (see :meth:`needs_ingest`).
            logs: every log the source yields; log ids must be unique. An empty sequence
                removes every log of the source (and still records ``content_hash``).

        Returns:
            The source's log ids, in the order given.

        Raises:
            InvalidLogError: a log cannot be stored losslessly (e.g. a non-finite value in a
                valid cell, a track or timestamp without any valid cell), or ids repeat.
            InvalidNameError: a log id cannot be used as a directory name.
            LogConflictError: a log id belongs to another source.
        """
        logs = list(logs)
        ids = [log.log_id for log in logs]
        dupes = sorted(i for i, c in Counter(ids).items() if c > 1)
        if dupes:
            raise InvalidLogError(f"source {source_key}: log id(s) {dupes[:5]} occur more than once")
        for log in logs:
            log_dir_name(log.log_id)
            _check_storable(log)
        digests = {log.log_id: _log_digest(log) for log in logs}
        with contextlib.closing(self._connect()) as con:
            before = _log_rows(con, source_key, ids)
        self._check_owners(source_key, ids, before)

        staging = self._new_staging()
        staged: dict[str, Path] = {}
        moved: list[Path] = []
        garbage: list[Path] = []
        kept: list[tuple[Path, LogMeta]] = []
        now = _now()
        metas = {log.log_id: LogMeta.of_log(log, source_key, now) for log in logs}
        try:
            for log in logs:
                row = before.get(log.log_id)
                if row is None or row.digest != digests[log.log_id]:
                    staged[log.log_id] = self._stage_log(staging, log, metas[log.log_id], digests[log.log_id])
            with self._write_txn() as con:
                current = _log_rows(con, source_key, ids)
                self._check_owners(source_key, ids, current)
                for log in logs:
                    log_id = log.log_id
                    row = current.get(log_id)
                    meta_json = json.dumps(metas[log_id].to_json_dict())
                    if log_id not in staged and (row is None or row.digest != digests[log_id]):
                        # Another writer changed the log since our first look: write it now.
                        staged[log_id] = self._stage_log(staging, log, metas[log_id], digests[log_id])
                    if log_id not in staged:
                        assert row is not None
                        con.execute("UPDATE logs SET meta = ? WHERE log_id = ?", (meta_json, log_id))
                        kept.append((self._root / row.dir, metas[log_id]))
                        continue
                    final = self._root / _LOGS_DIR / log_dir_name(log_id) / staged[log_id].name
                    final.parent.mkdir(parents=True, exist_ok=True)
                    os.replace(staged[log_id], final)
                    moved.append(final)
                    if row is not None:
                        garbage.append(self._root / row.dir)
                    rel_dir = final.relative_to(self._root).as_posix()
                    con.execute("DELETE FROM log_tables WHERE log_id = ?", (log_id,))
                    con.execute(
                        "INSERT OR REPLACE INTO logs (log_id, source_key, dir, digest, meta) "
                        "VALUES (?, ?, ?, ?, ?)",
                        (log_id, source_key, rel_dir, digests[log_id], meta_json),
                    )
                    con.execute(
                        "INSERT INTO log_tables (log_id, name, file, n_rows) VALUES (?, ?, ?, ?)",
                        (log_id, TRACKS_TABLE, f"{rel_dir}/{TRACKS_TABLE}.parquet", log.n_frames),
                    )
                wanted = set(ids)
                for row in current.values():
                    if row.source_key == source_key and row.log_id not in wanted:
                        _delete_log_rows(con, row.log_id)
                        garbage.append(self._root / row.dir)
                con.execute(
                    "INSERT OR REPLACE INTO sources (source_key, content_hash, ingested_at) VALUES (?, ?, ?)",
                    (source_key, content_hash, now.isoformat()),
                )
        except BaseException:
            for path in moved:
                _remove_tree(path)
            raise
        finally:
            _remove_tree(staging)
        for version_dir, meta in kept:
            with contextlib.suppress(OSError):
                _write_json_atomic(version_dir / "meta.json", _meta_file(meta, digests[meta.log_id]))
        self._discard(garbage)
        return ids

    def remove_log(self, log_id: str) -> None:
        """Remove a log with all its tables.

        The log's source is forgotten too (its other logs stay), so the next ingestion of that
        source re-ingests it instead of skipping it as unchanged.

        Raises:
            UnknownLogError: the log is not in the store.
        """
        with self._write_txn() as con:
            row = con.execute("SELECT source_key, dir FROM logs WHERE log_id = ?", (log_id,)).fetchone()
            if row is None:
                raise UnknownLogError(log_id)
            _delete_log_rows(con, log_id)
            con.execute("DELETE FROM sources WHERE source_key = ?", (row[0],))
        self._discard([self._root / row[1]])

    def remove_source(self, source_key: str) -> list[str]:
        """Remove a source and every log it yielded; returns the removed log ids (empty if unknown)."""
        with self._write_txn() as con:
            rows = con.execute(
                "SELECT log_id, dir FROM logs WHERE source_key = ? ORDER BY log_id", (source_key,)
            ).fetchall()
            for log_id, _ in rows:
                _delete_log_rows(con, log_id)
            con.execute("DELETE FROM sources WHERE source_key = ?", (source_key,))
        self._discard([self._root / d for _, d in rows])
        return [log_id for log_id, _ in rows]

    # ------------------------------------------------------------------ logs
    def load_log(self, log_id: str) -> Log:
        """Read a log back exactly as it was stored (same tracks, order, cells and metadata).

        Raises:
            UnknownLogError: the log is not in the store.
        """
        for attempt in range(_READ_ATTEMPTS):
            with contextlib.closing(self._connect()) as con:
                con.execute("BEGIN")
                row = con.execute("SELECT meta FROM logs WHERE log_id = ?", (log_id,)).fetchone()
                file = con.execute(
                    "SELECT file FROM log_tables WHERE log_id = ? AND name = ?", (log_id, TRACKS_TABLE)
                ).fetchone()
                con.execute("COMMIT")
            if row is None or file is None:
                raise UnknownLogError(log_id)
            path = self._root / file[0]
            try:
                table = pq.read_table(path)
            except FileNotFoundError:
                if attempt + 1 < _READ_ATTEMPTS:
                    continue
                raise
            return _log_from_table(table, LogMeta.from_json_dict(json.loads(row[0])), path)
        raise AssertionError("unreachable")  # pragma: no cover

    # ------------------------------------------------------------------ derived tables
    def write_table(self, log_id: str, name: str, table: pa.Table) -> None:
        """Store (or replace) derived table ``name`` of log ``log_id`` atomically.

        The stored table gets a leading ``log_id`` string column; if ``table`` already has
        one, every value must equal ``log_id``.

        Raises:
            InvalidNameError: ``name`` is not a valid table name (see :func:`check_table_name`).
            UnknownLogError: the log is not in the store.
            ValueError: ``table`` is not a ``pyarrow.Table`` or its ``log_id`` column disagrees.
        """
        self.write_tables(log_id, {name: table})

    def write_tables(self, log_id: str, tables: Mapping[str, pa.Table]) -> None:
        """Store several derived tables of one log in one atomic step (see :meth:`write_table`)."""
        self._write_derived({log_id: tables})

    def write_table_batch(self, name: str, tables_by_log: Mapping[str, pa.Table]) -> None:
        """Store derived table ``name`` for many logs in one atomic step (one catalog commit).

        Prefer this over a loop of :meth:`write_table` when a stage has processed many logs:
        the cost of a commit is paid once.

        Args:
            name: derived table name.
            tables_by_log: the table of each log, by log id (an empty table records
                "computed, nothing found").
        """
        self._write_derived({log_id: {name: table} for log_id, table in tables_by_log.items()})

    def _write_derived(self, entries: Mapping[str, Mapping[str, pa.Table]]) -> None:
        prepared = {
            log_id: {check_table_name(n): _with_log_id(t, log_id, n) for n, t in tables.items()}
            for log_id, tables in entries.items()
        }
        prepared = {log_id: tables for log_id, tables in prepared.items() if tables}
        if not prepared:
            return
        with contextlib.closing(self._connect()) as con:
            known = _existing_logs(con, list(prepared))
        unknown = [log_id for log_id in prepared if log_id not in known]
        if unknown:
            raise UnknownLogError(unknown[0])
        staging = self._new_staging()
        moved: list[Path] = []
        garbage: list[Path] = []
        try:
            staged: list[tuple[str, str, Path, int]] = []
            for log_id, tables in prepared.items():
                for name, table in tables.items():
                    path = staging / f"{name}.{uuid.uuid4().hex[:12]}.parquet"
                    _write_parquet(table, path)
                    staged.append((log_id, name, path, table.num_rows))
            with self._write_txn() as con:
                dirs = _existing_logs(con, list(prepared))
                for log_id, name, path, n_rows in staged:
                    if log_id not in dirs:
                        raise UnknownLogError(log_id)
                    final = self._root / dirs[log_id] / path.name
                    os.replace(path, final)
                    moved.append(final)
                    old = con.execute(
                        "SELECT file FROM log_tables WHERE log_id = ? AND name = ?", (log_id, name)
                    ).fetchone()
                    if old is not None:
                        garbage.append(self._root / old[0])
                    con.execute(
                        "INSERT OR REPLACE INTO log_tables (log_id, name, file, n_rows) VALUES (?, ?, ?, ?)",
                        (log_id, name, final.relative_to(self._root).as_posix(), n_rows),
                    )
        except BaseException:
            for path in moved:
                _remove_tree(path)
            raise
        finally:
            _remove_tree(staging)
        self._discard(garbage)

    def upsert_table_rows(
        self, log_id: str, name: str, rows: pa.Table, key_column: str, keys: Sequence[str] | None = None
    ) -> int:
        """Keyed upsert into derived table ``name`` of one log (returns its new row count).

        Rows whose ``key_column`` value is in ``keys`` (default: the values in ``rows``) are replaced
        by ``rows``; every other row is kept. Pass ``keys`` with an empty ``rows`` to delete.

        The read of the current rows, the merge and the catalog update happen under the catalog's
        write lock, so concurrent writers (processes mining different descriptions on the same
        log, say) never lose each other's rows. Returns the table's new row count.

        Raises:
            UnknownLogError: the log is not in the store.
            ValueError: ``key_column`` is missing from ``rows``.
        """
        name = check_table_name(name)
        if key_column not in rows.column_names:
            raise ValueError(f"key column {key_column!r} is not among the columns {rows.column_names}")
        new = _with_log_id(rows, log_id, name)
        wanted = keys if keys is not None else new.column(key_column).to_pylist()
        key_set = pa.array(sorted({str(k) for k in wanted}), pa.string())
        with self._write_txn() as con:
            dirs = _existing_logs(con, [log_id])
            if log_id not in dirs:
                raise UnknownLogError(log_id)
            old = con.execute(
                "SELECT file FROM log_tables WHERE log_id = ? AND name = ?", (log_id, name)
            ).fetchone()
            merged = new
            if old is not None:
                current = pq.read_table(self._root / old[0])
                if key_column in current.column_names:
                    stale = pc.is_in(current.column(key_column).cast(pa.string()), value_set=key_set)
                    current = current.filter(pc.invert(pc.fill_null(stale, False)))
                merged = pa.concat_tables([current, new], promote_options="permissive")
            final = self._root / dirs[log_id] / f"{name}.{uuid.uuid4().hex[:12]}.parquet"
            _write_parquet(merged, final)
            con.execute(
                "INSERT OR REPLACE INTO log_tables (log_id, name, file, n_rows) VALUES (?, ?, ?, ?)",
                (log_id, name, final.relative_to(self._root).as_posix(), merged.num_rows),
            )
        if old is not None:
            self._discard([self._root / old[0]])
        return int(merged.num_rows)

    def read_table(self, name: str, log_ids: Sequence[str] | None = None) -> pa.Table:
        """Rows of table ``name`` (``tracks``, ``meta`` or a derived table) over logs, by log id.

        Args:
            name: table name.
            log_ids: restrict to these logs; logs without the table contribute no rows.
                ``None`` means every log.

        Returns:
            The concatenated rows with a leading ``log_id`` column; columns missing in some
            logs are null there, numeric types are widened to a common type.

        Raises:
            UnknownTableError: no log has this table.
            UnknownLogError: a requested log is not in the store.
        """
        for attempt in range(_READ_ATTEMPTS):
            snap = self._snapshot(
                None if name == META_TABLE else [name], with_logs=name == META_TABLE or log_ids is not None
            )
            if log_ids is not None:
                missing = [i for i in log_ids if i not in snap.logs]
                if missing:
                    raise UnknownLogError(missing[0])
            if name == META_TABLE:
                wanted = sorted(snap.logs) if log_ids is None else list(dict.fromkeys(log_ids))
                return _meta_table([snap.logs[i] for i in wanted], snap)
            files = snap.tables.get(name)
            if not files:
                raise UnknownTableError(name, _table_list(snap))
            ids = sorted(files) if log_ids is None else [i for i in dict.fromkeys(log_ids) if i in files]
            try:
                if not ids:
                    schema = pq.read_schema(self._root / next(iter(files.values())))
                    return schema.empty_table()
                parts = [pq.read_table(self._root / files[i]) for i in ids]
            except FileNotFoundError:
                if attempt + 1 < _READ_ATTEMPTS:
                    continue
                raise
            return pa.concat_tables(parts, promote_options="permissive")
        raise AssertionError("unreachable")  # pragma: no cover

    def delete_table(self, name: str) -> int:
        """Delete derived table ``name`` from every log; returns how many logs held it.

        Raises:
            InvalidNameError: ``name`` is ``tracks`` or ``meta`` (use :meth:`remove_log`).
        """
        if name in RESERVED_TABLES:
            raise InvalidNameError(f"table {name!r} cannot be deleted (it is part of every log)")
        with self._write_txn() as con:
            files = [r[0] for r in con.execute("SELECT file FROM log_tables WHERE name = ?", (name,))]
            con.execute("DELETE FROM log_tables WHERE name = ?", (name,))
        self._discard([self._root / f for f in files])
        return len(files)

    # ------------------------------------------------------------------ queries
    def sql(self, query: str, params: Sequence[Any] | Mapping[str, Any] | None = None) -> pa.Table:
        """Run a DuckDB SQL query over the store and return the result as an Arrow table.

        Views: ``tracks`` (one row per valid track observation, columns ``log_id`` then
        :meth:`Log.to_arrow`'s), ``meta`` (one row per log: the :class:`LogMeta` fields plus
        ``tables``, the derived tables the log has), and one view per derived table. Each call
        runs on a private DuckDB cursor whose views cover one catalog snapshot.

        Args:
            query: SQL text, e.g. ``SELECT log_id, count(*) FROM tracks WHERE category = ? GROUP BY 1``.
            params: positional (``?``) or named (``$name``) parameter values.

        Raises:
            QueryError: DuckDB rejected or failed the query (the message lists the views).
        """
        words = {w.lower() for w in re.findall(r"[A-Za-z_][A-Za-z0-9_]*", query)}
        for attempt in range(_READ_ATTEMPTS):
            # Bind only the views the query mentions: binding a view over many files costs time.
            snap = self._snapshot(None if META_TABLE in words else words, with_logs=META_TABLE in words)
            con = self._duckdb_cursor()
            try:
                self._register_views(con, snap, words)
                rel = con.sql(query, params=params)
                return _relation_to_arrow(rel) if rel is not None else pa.table({})
            except duckdb.IOException as exc:
                if attempt + 1 < _READ_ATTEMPTS and self._generation() != snap.generation:
                    continue  # a writer replaced files under this snapshot: read the new one
                raise QueryError(f"{exc}\nviews: {', '.join(_table_list(snap))}") from None
            except duckdb.Error as exc:
                raise QueryError(f"{exc}\nviews: {', '.join(_table_list(snap))}") from None
            finally:
                con.close()
        raise AssertionError("unreachable")  # pragma: no cover

    # ------------------------------------------------------------------ summary, maintenance
    def info(self) -> StoreInfo:
        """Summarise the whole store: logs, tracks, frames, categories, tables, size on disk."""
        snap = self._snapshot()
        metas = [row.meta for row in snap.logs.values()]
        categories: Counter[str] = Counter()
        for m in metas:
            categories.update(m.categories)
        derived = {n: len(f) for n, f in sorted(snap.tables.items()) if n != TRACKS_TABLE}
        return StoreInfo(
            root=self._root,
            schema_version=SCHEMA_VERSION,
            n_sources=snap.n_sources,
            n_logs=len(metas),
            n_tracks=sum(m.n_tracks for m in metas),
            n_timestamps=sum(m.n_timestamps for m in metas),
            n_frames=sum(m.n_frames for m in metas),
            total_duration_s=float(sum(m.duration_s for m in metas)),
            categories=dict(sorted(categories.items())),
            datasets=dict(sorted(Counter(m.dataset for m in metas).items())),
            tables=tuple(derived),
            table_logs=derived,
            size_bytes=_tree_size(self._root),
        )

    def vacuum(self, staging_max_age_s: float = 3600.0) -> int:
        """Delete files no catalog entry references (leftovers of a killed process).

        Staging entries are deleted only when older than ``staging_max_age_s``, since another
        process may be writing them right now. Returns the number of paths removed.
        """
        removed = 0
        with self._write_txn() as con:
            dirs = {r[0] for r in con.execute("SELECT dir FROM logs")}
            files = {r[0] for r in con.execute("SELECT file FROM log_tables")}
            logs_root = self._root / _LOGS_DIR
            for log_dir in sorted(logs_root.iterdir()) if logs_root.is_dir() else []:
                for version in sorted(log_dir.iterdir()) if log_dir.is_dir() else [log_dir]:
                    rel = version.relative_to(self._root).as_posix()
                    if rel not in dirs:
                        _remove_tree(version)
                        removed += 1
                        continue
                    for f in version.iterdir():
                        if f.name != "meta.json" and f.relative_to(self._root).as_posix() not in files:
                            _remove_tree(f)
                            removed += 1
                with contextlib.suppress(OSError):
                    log_dir.rmdir()
            for entry in self._stale_staging(staging_max_age_s):
                _remove_tree(entry)
                removed += 1
        return removed

    def check(self, staging_max_age_s: float = 3600.0) -> StoreCheck:
        """What :meth:`vacuum` would remove, and catalog entries whose files are missing (read only)."""
        snap = self._snapshot()
        with contextlib.closing(self._connect()) as con:
            dirs = {r[0] for r in con.execute("SELECT dir FROM logs")}
            files = {r[0] for r in con.execute("SELECT file FROM log_tables")}
        orphans: list[str] = []
        logs_root = self._root / _LOGS_DIR
        for log_dir in sorted(logs_root.iterdir()) if logs_root.is_dir() else []:
            for version in sorted(log_dir.iterdir()) if log_dir.is_dir() else [log_dir]:
                rel = version.relative_to(self._root).as_posix()
                if rel not in dirs:
                    orphans.append(rel)
                    continue
                orphans += [
                    f.relative_to(self._root).as_posix()
                    for f in sorted(version.iterdir())
                    if f.name != "meta.json" and f.relative_to(self._root).as_posix() not in files
                ]
        missing = sorted(
            [
                f"{d}/{TRACKS_TABLE}.parquet"
                for d in dirs
                if not (self._root / d / f"{TRACKS_TABLE}.parquet").is_file()
            ]
            + [f for f in files if not (self._root / f).is_file()]
        )
        stale = [p.relative_to(self._root).as_posix() for p in self._stale_staging(staging_max_age_s)]
        return StoreCheck(
            root=str(self._root),
            n_logs=len(snap.logs),
            orphaned_files=tuple(orphans),
            missing_files=tuple(missing),
            stale_staging=tuple(stale),
            corpus_tables=tuple(t.name for t in self.corpus_tables()),
        )

    # ------------------------------------------------------------------ internals
    def _check_marker(self, marker: Path) -> None:
        try:
            data = json.loads(marker.read_text(encoding="utf-8"))
        except (OSError, ValueError) as exc:
            raise NotAStoreError(self._root, f"{_MARKER} is unreadable ({exc})") from None
        if not isinstance(data, dict) or data.get("format") != STORE_FORMAT:
            raise NotAStoreError(self._root, f"{_MARKER} does not describe a {STORE_FORMAT}")
        version = data.get("schema_version")
        if not isinstance(version, int) or version > SCHEMA_VERSION:
            raise StoreVersionError(
                f"{self._root}: store layout version {version!r} is newer than this scenariominer "
                f"supports ({SCHEMA_VERSION}); upgrade scenariominer"
            )

    def _duckdb_cursor(self) -> duckdb.DuckDBPyConnection:
        """Open a cheap cursor on this object's in-memory DuckDB; its temp views are private to it."""
        with self._duckdb_lock:
            if self._duckdb is None:
                self._duckdb = duckdb.connect(":memory:")
            return self._duckdb.cursor()

    def _connect(self) -> sqlite3.Connection:
        con = sqlite3.connect(self._root / _CATALOG, timeout=_BUSY_TIMEOUT_S, isolation_level=None)
        return con

    @contextlib.contextmanager
    def _write_txn(self) -> Iterator[sqlite3.Connection]:
        """Hold SQLite's write lock for one transaction; commit on success, roll back on error."""
        with contextlib.closing(self._connect()) as con:
            con.execute("BEGIN IMMEDIATE")
            try:
                yield con
                con.execute("UPDATE state SET value = value + 1 WHERE key = 'generation'")
                con.execute("COMMIT")
            except BaseException:
                if con.in_transaction:
                    con.execute("ROLLBACK")
                raise

    def _generation(self) -> int:
        with contextlib.closing(self._connect()) as con:
            return int(con.execute("SELECT value FROM state WHERE key = 'generation'").fetchone()[0])

    def _snapshot(self, names: Collection[str] | None = None, *, with_logs: bool = True) -> _Snapshot:
        """Read the catalog in one transaction.

        Args:
            names: list only these tables' files (``None``: all tables).
            with_logs: also read every log's catalog row (needed for ``meta`` and log checks).
        """
        with contextlib.closing(self._connect()) as con:
            con.execute("BEGIN")
            generation = int(con.execute("SELECT value FROM state WHERE key = 'generation'").fetchone()[0])
            n_sources = int(con.execute("SELECT count(*) FROM sources").fetchone()[0])
            logs: dict[str, _LogRow] = {}
            if with_logs:
                rows = con.execute("SELECT log_id, source_key, dir, digest, meta FROM logs ORDER BY log_id")
                logs = {r[0]: _LogRow(*r) for r in rows}
            all_names = tuple(r[0] for r in con.execute("SELECT DISTINCT name FROM log_tables ORDER BY name"))
            wanted = [n for n in all_names if names is None or n in names]
            tables: dict[str, dict[str, str]] = {}
            rows = con.execute(
                "SELECT log_id, name, file FROM log_tables WHERE name IN (SELECT value FROM json_each(?)) "
                "ORDER BY log_id",
                (json.dumps(wanted),),
            )
            for log_id, name, file in rows:
                tables.setdefault(name, {})[log_id] = file
            con.execute("COMMIT")
        return _Snapshot(generation, n_sources, logs, tables, all_names)

    def _check_owners(self, source_key: str, ids: Sequence[str], rows: Mapping[str, _LogRow]) -> None:
        for log_id in ids:
            row = rows.get(log_id)
            if row is not None and row.source_key != source_key:
                raise LogConflictError(
                    f"log {log_id!r} from source {source_key} already belongs to source {row.source_key}; "
                    "log ids must be unique across sources (remove the other source first)"
                )

    def _new_staging(self) -> Path:
        """A fresh staging folder ``<pid>-<random>``; stale staging of dead writers is removed first."""
        for entry in self._stale_staging(_STAGING_MAX_AGE_S):
            _remove_tree(entry)
        path = self._root / _STAGING_DIR / f"{os.getpid()}-{uuid.uuid4().hex[:12]}"
        path.mkdir(parents=True)
        return path

    def _stale_staging(self, max_age_s: float) -> list[Path]:
        """Staging folders whose writer is gone: its process no longer runs, or older than ``max_age_s``."""
        root = self._root / _STAGING_DIR
        if not root.is_dir():
            return []
        cutoff = time.time() - max_age_s
        out = []
        for entry in sorted(root.iterdir()):
            pid_text = entry.name.split("-", 1)[0]
            alive = pid_text.isdigit() and _process_alive(int(pid_text))
            try:
                old = entry.stat().st_mtime < cutoff
            except FileNotFoundError:
                continue
            if not alive or old:
                out.append(entry)
        return out

    def _stage_log(self, staging: Path, log: Log, meta: LogMeta, digest: str) -> Path:
        version = staging / uuid.uuid4().hex[:16]
        version.mkdir()
        table = log.to_arrow()
        table = table.add_column(0, "log_id", pa.repeat(pa.scalar(log.log_id, pa.string()), table.num_rows))
        _write_parquet(table, version / f"{TRACKS_TABLE}.parquet")
        _write_json_atomic(version / "meta.json", _meta_file(meta, digest))
        return version

    def _discard(self, paths: Sequence[Path]) -> None:
        """Delete replaced files after a commit (best effort; :meth:`vacuum` retries)."""
        for path in paths:
            _remove_tree(path)
            parent = path.parent
            if parent.parent == self._root / _LOGS_DIR:
                with contextlib.suppress(OSError):
                    parent.rmdir()  # only succeeds when the log has no version left

    def _register_views(
        self, con: duckdb.DuckDBPyConnection, snap: _Snapshot, words: Collection[str]
    ) -> None:
        """Create the views whose names occur in ``words``, over the snapshot's files."""
        if META_TABLE in words:
            con.register(META_TABLE, _meta_table(list(snap.logs.values()), snap))
        for name, files in snap.tables.items():
            if name not in words:
                continue
            paths = ", ".join(_sql_string(str(self._root / files[i])) for i in sorted(files))
            union = "" if name == TRACKS_TABLE else ", union_by_name = true"
            con.execute(f'CREATE TEMP VIEW "{name}" AS SELECT * FROM read_parquet([{paths}]{union})')
        if TRACKS_TABLE in words and TRACKS_TABLE not in snap.tables:
            con.register(TRACKS_TABLE, _TRACKS_SCHEMA.empty_table())


# ---------------------------------------------------------------------- helpers


_TRACKS_SCHEMA = pa.schema(
    [
        ("log_id", pa.string()),
        ("track_id", pa.string()),
        ("category", pa.string()),
        ("timestamp_ns", pa.int64()),
        ("is_ego", pa.bool_()),
        *[(name, pa.float64()) for name in STATE_FIELDS],
    ]
)


def _now() -> datetime:
    return datetime.now(UTC)


def _sql_string(text: str) -> str:
    return "'" + text.replace("'", "''") + "'"


def _relation_to_arrow(rel: duckdb.DuckDBPyRelation) -> pa.Table:
    to_table = getattr(rel, "to_arrow_table", None)  # duckdb >= 1.4
    result = to_table() if to_table is not None else rel.arrow()
    return result if isinstance(result, pa.Table) else result.read_all()


def _log_rows(con: sqlite3.Connection, source_key: str, log_ids: Sequence[str]) -> dict[str, _LogRow]:
    """Catalog rows (without metadata) of the source's logs and of ``log_ids``."""
    rows = con.execute(
        "SELECT log_id, source_key, dir, digest FROM logs "
        "WHERE source_key = ? OR log_id IN (SELECT value FROM json_each(?))",
        (source_key, json.dumps(list(log_ids))),
    )
    return {r[0]: _LogRow(*r) for r in rows}


def _existing_logs(con: sqlite3.Connection, log_ids: Sequence[str]) -> dict[str, str]:
    """Directory (relative to the root) of each of ``log_ids`` that is in the store."""
    rows = con.execute(
        "SELECT log_id, dir FROM logs WHERE log_id IN (SELECT value FROM json_each(?))",
        (json.dumps(list(log_ids)),),
    )
    return {r[0]: r[1] for r in rows}


def _delete_log_rows(con: sqlite3.Connection, log_id: str) -> None:
    con.execute("DELETE FROM log_tables WHERE log_id = ?", (log_id,))
    con.execute("DELETE FROM logs WHERE log_id = ?", (log_id,))


def _table_list(snap: _Snapshot) -> list[str]:
    return [TRACKS_TABLE, META_TABLE, *(n for n in snap.table_names if n != TRACKS_TABLE)]


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


def _write_parquet(table: pa.Table, path: Path) -> None:
    pq.write_table(table, path, compression=_PARQUET_COMPRESSION)
    _fsync(path)


def _write_json_atomic(path: Path, data: Mapping[str, Any]) -> None:
    tmp = path.with_name(f".{path.name}.{uuid.uuid4().hex[:8]}.tmp")
    try:
        tmp.write_text(json.dumps(data, indent=2, sort_keys=True) + "\n", encoding="utf-8")
        _fsync(tmp)
        os.replace(tmp, path)
    finally:
        with contextlib.suppress(FileNotFoundError):
            tmp.unlink()


def _fsync(path: Path) -> None:
    fd = os.open(path, os.O_RDONLY)
    try:
        os.fsync(fd)
    finally:
        os.close(fd)


def _remove_tree(path: Path) -> None:
    """Delete a file or directory, ignoring what is already gone (best effort)."""
    try:
        if path.is_dir() and not path.is_symlink():
            shutil.rmtree(path, ignore_errors=True)
        else:
            path.unlink(missing_ok=True)
    except OSError:
        pass


def _tree_size(root: Path) -> int:
    total = 0
    for dirpath, _, filenames in os.walk(root):
        for fname in filenames:
            with contextlib.suppress(OSError):
                total += os.stat(os.path.join(dirpath, fname)).st_size
    return total


def _process_alive(pid: int) -> bool:
    """Whether a process with this id runs on this machine (a staging folder's writer)."""
    if pid == os.getpid():
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True
