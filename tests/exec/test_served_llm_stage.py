"""The LLM stage against a served model fans out over the workers, within the concurrency limit,
and stores what the one-process run stores. The server is a real HTTP server on loopback that
speaks the OpenAI chat API with deterministic canned answers (a test double for the model only)."""

from __future__ import annotations

import json
import re
import threading
import time
from collections.abc import Iterator
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from pathlib import Path

import pyarrow as pa
import pyarrow.compute as pc
import pytest

from scenariominer import api
from scenariominer.config import Config, load_config
from scenariominer.exec import InlineExecutor, ProcessExecutor
from scenariominer.exec.base import Executor

LIMIT = 2  # llm.max_concurrency
VOLATILE = {"seconds", "analyzed_at", "latency_s", "llm_latency_s"}


class _Counter:
    def __init__(self) -> None:
        self.lock = threading.Lock()
        self.in_flight = 0
        self.peak = 0
        self.calls = 0


def _answer(prompt: str) -> str:
    """The first allowed category the prompt offers, as a well-formed judge answer."""
    allowed = re.findall(r"Allowed categories: (.*)\.$", prompt, re.MULTILINE)
    options = allowed[0].split(", ") if allowed else re.findall(r"The category is (\w+);", prompt)
    category = options[0] if options else "unknown_but_relevant"
    reply = {"description": "The guest makes the ego brake.", "category": category, "explanation": "e"}
    return json.dumps(reply)


def _handler(counter: _Counter) -> type[BaseHTTPRequestHandler]:
    class Handler(BaseHTTPRequestHandler):
        def do_POST(self) -> None:  # noqa: N802 - the http.server API
            body = json.loads(self.rfile.read(int(self.headers["Content-Length"])))
            with counter.lock:
                counter.in_flight += 1
                counter.calls += 1
                counter.peak = max(counter.peak, counter.in_flight)
            time.sleep(0.15)  # long enough for concurrent requests to overlap
            content = _answer(body["messages"][-1]["content"])
            with counter.lock:
                counter.in_flight -= 1
            reply = {
                "choices": [{"message": {"role": "assistant", "content": content}, "finish_reason": "stop"}],
                "usage": {"prompt_tokens": 10, "completion_tokens": 10},
            }
            data = json.dumps(reply).encode()
            self.send_response(200)
            self.send_header("Content-Type", "application/json")
            self.send_header("Content-Length", str(len(data)))
            self.end_headers()
            self.wfile.write(data)

        def log_message(self, format: str, *args: object) -> None:  # noqa: A002 - silence the log
            """Quiet."""

    return Handler


@pytest.fixture()
def server() -> Iterator[tuple[str, _Counter]]:
    counter = _Counter()
    httpd = ThreadingHTTPServer(("127.0.0.1", 0), _handler(counter))
    thread = threading.Thread(target=httpd.serve_forever, daemon=True)
    thread.start()
    yield f"http://127.0.0.1:{httpd.server_address[1]}/v1", counter
    httpd.shutdown()
    httpd.server_close()


@pytest.fixture(scope="module")
def logs_dir(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("synth") / "logs"
    api.synth(out, 6, seed=21)
    return out


def _config(tmp_path: Path, base_url: str) -> Config:
    path = tmp_path / "cfg.toml"
    path.write_text(
        f'[llm]\nbackend = "openai"\nbase_url = "{base_url}"\nmodel = "fake"\nstructured_mode = "prompt"\n'
        f"cache = false\nmax_concurrency = {LIMIT}\n"
        '[embedding]\nbackend = "hashing"\nhashing_dim = 16\n[explain]\njudge = "llm"\n'
    )
    return load_config(path)


def _events(root: Path, logs_dir: Path, config: Config, executor: Executor) -> pa.Table:
    store = api.open_store(root, config)
    api.ingest([logs_dir], store, config, executor=InlineExecutor())
    report = api.analyze(store, api.AnalyzeRequest(), config, executor=executor)
    assert report.n_failed == 0 and report.n_pending == 0 and report.n_llm_calls > 0
    table = store.read_table("events")
    keep = [c for c in table.column_names if c not in VOLATILE]
    table = table.select(keep)
    for i, field in enumerate(table.schema):
        if pa.types.is_floating(field.type):
            table = table.set_column(i, field, pc.if_else(pc.is_nan(table.column(i)), None, table.column(i)))
    return table.sort_by([("event_id", "ascending")])


def test_served_llm_stage_runs_in_the_workers_within_the_limit(
    tmp_path: Path, logs_dir: Path, server: tuple[str, _Counter]
) -> None:
    base_url, counter = server
    config = _config(tmp_path, base_url)
    alone = _events(tmp_path / "local", logs_dir, config, InlineExecutor())
    assert counter.peak == 1  # one process, one request at a time
    calls_alone, counter.peak = counter.calls, 0
    pool = ProcessExecutor(3, min_items=1)
    try:
        fanned = _events(tmp_path / "pool", logs_dir, config, pool)
    finally:
        pool.close()
    assert counter.calls == 2 * calls_alone  # the same questions again, none skipped
    assert counter.peak == LIMIT  # requests overlapped, never beyond llm.max_concurrency
    assert fanned.num_rows > 0 and fanned.equals(alone)
