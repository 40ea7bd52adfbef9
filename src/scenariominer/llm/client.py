"""The chat client every feature uses: structured output with one repair round, cache, accounting.

Example::

    class Verdict(BaseModel):
        label: Literal["braking", "not_braking"]
        reason: str

    client = make_chat_client(config)
    verdict = client.chat([system("You label manoeuvres."), user(prompt)], Verdict)
    code = client.complete([user("Write a Python function ...")])

A structured call validates the answer against the schema. When it fails, the model is shown its
answer and the validation error and asked again (``repair_rounds`` times, default once); when that
fails too, :class:`~scenariominer.llm.errors.StructuredOutputError` carries every raw answer. A
wrong object is never returned.
"""

from __future__ import annotations

import json
import threading
import time
from collections.abc import Callable, Mapping, Sequence
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, replace
from typing import Any, Generic, TypeVar, Unpack, overload

from pydantic import BaseModel, ValidationError

from scenariominer.llm.base import (
    ChatBackend,
    ChatRequest,
    Completion,
    GenerationOverrides,
    GenerationParams,
    Message,
    MessageLike,
    Role,
    assistant,
    normalize_messages,
    user,
)
from scenariominer.llm.cache import ResponseCache
from scenariominer.llm.errors import LLMError, MissingDependencyError, StructuredOutputError
from scenariominer.llm.usage import CallKind, UsageCounter

__all__ = ["ChatClient", "OutputSpec", "StructuredResult"]

M = TypeVar("M", bound=BaseModel)
T = TypeVar("T")
R = TypeVar("R")

#: What a structured call asks for: a pydantic model class or a JSON schema (a dict).
OutputSpec = type[BaseModel] | Mapping[str, Any]

_SCHEMA_INSTRUCTION = (
    "Answer with exactly one JSON value that conforms to the following JSON schema, "
    "with no other text before or after it:\n{schema}"
)
_REPAIR_INSTRUCTION = (
    "Your previous answer is invalid: {error}\n"
    "Answer again with only the corrected JSON value, conforming to the schema."
)


@dataclass(frozen=True)
class StructuredResult(Generic[T]):
    """A validated object together with how it was obtained.

    Attributes:
        value: the validated object (a pydantic model instance, or plain JSON data for a dict schema).
        raw_outputs: every raw answer, in order; more than one when a repair round was needed.
        completions: the backend completions behind ``raw_outputs`` (token counts, latency, cache flag).
    """

    value: T
    raw_outputs: tuple[str, ...]
    completions: tuple[Completion, ...]

    @property
    def attempts(self) -> int:
        """Number of answers needed (1 = valid at once)."""
        return len(self.raw_outputs)


class _Validator:
    """Parses and validates answers against a pydantic model or a JSON schema."""

    def __init__(self, output: OutputSpec) -> None:
        self.model: type[BaseModel] | None = None
        if isinstance(output, type) and issubclass(output, BaseModel):
            self.model = output
            self.schema: dict[str, Any] = output.model_json_schema()
            self.name = output.__name__
            self._jsonschema: Any = None
        elif isinstance(output, Mapping):
            self.schema = dict(output)
            self.name = str(self.schema.get("title", "response"))
            try:
                import jsonschema
            except ImportError:  # pragma: no cover - jsonschema is a core dependency
                raise MissingDependencyError(
                    "jsonschema", "validating against a JSON schema", "pip install jsonschema"
                ) from None
            cls = jsonschema.validators.validator_for(self.schema)
            try:
                cls.check_schema(self.schema)
            except jsonschema.SchemaError as exc:
                raise ValueError(f"invalid JSON schema: {exc.message}") from None
            self._jsonschema = cls(self.schema)
        else:
            raise TypeError(f"output must be a pydantic model class or a JSON schema dict, got {output!r}")

    def validate(self, completion: Completion) -> tuple[Any, str]:
        """``(value, "")`` for a valid answer, else ``(None, error message)``."""
        try:
            data = _parse_json(completion.text)
        except ValueError as exc:
            cut = completion.finish_reason == "length"
            return None, f"{exc}" + (" (the answer was cut off at max_tokens)" if cut else "")
        if self.model is not None:
            try:
                return self.model.model_validate(data), ""
            except ValidationError as exc:
                problems = "; ".join(
                    f"{'.'.join(str(p) for p in e['loc']) or '<root>'}: {e['msg']}" for e in exc.errors()
                )
                return None, f"the JSON does not match the schema: {problems}"
        errors = sorted(self._jsonschema.iter_errors(data), key=lambda e: list(e.absolute_path))
        if errors:
            problems = "; ".join(
                f"{'.'.join(str(p) for p in e.absolute_path) or '<root>'}: {e.message}" for e in errors[:10]
            )
            return None, f"the JSON does not match the schema: {problems}"
        return data, ""


