"""Messages, decoding parameters, requests and the :class:`ChatBackend` Protocol.

A backend turns one :class:`ChatRequest` into one :class:`Completion` (raw text plus token
counts). Everything else (schema validation, the repair round, caching, accounting, batching)
lives in :class:`scenariominer.llm.client.ChatClient`, so a backend stays a thin adapter.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from enum import StrEnum
from typing import Any, Protocol, TypedDict, runtime_checkable

__all__ = [
    "ChatBackend",
    "ChatRequest",
    "Completion",
    "GenerationOverrides",
    "GenerationParams",
    "Message",
    "MessageLike",
    "Role",
    "assistant",
    "normalize_messages",
    "system",
    "user",
]


class Role(StrEnum):
    """Author of a chat message."""

    SYSTEM = "system"
    USER = "user"
    ASSISTANT = "assistant"


@dataclass(frozen=True)
class Message:
    """One chat message.

    Attributes:
        role: who wrote it.
        content: the text.
    """

    role: Role
    content: str

    def to_dict(self) -> dict[str, str]:
        """Return the OpenAI wire form ``{"role": ..., "content": ...}``."""
        return {"role": self.role.value, "content": self.content}


#: A :class:`Message` or a mapping with ``role`` and ``content`` keys (the OpenAI wire form).
MessageLike = Message | Mapping[str, str]


def system(content: str) -> Message:
    """Make a system message."""
    return Message(Role.SYSTEM, content)


def user(content: str) -> Message:
    """Make a user message."""
    return Message(Role.USER, content)


def assistant(content: str) -> Message:
    """Make an assistant message."""
    return Message(Role.ASSISTANT, content)


def normalize_messages(messages: Sequence[MessageLike]) -> tuple[Message, ...]:
    """Validate and convert messages to :class:`Message`.

    Raises:
        ValueError: empty conversation, unknown role, or a mapping without ``role``/``content``.
    """
    if isinstance(messages, str | bytes):
        raise TypeError("messages must be a sequence of messages, not a string; wrap it with user(...)")
    if not messages:
        raise ValueError("a chat request needs at least one message")
    out: list[Message] = []
    for i, m in enumerate(messages):
        if isinstance(m, Message):
            out.append(m)
            continue
        try:
            role, content = m["role"], m["content"]
        except (KeyError, TypeError):
            raise ValueError(f"message {i} must have 'role' and 'content', got {m!r}") from None
        try:
            out.append(Message(Role(role), str(content)))
        except ValueError:
            raise ValueError(
                f"message {i} has unknown role {role!r}; use one of {[r.value for r in Role]}"
            ) from None
    return tuple(out)


class GenerationOverrides(TypedDict, total=False):
    """Per-call overrides of :class:`GenerationParams` (keyword arguments of the client)."""

    temperature: float
    top_p: float
    top_k: int
    max_tokens: int
    seed: int
    stop: tuple[str, ...]


@dataclass(frozen=True)
class GenerationParams:
    """Decoding parameters of one call; defaults are greedy (the braking paper's setting).

    Attributes:
        temperature: sampling temperature; 0 decodes greedily.
        top_p: nucleus-sampling mass (1 = off).
        top_k: top-k cut-off (1 = greedy; 0 = off).
        max_tokens: upper bound on generated tokens.
        seed: sampling seed (matters only when temperature > 0).
        stop: strings that end generation.
    """

    temperature: float = 0.0
    top_p: float = 1.0
    top_k: int = 1
    max_tokens: int = 1024
    seed: int = 0
    stop: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        if self.temperature < 0:
            raise ValueError(f"temperature must be >= 0, got {self.temperature}")
        if not 0 < self.top_p <= 1:
            raise ValueError(f"top_p must be in (0, 1], got {self.top_p}")
        if self.top_k < 0:
            raise ValueError(f"top_k must be >= 0, got {self.top_k}")
        if self.max_tokens <= 0:
            raise ValueError(f"max_tokens must be > 0, got {self.max_tokens}")

    def with_overrides(self, overrides: GenerationOverrides) -> GenerationParams:
        """Return a copy with the given fields replaced (unknown names raise ``TypeError``)."""
        if not overrides:
            return self
        values: dict[str, Any] = dict(overrides)
        if "stop" in values:
            values["stop"] = tuple(values["stop"])
        return dataclasses.replace(self, **values)

    def to_dict(self) -> dict[str, Any]:
        """All fields as a JSON-serialisable dict (part of the cache key)."""
        d = dataclasses.asdict(self)
        d["stop"] = list(self.stop)
        return d


@dataclass(frozen=True)
class ChatRequest:
    """Everything that determines a backend's answer.

    Attributes:
        messages: the conversation, oldest first.
        params: decoding parameters.
        json_schema: JSON schema the answer must follow (backends that can constrain decoding use
            it; others ignore it and the client validates); ``None`` for free text.
        schema_name: short name of the schema (sent to servers that require one).
        grammar: a llama.cpp GBNF grammar the answer must follow (free text that is not JSON, such
            as a mining program); backends that cannot constrain decoding by a grammar ignore it.
            Mutually exclusive with ``json_schema``.
    """

    messages: tuple[Message, ...]
    params: GenerationParams = field(default_factory=GenerationParams)
    json_schema: Mapping[str, Any] | None = None
    schema_name: str = "response"
    grammar: str | None = None

    def __post_init__(self) -> None:
        if self.grammar is not None and self.json_schema is not None:
            raise ValueError("a request takes a JSON schema or a grammar, not both")

    def messages_as_dicts(self) -> list[dict[str, str]]:
        """Return the messages in OpenAI wire form."""
        return [m.to_dict() for m in self.messages]

    def cache_key(self, backend: str, model: str) -> str:
        """SHA-256 (hex) of backend, model, messages, schema and parameters, canonically encoded."""
        payload = {
            "backend": backend,
            "model": model,
            "messages": self.messages_as_dicts(),
            "params": self.params.to_dict(),
            "json_schema": self.json_schema,
            "schema_name": self.schema_name if self.json_schema is not None else None,
        }
        if self.grammar is not None:  # only when set, so keys of grammar-free requests stay as they were
            payload["grammar"] = self.grammar
        blob = json.dumps(payload, sort_keys=True, separators=(",", ":"), ensure_ascii=False)
        return hashlib.sha256(blob.encode("utf-8")).hexdigest()


@dataclass(frozen=True)
class Completion:
    """One backend answer.

    Attributes:
        text: the generated text (the assistant message's content).
        prompt_tokens: tokens in the prompt as counted by the backend (0 if it did not say).
        completion_tokens: generated tokens (0 if the backend did not say).
        latency_s: wall-clock seconds of the call (of the original call when served from cache).
        finish_reason: why generation stopped (``"stop"``, ``"length"``, ...; ``""`` if unknown).
        cached: whether this answer came from the on-disk cache.
        prompt_eval_s: seconds the backend spent evaluating prompt tokens (0 if it did not say).
        reused_prompt_tokens: prompt tokens taken from an already evaluated prefix (in memory or
            restored from disk) instead of being evaluated.
    """

    text: str
    prompt_tokens: int = 0
    completion_tokens: int = 0
    latency_s: float = 0.0
    finish_reason: str = ""
    cached: bool = False
    prompt_eval_s: float = 0.0
    reused_prompt_tokens: int = 0

    def to_json(self) -> str:
        """Serialise for the cache (``cached`` is not stored)."""
        d = dataclasses.asdict(self)
        d.pop("cached")
        return json.dumps(d, ensure_ascii=False)

    @classmethod
    def from_json(cls, blob: str, *, cached: bool = True) -> Completion:
        """Inverse of :meth:`to_json`."""
        d = json.loads(blob)
        return cls(
            text=str(d["text"]),
            prompt_tokens=int(d.get("prompt_tokens", 0)),
            completion_tokens=int(d.get("completion_tokens", 0)),
            latency_s=float(d.get("latency_s", 0.0)),
            finish_reason=str(d.get("finish_reason", "")),
            cached=cached,
            prompt_eval_s=float(d.get("prompt_eval_s", 0.0)),
            reused_prompt_tokens=int(d.get("reused_prompt_tokens", 0)),
        )


@runtime_checkable
class ChatBackend(Protocol):
    """A chat-completion engine: one request in, one raw completion out.

    Implementations: :class:`~scenariominer.llm.llamacpp.LlamaCppBackend`,
    :class:`~scenariominer.llm.openai_compat.OpenAICompatBackend`,
    :class:`~scenariominer.testing.ScriptedBackend` (the test fake).
    """

    @property
    def name(self) -> str:
        """Backend kind (``"llamacpp"``, ``"openai"``, ``"scripted"``), part of the cache key."""
        ...

    @property
    def model(self) -> str:
        """Identity of the model (name, or file identity), part of the cache key."""
        ...

    @property
    def concurrent(self) -> bool:
        """Whether :meth:`complete` may be called from several threads at once."""
        ...

    def complete(self, request: ChatRequest) -> Completion:
        """Generate the answer to ``request``.

        Raises:
            BackendError: the call failed (subclasses name the cause).
        """
        ...

    def close(self) -> None:
        """Release connections or model memory; the backend is unusable afterwards."""
        ...
