"""Corpus-level tables: artefacts of the whole corpus (models, windows, clusters, graphs, case bases).

Per-log tables belong to one log and are replaced with it. A corpus table belongs to the store: it
is named, has a schema version chosen by its writer, and holds rows under unique string keys (for
example a model's configuration and data hash, a window id, a case id). Each row is a JSON object
plus an optional binary payload (model weights, an array as ``.npy`` bytes).

Writes are keyed upserts: rows with the keys written replace the old ones, every other row stays.
Each write is one SQLite transaction under the catalog's write lock (``BEGIN IMMEDIATE``), so any
number of processes can write to the same table at once and none loses another's rows; a reader
sees the table as of one committed write. Every committed write bumps the table's ``version``,
which readers can record to notice later changes (a cache of derived results, for instance).
"""

from __future__ import annotations

import contextlib
import json
import sqlite3
from collections.abc import Iterable, Iterator, Mapping, Sequence
from dataclasses import dataclass
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

from scenariominer import errors as _errors

__all__ = ["CorpusRow", "CorpusSchemaError", "CorpusTable", "CorpusTableInfo"]

_SCHEMA = """
CREATE TABLE IF NOT EXISTS corpus_tables (
    name TEXT PRIMARY KEY,
    schema_version INTEGER NOT NULL,
    version INTEGER NOT NULL,
    n_rows INTEGER NOT NULL,
    updated_at TEXT NOT NULL
);
CREATE TABLE IF NOT EXISTS corpus_rows (
    name TEXT NOT NULL,
    key TEXT NOT NULL,
    data TEXT NOT NULL,
    blob BLOB,
    version INTEGER NOT NULL,
    updated_at TEXT NOT NULL,
    PRIMARY KEY (name, key)
);
"""


_UPSERT_ROW = (
    "INSERT INTO corpus_rows (name, key, data, blob, version, updated_at) VALUES (?, ?, ?, ?, ?, ?) "
    "ON CONFLICT (name, key) DO UPDATE SET data = excluded.data, blob = excluded.blob, "
    "version = excluded.version, updated_at = excluded.updated_at"
)
_UPSERT_TABLE = (
    "INSERT INTO corpus_tables (name, schema_version, version, n_rows, updated_at) VALUES (?, ?, ?, ?, ?) "
    "ON CONFLICT (name) DO UPDATE SET version = excluded.version, n_rows = excluded.n_rows, "
    "updated_at = excluded.updated_at"
)


class CorpusSchemaError(_errors.StoreError, ValueError):
    """A corpus table was opened with a schema version other than the one it was written with."""


@dataclass(frozen=True)
class CorpusRow:
    """One row of a corpus table.

    Attributes:
        key: the row's unique key within its table.
        data: the JSON object stored under it.
        blob: the binary payload, if any.
        version: the table version at which the row was last written.
    """

    key: str
    data: Mapping[str, Any]
    blob: bytes | None
    version: int


@dataclass(frozen=True)
class CorpusTableInfo:
    """Name, schema version, version (committed writes so far) and row count of a corpus table."""

    name: str
    schema_version: int
    version: int
    n_rows: int
    updated_at: str


