"""A scripted chat backend: the fake that tests (ours and downstream) use instead of a model."""

from __future__ import annotations

import threading
from collections.abc import Callable, Iterable
from typing import TypeAlias

from scenariominer.llm.base import ChatRequest, Completion
from scenariominer.llm.errors import LLMError

__all__ = ["ScriptExhaustedError", "ScriptedBackend", "ScriptedReply"]

#: What a script step can be: the answer text, a full completion, an exception to raise, or a
#: function of the request returning the answer text.
ScriptedReply: TypeAlias = str | Completion | BaseException | Callable[[ChatRequest], str]


class ScriptExhaustedError(LLMError):
    """The backend was called more often than it has scripted replies."""


class ScriptedBackend:
    """Returns canned replies in order and records every request it receives.

    Token counts of string replies are word counts, so accounting can be tested too.

    Example:
        >>> backend = ScriptedBackend(['{"answer": 4}'])
        >>> backend.complete(ChatRequest((user("2+2?"),))).text
        '{"answer": 4}'

    Attributes:
        requests: every request received, in call order.
    """

    name = "scripted"
    concurrent = True

    def __init__(self, replies: Iterable[ScriptedReply], model: str = "scripted-model") -> None:
        self._replies = list(replies)
        self._model = model
        self._lock = threading.Lock()
        self.requests: list[ChatRequest] = []

    @property
    def model(self) -> str:
        """The model label given at construction."""
        return self._model

    @property
    def remaining(self) -> int:
        """Replies not yet consumed."""
        return len(self._replies) - len(self.requests)

    def complete(self, request: ChatRequest) -> Completion:
        """Record ``request`` and return (or raise) the next scripted reply."""
        with self._lock:
            index = len(self.requests)
            self.requests.append(request)
        if index >= len(self._replies):
            raise ScriptExhaustedError(
                f"ScriptedBackend got call {index + 1} but holds only {len(self._replies)} replies"
            )
        reply = self._replies[index]
        if isinstance(reply, BaseException):
            raise reply
        if isinstance(reply, Completion):
            return reply
        text = reply if isinstance(reply, str) else reply(request)
        prompt_words = sum(len(m.content.split()) for m in request.messages)
        return Completion(
            text=text,
            prompt_tokens=prompt_words,
            completion_tokens=len(text.split()),
            finish_reason="stop",
        )

    def close(self) -> None:
        """Nothing to release."""
