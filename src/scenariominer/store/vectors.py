"""Exact cosine vector search, and embeddings stored as derived tables of the scenario store.

:class:`VectorIndex` is the Protocol every vector index implements; :class:`ExactCosineIndex`
is the built-in exact implementation (unit-normalised float32 rows, one matrix product per
batch of queries, top-k by :func:`numpy.argpartition`). Exact search over ``K`` vectors of
dimension ``D`` costs ``K·D`` multiply-adds per query, which is fast enough for the store's
scale (a million 384-dimensional vectors is about 1.5 GB and tens of milliseconds per query).

Embeddings live in the store as ordinary per-log tables with columns ``log_id``, ``item_id``,
``model``, ``dim`` and ``vector`` (``list<float32>``, unit length). Every row names the model
that produced it, so :func:`search_embeddings` can refuse to compare vectors from different
models or dimensions (:class:`EmbeddingMismatchError`) instead of returning meaningless scores.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Sequence
from typing import TYPE_CHECKING, NamedTuple, Protocol, runtime_checkable

import numpy as np
import pyarrow as pa
import pyarrow.compute as pc
from numpy.typing import ArrayLike, NDArray

from scenariominer import errors as _errors

if TYPE_CHECKING:
    from scenariominer.store.store import ScenarioStore

Float32Array = NDArray[np.float32]

#: Columns of an embeddings table (besides the store's ``log_id``).
EMBEDDING_COLUMNS: tuple[str, ...] = ("item_id", "model", "dim", "vector")

#: Upper bound on the number of scores held at once by a batched search (64 MiB of float32).
_MAX_SCORES_PER_BLOCK = 1 << 24
#: Rows normalised at a time by :func:`normalize_rows`.
_NORMALIZE_BLOCK_ROWS = 8192


class ZeroVectorError(_errors.StoreError, ValueError):
    """A vector has zero length (or non-finite entries) and has no direction to compare."""


class EmbeddingMismatchError(_errors.EmbeddingMismatchError):
    """Vectors from different models or dimensions were about to be compared."""


class VectorHit(NamedTuple):
    """One search result of a :class:`VectorIndex`.

    Attributes:
        id: identifier given to :meth:`VectorIndex.add`.
        score: cosine similarity in ``[-1, 1]``.
    """

    id: str
    score: float


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


@runtime_checkable
class VectorIndex(Protocol):
    """A searchable set of vectors with string ids; scores are cosine similarities."""

    @property
    def dim(self) -> int:
        """Dimension ``D`` of the vectors."""
        ...

    def __len__(self) -> int:
        """Return the number of vectors held."""
        ...

    def add(self, ids: Sequence[str], vectors: ArrayLike) -> None:
        """Add ``(K, D)`` vectors under ``K`` unique ids."""
        ...

    def search(self, query: ArrayLike, k: int) -> list[VectorHit]:
        """Return the ``k`` vectors most similar to ``query`` ``(D,)``, best first."""
        ...

    def search_batch(self, queries: ArrayLike, k: int) -> list[list[VectorHit]]:
        """:meth:`search` for each row of ``queries`` ``(Q, D)``."""
        ...


def normalize_rows(vectors: ArrayLike, ids: Sequence[str] | None = None) -> Float32Array:
    """Scale each row of ``vectors`` ``(K, D)`` to unit length, as float32.

    Args:
        vectors: ``(K, D)`` array-like of finite numbers.
        ids: names of the rows, used in error messages.

    Raises:
        ValueError: ``vectors`` is not two-dimensional or has non-finite entries.
        ZeroVectorError: a row has zero length.
    """
    arr = np.asarray(vectors)
    if arr.ndim != 2:
        raise ValueError(f"vectors must be a (K, D) array, got shape {arr.shape}")
    if not np.issubdtype(arr.dtype, np.floating):
        arr = arr.astype(np.float64)
    out = np.empty(arr.shape, dtype=np.float32)
    # Row blocks keep the float64 temporaries small for large inputs.
    for start in range(0, arr.shape[0], _NORMALIZE_BLOCK_ROWS):
        block = arr[start : start + _NORMALIZE_BLOCK_ROWS].astype(np.float64)
        finite = np.all(np.isfinite(block), axis=1)
        if not finite.all():
            bad = np.logical_not(finite)
            raise ValueError(f"vector(s) {_names(bad, ids, start)} contain NaN or infinite values")
        norms = np.sqrt(np.einsum("ij,ij->i", block, block))
        zero = norms == 0.0
        if zero.any():
            raise ZeroVectorError(
                f"vector(s) {_names(zero, ids, start)} have zero length; cosine similarity is undefined"
            )
        out[start : start + block.shape[0]] = block / norms[:, None]
    return out


def top_k(scores: NDArray[np.floating], k: int) -> NDArray[np.intp]:
    """Column indices of the ``k`` largest scores of each row of ``scores`` ``(Q, N)``, best first.

    Ties are ordered by column index. ``k`` is capped at ``N``.

    Returns:
        ``(Q, min(k, N))`` indices.
    """
    if k < 1:
        raise ValueError(f"k must be at least 1, got {k}")
    n = scores.shape[1]
    k = min(k, n)
    if k == 0:
        return np.empty((scores.shape[0], 0), dtype=np.intp)
    if k < n:
        part = np.argpartition(-scores, k - 1, axis=1)[:, :k]
    else:
        part = np.broadcast_to(np.arange(n), scores.shape)
    part_scores = np.take_along_axis(scores, part, axis=1)
    order = np.lexsort((part, -part_scores), axis=1)
    return np.take_along_axis(part, order, axis=1)


class ExactCosineIndex:
    """Exact cosine-similarity search over unit-normalised float32 vectors held in memory.

    Attributes:
        dim: dimension ``D`` of the vectors.
    """

    def __init__(self, dim: int, *, max_scores_per_block: int = _MAX_SCORES_PER_BLOCK) -> None:
        """Create an empty index for ``dim``-dimensional vectors.

        Args:
            dim: vector dimension ``D``.
            max_scores_per_block: bound on the ``queries × vectors`` scores computed at once.
        """
        if dim < 1:
            raise ValueError(f"dim must be at least 1, got {dim}")
        self._dim = int(dim)
        self._max_scores = max(1, int(max_scores_per_block))
        self._ids: list[str] = []
        self._id_set: set[str] = set()
        self._blocks: list[Float32Array] = []
        self._matrix: Float32Array = np.empty((0, self._dim), dtype=np.float32)

    @property
    def dim(self) -> int:
        """Dimension ``D`` of the vectors."""
        return self._dim

    @property
    def ids(self) -> tuple[str, ...]:
        """Ids in insertion order."""
        return tuple(self._ids)

    def __len__(self) -> int:
        return len(self._ids)

    def add(self, ids: Sequence[str], vectors: ArrayLike) -> None:
        """Add ``(K, D)`` vectors under ``K`` unique ids (normalised to unit length).

        Raises:
            ValueError: shapes disagree, an id repeats, or a vector is not finite.
            EmbeddingMismatchError: ``D`` differs from the index dimension.
            ZeroVectorError: a vector has zero length.
        """
        ids = [str(i) for i in ids]
        arr = np.asarray(vectors)
        if arr.ndim != 2 or arr.shape[0] != len(ids):
            raise ValueError(
                f"expected ({len(ids)}, {self._dim}) vectors for {len(ids)} ids, got shape {arr.shape}"
            )
        if arr.shape[1] != self._dim:
            raise EmbeddingMismatchError(
                f"vectors have dimension {arr.shape[1]}, the index holds {self._dim}"
            )
        counts = Counter(ids)
        dup = next((i for i in ids if counts[i] > 1 or i in self._id_set), None)
        if dup is not None:
            raise ValueError(f"id {dup!r} occurs more than once in the index")
        unit = normalize_rows(arr, ids)
        self._blocks.append(unit)
        self._ids.extend(ids)
        self._id_set.update(ids)

    def search(self, query: ArrayLike, k: int) -> list[VectorHit]:
        """Return the ``k`` vectors most similar to ``query`` ``(D,)``, best first (fewer if fewer are held).

        Raises:
            EmbeddingMismatchError: the query dimension differs from the index dimension.
            ZeroVectorError: the query has zero length.
        """
        q = np.asarray(query)
        if q.ndim != 1:
            raise ValueError(
                f"query must be a (D,) vector, got shape {q.shape}; use search_batch for several"
            )
        return self.search_batch(q[None, :], k)[0]

    def search_batch(self, queries: ArrayLike, k: int) -> list[list[VectorHit]]:
        """:meth:`search` for each row of ``queries`` ``(Q, D)``, in blocks of bounded memory."""
        q = np.asarray(queries)
        if q.ndim != 2:
            raise ValueError(f"queries must be a (Q, D) array, got shape {q.shape}")
        if q.shape[1] != self._dim:
            raise EmbeddingMismatchError(f"query has dimension {q.shape[1]}, the index holds {self._dim}")
        unit = normalize_rows(q, [f"query {i}" for i in range(q.shape[0])])
        if k < 1:
            raise ValueError(f"k must be at least 1, got {k}")
        matrix = self._stacked()
        out: list[list[VectorHit]] = []
        rows_per_block = max(1, self._max_scores // max(1, matrix.shape[0]))
        for start in range(0, unit.shape[0], rows_per_block):
            scores = unit[start : start + rows_per_block] @ matrix.T
            best = top_k(scores, k)
            best_scores = np.take_along_axis(scores, best, axis=1)
            for idx_row, score_row in zip(best.tolist(), best_scores.tolist(), strict=True):
                out.append(
                    [VectorHit(self._ids[i], float(s)) for i, s in zip(idx_row, score_row, strict=True)]
                )
        return out

    def _stacked(self) -> Float32Array:
        if self._blocks:
            self._matrix = np.concatenate([self._matrix, *self._blocks], axis=0)
            self._blocks = []
        return self._matrix


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
    scores = unit_q @ matrix.T
    best = top_k(scores, k)[0]
    log_col = keys.column("log_id").to_numpy(zero_copy_only=False)
    item_col = keys.column("item_id").to_numpy(zero_copy_only=False)
    return [EmbeddingHit(str(log_col[i]), str(item_col[i]), float(scores[0, i])) for i in best]


def _names(mask: NDArray[np.bool_], ids: Sequence[str] | None, offset: int = 0) -> list[str]:
    rows = (np.flatnonzero(mask)[:5] + offset).tolist()
    return [ids[i] for i in rows] if ids is not None else [f"row {i}" for i in rows]
