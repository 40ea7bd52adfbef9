"""The scenario store: Parquet files per log, a SQLite catalog, DuckDB queries, exact vector search.

Typical use::

    from scenariominer.store import ScenarioStore, resolve_store_path

    store = ScenarioStore.open(resolve_store_path())
    if store.needs_ingest(source.key, content_hash):
        store.replace_source(source.key, content_hash, logs)
    store.sql("SELECT log_id, count(DISTINCT track_id) FROM tracks WHERE category = ? GROUP BY 1", ["BUS"])

See ``docs/store.md`` for the layout and the consistency guarantees.
"""

from scenariominer.store.corpus import CorpusRow, CorpusSchemaError, CorpusTable, CorpusTableInfo
from scenariominer.store.errors import (
    InvalidLogError,
    InvalidNameError,
    LogConflictError,
    NotAStoreError,
    QueryError,
    StoreError,
    StoreVersionError,
    UnknownLogError,
    UnknownTableError,
)
from scenariominer.store.layout import (
    META_TABLE,
    SCHEMA_VERSION,
    STORE_ENV_VAR,
    TRACKS_TABLE,
    check_table_name,
    default_store_path,
    resolve_store_path,
)
from scenariominer.store.records import (
    LogMeta,
    SourceRecord,
    StoreCheck,
    StoreInfo,
)
from scenariominer.store.ref import StoreRef
from scenariominer.store.store import (
    ScenarioStore,
)
from scenariominer.store.vectors import (
    EmbeddingHit,
    EmbeddingMismatchError,
    ExactCosineIndex,
    VectorHit,
    VectorIndex,
    ZeroVectorError,
    load_embeddings,
    normalize_rows,
    search_embeddings,
    write_embeddings,
)

__all__ = [
    "CorpusRow",
    "CorpusSchemaError",
    "CorpusTable",
    "CorpusTableInfo",
    "StoreCheck",
    "META_TABLE",
    "SCHEMA_VERSION",
    "STORE_ENV_VAR",
    "TRACKS_TABLE",
    "EmbeddingHit",
    "EmbeddingMismatchError",
    "ExactCosineIndex",
    "InvalidLogError",
    "InvalidNameError",
    "LogConflictError",
    "LogMeta",
    "NotAStoreError",
    "QueryError",
    "ScenarioStore",
    "SourceRecord",
    "StoreError",
    "StoreInfo",
    "StoreRef",
    "StoreVersionError",
    "UnknownLogError",
    "UnknownTableError",
    "VectorHit",
    "VectorIndex",
    "ZeroVectorError",
    "check_table_name",
    "default_store_path",
    "load_embeddings",
    "normalize_rows",
    "resolve_store_path",
    "search_embeddings",
    "write_embeddings",
]
