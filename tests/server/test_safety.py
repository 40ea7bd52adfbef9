"""Token, bind address and job persistence across restarts of a real `scenariominer serve` process."""

from __future__ import annotations

import contextlib
import os
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

import httpx
import pytest
from typer.testing import CliRunner

TOKEN = "correct-horse-battery"


def test_token_is_required_when_set(servers: Any) -> None:
    with servers.start(servers.settings(token=TOKEN)) as server, httpx.Client(base_url=server.url) as c:
        missing = c.get("/api/logs")
        assert missing.status_code == 401 and "token" in missing.json()["error"]
        wrong = c.get("/api/logs", headers={"Authorization": "Bearer not-the-token"})
        assert wrong.status_code == 401
        right = c.get("/api/logs", headers={"Authorization": f"Bearer {TOKEN}"})
        assert right.status_code == 200 and right.json()
        posted = c.post("/api/jobs/analyze", json={"llm": False})
        assert posted.status_code == 401  # no job without the token
        assert c.get("/").status_code == 200  # the UI's files hold no data; it asks for the token


def test_binding_off_loopback_needs_a_token(built_store: Any) -> None:
    from scenariominer.cli import app
    from scenariominer.errors import ConfigError
    from scenariominer.server import ServerSettings

    with pytest.raises(ConfigError, match="--token"):
        ServerSettings.create(built_store.root, host="0.0.0.0")
    assert ServerSettings.create(built_store.root, host="0.0.0.0", token=TOKEN).token == TOKEN
    assert ServerSettings.create(built_store.root, host="::1").token is None  # loopback: optional
    result = CliRunner().invoke(app, ["serve", "--store", str(built_store.root), "--host", "0.0.0.0"])
    assert result.exit_code == 2 and "--token" in result.output


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port: int = s.getsockname()[1]
        return port


def _start(built_store: Any, data_root: Path, port: int) -> subprocess.Popen[bytes]:
    cmd = [
        str(Path(sys.executable).with_name("scenariominer")), "serve", "--store", str(built_store.root),
        "--config", str(built_store.config), "--port", str(port), "--data-root", str(data_root),
        "--workers", "1", "--max-queued", "1",
    ]  # fmt: skip
    proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline:
        try:
            if httpx.get(f"http://127.0.0.1:{port}/api/health", timeout=1).status_code == 200:
                return proc
        except httpx.TransportError:
            time.sleep(0.2)
    proc.kill()
    raise AssertionError(f"server did not start: {proc.stderr.read().decode() if proc.stderr else ''}")


def _children(pid: int) -> list[int]:
    out = []
    for task in Path(f"/proc/{pid}/task").iterdir():
        text = (task / "children").read_text().split()
        out += [int(c) for c in text]
    return out


def _state(c: httpx.Client, job_id: str) -> str:
    state: str = c.get(f"/api/jobs/{job_id}").json()["state"]
    return state


def test_jobs_survive_a_crash_and_a_stop_as_interrupted(built_store: Any, tmp_path: Path) -> None:
    port = _free_port()
    url = f"http://127.0.0.1:{port}"
    # 1. a crash (SIGKILL) with one job running and one queued
    proc = _start(built_store, tmp_path, port)
    with httpx.Client(base_url=url, timeout=30) as c:
        running = c.post("/api/jobs/synth", json={"out_dir": str(tmp_path / "a"), "n": 1000}).json()
        deadline = time.monotonic() + 60
        while _state(c, running["id"]) != "running" and time.monotonic() < deadline:
            time.sleep(0.1)
        queued = c.post("/api/jobs/synth", json={"out_dir": str(tmp_path / "b"), "n": 1000}).json()
        refused = c.post("/api/jobs/synth", json={"out_dir": str(tmp_path / "c"), "n": 1000})
        assert refused.status_code == 429 and "waiting" in refused.json()["error"]  # bounded queue
        workers = _children(proc.pid)
    proc.send_signal(signal.SIGKILL)
    proc.wait(timeout=30)
    for pid in workers:  # the crashed server's worker outlives it: end it here
        with contextlib.suppress(ProcessLookupError):
            os.kill(pid, signal.SIGKILL)
    # 2. the restarted server shows both, interrupted, then is stopped cleanly while a job runs
    proc = _start(built_store, tmp_path, port)
    try:
        with httpx.Client(base_url=url, timeout=30) as c:
            jobs = {j["id"]: j for j in c.get("/api/jobs").json()}
            for job in (running, queued):
                assert jobs[job["id"]]["state"] == "interrupted"
                assert "server stopped" in jobs[job["id"]]["error"]
            third = c.post("/api/jobs/synth", json={"out_dir": str(tmp_path / "d"), "n": 1000}).json()
            deadline = time.monotonic() + 60
            while _state(c, third["id"]) != "running" and time.monotonic() < deadline:
                time.sleep(0.1)
        proc.send_signal(signal.SIGINT)
        assert proc.wait(timeout=60) == 0
        proc = _start(built_store, tmp_path, port)
        with httpx.Client(base_url=url, timeout=30) as c:
            assert _state(c, third["id"]) == "interrupted"
    finally:
        proc.send_signal(signal.SIGINT)
        proc.wait(timeout=60)


def test_one_server_per_job_table(servers: Any) -> None:
    from scenariominer.server import create_app
    from scenariominer.server.jobs import JobTableBusyError

    settings = servers.settings()
    with servers.start(settings), pytest.raises(JobTableBusyError, match="one server per store"):
        create_app(settings)
    with servers.start(settings) as again:  # the first one stopped: its lock is gone
        assert httpx.get(again.url + "/api/health").status_code == 200
