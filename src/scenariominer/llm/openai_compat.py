"""Backends for servers that speak the OpenAI HTTP API (``/chat/completions``, ``/embeddings``).

Works with Ollama, vLLM, the llama.cpp server, OpenAI and Gemini's OpenAI-compatible endpoint.
Transport problems become :class:`~scenariominer.llm.errors.BackendError` subclasses that name
the URL and the cause: connection refused, timeout, an HTTP error status, a body that is not the
expected JSON. Connection errors and HTTP 429/5xx are retried with exponential back-off.
"""

from __future__ import annotations

import contextlib
import os
import re
import time
from collections.abc import Callable, Mapping
from typing import Any

import httpx

from scenariominer.config.llm import StructuredMode
from scenariominer.llm.base import ChatRequest, Completion
from scenariominer.llm.errors import (
    BackendConnectionError,
    BackendHTTPError,
    BackendResponseError,
    BackendTimeoutError,
)

__all__ = ["OpenAICompatBackend", "OpenAIHTTP", "resolve_api_key"]

_RETRY_STATUS = frozenset({429, 500, 502, 503, 504})
_BACKOFF_S = 0.5
_MAX_RETRY_AFTER_S = 30.0


def resolve_api_key(api_key: str, api_key_env: str, environ: Mapping[str, str] | None = None) -> str:
    """``api_key`` if set, else the value of the variable ``api_key_env`` (``""`` if unset)."""
    if api_key:
        return api_key
    env = os.environ if environ is None else environ
    return env.get(api_key_env, "") if api_key_env else ""


class OpenAIHTTP:
    """A small JSON-over-HTTP client for one OpenAI-compatible server (thread-safe).

    Args:
        base_url: API root including ``/v1`` (e.g. ``http://127.0.0.1:11434/v1``).
        api_key: bearer token; ``""`` sends no ``Authorization`` header.
        timeout_s: seconds a request may take (connect, read and write each).
        max_retries: retries after a connection error or HTTP 429/5xx.
        max_connections: connection pool size (at least the intended concurrency).
        transport: custom httpx transport (tests).
        sleep: waits between retries (``time.sleep``; tests pass a fake clock's ``sleep``).
    """

    def __init__(
        self,
        base_url: str,
        *,
        api_key: str = "",
        timeout_s: float = 120.0,
        max_retries: int = 2,
        max_connections: int = 4,
        transport: httpx.BaseTransport | None = None,
        sleep: Callable[[float], None] = time.sleep,
    ) -> None:
        if not base_url.startswith(("http://", "https://")):
            raise ValueError(f"base_url must start with http:// or https://, got {base_url!r}")
        self.base_url = base_url.rstrip("/")
        self.timeout_s = timeout_s
        self.max_retries = max_retries
        self._wait = sleep
        headers = {"Accept": "application/json"}
        if api_key:
            headers["Authorization"] = f"Bearer {api_key}"
        self._client = httpx.Client(
            base_url=self.base_url,
            headers=headers,
            timeout=httpx.Timeout(timeout_s),
            limits=httpx.Limits(max_connections=max_connections, max_keepalive_connections=max_connections),
            transport=transport,
        )

    def post_json(self, path: str, payload: Mapping[str, Any]) -> dict[str, Any]:
        """POST ``payload`` as JSON to ``base_url + path`` and return the decoded JSON object.

        Raises:
            BackendConnectionError: the server could not be reached (after retries).
            BackendTimeoutError: no answer within ``timeout_s``.
            BackendHTTPError: an HTTP error status (after retries for 429/5xx).
            BackendResponseError: the body is not a JSON object.
        """
        url = f"{self.base_url}{path}"
        attempt = 0
        while True:
            try:
                response = self._client.post(path, json=payload)
            except httpx.TimeoutException:
                raise BackendTimeoutError(url, self.timeout_s) from None
            except httpx.TransportError as exc:
                if attempt < self.max_retries:
                    self._sleep(attempt, None)
                    attempt += 1
                    continue
                raise BackendConnectionError(
                    f"cannot reach the server: {exc or type(exc).__name__}; is it running at this URL?", url
                ) from None
            if response.status_code in _RETRY_STATUS and attempt < self.max_retries:
                self._sleep(attempt, response.headers.get("retry-after"))
                attempt += 1
                continue
            if response.status_code >= 400:
                raise BackendHTTPError(url, response.status_code, _error_message(response))
            try:
                body = response.json()
            except ValueError:
                raise BackendResponseError(
                    f"the answer is not JSON (content-type {response.headers.get('content-type', '?')!r}, "
                    f"body starts {response.text[:200]!r})",
                    url,
                ) from None
            if not isinstance(body, dict):
                raise BackendResponseError(f"expected a JSON object, got {type(body).__name__}", url)
            return body

    def _sleep(self, attempt: int, retry_after: str | None) -> None:
        """Wait before retry ``attempt``: exponential back-off, or the server's ``Retry-After`` (capped)."""
        delay = _BACKOFF_S * 2**attempt
        if retry_after:
            with contextlib.suppress(ValueError):
                delay = min(max(float(retry_after), 0.0), _MAX_RETRY_AFTER_S)
        self._wait(delay)

    def close(self) -> None:
        """Close the connection pool."""
        self._client.close()


