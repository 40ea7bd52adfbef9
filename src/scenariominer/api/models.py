"""Use cases ``llm check`` and ``llm serve``.

``llm check``: which model backends are configured, and do they answer; ``llm serve``: the
embedded model behind an OpenAI-compatible HTTP server.
"""

from __future__ import annotations

from dataclasses import dataclass

from scenariominer.config import Config
from scenariominer.llm.cache import resolve_cache_dir
from scenariominer.llm.check import ChatCheck, EmbeddingCheck, check_chat, check_embeddings
from scenariominer.llm.model_files import resolve_model_file
from scenariominer.llm.server import ServeSettings, server_command
from scenariominer.llm.usage import UsageCounter

__all__ = ["LLMCheckResult", "llm_check", "serve", "serve_settings"]


@dataclass(frozen=True)
class LLMCheckResult:
    """Outcome of :func:`llm_check` (a check not asked for is ``None``)."""

    chat: ChatCheck | None
    embeddings: EmbeddingCheck | None


def llm_check(
    config: Config, *, chat: bool = True, embeddings: bool = False, usage: UsageCounter | None = None
) -> LLMCheckResult:
    """Verify the model file and make one tiny structured call; optionally embed four sentences.

    ``usage`` accumulates the calls made (pass one to report it even when a check fails).

    Raises:
        LLMError: a backend cannot be loaded or reached, or answered unusably.
    """
    return LLMCheckResult(
        check_chat(config, usage) if chat else None,
        check_embeddings(config, usage) if embeddings else None,
    )


def serve_settings(config: Config, *, host: str = "127.0.0.1", port: int = 8765) -> ServeSettings:
    """What ``llm serve`` serves: the configured GGUF file (the bundled model by default).

    Raises:
        ModelNotAvailableError: the model file or the packages carrying it are missing.
    """
    cfg = config.llm
    model_file = resolve_model_file(cfg.model_path, resolve_cache_dir(cfg.cache_dir))
    return ServeSettings(model_file.path, host=host, port=port, n_ctx=cfg.n_ctx, n_threads=cfg.n_threads)


def serve(settings: ServeSettings) -> int:
    """Run the OpenAI-compatible server in the foreground until it is stopped; its exit status.

    Raises:
        MissingDependencyError: llama-cpp-python's server extra is not installed.
    """
    import subprocess

    try:
        return subprocess.call(server_command(settings))
    except KeyboardInterrupt:
        return 0
