"""Building chat clients and embedders from the configuration."""

from __future__ import annotations

from pathlib import Path

import pytest

from scenariominer.config import Config
from scenariominer.config.llm import EmbeddingConfig, LLMConfig, StructuredMode
from scenariominer.llm import (
    GenerationParams,
    HashingEmbedder,
    LlamaCppBackend,
    ModelNotAvailableError,
    OpenAICompatBackend,
    OpenAICompatEmbedder,
    make_chat_client,
    make_embedder,
    user,
)


def openai_config(url: str, tmp_path: Path, **kw: object) -> LLMConfig:
    return LLMConfig(
        backend="openai", base_url=url, model="qwen2.5-coder:1.5b", cache_dir=str(tmp_path), **kw
    )  # type: ignore[arg-type]


def test_openai_client_uses_config_values_and_key_from_environment(openai_server, tmp_path, monkeypatch):
    monkeypatch.setenv("MY_LLM_KEY", "sk-from-env")
    cfg = openai_config(
        openai_server.base_url,
        tmp_path,
        api_key_env="MY_LLM_KEY",
        structured_mode="prompt",
        top_k=0,
        max_tokens=99,
    )
    with make_chat_client(Config(llm=cfg)) as client:
        assert isinstance(client.backend, OpenAICompatBackend)
        assert client.backend.structured_mode is StructuredMode.PROMPT
        assert client.params == GenerationParams(temperature=0.0, top_p=1.0, top_k=0, max_tokens=99, seed=0)
        client.complete([user("hi")])
        client.complete([user("hi")])  # served from the cache in tmp_path
    (body,) = openai_server.bodies("/v1/chat/completions")
    assert body["max_tokens"] == 99
    assert "top_k" not in body
    assert openai_server.requests[0][2]["authorization"] == "Bearer sk-from-env"
    assert (tmp_path / "llm-cache.sqlite3").is_file()


def test_cache_can_be_disabled(openai_server, tmp_path):
    with make_chat_client(openai_config(openai_server.base_url, tmp_path, cache=False)) as client:
        assert client.cache is None
        client.complete([user("hi")])
        client.complete([user("hi")])
    assert len(openai_server.bodies("/v1/chat/completions")) == 2


def test_llamacpp_client_with_a_missing_model_path_says_what_to_do(tmp_path):
    cfg = LLMConfig(model_path=str(tmp_path / "absent.gguf"), cache_dir=str(tmp_path))
    with pytest.raises(ModelNotAvailableError, match=r"absent.gguf.*is not a file.*scenariominer\[llm\]"):
        make_chat_client(cfg)


def test_llamacpp_client_with_a_user_gguf_does_not_load_it_yet(tmp_path):
    gguf = tmp_path / "tiny.gguf"
    gguf.write_bytes(b"GGUF" + b"\x00" * 28)
    client = make_chat_client(LLMConfig(model_path=str(gguf), cache_dir=str(tmp_path), n_threads=3))
    backend = client.backend
    assert isinstance(backend, LlamaCppBackend)
    assert backend.model_file.path == gguf.resolve()
    assert backend.model_name == "tiny"
    assert backend.n_threads == 3
    assert backend.load_time_s is None
    client.close()


def test_make_embedder_selects_the_backend(tmp_path):
    hashing = make_embedder(Config(embedding=EmbeddingConfig(backend="hashing", hashing_dim=32)))  # type: ignore[arg-type]
    assert isinstance(hashing, HashingEmbedder)
    assert hashing.embed(["x"]).dim == 32
    server = make_embedder(
        EmbeddingConfig(backend="openai", model="nomic-embed-text", cache_dir=str(tmp_path), batch_size=7)  # type: ignore[arg-type]
    )
    assert isinstance(server, OpenAICompatEmbedder)
    assert (server.model, server.batch_size) == ("nomic-embed-text", 7)
    assert server.cache is not None


def test_sentence_transformer_with_missing_folder_is_reported(tmp_path):
    cfg = EmbeddingConfig(model_path=str(tmp_path / "nope"), cache=False)
    with pytest.raises(ModelNotAvailableError, match="embedding.model_path"):
        make_embedder(cfg)