def _error_message(response: httpx.Response) -> str:
    """Return the error message of a JSON body (``error.message``, ``error``, ``detail``), else the text."""
    try:
        body = response.json()
    except ValueError:
        return response.text.strip() or response.reason_phrase
    if isinstance(body, dict):
        err = body.get("error", body.get("detail"))
        if isinstance(err, dict) and err.get("message"):
            return str(err["message"])
        if isinstance(err, str) and err:
            return err
    return response.text.strip()


def _schema_name(name: str) -> str:
    """Make a name the OpenAI API accepts for ``json_schema.name`` (``[a-zA-Z0-9_-]{1,64}``)."""
    cleaned = re.sub(r"[^a-zA-Z0-9_-]", "_", name)[:64]
    return cleaned or "response"


class OpenAICompatBackend:
    """Chat backend over an OpenAI-compatible ``/chat/completions`` endpoint.

    Args:
        http: the HTTP client for the server.
        model: model name sent to the server.
        structured_mode: how schema-conforming JSON is requested (see
            :class:`~scenariominer.config.llm.StructuredMode`).
        send_top_k: include ``top_k`` in requests (some servers, api.openai.com among them,
            reject the field).
    """

    name = "openai"
    concurrent = True

    def __init__(
        self,
        http: OpenAIHTTP,
        model: str,
        *,
        structured_mode: StructuredMode = StructuredMode.JSON_SCHEMA,
        send_top_k: bool = True,
    ) -> None:
        if not model:
            raise ValueError("an OpenAI-compatible backend needs a model name (llm.model)")
        self.http = http
        self._model = model
        self.structured_mode = StructuredMode(structured_mode)
        self.send_top_k = send_top_k

    @property
    def model(self) -> str:
        """Model name plus server URL (the same name on two servers may be two models)."""
        return f"{self._model}@{self.http.base_url}"

    def payload(self, request: ChatRequest) -> dict[str, Any]:
        """Build the JSON body sent for ``request``."""
        p = request.params
        body: dict[str, Any] = {
            "model": self._model,
            "messages": request.messages_as_dicts(),
            "temperature": p.temperature,
            "top_p": p.top_p,
            "max_tokens": p.max_tokens,
            "seed": p.seed,
            "stream": False,
        }
        if self.send_top_k and p.top_k > 0:
            body["top_k"] = p.top_k
        if p.stop:
            body["stop"] = list(p.stop)
        if request.json_schema is not None:
            if self.structured_mode is StructuredMode.JSON_SCHEMA:
                body["response_format"] = {
                    "type": "json_schema",
                    "json_schema": {
                        "name": _schema_name(request.schema_name),
                        "schema": dict(request.json_schema),
                    },
                }
            elif self.structured_mode is StructuredMode.JSON_OBJECT:
                body["response_format"] = {"type": "json_object"}
            elif self.structured_mode is StructuredMode.JSON_OBJECT_SCHEMA:
                body["response_format"] = {"type": "json_object", "schema": dict(request.json_schema)}
        if request.grammar is not None and self.structured_mode is StructuredMode.JSON_OBJECT_SCHEMA:
            # llama.cpp servers (the mode's only users) take a GBNF grammar as a request field;
            # other servers would reject the unknown field, so they get none.
            body["grammar"] = request.grammar
        return body

    def complete(self, request: ChatRequest) -> Completion:
        """POST the request and return the first choice.

        Raises:
            BackendError: transport, status or format problem (see :meth:`OpenAIHTTP.post_json`).
        """
        t0 = time.perf_counter()
        body = self.http.post_json("/chat/completions", self.payload(request))
        latency = time.perf_counter() - t0
        url = f"{self.http.base_url}/chat/completions"
        try:
            choice = body["choices"][0]
            message = choice["message"]
        except (KeyError, IndexError, TypeError):
            raise BackendResponseError(
                f"no choices[0].message in the answer: {str(body)[:300]}", url
            ) from None
        content = message.get("content")
        if content is None:
            refusal = message.get("refusal")
            raise BackendResponseError(
                f"the answer has no content{f' (refusal: {refusal!r})' if refusal else ''}", url
            )
        usage = body.get("usage") or {}
        return Completion(
            text=str(content),
            prompt_tokens=int(usage.get("prompt_tokens") or 0),
            completion_tokens=int(usage.get("completion_tokens") or 0),
            latency_s=latency,
            finish_reason=str(choice.get("finish_reason") or ""),
        )

    def close(self) -> None:
        """Close the HTTP connection pool."""
        self.http.close()