class CorpusTable:
    """A named, versioned, keyed table of the store (see the module docstring).

    Args:
        catalog: path of the store's SQLite catalog.
        name: table name (checked by the store's table-name rule).
        schema_version: the layout of ``data`` this writer uses; opening a table written with
            another schema version raises :class:`CorpusSchemaError` (re-build it, or
            :meth:`clear` it first with ``replace_schema=True``).
    """

    def __init__(
        self, catalog: Path, name: str, schema_version: int, *, busy_timeout_s: float = 60.0
    ) -> None:
        self._catalog = catalog
        self.name = name
        self.schema_version = int(schema_version)
        self._timeout = busy_timeout_s
        with contextlib.closing(self._connect()) as con:
            con.executescript(_SCHEMA)
            row = con.execute("SELECT schema_version FROM corpus_tables WHERE name = ?", (name,)).fetchone()
        if row is not None and int(row[0]) != self.schema_version:
            raise CorpusSchemaError(
                f"corpus table {name!r} was written with schema version {row[0]}, this code uses "
                f"{self.schema_version}; rebuild the table (its rows cannot be read as they are)"
            )

    # ------------------------------------------------------------------ writing
    def upsert(self, rows: Mapping[str, Mapping[str, Any]], blobs: Mapping[str, bytes] | None = None) -> int:
        """Insert or replace the rows under these keys, atomically; returns the new table version.

        Raises:
            ValueError: a key is empty or a row is not JSON-serialisable.
        """
        blobs = blobs or {}
        unknown = set(blobs) - set(rows)
        if unknown:
            raise ValueError(f"blobs for keys without a row: {sorted(unknown)[:3]}")
        encoded = [(_key(k), _encode(k, v), blobs.get(k)) for k, v in rows.items()]
        with self._write() as (con, version, now):
            con.executemany(_UPSERT_ROW, [(self.name, k, d, b, version, now) for k, d, b in encoded])
        return version

    def delete(self, keys: Iterable[str]) -> int:
        """Delete the rows under ``keys`` (absent keys are ignored); returns how many were deleted."""
        keys = [_key(k) for k in keys]
        with self._write() as (con, _version, _now):
            before = con.total_changes
            con.executemany(
                "DELETE FROM corpus_rows WHERE name = ? AND key = ?", [(self.name, k) for k in keys]
            )
            return con.total_changes - before

    def clear(self) -> None:
        """Delete every row and the table's record (its schema version included)."""
        with contextlib.closing(self._connect()) as con:
            con.execute("BEGIN IMMEDIATE")
            con.execute("DELETE FROM corpus_rows WHERE name = ?", (self.name,))
            con.execute("DELETE FROM corpus_tables WHERE name = ?", (self.name,))
            con.execute("COMMIT")

    # ------------------------------------------------------------------ reading
    def get(self, key: str) -> CorpusRow | None:
        """The row under ``key``, or ``None``."""
        with contextlib.closing(self._connect()) as con:
            r = con.execute(
                "SELECT key, data, blob, version FROM corpus_rows WHERE name = ? AND key = ?",
                (self.name, key),
            ).fetchone()
        return None if r is None else CorpusRow(r[0], json.loads(r[1]), r[2], int(r[3]))

    def rows(self, keys: Sequence[str] | None = None, *, with_blobs: bool = False) -> list[CorpusRow]:
        """Rows (all, or those under ``keys``) in key order, as of one committed write."""
        blob = "blob" if with_blobs else "NULL"
        sql = f"SELECT key, data, {blob}, version FROM corpus_rows WHERE name = ?"
        params: list[Any] = [self.name]
        if keys is not None:
            sql += " AND key IN (SELECT value FROM json_each(?))"
            params.append(json.dumps(list(keys)))
        with contextlib.closing(self._connect()) as con:
            out = [
                CorpusRow(r[0], json.loads(r[1]), r[2], int(r[3]))
                for r in con.execute(sql + " ORDER BY key", params)
            ]
        return out

    def keys(self) -> list[str]:
        """Every key, sorted."""
        with contextlib.closing(self._connect()) as con:
            return [
                r[0]
                for r in con.execute("SELECT key FROM corpus_rows WHERE name = ? ORDER BY key", (self.name,))
            ]

    def info(self) -> CorpusTableInfo:
        """Schema version, version and row count (version 0 and no rows before the first write)."""
        with contextlib.closing(self._connect()) as con:
            r = con.execute(
                "SELECT schema_version, version, n_rows, updated_at FROM corpus_tables WHERE name = ?",
                (self.name,),
            ).fetchone()
        if r is None:
            return CorpusTableInfo(self.name, self.schema_version, 0, 0, "")
        return CorpusTableInfo(self.name, int(r[0]), int(r[1]), int(r[2]), str(r[3]))

    # ------------------------------------------------------------------ internals
    def _connect(self) -> sqlite3.Connection:
        return sqlite3.connect(self._catalog, timeout=self._timeout, isolation_level=None)

    @contextlib.contextmanager
    def _write(self) -> Iterator[tuple[sqlite3.Connection, int, str]]:
        """One write transaction: yields the connection, the new version and the time; commits."""
        now = datetime.now(UTC).isoformat()
        with contextlib.closing(self._connect()) as con:
            con.execute("BEGIN IMMEDIATE")
            try:
                r = con.execute("SELECT version FROM corpus_tables WHERE name = ?", (self.name,)).fetchone()
                version = (int(r[0]) if r else 0) + 1
                yield con, version, now
                n_rows = con.execute(
                    "SELECT count(*) FROM corpus_rows WHERE name = ?", (self.name,)
                ).fetchone()[0]
                con.execute(_UPSERT_TABLE, (self.name, self.schema_version, version, int(n_rows), now))
                con.execute("COMMIT")
            except BaseException:
                if con.in_transaction:
                    con.execute("ROLLBACK")
                raise


def list_corpus_tables(catalog: Path) -> list[CorpusTableInfo]:
    """Every corpus table of a catalog, by name."""
    with contextlib.closing(sqlite3.connect(catalog, isolation_level=None)) as con:
        con.executescript(_SCHEMA)
        rows = con.execute(
            "SELECT name, schema_version, version, n_rows, updated_at FROM corpus_tables ORDER BY name"
        ).fetchall()
    return [CorpusTableInfo(r[0], int(r[1]), int(r[2]), int(r[3]), str(r[4])) for r in rows]


def _key(key: str) -> str:
    if not isinstance(key, str) or not key:
        raise ValueError(f"corpus row keys must be non-empty strings, got {key!r}")
    return key


def _encode(key: str, row: Mapping[str, Any]) -> str:
    try:
        return json.dumps(dict(row), sort_keys=True, allow_nan=True)
    except (TypeError, ValueError) as exc:
        raise ValueError(f"row {key!r} cannot be stored as JSON: {exc}") from None
