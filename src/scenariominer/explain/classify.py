"""LLM scenario understanding: rephrase, classify and explain one description (Fig. 4d-e).

The answer schema is built from the category set: ``category`` is a JSON-schema ``enum`` of the
allowed names, so a backend that constrains decoding (the embedded llama.cpp model) can only
produce an allowed name, and any other backend's answer is validated against it. An invalid
answer (not JSON, missing keys, an unknown category) gets the chat client's repair round; if it is
still invalid, the event is recorded with category ``invalid`` and the raw answer, and a backend
failure with category ``error``. :func:`classify_description` never raises for a bad answer, so
one event cannot stop a batch.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from enum import StrEnum
from typing import Any, Literal

from pydantic import BaseModel, Field, create_model

from scenariominer.config.tags import TagConfig
from scenariominer.explain.categories import ERROR_CATEGORY, INVALID_CATEGORY, CategorySet
from scenariominer.explain.prompts import build_messages
from scenariominer.llm.base import Message
from scenariominer.llm.client import ChatClient
from scenariominer.llm.errors import LLMError, StructuredOutputError

__all__ = [
    "DESCRIPTION_MAX_CHARS",
    "EXPLANATION_MAX_CHARS",
    "Classification",
    "ClassificationStatus",
    "ask",
    "classify_description",
    "understanding_model",
]

#: Longest rephrased description accepted (characters). The bound is part of the JSON schema, so
#: a grammar-constrained model cannot ramble past it (small models ignore "be brief").
DESCRIPTION_MAX_CHARS = 160
#: Longest explanation accepted (characters), enforced the same way.
EXPLANATION_MAX_CHARS = 160


class ClassificationStatus(StrEnum):
    """How an event's LLM answer was obtained.

    Attributes:
        OK: valid at the first attempt.
        REPAIRED: valid after the repair round.
        INVALID: still invalid after the repair round (category ``invalid``).
        ERROR: the backend failed (category ``error``).
        PENDING: not asked yet (the run's LLM limit was reached); the category is the rules'.
        RULES: decided by the rules alone, no model asked (``--llm off`` / judge ``rules``).
    """

    OK = "ok"
    REPAIRED = "repaired"
    INVALID = "invalid"
    ERROR = "error"
    PENDING = "pending"
    RULES = "rules"


@dataclass(frozen=True)
class Classification:
    """The LLM's understanding of one scenario (Fig. 4e), or why there is none.

    Attributes:
        category: a name of the category set, or ``invalid`` / ``error`` / ``pending``.
        description: the LLM's rephrased description ("" when there is none).
        explanation: why the LLM chose the category ("" when there is none).
        status: how the answer was obtained.
        raw_answer: the last raw answer text (kept for invalid answers; "" otherwise).
        error: the validation or backend error ("" when valid).
        attempts: number of answers requested (0 when pending or the backend failed at once).
        latency_s: seconds spent in the backend for this event (0 for cached answers).
        cached: whether every answer came from the on-disk cache.
        notes: repairs made to the answer (e.g. an explanation replaced for quoting numbers
            that are not in the facts).
    """

    category: str
    description: str
    explanation: str
    status: ClassificationStatus
    raw_answer: str = ""
    error: str = ""
    attempts: int = 0
    latency_s: float = 0.0
    cached: bool = False
    notes: tuple[str, ...] = ()

    @property
    def is_valid(self) -> bool:
        """Whether the category is one of the category set."""
        return self.status in (ClassificationStatus.OK, ClassificationStatus.REPAIRED)


def understanding_model(categories: CategorySet) -> type[BaseModel]:
    """Pydantic model of the answer: ``{description, category, explanation}``.

    ``category`` is an enum of the category names; both texts have a maximum length.
    """
    names = tuple(categories.names)
    category_type: Any = Literal[names]  # type: ignore[valid-type]
    return create_model(
        "ScenarioUnderstanding",
        description=(str, Field(max_length=DESCRIPTION_MAX_CHARS)),
        category=(category_type, ...),
        explanation=(str, Field(max_length=EXPLANATION_MAX_CHARS)),
    )


def _salvage(raw: str) -> tuple[str, str]:
    """Description and explanation from an invalid answer, when it is a JSON object that has them."""
    try:
        data = json.loads(raw)
    except (json.JSONDecodeError, TypeError):
        return "", ""
    if not isinstance(data, dict):
        return "", ""
    desc, expl = data.get("description", ""), data.get("explanation", "")
    return (desc if isinstance(desc, str) else ""), (expl if isinstance(expl, str) else "")


def classify_description(
    client: ChatClient,
    description: str,
    categories: CategorySet,
    tag_cfg: TagConfig | None = None,
    *,
    max_tokens: int | None = None,
) -> Classification:
    """Ask the LLM to rephrase, classify and explain one scenario description.

    Args:
        client: the chat client (its repair rounds and cache apply).
        description: the structured description of the event.
        categories: the categories the LLM may answer with.
        tag_cfg: tag thresholds quoted in the prompt.
        max_tokens: bound on each answer's tokens (``None`` keeps the client's default).

    Returns:
        The classification; never raises for an invalid answer or a backend failure.
    """
    model = understanding_model(categories)
    messages = build_messages(description, categories, tag_cfg)
    return ask(client, messages, model, max_tokens=max_tokens)


def ask(
    client: ChatClient, messages: list[Message], model: type[BaseModel], *, max_tokens: int | None = None
) -> Classification:
    """Ask for one structured answer with ``description``, ``explanation`` and maybe ``category``.

    An answer without a ``category`` field (the caller already knows it) gets ``category=""``.
    Never raises for an invalid answer or a backend failure: they become ``invalid`` / ``error``.
    """
    overrides: dict[str, Any] = {} if max_tokens is None else {"max_tokens": max_tokens}
    try:
        result = client.chat_result(messages, model, **overrides)
    except StructuredOutputError as exc:
        raw = exc.raw_outputs[-1] if exc.raw_outputs else ""
        desc, expl = _salvage(raw)
        return Classification(
            category=INVALID_CATEGORY,
            description=desc,
            explanation=expl,
            status=ClassificationStatus.INVALID,
            raw_answer=raw,
            error=exc.errors[-1] if exc.errors else str(exc),
            attempts=len(exc.raw_outputs),
        )
    except LLMError as exc:
        return Classification(
            category=ERROR_CATEGORY,
            description="",
            explanation="",
            status=ClassificationStatus.ERROR,
            error=f"{type(exc).__name__}: {exc}",
        )
    value = result.value
    completions = result.completions
    return Classification(
        category=str(getattr(value, "category", "")),
        description=str(value.description).strip(),
        explanation=str(value.explanation).strip(),
        status=ClassificationStatus.OK if result.attempts == 1 else ClassificationStatus.REPAIRED,
        attempts=result.attempts,
        latency_s=float(sum(c.latency_s for c in completions if not c.cached)),
        cached=all(c.cached for c in completions),
    )
