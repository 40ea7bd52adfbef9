"""The vector indexes behind every ranking: exact, approximate (faiss HNSW) and the size-based choice."""

from __future__ import annotations

import numpy as np
import pytest

from scenariominer.errors import EmbeddingMismatchError, MissingExtraError
from scenariominer.retrieval import ExactCosineIndex, HnswIndex, make_index, rank


def _clustered(rng: np.random.Generator, n: int, dim: int) -> np.ndarray:
    centres = rng.normal(size=(20, dim))
    return centres[rng.integers(0, 20, n)] + 0.3 * rng.normal(size=(n, dim))


def test_rank_orders_every_row_by_cosine_and_keeps_row_order_on_ties() -> None:
    vectors = np.array([[1.0, 0.0], [0.0, 1.0], [1.0, 1.0], [2.0, 0.0]])
    hits = rank(vectors, np.array([1.0, 0.0]), ["a", "b", "c", "d"])
    assert [h.id for h in hits] == ["a", "d", "c", "b"]  # a and d tie at 1.0: row order
    assert hits[0].score == pytest.approx(1.0) and hits[2].score == pytest.approx(np.sqrt(0.5))
    assert rank(np.zeros((0, 2)), np.array([1.0, 0.0])) == []


def test_hnsw_finds_what_exact_search_finds() -> None:
    pytest.importorskip("faiss")
    rng = np.random.default_rng(0)
    data = _clustered(rng, 3000, 32)
    ids = [f"v{i}" for i in range(len(data))]
    exact, approx = ExactCosineIndex(32), HnswIndex(32)
    exact.add(ids, data)
    approx.add(ids, data)
    queries = _clustered(rng, 50, 32)
    recall = np.mean(
        [
            len({h.id for h in a} & {h.id for h in e}) / 10
            for a, e in zip(approx.search_batch(queries, 10), exact.search_batch(queries, 10), strict=True)
        ]
    )
    assert recall >= 0.9
    # scores are the true cosines of the vectors returned
    hit = approx.search(queries[0], 1)[0]
    v, q = data[int(hit.id[1:])], queries[0]
    assert hit.score == pytest.approx(float(v @ q / np.linalg.norm(v) / np.linalg.norm(q)), abs=1e-5)


def test_hnsw_refuses_duplicates_and_wrong_dimensions() -> None:
    pytest.importorskip("faiss")
    index = HnswIndex(4)
    index.add(["a"], np.ones((1, 4)))
    with pytest.raises(ValueError, match="more than once"):
        index.add(["a"], np.ones((1, 4)))
    with pytest.raises(EmbeddingMismatchError):
        index.search(np.ones(3), 1)
    assert [h.id for h in index.search(np.ones(4), 5)] == ["a"]  # fewer than k held


def test_make_index_chooses_by_size() -> None:
    assert isinstance(make_index(8, 10, ann_threshold=100), ExactCosineIndex)
    assert isinstance(make_index(8, 10, ann_threshold=0), ExactCosineIndex)
    big = make_index(8, 1000, ann_threshold=100)
    try:
        import faiss  # noqa: F401

        assert isinstance(big, HnswIndex)
    except ImportError:
        assert isinstance(big, ExactCosineIndex)  # exact is the fallback without the extra


def test_a_missing_extra_names_the_install_command(monkeypatch: pytest.MonkeyPatch) -> None:
    import builtins

    real_import = builtins.__import__

    def no_faiss(name: str, *args: object, **kwargs: object) -> object:
        if name == "faiss":
            raise ImportError("No module named 'faiss'")
        return real_import(name, *args, **kwargs)  # type: ignore[arg-type]

    monkeypatch.setattr(builtins, "__import__", no_faiss)
    monkeypatch.delitem(__import__("sys").modules, "faiss", raising=False)
    with pytest.raises(MissingExtraError, match=r"pip install 'scenariominer\[ann\]'"):
        HnswIndex(4)
