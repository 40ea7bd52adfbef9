"""One recommendation: retrieve cases, build the dynamic prompt, ask the model (sections 3.2-3.3).

The answer is decoded under the JSON schema of :func:`~scenariominer.cbr.prompts.answer_schema`
(the manoeuvre an enum of the configured set, short capped text fields). An answer that still
violates the schema after the client's repair round raises :class:`CbrError` naming the violation.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Any

from scenariominer.cbr.cases import CaseBase
from scenariominer.cbr.prompts import answer_schema, system_prompt, user_prompt
from scenariominer.cbr.retrieve import Retrieved, retrieve
from scenariominer.cbr.vocab import CbrError
from scenariominer.llm.base import system, user
from scenariominer.llm.client import ChatClient
from scenariominer.llm.embeddings import Embedder
from scenariominer.llm.errors import StructuredOutputError
from scenariominer.llm.text import tidy_cut_text

__all__ = ["Query", "Recommendation", "RecommendSettings", "recommend"]


@dataclass(frozen=True)
class Query:
    """A new risk scene: its id, caption and risk type (the key of a case)."""

    event_id: str
    caption: str
    risk_type: str


@dataclass(frozen=True)
class RecommendSettings:
    """How to prompt: ``k`` cases chosen by ``selection``, risk-aware or not, answer caps."""

    k: int = 3
    selection: str = "similarity"
    risk_aware: bool = True
    seed: int = 0
    max_field_chars: int = 120
    max_tokens: int = 256

    @property
    def label(self) -> str:
        """Short name of the configuration, e.g. ``aware/similarity/k3`` or ``unaware/k0``."""
        aware = "aware" if self.risk_aware else "unaware"
        return f"{aware}/k0" if self.k == 0 else f"{aware}/{self.selection}/k{self.k}"


@dataclass(frozen=True)
class Recommendation:
    """The model's answer for one query.

    Attributes:
        event_id: the query id.
        manoeuvre: the recommended manoeuvre (a configured name).
        answer: every field of the answer (road context ... justification).
        retrieved: the few-shot cases with their similarity.
        settings: the prompt configuration.
        latency_s: wall-clock seconds of the model call(s) (near 0 for cached answers).
        attempts: answers needed (2 = one repair round).
        cached: the answer came from the response cache.
    """

    event_id: str
    manoeuvre: str
    answer: dict[str, str]
    retrieved: tuple[Retrieved, ...]
    settings: RecommendSettings
    latency_s: float
    attempts: int
    cached: bool

    def to_json_dict(self) -> dict[str, Any]:
        """JSON-ready form (retrieved cases by id and score)."""
        return {
            "event_id": self.event_id,
            "manoeuvre": self.manoeuvre,
            "answer": dict(self.answer),
            "retrieved": [{"case_id": r.case.case_id, "score": r.score} for r in self.retrieved],
            "configuration": self.settings.label,
            "latency_s": self.latency_s,
            "attempts": self.attempts,
            "cached": self.cached,
        }


def recommend(
    query: Query,
    base: CaseBase,
    client: ChatClient,
    embedder: Embedder,
    settings: RecommendSettings,
    *,
    exclude: tuple[str, ...] = (),
) -> Recommendation:
    """Recommend an evasive manoeuvre for ``query``.

    Raises:
        CbrError: unknown risk type, or no schema-valid answer after the repair round.
        LLMError: the backend failed.
    """
    risk = base.risk_types.get(query.risk_type)
    found = retrieve(
        base,
        query.caption,
        query.risk_type,
        settings.k,
        selection=settings.selection,
        embedder=embedder,
        seed=settings.seed,
        exclude=exclude,
    )
    shown_risk = risk if settings.risk_aware else None
    messages = [
        system(system_prompt(base.risk_types, base.manoeuvres)),
        user(
            user_prompt(query.event_id, query.caption, shown_risk, [r.case for r in found], base.risk_types)
        ),
    ]
    schema = answer_schema(base.manoeuvres, settings.max_field_chars)
    start = time.perf_counter()
    try:
        result = client.chat_result(messages, schema, max_tokens=settings.max_tokens)
    except StructuredOutputError as exc:
        raise CbrError(
            f"event {query.event_id}: the model's answer violates the answer schema after "
            f"{len(exc.raw_outputs)} attempt(s): {exc.errors[-1] if exc.errors else exc}"
        ) from exc
    latency = time.perf_counter() - start
    # a field the model wrote up to its cap ends at its last full sentence or clause, not mid-word
    answer = {
        k: str(v) if k == "manoeuvre" else tidy_cut_text(str(v), settings.max_field_chars)
        for k, v in dict(result.value).items()
    }
    return Recommendation(
        event_id=query.event_id,
        manoeuvre=answer["manoeuvre"],
        answer=answer,
        retrieved=tuple(found),
        settings=settings,
        latency_s=latency,
        attempts=result.attempts,
        cached=all(c.cached for c in result.completions),
    )