def _parse_json(text: str) -> Any:
    """Parse the JSON value in ``text``, tolerating Markdown code fences and leading prose.

    Raises:
        ValueError: no JSON value could be read.
    """
    body = text.strip()
    if body.startswith("```"):
        body = body.split("\n", 1)[1] if "\n" in body else ""
        body = body.rsplit("```", 1)[0].strip()
    if not body:
        raise ValueError("the answer is empty")
    try:
        # strict=False: a raw newline or tab inside a string (small models write them) is kept
        return json.loads(body, strict=False)
    except json.JSONDecodeError as exc:
        first_error = exc
    starts = [i for i in (body.find("{"), body.find("[")) if i >= 0]
    if starts:
        try:
            value, _end = json.JSONDecoder(strict=False).raw_decode(body, min(starts))
            return value
        except json.JSONDecodeError:
            pass
    raise ValueError(f"the answer is not valid JSON ({first_error.msg} at char {first_error.pos})")


def _with_schema_instruction(messages: tuple[Message, ...], schema: Mapping[str, Any]) -> tuple[Message, ...]:
    """Append the schema instruction to the leading system message (or add one)."""
    compact = json.dumps(schema, ensure_ascii=False, separators=(",", ":"))  # fewer prompt tokens
    text = _SCHEMA_INSTRUCTION.format(schema=compact)
    if messages[0].role is Role.SYSTEM:
        head = Message(Role.SYSTEM, f"{messages[0].content}\n\n{text}")
        return (head, *messages[1:])
    return (Message(Role.SYSTEM, text), *messages)


