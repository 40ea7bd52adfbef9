"""One vector index and ranking for every search of the project (see :mod:`.index`)."""

from scenariominer.retrieval.index import (
    DEFAULT_ANN_THRESHOLD,
    EmbeddingMismatchError,
    ExactCosineIndex,
    HnswIndex,
    VectorHit,
    VectorIndex,
    ZeroVectorError,
    make_index,
    normalize_rows,
    rank,
    top_k,
)

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
