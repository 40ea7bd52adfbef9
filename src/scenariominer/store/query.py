"""Helpers of the DuckDB query layer (views over the catalog's Parquet files)."""

from __future__ import annotations

from collections.abc import Collection
from pathlib import Path

import duckdb
import pyarrow as pa

from scenariominer.store.layout import _TRACKS_SCHEMA, META_TABLE, TRACKS_TABLE
from scenariominer.store.records import _meta_table, _Snapshot


def _sql_string(text: str) -> str:
    return "'" + text.replace("'", "''") + "'"


def _relation_to_arrow(rel: duckdb.DuckDBPyRelation) -> pa.Table:
    to_table = getattr(rel, "to_arrow_table", None)  # duckdb >= 1.4
    result = to_table() if to_table is not None else rel.arrow()
    return result if isinstance(result, pa.Table) else result.read_all()


def register_views(
    con: duckdb.DuckDBPyConnection, root: Path, snap: _Snapshot, words: Collection[str]
) -> None:
    """Create the views whose names occur in ``words``, over the snapshot's files."""
    if META_TABLE in words:
        con.register(META_TABLE, _meta_table(list(snap.logs.values()), snap))
    for name, files in snap.tables.items():
        if name not in words:
            continue
        paths = ", ".join(_sql_string(str(root / files[i])) for i in sorted(files))
        union = "" if name == TRACKS_TABLE else ", union_by_name = true"
        con.execute(f'CREATE TEMP VIEW "{name}" AS SELECT * FROM read_parquet([{paths}]{union})')
    if TRACKS_TABLE in words and TRACKS_TABLE not in snap.tables:
        con.register(TRACKS_TABLE, _TRACKS_SCHEMA.empty_table())
