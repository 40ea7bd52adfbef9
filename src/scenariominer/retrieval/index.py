"""Vector indexes: the one place where vectors are ranked by cosine similarity.

:class:`VectorIndex` is the Protocol every index implements. :class:`ExactCosineIndex` holds
unit-normalised float32 rows and scores a batch of queries with one matrix product, top-k by
:func:`numpy.argpartition` (``K·D`` multiply-adds per query: a million 384-dimensional vectors is
about 1.5 GB and tens of milliseconds per query). :class:`HnswIndex` is the approximate backend
(faiss HNSW graph over inner products of unit vectors; the optional ``ann`` extra), and
:func:`make_index` chooses between them by size (``ann_threshold``, measured in
``benchmarks/retrieval.py``). Every ranking of the project goes through these: event search,
few-shot example selection, retrieval evaluation, store embedding search.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Sequence
from typing import Any, NamedTuple, Protocol, runtime_checkable

import numpy as np
from numpy.typing import ArrayLike, NDArray

from scenariominer import errors as _errors

__all__ = [
    "DEFAULT_ANN_THRESHOLD",
    "EmbeddingMismatchError",
    "ExactCosineIndex",
    "HnswIndex",
    "VectorHit",
    "VectorIndex",
    "ZeroVectorError",
    "make_index",
    "normalize_rows",
    "rank",
    "top_k",
]

Float32Array = NDArray[np.float32]

#: Upper bound on the number of scores held at once by a batched search (64 MiB of float32).
_MAX_SCORES_PER_BLOCK = 1 << 24
#: Rows normalised at a time by :func:`normalize_rows`.
_NORMALIZE_BLOCK_ROWS = 8192
#: Index size from which :func:`make_index` builds an approximate index (when faiss is installed).
#: Measured (benchmarks/retrieval.py, 384-d, 2 cores): exact search costs about 4 ms per query at
#: 100k vectors, so below this size exactness is worth more than the few milliseconds HNSW saves.
DEFAULT_ANN_THRESHOLD = 200_000


class ZeroVectorError(_errors.ScenarioMinerError, ValueError):
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
        arr = _checked(vectors, len(ids), self._dim)
        dup = _duplicate(ids, self._id_set)
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
        unit = _queries(queries, self._dim, k)
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


class HnswIndex:
    """Approximate cosine search: a faiss HNSW graph over unit vectors (inner product = cosine).

    Same interface as :class:`ExactCosineIndex`. Needs the optional ``ann`` extra
    (``pip install 'scenariominer[ann]'``, faiss-cpu). Scores are exact cosines of the returned
    vectors; the approximation is which vectors are returned (recall measured in
    ``benchmarks/retrieval.py``).

    Args:
        dim: vector dimension ``D``.
        m: graph degree (faiss ``M``).
        ef_search: candidate list size at query time (higher: better recall, slower).
    """

    def __init__(self, dim: int, *, m: int = 48, ef_search: int = 1024) -> None:
        from scenariominer._optional import require

        faiss = require("faiss", extra="ann", purpose="approximate vector search")
        if dim < 1:
            raise ValueError(f"dim must be at least 1, got {dim}")
        self._dim = int(dim)
        self._index: Any = faiss.IndexHNSWFlat(self._dim, m, faiss.METRIC_INNER_PRODUCT)
        self._index.hnsw.efSearch = ef_search
        self._ids: list[str] = []
        self._id_set: set[str] = set()

    @property
    def dim(self) -> int:
        """Dimension ``D`` of the vectors."""
        return self._dim

    def __len__(self) -> int:
        return len(self._ids)

    def add(self, ids: Sequence[str], vectors: ArrayLike) -> None:
        """Add ``(K, D)`` vectors under ``K`` unique ids (normalised to unit length)."""
        ids = [str(i) for i in ids]
        arr = _checked(vectors, len(ids), self._dim)
        dup = _duplicate(ids, self._id_set)
        if dup is not None:
            raise ValueError(f"id {dup!r} occurs more than once in the index")
        self._index.add(normalize_rows(arr, ids))
        self._ids.extend(ids)
        self._id_set.update(ids)

    def search(self, query: ArrayLike, k: int) -> list[VectorHit]:
        """The ``k`` (approximately) most similar vectors to ``query`` ``(D,)``, best first."""
        return self.search_batch(np.asarray(query)[None, :], k)[0]

    def search_batch(self, queries: ArrayLike, k: int) -> list[list[VectorHit]]:
        """:meth:`search` for each row of ``queries`` ``(Q, D)``."""
        q = _queries(queries, self._dim, k)
        scores, idx = self._index.search(q, min(k, len(self._ids)) or 1)
        return [
            [VectorHit(self._ids[i], float(s)) for i, s in zip(row_i, row_s, strict=True) if i >= 0]
            for row_i, row_s in zip(idx.tolist(), scores.tolist(), strict=True)
        ]


def make_index(dim: int, n_expected: int, *, ann_threshold: int = DEFAULT_ANN_THRESHOLD) -> VectorIndex:
    """The index to use for about ``n_expected`` vectors: exact below ``ann_threshold``, else HNSW.

    Falls back to the exact index when faiss is not installed (exact search is always correct;
    only slower at large sizes). ``ann_threshold <= 0`` disables the approximate backend.
    """
    if 0 < ann_threshold <= n_expected:
        try:
            return HnswIndex(dim)
        except _errors.ScenarioMinerError:
            pass
    return ExactCosineIndex(dim)


def rank(vectors: ArrayLike, query: ArrayLike, ids: Sequence[str] | None = None) -> list[VectorHit]:
    """Every row of ``vectors`` ``(K, D)`` ranked by cosine similarity to ``query`` ``(D,)``, best first.

    Ties keep row order. For small sets ranked once (few-shot examples, one evaluation query);
    ids default to the row numbers as strings.
    """
    arr = np.asarray(vectors)
    names = [str(i) for i in range(arr.shape[0])] if ids is None else [str(i) for i in ids]
    if arr.shape[0] == 0:
        return []
    index = ExactCosineIndex(arr.shape[1])
    index.add(names, arr)
    return index.search(query, len(names))


def _checked(vectors: ArrayLike, n: int, dim: int) -> NDArray[Any]:
    arr = np.asarray(vectors)
    if arr.ndim != 2 or arr.shape[0] != n:
        raise ValueError(f"expected ({n}, {dim}) vectors for {n} ids, got shape {arr.shape}")
    if arr.shape[1] != dim:
        raise EmbeddingMismatchError(f"vectors have dimension {arr.shape[1]}, the index holds {dim}")
    return arr


def _duplicate(ids: Sequence[str], existing: set[str]) -> str | None:
    counts = Counter(ids)
    return next((i for i in ids if counts[i] > 1 or i in existing), None)


def _queries(queries: ArrayLike, dim: int, k: int) -> Float32Array:
    q = np.asarray(queries)
    if q.ndim != 2:
        raise ValueError(f"queries must be a (Q, D) array, got shape {q.shape}")
    if q.shape[1] != dim:
        raise EmbeddingMismatchError(f"query has dimension {q.shape[1]}, the index holds {dim}")
    if k < 1:
        raise ValueError(f"k must be at least 1, got {k}")
    return normalize_rows(q, [f"query {i}" for i in range(q.shape[0])])


def _names(mask: NDArray[np.bool_], ids: Sequence[str] | None, offset: int = 0) -> list[str]:
    rows = (np.flatnonzero(mask)[:5] + offset).tolist()
    return [ids[i] for i in rows] if ids is not None else [f"row {i}" for i in rows]
