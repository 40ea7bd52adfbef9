"""Embeddings stored as derived tables of the scenario store, searched through :mod:`scenariominer.retrieval`.

Embeddings live in the store as ordinary per-log tables with columns ``log_id``, ``item_id``,
``model``, ``dim`` and ``vector`` (``list<float32>``, unit length). Every row names the model
that produced it, so :func:`search_embeddings` can refuse to compare vectors from different
models or dimensions (:class:`EmbeddingMismatchError`) instead of returning meaningless scores.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, NamedTuple

import numpy as np
import pyarrow as pa
import pyarrow.compute as pc
from numpy.typing import ArrayLike, NDArray

from scenariominer.retrieval import (
    EmbeddingMismatchError,
    ExactCosineIndex,
    VectorHit,
    VectorIndex,
    ZeroVectorError,
    make_index,
    normalize_rows,
    top_k,
)

if TYPE_CHECKING:
    from scenariominer.store.store import ScenarioStore

__all__ = [
    "EMBEDDING_COLUMNS",
    "EmbeddingHit",
    "EmbeddingMismatchError",
    "ExactCosineIndex",
    "VectorHit",
    "VectorIndex",
    "ZeroVectorError",
    "embeddings_table",
    "load_embeddings",
    "normalize_rows",
    "search_embeddings",
    "top_k",
]

Float32Array = NDArray[np.float32]

#: Columns of an embeddings table (besides the store's ``log_id``).
EMBEDDING_COLUMNS: tuple[str, ...] = ("item_id", "model", "dim", "vector")


class EmbeddingHit(NamedTuple):
    """One search result over a store's embeddings table.

    Attributes:
        log_id: log holding the item.
        item_id: the item's id within the log (a scenario, an event, a track, ...).
        score: cosine similarity in ``[-1, 1]``.
    """

    log_id: str
    item_id: str
    score: float


# ---------------------------------------------------------------------- store helpers


def embeddings_table(ids: Sequence[str], vectors: ArrayLike, model: str) -> pa.Table:
    """Build an embeddings table: one row per item with its model, dimension and unit vector.

    Args:
        ids: ``K`` unique item ids.
        vectors: ``(K, D)`` vectors; normalised to unit length and stored as float32.
        model: name of the embedding model (compared exactly when searching).

    Raises:
        ValueError: shapes disagree, ids repeat, ``model`` is empty, or a vector is not finite.
        ZeroVectorError: a vector has zero length.
    """
    ids = [str(i) for i in ids]
    if not model:
        raise ValueError("model must name the embedding model")
    arr = np.asarray(vectors)
    if arr.ndim != 2 or arr.shape[0] != len(ids):
        raise ValueError(f"expected (K={len(ids)}, D) vectors, got shape {arr.shape}")
    if len(set(ids)) != len(ids):
        raise ValueError("item ids must be unique within a log")
    unit = normalize_rows(arr, ids)
    k, d = unit.shape
    offsets = pa.array(np.arange(0, (k + 1) * d, d, dtype=np.int32))
    return pa.table(
        {
            "item_id": pa.array(ids, pa.string()),
            "model": pa.repeat(pa.scalar(model, pa.string()), k),
            "dim": pa.repeat(pa.scalar(d, pa.int32()), k),
            "vector": pa.ListArray.from_arrays(offsets, pa.array(unit.ravel(), pa.float32())),
        }
    )


def write_embeddings(
    store: ScenarioStore,
    log_id: str,
    table_name: str,
    ids: Sequence[str],
    vectors: ArrayLike,
    model: str,
) -> None:
    """Store the embeddings of one log's items as derived table ``table_name`` (replacing it).

    Args:
        store: destination store.
        log_id: log the items belong to.
        table_name: derived table name, e.g. ``description_embeddings``.
        ids: ``K`` unique item ids.
        vectors: ``(K, D)`` float vectors.
        model: embedding model name, stored on every row.

    Raises:
        ZeroVectorError: a vector has zero length.
        ValueError: see :func:`embeddings_table`; also store errors from ``write_table``.
    """
    store.write_table(log_id, table_name, embeddings_table(ids, vectors, model))


def load_embeddings(
    store: ScenarioStore,
    table_name: str,
    model: str,
    dim: int | None = None,
    log_ids: Sequence[str] | None = None,
) -> tuple[pa.Table, Float32Array]:
    """Read an embeddings table and check that every row comes from ``model`` (and ``dim``).

    Returns:
        The ``(log_id, item_id)`` key table ``(K rows)`` and the ``(K, D)`` unit vectors.

    Raises:
        EmbeddingMismatchError: some rows come from another model or have another dimension.
        ValueError: the table is not an embeddings table.
    """
    table = store.read_table(table_name, log_ids)
    missing = [c for c in EMBEDDING_COLUMNS if c not in table.column_names]
    if missing:
        raise ValueError(f"table {table_name!r} is not an embeddings table (missing column(s) {missing})")
    stored_models = sorted(str(m) for m in pc.unique(table.column("model")).to_pylist())
    if stored_models and stored_models != [model]:
        others = [m for m in stored_models if m != model]
        bad_logs = pc.unique(table.filter(pc.not_equal(table.column("model"), model)).column("log_id"))
        raise EmbeddingMismatchError(
            f"table {table_name!r} holds vectors from model(s) {others} "
            f"(e.g. logs {bad_logs.to_pylist()[:3]}), the query is from {model!r}; "
            f"re-embed those logs with {model!r} or query with the matching model"
        )
    vector = table.column("vector").combine_chunks()
    lengths = pc.list_value_length(vector)
    dims = sorted(
        {int(d) for d in pc.unique(lengths).to_pylist()} | set(pc.unique(table.column("dim")).to_pylist())
    )
    if len(dims) > 1 or (dim is not None and dims and dims != [dim]):
        expected = f"the query has dimension {dim}" if dim is not None else "they must agree"
        raise EmbeddingMismatchError(
            f"table {table_name!r} holds {model!r} vectors of dimension(s) {dims}; {expected}"
        )
    d = dims[0] if dims else (dim or 0)
    flat = vector.flatten().to_numpy(zero_copy_only=False).astype(np.float32, copy=False)
    return table.select(["log_id", "item_id"]), flat.reshape(table.num_rows, d)


def search_embeddings(
    store: ScenarioStore,
    table_name: str,
    query: ArrayLike,
    k: int,
    model: str,
    log_ids: Sequence[str] | None = None,
) -> list[EmbeddingHit]:
    """Return the ``k`` stored items most similar to ``query`` ``(D,)`` by cosine similarity, best first.

    Args:
        store: the store.
        table_name: embeddings table written by :func:`write_embeddings`.
        query: ``(D,)`` query vector from ``model``.
        k: number of hits (fewer if the table is smaller).
        model: model that produced ``query``; every stored row must come from it.
        log_ids: restrict the search to these logs.

    Raises:
        EmbeddingMismatchError: stored vectors come from another model or dimension.
        ZeroVectorError: the query has zero length.
    """
    q = np.asarray(query)
    if q.ndim != 1:
        raise ValueError(f"query must be a (D,) vector, got shape {q.shape}")
    unit_q = normalize_rows(q[None, :], ["query"])
    keys, matrix = load_embeddings(store, table_name, model, dim=q.shape[0], log_ids=log_ids)
    if matrix.shape[0] == 0:
        return []
    index = make_index(matrix.shape[1], matrix.shape[0])
    index.add([str(i) for i in range(matrix.shape[0])], matrix)
    log_col = keys.column("log_id").to_numpy(zero_copy_only=False)
    item_col = keys.column("item_id").to_numpy(zero_copy_only=False)
    return [
        EmbeddingHit(str(log_col[int(h.id)]), str(item_col[int(h.id)]), h.score)
        for h in index.search(unit_q[0], k)
    ]