class ChatClient:
    """Chat completion with structured output, repair round, cache, accounting and batching.

    Args:
        backend: the engine (:class:`~scenariominer.llm.base.ChatBackend`).
        params: default decoding parameters (greedy unless changed); calls may override fields.
        cache: on-disk cache of answers; ``None`` disables caching.
        usage: counter of calls, cache hits, tokens and latency (a fresh one when ``None``).
        repair_rounds: re-asks after an invalid structured answer before giving up.
        max_concurrency: requests in flight at once in ``*_many`` calls on a concurrent backend.
        schema_in_prompt: also state the JSON schema in the system message (helps small models and
            servers that cannot constrain decoding; constrained decoding is used regardless).
    """

    def __init__(
        self,
        backend: ChatBackend,
        *,
        params: GenerationParams | None = None,
        cache: ResponseCache | None = None,
        usage: UsageCounter | None = None,
        repair_rounds: int = 1,
        max_concurrency: int = 4,
        schema_in_prompt: bool = True,
    ) -> None:
        if repair_rounds < 0:
            raise ValueError(f"repair_rounds must be >= 0, got {repair_rounds}")
        if max_concurrency < 1:
            raise ValueError(f"max_concurrency must be >= 1, got {max_concurrency}")
        self.backend = backend
        self.params = params or GenerationParams()
        self.cache = cache
        self.usage = usage if usage is not None else UsageCounter()
        self.repair_rounds = repair_rounds
        self.max_concurrency = max_concurrency
        self.schema_in_prompt = schema_in_prompt
        self._serial = threading.Lock()

    # -- single calls -------------------------------------------------------------------------

    def completion(
        self,
        messages: Sequence[MessageLike],
        *,
        grammar: str | None = None,
        **overrides: Unpack[GenerationOverrides],
    ) -> Completion:
        """Free-text completion with token counts and latency.

        Args:
            messages: the conversation.
            grammar: a GBNF grammar the answer must follow, for backends that constrain decoding
                (the embedded llama.cpp model, a llama.cpp server); others ignore it.
            **overrides: decoding parameters for this call.

        Raises:
            BackendError: the backend call failed.
        """
        request = ChatRequest(
            normalize_messages(messages), self.params.with_overrides(overrides), grammar=grammar
        )
        return self._call(request)

    def complete(self, messages: Sequence[MessageLike], **overrides: Unpack[GenerationOverrides]) -> str:
        """Free-text completion (e.g. generated code): the assistant's answer text."""
        return self.completion(messages, **overrides).text

    @overload
    def chat(
        self, messages: Sequence[MessageLike], output: type[M], **overrides: Unpack[GenerationOverrides]
    ) -> M: ...

    @overload
    def chat(
        self,
        messages: Sequence[MessageLike],
        output: Mapping[str, Any],
        **overrides: Unpack[GenerationOverrides],
    ) -> Any: ...

    def chat(
        self, messages: Sequence[MessageLike], output: OutputSpec, **overrides: Unpack[GenerationOverrides]
    ) -> Any:
        """Structured completion: a validated instance of ``output``.

        Args:
            messages: the conversation.
            output: a pydantic model class (returns an instance) or a JSON schema (returns the
                parsed JSON data after validating it).
            **overrides: decoding parameters for this call.

        Raises:
            StructuredOutputError: no valid answer after the repair rounds.
            BackendError: a backend call failed.
        """
        return self.chat_result(messages, output, **overrides).value

    def chat_result(
        self, messages: Sequence[MessageLike], output: OutputSpec, **overrides: Unpack[GenerationOverrides]
    ) -> StructuredResult[Any]:
        """Like :meth:`chat`, also returning the raw answers and completions."""
        validator = _Validator(output)
        msgs = normalize_messages(messages)
        if self.schema_in_prompt:
            msgs = _with_schema_instruction(msgs, validator.schema)
        params = self.params.with_overrides(overrides)
        raws: list[str] = []
        errors: list[str] = []
        completions: list[Completion] = []
        for _attempt in range(self.repair_rounds + 1):
            request = ChatRequest(msgs, params, validator.schema, validator.name)
            completion = self._call(request)
            completions.append(completion)
            raws.append(completion.text)
            value, error = validator.validate(completion)
            if not error:
                return StructuredResult(value, tuple(raws), tuple(completions))
            errors.append(error)
            msgs = (*msgs, assistant(completion.text), user(_REPAIR_INSTRUCTION.format(error=error)))
        raise StructuredOutputError(validator.name, raws, errors)

    # -- batches ------------------------------------------------------------------------------

    @overload
    def chat_many(
        self,
        conversations: Sequence[Sequence[MessageLike]],
        output: type[M],
        *,
        return_exceptions: bool = False,
        **overrides: Unpack[GenerationOverrides],
    ) -> list[M]: ...

    @overload
    def chat_many(
        self,
        conversations: Sequence[Sequence[MessageLike]],
        output: Mapping[str, Any],
        *,
        return_exceptions: bool = False,
        **overrides: Unpack[GenerationOverrides],
    ) -> list[Any]: ...

    def chat_many(
        self,
        conversations: Sequence[Sequence[MessageLike]],
        output: OutputSpec,
        *,
        return_exceptions: bool = False,
        **overrides: Unpack[GenerationOverrides],
    ) -> list[Any]:
        """:meth:`chat` over many conversations, in input order.

        Runs up to ``max_concurrency`` requests at once on a concurrent backend (a server) and
        one at a time on the embedded model.

        Args:
            conversations: one message list per request.
            output: as in :meth:`chat`.
            return_exceptions: put each :class:`LLMError` in the result list at its position
                instead of raising the first one.
            **overrides: decoding parameters for every call.
        """
        _Validator(output)  # fail fast on a bad schema, before any call
        return self._map(lambda msgs: self.chat(msgs, output, **overrides), conversations, return_exceptions)

    def complete_many(
        self,
        conversations: Sequence[Sequence[MessageLike]],
        *,
        return_exceptions: bool = False,
        **overrides: Unpack[GenerationOverrides],
    ) -> list[Any]:
        """:meth:`complete` over many conversations, in input order (concurrency as :meth:`chat_many`)."""
        return self._map(lambda msgs: self.complete(msgs, **overrides), conversations, return_exceptions)

    def _map(
        self,
        fn: Callable[[Sequence[MessageLike]], R],
        items: Sequence[Sequence[MessageLike]],
        return_exceptions: bool,
    ) -> list[Any]:
        def run(msgs: Sequence[MessageLike]) -> R | LLMError:
            try:
                return fn(msgs)
            except LLMError as exc:
                if return_exceptions:
                    return exc
                raise

        workers = min(self.max_concurrency, len(items)) if self.backend.concurrent else 1
        if workers <= 1:
            return [run(m) for m in items]
        with ThreadPoolExecutor(max_workers=workers, thread_name_prefix="llm") as pool:
            return list(pool.map(run, items))

    # -- plumbing -----------------------------------------------------------------------------

    def _call(self, request: ChatRequest) -> Completion:
        backend = self.backend
        key = request.cache_key(backend.name, backend.model)
        if self.cache is not None:
            hit = self.cache.get_completion(key)
            if hit is not None:
                self.usage.record_chat(backend.name, backend.model, hit)
                return hit
        t0 = time.perf_counter()
        try:
            if backend.concurrent:
                completion = backend.complete(request)
            else:
                with self._serial:
                    completion = backend.complete(request)
        except BaseException:
            self.usage.record_failure(CallKind.CHAT, backend.name, backend.model)
            raise
        completion = replace(completion, latency_s=time.perf_counter() - t0, cached=False)
        if self.cache is not None:
            self.cache.put_completion(key, backend.name, backend.model, completion)
        self.usage.record_chat(backend.name, backend.model, completion)
        return completion

    def close(self) -> None:
        """Close the backend and the cache."""
        self.backend.close()
        if self.cache is not None:
            self.cache.close()

    def __enter__(self) -> ChatClient:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
