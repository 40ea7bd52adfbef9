"""Exact cosine search: agrees with brute force, and refuses to compare incompatible vectors."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from scenariominer.data.log import build_log
from scenariominer.store import (
    EmbeddingMismatchError,
    ExactCosineIndex,
    ScenarioStore,
    VectorIndex,
    ZeroVectorError,
    load_embeddings,
    normalize_rows,
    search_embeddings,
    write_embeddings,
)
from scenariominer.store.vectors import top_k


def brute_force(matrix: np.ndarray, query: np.ndarray, k: int) -> tuple[list[int], np.ndarray]:
    """Reference answer in float64: sort all cosine similarities, ties by index."""
    m = matrix / np.linalg.norm(matrix, axis=1, keepdims=True)
    q = query / np.linalg.norm(query)
    scores = m @ q
    order = sorted(range(len(scores)), key=lambda i: (-scores[i], i))[:k]
    return order, scores[order]


def test_exact_index_matches_brute_force_on_random_vectors() -> None:
    rng = np.random.default_rng(7)
    vectors = rng.normal(size=(500, 32))
    queries = rng.normal(size=(6, 32))
    index = ExactCosineIndex(32)
    index.add([f"v{i}" for i in range(300)], vectors[:300])
    index.add([f"v{i}" for i in range(300, 500)], vectors[300:])  # two batches
    results = index.search_batch(queries, k=10)
    for query, hits in zip(queries, results, strict=True):
        order, scores = brute_force(vectors, query, 10)
        assert [h.id for h in hits] == [f"v{i}" for i in order]
        np.testing.assert_allclose([h.score for h in hits], scores, atol=1e-5)


def test_batched_search_in_small_blocks_gives_the_same_answer() -> None:
    rng = np.random.default_rng(3)
    vectors = rng.normal(size=(200, 8))
    queries = rng.normal(size=(9, 8))
    big, small = ExactCosineIndex(8), ExactCosineIndex(8, max_scores_per_block=450)  # 2 queries per block
    for index in (big, small):
        index.add([str(i) for i in range(200)], vectors)
    for whole, blocked in zip(big.search_batch(queries, 5), small.search_batch(queries, 5), strict=True):
        assert [h.id for h in whole] == [h.id for h in blocked]
        # float32 matrix products of different shapes may differ in the last bit
        np.testing.assert_allclose([h.score for h in whole], [h.score for h in blocked], atol=1e-6)


def test_known_answer_on_hand_built_vectors() -> None:
    index = ExactCosineIndex(2)
    index.add(["east", "north", "north_east", "west"], [[2.0, 0.0], [0.0, 5.0], [1.0, 1.0], [-3.0, 0.0]])
    hits = index.search([1.0, 0.0], k=3)
    assert [h.id for h in hits] == ["east", "north_east", "north"]
    np.testing.assert_allclose([h.score for h in hits], [1.0, np.sqrt(0.5), 0.0], atol=1e-6)
    everything = index.search([1.0, 0.0], k=10)  # k larger than the index
    assert [h.id for h in everything] == ["east", "north_east", "north", "west"]
    assert everything[-1].score == pytest.approx(-1.0)


def test_top_k_orders_ties_by_position() -> None:
    scores = np.array([[0.5, 0.9, 0.5, 0.9, 0.1]])
    assert top_k(scores, 4).tolist() == [[1, 3, 0, 2]]
    with pytest.raises(ValueError, match="at least 1"):
        top_k(scores, 0)


def test_the_exact_index_satisfies_the_protocol() -> None:
    assert isinstance(ExactCosineIndex(4), VectorIndex)
    assert ExactCosineIndex(4).search([1.0, 0.0, 0.0, 0.0], k=3) == []


def test_zero_and_non_finite_vectors_are_errors_naming_the_item() -> None:
    index = ExactCosineIndex(3)
    with pytest.raises(ZeroVectorError, match=r"\['b'\] have zero length"):
        index.add(["a", "b"], [[1.0, 0.0, 0.0], [0.0, 0.0, 0.0]])
    assert len(index) == 0
    index.add(["a"], [[1.0, 0.0, 0.0]])
    with pytest.raises(ZeroVectorError):
        index.search([0.0, 0.0, 0.0], k=1)
    with pytest.raises(ValueError, match="NaN or infinite"):
        normalize_rows([[np.nan, 1.0, 0.0]])


def test_dimension_mismatch_and_duplicate_ids_are_refused() -> None:
    index = ExactCosineIndex(3)
    index.add(["a"], [[1.0, 0.0, 0.0]])
    with pytest.raises(EmbeddingMismatchError, match="dimension 2"):
        index.add(["b"], [[1.0, 0.0]])
    with pytest.raises(EmbeddingMismatchError, match="dimension 4"):
        index.search([1.0, 0.0, 0.0, 0.0], k=1)
    with pytest.raises(ValueError, match="'a' occurs more than once"):
        index.add(["a"], [[0.0, 1.0, 0.0]])


def test_normalize_rows_gives_unit_float32_rows() -> None:
    unit = normalize_rows([[3.0, 4.0], [0.0, -2.0]])
    assert unit.dtype == np.float32
    np.testing.assert_allclose(unit, [[0.6, 0.8], [0.0, -1.0]], atol=1e-7)


# ---------------------------------------------------------------------- stored embeddings


def _tiny_log(log_id: str):  # type: ignore[no-untyped-def]
    x = np.array([0.0, 1.0])
    return build_log(
        log_id=log_id,
        track_id=["ego", "ego"],
        category=["EGO_VEHICLE", "EGO_VEHICLE"],
        timestamp_ns=[0, 100_000_000],
        fields={"x_m": x, "y_m": x * 0, "yaw_rad": x * 0, "length_m": x * 0 + 4, "width_m": x * 0 + 2},
        ego_track_id=None,
        source="<test>",
    )


@pytest.fixture()
def store(tmp_path: Path) -> ScenarioStore:
    st = ScenarioStore.open(tmp_path / "store")
    st.replace_source("src", "h", [_tiny_log("A"), _tiny_log("B")])
    return st


def test_search_over_stored_embeddings_matches_brute_force(store: ScenarioStore) -> None:
    rng = np.random.default_rng(11)
    vec_a, vec_b = rng.normal(size=(40, 16)), rng.normal(size=(25, 16))
    write_embeddings(store, "A", "scenario_embeddings", [f"a{i}" for i in range(40)], vec_a, "mini-lm")
    write_embeddings(store, "B", "scenario_embeddings", [f"b{i}" for i in range(25)], vec_b, "mini-lm")
    query = rng.normal(size=16)
    hits = search_embeddings(store, "scenario_embeddings", query, k=7, model="mini-lm")
    everything = np.vstack([vec_a, vec_b])
    keys = [("A", f"a{i}") for i in range(40)] + [("B", f"b{i}") for i in range(25)]
    order, scores = brute_force(everything, query, 7)
    assert [(h.log_id, h.item_id) for h in hits] == [keys[i] for i in order]
    np.testing.assert_allclose([h.score for h in hits], scores, atol=1e-5)
    only_b = search_embeddings(store, "scenario_embeddings", query, k=3, model="mini-lm", log_ids=["B"])
    assert {h.log_id for h in only_b} == {"B"}
    log_id, item_id, score = only_b[0]
    assert log_id == "B" and item_id.startswith("b") and -1.0 <= score <= 1.0


def test_stored_rows_carry_model_dimension_and_unit_vectors(store: ScenarioStore) -> None:
    write_embeddings(store, "A", "emb", ["x", "y"], [[3.0, 4.0], [0.0, 2.0]], "m1")
    table = store.read_table("emb")
    assert table.column_names == ["log_id", "item_id", "model", "dim", "vector"]
    assert table.column("model").to_pylist() == ["m1", "m1"]
    assert table.column("dim").to_pylist() == [2, 2]
    keys, matrix = load_embeddings(store, "emb", "m1")
    assert keys.to_pydict() == {"log_id": ["A", "A"], "item_id": ["x", "y"]}
    np.testing.assert_allclose(matrix, [[0.6, 0.8], [0.0, 1.0]], atol=1e-7)


def test_vectors_from_another_model_are_refused(store: ScenarioStore) -> None:
    write_embeddings(store, "A", "emb", ["x"], [[1.0, 0.0]], "model-one")
    write_embeddings(store, "B", "emb", ["y"], [[0.0, 1.0]], "model-two")
    with pytest.raises(EmbeddingMismatchError, match=r"model\(s\) \['model-two'\] \(e.g. logs \['B'\]\)"):
        search_embeddings(store, "emb", [1.0, 0.0], k=1, model="model-one")


def test_vectors_of_another_dimension_are_refused(store: ScenarioStore) -> None:
    write_embeddings(store, "A", "emb", ["x"], [[1.0, 0.0]], "m")
    write_embeddings(store, "B", "emb", ["y"], [[0.0, 1.0, 0.0]], "m")
    with pytest.raises(EmbeddingMismatchError, match=r"dimension\(s\) \[2, 3\]"):
        search_embeddings(store, "emb", [1.0, 0.0], k=1, model="m")
    # Restricted to A alone the dimensions agree, but the query must match them too.
    assert search_embeddings(store, "emb", [1.0, 0.0], k=1, model="m", log_ids=["A"])[0].item_id == "x"
    with pytest.raises(EmbeddingMismatchError, match="query has dimension 3"):
        search_embeddings(store, "emb", [1.0, 0.0, 0.0], k=1, model="m", log_ids=["A"])


def test_zero_vectors_are_refused_when_written_and_when_queried(store: ScenarioStore) -> None:
    with pytest.raises(ZeroVectorError, match=r"\['y'\]"):
        write_embeddings(store, "A", "emb", ["x", "y"], [[1.0, 0.0], [0.0, 0.0]], "m")
    assert store.table_names() == []
    write_embeddings(store, "A", "emb", ["x"], [[1.0, 0.0]], "m")
    with pytest.raises(ZeroVectorError):
        search_embeddings(store, "emb", [0.0, 0.0], k=1, model="m")
