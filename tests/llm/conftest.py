"""Fixtures for the LLM layer: a real OpenAI-compatible HTTP server on loopback.

The server is a small FastAPI app run by uvicorn in a background thread on 127.0.0.1 with a
free port. By default it answers ``/v1/chat/completions`` and ``/v1/embeddings`` with bodies
shaped like recorded Ollama answers; a test can queue scripted answers (status, body, delay,
content type) and inspect every request the server received.
"""

from __future__ import annotations

import asyncio
import hashlib
import json
import socket
import threading
import time
from collections import deque
from collections.abc import Iterator
from dataclasses import dataclass, field
from typing import Any

import pytest

try:  # the dev extra; without it the server fixture skips the tests that need it
    from fastapi import FastAPI, Request
    from fastapi.responses import JSONResponse, Response
except ImportError:  # pragma: no cover
    FastAPI = None  # type: ignore[assignment,misc]

# Shaped like an answer of Ollama 0.5's OpenAI-compatible endpoint (qwen2.5-coder:1.5b).
RECORDED_CHAT = {
    "id": "chatcmpl-417",
    "object": "chat.completion",
    "created": 1735689600,
    "model": "qwen2.5-coder:1.5b",
    "system_fingerprint": "fp_ollama",
    "choices": [
        {
            "index": 0,
            "message": {"role": "assistant", "content": '{"maneuver": "braking", "confidence": 0.9}'},
            "finish_reason": "stop",
        }
    ],
    "usage": {"prompt_tokens": 87, "completion_tokens": 14, "total_tokens": 101},
}


def chat_body(content: str, *, prompt_tokens: int = 87, completion_tokens: int = 14) -> dict[str, Any]:
    """A recorded-style chat answer carrying ``content``."""
    body = json.loads(json.dumps(RECORDED_CHAT))
    body["choices"][0]["message"]["content"] = content
    body["usage"] = {
        "prompt_tokens": prompt_tokens,
        "completion_tokens": completion_tokens,
        "total_tokens": prompt_tokens + completion_tokens,
    }
    return body


def fake_vector(text: str, dim: int) -> list[float]:
    """A deterministic, un-normalised vector for ``text`` (what the fake server embeds)."""
    digest = hashlib.sha256(text.encode()).digest()
    return [float(digest[i % len(digest)]) - 127.5 for i in range(dim)]


@dataclass
class Scripted:
    """One scripted answer.

    Attributes:
        status: HTTP status.
        body: JSON-serialisable body, or raw text when ``raw`` is set.
        raw: send ``body`` as this exact text instead of JSON.
        delay_s: seconds to wait before answering.
        content_type: the Content-Type of a raw body.
    """

    status: int = 200
    body: Any = None
    raw: str | None = None
    delay_s: float = 0.0
    content_type: str = "text/html"


@dataclass
class FakeOpenAIServer:
    """State of the loopback server: queued answers and received requests."""

    base_url: str = ""
    embed_dim: int = 8
    requests: list[tuple[str, dict[str, Any], dict[str, str]]] = field(default_factory=list)
    queue: deque[Scripted] = field(default_factory=deque)
    lock: threading.Lock = field(default_factory=threading.Lock)
    in_flight: int = 0
    max_in_flight: int = 0

    def push(
        self,
        body: Any = None,
        *,
        status: int = 200,
        raw: str | None = None,
        delay_s: float = 0.0,
        content_type: str = "text/html",
    ) -> None:
        """Queue one answer for the next request (either endpoint); answers are used in order."""
        with self.lock:
            self.queue.append(Scripted(status, body, raw, delay_s, content_type))

    def push_chat(self, content: str, *, prompt_tokens: int = 87, completion_tokens: int = 14) -> None:
        """Queue a recorded-style chat answer whose message content is ``content``."""
        self.push(chat_body(content, prompt_tokens=prompt_tokens, completion_tokens=completion_tokens))

    def reset(self) -> None:
        """Forget queued answers and received requests."""
        with self.lock:
            self.queue.clear()
            self.requests.clear()
            self.in_flight = 0
            self.max_in_flight = 0
            self.embed_dim = 8

    def bodies(self, path: str) -> list[dict[str, Any]]:
        """JSON bodies received on ``path`` (e.g. ``/v1/chat/completions``)."""
        with self.lock:
            return [body for p, body, _h in self.requests if p == path]


def _build_app(state: FakeOpenAIServer) -> Any:
    app = FastAPI()

    async def handle(request: Request, default: Any) -> Response:
        payload = await request.json()
        with state.lock:
            state.requests.append((request.url.path, payload, dict(request.headers)))
            scripted = state.queue.popleft() if state.queue else None
            state.in_flight += 1
            state.max_in_flight = max(state.max_in_flight, state.in_flight)
        try:
            if scripted is None:
                await asyncio.sleep(0.05)  # long enough for concurrent requests to overlap
                return JSONResponse(default(payload))
            if scripted.delay_s:
                await asyncio.sleep(scripted.delay_s)
            if scripted.raw is not None:
                return Response(scripted.raw, status_code=scripted.status, media_type=scripted.content_type)
            return JSONResponse(scripted.body, status_code=scripted.status)
        finally:
            with state.lock:
                state.in_flight -= 1

    def default_chat(payload: dict[str, Any]) -> dict[str, Any]:
        return RECORDED_CHAT

    def default_embeddings(payload: dict[str, Any]) -> dict[str, Any]:
        texts = payload["input"]
        data = [
            {"object": "embedding", "index": i, "embedding": fake_vector(t, state.embed_dim)}
            for i, t in enumerate(texts)
        ]
        data.reverse()  # servers may answer out of order; the index field decides
        return {
            "object": "list",
            "data": data,
            "model": payload["model"],
            "usage": {"prompt_tokens": 3 * len(texts), "total_tokens": 3 * len(texts)},
        }

    @app.post("/v1/chat/completions")
    async def chat(request: Request) -> Response:
        return await handle(request, default_chat)

    @app.post("/v1/embeddings")
    async def embeddings(request: Request) -> Response:
        return await handle(request, default_embeddings)

    return app


def _free_port() -> int:
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


@pytest.fixture(scope="session")
def _openai_server_session() -> Iterator[FakeOpenAIServer]:
    pytest.importorskip("fastapi", reason="the loopback server needs the dev extra (fastapi)")
    uvicorn = pytest.importorskip("uvicorn", reason="the loopback server needs the dev extra (uvicorn)")
    state = FakeOpenAIServer()
    port = _free_port()
    config = uvicorn.Config(
        _build_app(state),
        host="127.0.0.1",
        port=port,
        log_level="error",
        access_log=False,
        lifespan="off",
        timeout_graceful_shutdown=1,
    )
    server = uvicorn.Server(config)
    thread = threading.Thread(target=server.run, name="fake-openai-server", daemon=True)
    thread.start()
    deadline = time.monotonic() + 10
    while not server.started:
        if time.monotonic() > deadline or not thread.is_alive():
            pytest.fail("the loopback OpenAI-compatible test server did not start")
        time.sleep(0.01)
    state.base_url = f"http://127.0.0.1:{port}/v1"
    yield state
    server.should_exit = True
    thread.join(timeout=5)


@pytest.fixture
def openai_server(_openai_server_session: FakeOpenAIServer) -> Iterator[FakeOpenAIServer]:
    """The loopback server, with no queued answers and no recorded requests."""
    _openai_server_session.reset()
    yield _openai_server_session
    _openai_server_session.reset()


@pytest.fixture
def unused_url() -> str:
    """A loopback URL where nothing listens (connection refused)."""
    return f"http://127.0.0.1:{_free_port()}/v1"
