"""The [llm] and [embedding] configuration sections: greedy defaults, TOML, environment, validation."""

from __future__ import annotations

from pathlib import Path

import pytest

from scenariominer.config import ConfigError, load_config
from scenariominer.config.llm import (
    ChatBackendName,
    EmbeddingBackendName,
    EmbeddingConfig,
    LLMConfig,
    StructuredMode,
)


def test_defaults_are_offline_and_greedy() -> None:
    cfg = load_config(environ={})
    assert cfg.llm == LLMConfig()
    assert cfg.llm.backend is ChatBackendName.LLAMACPP
    assert (cfg.llm.temperature, cfg.llm.top_p, cfg.llm.top_k) == (0.0, 1.0, 1)
    assert cfg.llm.model_path == ""  # the bundled model
    assert cfg.llm.max_concurrency == 4
    assert cfg.llm.repair_rounds == 1
    assert cfg.embedding.backend is EmbeddingBackendName.SENTENCE_TRANSFORMERS
    assert cfg.embedding.model == "all-MiniLM-L6-v2"


def test_toml_selects_an_openai_compatible_server(tmp_path: Path) -> None:
    p = tmp_path / "c.toml"
    p.write_text(
        '[llm]\nbackend = "openai"\nmodel = "qwen2.5-coder:7b"\nstructured_mode = "json_object"\n'
        'max_concurrency = 8\n[embedding]\nbackend = "openai"\nmodel = "nomic-embed-text"\n'
    )
    cfg = load_config(p, environ={})
    assert cfg.llm.backend is ChatBackendName.OPENAI
    assert cfg.llm.model == "qwen2.5-coder:7b"
    assert cfg.llm.structured_mode is StructuredMode.JSON_OBJECT
    assert cfg.llm.max_concurrency == 8
    assert cfg.embedding.backend is EmbeddingBackendName.OPENAI


def test_environment_overrides_llm_fields(tmp_path: Path) -> None:
    cfg = load_config(
        environ={
            "SCENARIOMINER__LLM__BACKEND": "openai",
            "SCENARIOMINER__LLM__API_KEY": "sk-env",
            "SCENARIOMINER__LLM__TEMPERATURE": "0.2",
            "SCENARIOMINER__LLM__CACHE": "false",
            "SCENARIOMINER__EMBEDDING__BACKEND": "hashing",
        }
    )
    assert cfg.llm.backend is ChatBackendName.OPENAI
    assert cfg.llm.api_key == "sk-env"
    assert cfg.llm.temperature == 0.2
    assert cfg.llm.cache is False
    assert cfg.embedding.backend is EmbeddingBackendName.HASHING


@pytest.mark.parametrize(
    ("env", "message"),
    [
        (
            {"SCENARIOMINER__LLM__BACKEND": "gpt"},
            r"LLMConfig.backend must be one of \['llamacpp', 'openai'\]",
        ),
        ({"SCENARIOMINER__LLM__STRUCTURED_MODE": "xml"}, "structured_mode must be one of"),
        ({"SCENARIOMINER__LLM__TEMPERATURE": "-1"}, "llm.temperature must be >= 0"),
        ({"SCENARIOMINER__LLM__TOP_P": "0"}, r"llm.top_p must be in \(0, 1\]"),
        ({"SCENARIOMINER__LLM__MAX_CONCURRENCY": "0"}, "llm.max_concurrency must be >= 1"),
        ({"SCENARIOMINER__EMBEDDING__BACKEND": "word2vec"}, "EmbeddingConfig.backend must be one of"),
        ({"SCENARIOMINER__EMBEDDING__BATCH_SIZE": "0"}, "embedding.batch_size must be >= 1"),
    ],
)
def test_invalid_values_raise_config_error_naming_the_key(env: dict[str, str], message: str) -> None:
    with pytest.raises(ConfigError, match=message):
        load_config(environ=env)


def test_sections_can_be_built_directly() -> None:
    assert LLMConfig(backend="openai").backend is ChatBackendName.OPENAI  # type: ignore[arg-type]
    assert EmbeddingConfig(hashing_dim=16).hashing_dim == 16
