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
import json
import os
import re
import sqlite3
import threading
import time
import uuid
from collections import Counter
from collections.abc import Collection, Iterator, Mapping, Sequence
from datetime import datetime
from pathlib import Path
from typing import Any

import duckdb
import pyarrow as pa
import pyarrow.compute as pc
import pyarrow.parquet as pq

from scenariominer.data.log import Log
from scenariominer.store.catalog import (
    _CATALOG_SCHEMA,
    _TABLE_NAMES_SQL,
    _delete_log_rows,
    _existing_logs,
    _table_list,
)
from scenariominer.store.corpus import CorpusTable, CorpusTableInfo, list_corpus_tables
from scenariominer.store.errors import (
    InvalidNameError,
    LogConflictError,
    NotAStoreError,
    QueryError,
    StoreVersionError,
    UnknownLogError,
    UnknownTableError,
)
from scenariominer.store.layout import (
    _BUSY_TIMEOUT_S,
    _CATALOG,
    _LOGS_DIR,
    _MARKER,
    _READ_ATTEMPTS,
    _STAGING_DIR,
    _STAGING_MAX_AGE_S,
    META_TABLE,
    RESERVED_TABLES,
    SCHEMA_VERSION,
    STORE_FORMAT,
    TRACKS_TABLE,
    _process_alive,
    _read_parquet,
    _remove_tree,
    _tree_size,
    _write_json_atomic,
    _write_parquet,
    check_table_name,
    find_orphans,
)
from scenariominer.store.query import (
    _relation_to_arrow,
    register_views,
)
from scenariominer.store.records import (
    LogMeta,
    SourceRecord,
    StoreCheck,
    StoreInfo,
    _log_from_table,
    _LogRow,
    _meta_file,
    _meta_table,
    _now,
    _Snapshot,
    _with_log_id,
)
from scenariominer.store.writes import SourceContent, replace_sources

# ---------------------------------------------------------------------- errors


# ---------------------------------------------------------------------- records


