"""A sandbox child dies with its host: a killed host must not leave a busy program running."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

HOST = """
from scenariominer.config.mining import MiningConfig, SandboxConfig
from scenariominer.mine.context import LogContext
from scenariominer.mine.sandbox import run_program
from scenariominer.testing import LogBuilder, times

ctx = LogContext(LogBuilder(times(2.0)).ego(speed_mps=5.0).build())
busy = "x = [a for a in range(10**5) for b in range(10**5) if a < 0]"
print("host ready", flush=True)
run_program(busy, ctx, config=MiningConfig(sandbox=SandboxConfig(timeout_s=120.0, cpu_s=120)))
"""


def _session_members(sid: int) -> list[int]:
    out = []
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            fields = (entry / "stat").read_text().rsplit(")", 1)[1].split()
        except OSError:
            continue
        if int(fields[3]) == sid and fields[0] != "Z":  # session id; zombies are already dead
            out.append(int(entry.name))
    return out


@pytest.mark.skipif(not Path("/proc/self/stat").exists(), reason="needs /proc (Linux)")
def test_killing_the_host_ends_the_sandbox_child() -> None:
    host = subprocess.Popen(
        [sys.executable, "-c", HOST], stdout=subprocess.PIPE, text=True, start_new_session=True
    )
    try:
        assert host.stdout is not None and host.stdout.readline().strip() == "host ready"
        deadline = time.monotonic() + 30
        while len(_session_members(host.pid)) < 3 and time.monotonic() < deadline:
            time.sleep(0.2)  # host, fork server and the busy child
        assert len(_session_members(host.pid)) >= 3
        os.kill(host.pid, signal.SIGKILL)
        host.wait(10)
        deadline = time.monotonic() + 10
        while _session_members(host.pid) and time.monotonic() < deadline:
            time.sleep(0.2)
        assert _session_members(host.pid) == []
    finally:
        for pid in _session_members(host.pid):
            os.kill(pid, signal.SIGKILL)
        if host.poll() is None:
            host.kill()
