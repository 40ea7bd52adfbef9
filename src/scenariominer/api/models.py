"""Use case ``llm check``: which model backends are configured, and do they answer."""

from __future__ import annotations

from dataclasses import dataclass

from scenariominer.config import Config
from scenariominer.llm.check import ChatCheck, EmbeddingCheck, check_chat, check_embeddings
from scenariominer.llm.usage import UsageCounter

__all__ = ["LLMCheckResult", "llm_check"]


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
