"""Build chat clients and embedders from the configuration."""

from __future__ import annotations

from scenariominer.config import Config
from scenariominer.config.llm import ChatBackendName, EmbeddingBackendName, EmbeddingConfig, LLMConfig
from scenariominer.llm.base import ChatBackend, GenerationParams
from scenariominer.llm.cache import ResponseCache, resolve_cache_dir
from scenariominer.llm.client import ChatClient
from scenariominer.llm.embeddings import (
    Embedder,
    HashingEmbedder,
    OpenAICompatEmbedder,
    SentenceTransformerEmbedder,
)
from scenariominer.llm.llamacpp import LlamaCppBackend
from scenariominer.llm.model_files import DEFAULT_MODEL, resolve_model_file
from scenariominer.llm.openai_compat import OpenAICompatBackend, OpenAIHTTP, resolve_api_key
from scenariominer.llm.prefix_cache import PREFIX_DIRNAME
from scenariominer.llm.usage import UsageCounter

__all__ = ["generation_params", "make_chat_backend", "make_chat_client", "make_embedder"]


def _llm_config(config: Config | LLMConfig) -> LLMConfig:
    return config if isinstance(config, LLMConfig) else config.llm


def _embedding_config(config: Config | EmbeddingConfig) -> EmbeddingConfig:
    return config if isinstance(config, EmbeddingConfig) else config.embedding


def generation_params(config: Config | LLMConfig) -> GenerationParams:
    """Default decoding parameters of the configured client."""
    cfg = _llm_config(config)
    return GenerationParams(
        temperature=cfg.temperature,
        top_p=cfg.top_p,
        top_k=cfg.top_k,
        max_tokens=cfg.max_tokens,
        seed=cfg.seed,
    )


def make_chat_backend(config: Config | LLMConfig, *, verify_model: bool = False) -> ChatBackend:
    """Build the configured chat backend (the embedded model is loaded lazily, on the first call).

    Args:
        config: root config or its ``llm`` section.
        verify_model: hash the GGUF file now (re-checks the bundled model against its pin).

    Raises:
        ModelNotAvailableError: the model file or the packages carrying it are missing.
        ModelIntegrityError: the bundled model fails verification.
    """
    cfg = _llm_config(config)
    if cfg.backend is ChatBackendName.LLAMACPP:
        model_file = resolve_model_file(cfg.model_path, resolve_cache_dir(cfg.cache_dir), verify=verify_model)
        label = cfg.model
        if cfg.model_path and cfg.model == LLMConfig.model:
            label = model_file.path.stem
        elif not cfg.model_path:
            label = DEFAULT_MODEL.name
        cache_dir = resolve_cache_dir(cfg.cache_dir)
        return LlamaCppBackend(
            model_file,
            model_name=label,
            n_ctx=cfg.n_ctx,
            n_threads=cfg.n_threads,
            seed=cfg.seed,
            prefix_dir=cache_dir / PREFIX_DIRNAME if cfg.prefix_cache else None,
            prefix_min_tokens=cfg.prefix_cache_min_tokens,
            prefix_max_bytes=cfg.prefix_cache_max_mb << 20,
        )
    http = OpenAIHTTP(
        cfg.base_url,
        api_key=resolve_api_key(cfg.api_key, cfg.api_key_env),
        timeout_s=cfg.timeout_s,
        max_retries=cfg.max_retries,
        max_connections=cfg.max_concurrency,
    )
    return OpenAICompatBackend(
        http, cfg.model, structured_mode=cfg.structured_mode, send_top_k=cfg.send_top_k
    )


def make_chat_client(
    config: Config | LLMConfig, *, usage: UsageCounter | None = None, use_cache: bool | None = None
) -> ChatClient:
    """Build the chat client every feature uses from ``[llm]``.

    Args:
        config: root config or its ``llm`` section.
        usage: counter shared with other clients of the same command (a fresh one if ``None``).
        use_cache: override ``llm.cache`` (``False`` forces real calls, e.g. for a health check).

    Raises:
        ModelNotAvailableError: the model file or the packages carrying it are missing.
    """
    cfg = _llm_config(config)
    backend = make_chat_backend(cfg)
    cached = cfg.cache if use_cache is None else use_cache
    return ChatClient(
        backend,
        params=generation_params(cfg),
        cache=ResponseCache.in_dir(cfg.cache_dir) if cached else None,
        usage=usage,
        repair_rounds=cfg.repair_rounds,
        max_concurrency=cfg.max_concurrency,
    )


def make_embedder(
    config: Config | EmbeddingConfig, *, usage: UsageCounter | None = None, use_cache: bool | None = None
) -> Embedder:
    """Build the configured text embedder from ``[embedding]``.

    Args:
        config: root config or its ``embedding`` section.
        usage: counter shared with other clients of the same command.
        use_cache: override ``embedding.cache``.

    Raises:
        ModelNotAvailableError: the sentence-transformers model folder is missing.
    """
    cfg = _embedding_config(config)
    cached = cfg.cache if use_cache is None else use_cache
    if cfg.backend is EmbeddingBackendName.HASHING:
        return HashingEmbedder(cfg.hashing_dim, usage=usage)
    cache = ResponseCache.in_dir(cfg.cache_dir) if cached else None
    if cfg.backend is EmbeddingBackendName.SENTENCE_TRANSFORMERS:
        label = "" if cfg.model == EmbeddingConfig.model else cfg.model
        return SentenceTransformerEmbedder(
            cfg.model_path or None,
            model=label,
            device=cfg.device,
            batch_size=cfg.batch_size,
            cache=cache,
            usage=usage,
        )
    http = OpenAIHTTP(
        cfg.base_url,
        api_key=resolve_api_key(cfg.api_key, cfg.api_key_env),
        timeout_s=cfg.timeout_s,
        max_retries=cfg.max_retries,
        max_connections=cfg.max_concurrency,
    )
    return OpenAICompatEmbedder(
        http,
        cfg.model,
        batch_size=cfg.batch_size,
        max_concurrency=cfg.max_concurrency,
        cache=cache,
        usage=usage,
    )