# ---------------------------------------------------------------------- locations


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
        if not marker.is_file() and self._root.is_dir():
            # Writers may create the store at once: another one's marker may be half written
            # (its temporary file) or appear between the two looks at it.
            foreign = [p for p in self._root.iterdir() if not _is_marker_temp(p.name)]
            if foreign and not marker.is_file():
                raise NotAStoreError(
                    self._root,
                    f"directory is not empty and has no {_MARKER}; refusing to use it as a store "
                    "(choose an empty or new directory)",
                )
        if marker.is_file():
            self._check_marker(marker)
        elif not create:
            raise NotAStoreError(self._root, "no store here")
        else:
            self._root.mkdir(parents=True, exist_ok=True)
            _write_json_atomic(
                marker,
                {"format": STORE_FORMAT, "schema_version": SCHEMA_VERSION, "created_at": _now().isoformat()},
            )
        with contextlib.closing(self._connect()) as con:
            if con.execute("SELECT count(*) FROM sqlite_master WHERE name = 'log_tables'").fetchone()[0] == 0:
                # One transaction, so a writer opening the store meanwhile never sees half a schema.
                con.executescript(f"BEGIN IMMEDIATE;{_CATALOG_SCHEMA}COMMIT;")

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
            return [r[0] for r in con.execute(_TABLE_NAMES_SQL) if r[0] != TRACKS_TABLE]

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
        (outcome,) = replace_sources(self, [(source_key, content_hash, logs)])
        if isinstance(outcome, Exception):
            raise outcome
        return outcome

    def replace_sources(self, batch: Sequence[SourceContent]) -> list[list[str] | Exception]:
        """Several :meth:`replace_source` calls in one catalog transaction, each source atomic on its own.

        Args:
            batch: ``(source_key, content_hash, logs)`` per source; source keys must differ.

        Returns:
            Per source, in the order given: its log ids, or the error that kept it out
            (:class:`InvalidLogError`, :class:`InvalidNameError`, :class:`LogConflictError`);
            the other sources are stored.

        Raises:
            OSError, sqlite3.Error: writing files or the catalog failed; nothing of the batch is stored.
        """
        return replace_sources(self, batch)

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
                table = _read_parquet(path)
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
                None if name == META_TABLE else [name],
                with_logs=name == META_TABLE or log_ids is not None,
                log_ids=log_ids,  # only the requested logs' catalog rows: cost independent of store size
            )
            if log_ids is not None:
                missing = [i for i in log_ids if i not in snap.logs]
                if missing:
                    raise UnknownLogError(missing[0])
            if name == META_TABLE:
                wanted = sorted(snap.logs) if log_ids is None else list(dict.fromkeys(log_ids))
                return _meta_table([snap.logs[i] for i in wanted], snap)
            if name not in snap.table_names:
                raise UnknownTableError(name, _table_list(snap))
            files = snap.tables.get(name, {})
            ids = sorted(files) if log_ids is None else [i for i in dict.fromkeys(log_ids) if i in files]
            try:
                if not ids:  # none of the requested logs has the table: its columns, no rows
                    sample = self._any_table_file(name)
                    if sample is None:  # deleted since the snapshot
                        if attempt + 1 < _READ_ATTEMPTS:
                            continue
                        raise UnknownTableError(name, _table_list(snap))
                    return pq.read_schema(self._root / sample).empty_table()
                parts = [_read_parquet(self._root / files[i]) for i in ids]
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
                register_views(con, self._root, snap, words)
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
            for path in find_orphans(self._root, dirs, files):
                _remove_tree(path)
                removed += 1
                with contextlib.suppress(OSError):
                    path.parent.rmdir()  # a log folder left without any version
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
        orphans = [p.relative_to(self._root).as_posix() for p in find_orphans(self._root, dirs, files)]
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

    def _any_table_file(self, name: str) -> str | None:
        """One file of table ``name`` (relative to the root), or ``None`` when no log has it."""
        with contextlib.closing(self._connect()) as con:
            row = con.execute("SELECT file FROM log_tables WHERE name = ? LIMIT 1", (name,)).fetchone()
        return None if row is None else str(row[0])

    def _generation(self) -> int:
        with contextlib.closing(self._connect()) as con:
            return int(con.execute("SELECT value FROM state WHERE key = 'generation'").fetchone()[0])

    def _snapshot(
        self,
        names: Collection[str] | None = None,
        *,
        with_logs: bool = True,
        log_ids: Sequence[str] | None = None,
    ) -> _Snapshot:
        """Read the catalog in one transaction.

        Args:
            names: list only these tables' files (``None``: all tables).
            with_logs: also read the logs' catalog rows (needed for ``meta`` and log checks).
            log_ids: read only these logs' rows and files (``None``: every log); an index lookup
                per id, so reading a few logs costs the same in a store of any size.
        """
        in_ids = "log_id IN (SELECT value FROM json_each(?))"
        id_param = () if log_ids is None else (json.dumps(list(log_ids)),)
        with contextlib.closing(self._connect()) as con:
            con.execute("BEGIN")
            generation = int(con.execute("SELECT value FROM state WHERE key = 'generation'").fetchone()[0])
            n_sources = int(con.execute("SELECT count(*) FROM sources").fetchone()[0])
            logs: dict[str, _LogRow] = {}
            if with_logs:
                rows = con.execute(
                    "SELECT log_id, source_key, dir, digest, meta FROM logs"
                    f"{'' if log_ids is None else ' WHERE ' + in_ids} ORDER BY log_id",
                    id_param,
                )
                logs = {r[0]: _LogRow(*r) for r in rows}
            all_names = tuple(r[0] for r in con.execute(_TABLE_NAMES_SQL))
            wanted = [n for n in all_names if names is None or n in names]
            tables: dict[str, dict[str, str]] = {}
            rows = con.execute(
                "SELECT log_id, name, file FROM log_tables WHERE name IN (SELECT value FROM json_each(?))"
                f"{'' if log_ids is None else ' AND ' + in_ids} ORDER BY log_id",
                (json.dumps(wanted), *id_param),
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


# ---------------------------------------------------------------------- helpers


def _is_marker_temp(name: str) -> bool:
    """Whether ``name`` is a temporary file of a marker being written (see ``_write_json_atomic``)."""
    return name.startswith(f".{_MARKER}.") and name.endswith(".tmp")
