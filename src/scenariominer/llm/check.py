"""Health checks behind ``scenariominer llm check``: which backend is active, and whether it answers."""

from __future__ import annotations

import time
from dataclasses import dataclass
from enum import StrEnum
from typing import Any

from pydantic import BaseModel, Field

from scenariominer.config import Config
from scenariominer.llm.base import system, user
from scenariominer.llm.client import ChatClient
from scenariominer.llm.embeddings import SentenceTransformerEmbedder
from scenariominer.llm.factory import generation_params, make_chat_backend, make_embedder
from scenariominer.llm.llamacpp import LlamaCppBackend
from scenariominer.llm.model_files import ModelFile
from scenariominer.llm.openai_compat import OpenAICompatBackend
from scenariominer.llm.usage import UsageCounter

__all__ = ["ChatCheck", "CheckManeuver", "EmbeddingCheck", "check_chat", "check_embeddings"]

CHECK_SENTENCES = (
    "The ego vehicle brakes hard behind a stopped truck.",
    "The ego vehicle decelerates sharply because the lead vehicle stopped.",
    "A pedestrian crosses the street at a zebra crossing.",
    "A cyclist overtakes a parked car on the right.",
)


class ManeuverLabel(StrEnum):
    """Labels of the check's tiny classification task."""

    BRAKING = "braking"
    ACCELERATING = "accelerating"
    TURNING = "turning"
    LANE_CHANGE = "lane_change"
    CONSTANT_SPEED = "constant_speed"


class CheckManeuver(BaseModel):
    """The object the check asks the model for."""

    maneuver: ManeuverLabel = Field(description="the ego vehicle's manoeuvre")
    confidence: float = Field(ge=0.0, le=1.0, description="confidence between 0 and 1")


CHECK_MESSAGES = (
    system("You classify short descriptions of a vehicle's motion."),
    user(
        "On a straight road, the ego vehicle slowed down from 14 m/s to 3 m/s within 2 seconds. "
        "Classify the manoeuvre."
    ),
)


@dataclass(frozen=True)
class ChatCheck:
    """Result of one real (uncached) structured call.

    Attributes:
        backend: backend name.
        model: model identity.
        base_url: server URL (``None`` for the embedded backend).
        model_file: the GGUF file with its verified hash (``None`` for a server).
        load_time_s: seconds to load the embedded model (``None`` for a server).
        value: the validated object, as a dict.
        attempts: answers needed (2 means the repair round was used).
        latency_s: seconds of the structured call (excluding model load).
        prompt_tokens: prompt tokens of the call(s).
        completion_tokens: generated tokens of the call(s).
    """

    backend: str
    model: str
    base_url: str | None
    model_file: ModelFile | None
    load_time_s: float | None
    value: dict[str, Any]
    attempts: int
    latency_s: float
    prompt_tokens: int
    completion_tokens: int


@dataclass(frozen=True)
class EmbeddingCheck:
    """Result of embedding :data:`CHECK_SENTENCES`.

    Attributes:
        backend: backend name.
        model: model name.
        dim: vector dimension.
        load_time_s: seconds to load a local model (``None`` otherwise).
        n_texts: texts embedded.
        seconds: wall-clock seconds of the embedding call (excluding load).
        related_cosine: cosine of the two braking sentences.
        unrelated_cosine: cosine of a braking sentence and the pedestrian sentence.
    """

    backend: str
    model: str
    dim: int
    load_time_s: float | None
    n_texts: int
    seconds: float
    related_cosine: float
    unrelated_cosine: float

    @property
    def texts_per_s(self) -> float:
        """Throughput of the call."""
        return self.n_texts / self.seconds if self.seconds > 0 else float("inf")


def check_chat(config: Config, usage: UsageCounter | None = None) -> ChatCheck:
    """Resolve (and verify) the model, then make one real structured call, bypassing the cache.

    Raises:
        LLMError: the model is missing or corrupt, or the call failed (subclasses name the cause).
    """
    backend = make_chat_backend(config, verify_model=True)
    client = ChatClient(
        backend,
        params=generation_params(config),
        cache=None,
        usage=usage,
        repair_rounds=config.llm.repair_rounds,
    )
    try:
        load_time_s = backend.load() if isinstance(backend, LlamaCppBackend) else None
        t0 = time.perf_counter()
        result = client.chat_result(list(CHECK_MESSAGES), CheckManeuver, max_tokens=64)
        latency_s = time.perf_counter() - t0
    finally:
        client.close()
    return ChatCheck(
        backend=backend.name,
        model=backend.model,
        base_url=backend.http.base_url if isinstance(backend, OpenAICompatBackend) else None,
        model_file=backend.model_file if isinstance(backend, LlamaCppBackend) else None,
        load_time_s=load_time_s,
        value=result.value.model_dump(mode="json"),
        attempts=result.attempts,
        latency_s=latency_s,
        prompt_tokens=sum(c.prompt_tokens for c in result.completions),
        completion_tokens=sum(c.completion_tokens for c in result.completions),
    )


def check_embeddings(config: Config, usage: UsageCounter | None = None) -> EmbeddingCheck:
    """Embed four fixed sentences with the configured embedder, bypassing the cache.

    Raises:
        LLMError: the model is missing or the call failed.
    """
    embedder = make_embedder(config, usage=usage, use_cache=False)
    load_time_s = embedder.load() if isinstance(embedder, SentenceTransformerEmbedder) else None
    t0 = time.perf_counter()
    emb = embedder.embed(list(CHECK_SENTENCES))
    seconds = time.perf_counter() - t0
    close = getattr(embedder, "close", None)
    if callable(close):
        close()
    sims = emb.cosine(emb)
    return EmbeddingCheck(
        backend=embedder.backend,
        model=emb.model,
        dim=emb.dim,
        load_time_s=load_time_s,
        n_texts=len(emb),
        seconds=seconds,
        related_cosine=float(sims[0, 1]),
        unrelated_cosine=float(sims[0, 2]),
    )
