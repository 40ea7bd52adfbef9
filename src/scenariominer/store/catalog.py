"""The SQLite catalog: its schema and the queries the store runs in write transactions."""

from __future__ import annotations

import json
import sqlite3
from collections.abc import Sequence

from scenariominer.store.layout import (
    META_TABLE,
    TRACKS_TABLE,
)
from scenariominer.store.records import (
    _LogRow,
    _Snapshot,
)

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


#: Every table name in ``log_tables``, sorted. A skip-scan of the ``name`` index (one seek per
#: distinct name) instead of ``SELECT DISTINCT``, which reads an index entry per (log, table):
#: every snapshot runs it, so it must not grow with the number of logs.
_TABLE_NAMES_SQL = """
WITH RECURSIVE names(name) AS (
    SELECT min(name) FROM log_tables
    UNION ALL
    SELECT (SELECT min(name) FROM log_tables WHERE name > names.name) FROM names WHERE name IS NOT NULL
)
SELECT name FROM names WHERE name IS NOT NULL ORDER BY name
"""


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
