"""Serve the embedded model over HTTP: llama-cpp-python's OpenAI-compatible server as a subprocess.

``scenariominer llm serve`` runs it in the foreground; :class:`ServedModel` starts it in the
background (tests, benchmarks) and waits until ``/v1/models`` answers. Any command then talks to
it through the ``openai`` chat backend::

    [llm]
    backend = "openai"
    base_url = "http://127.0.0.1:8765/v1"
    model = "scenariominer"              # the served alias
    structured_mode = "json_object_schema"

llama-cpp-python's server answers one request at a time (it holds one model context behind a
lock), so concurrent clients queue rather than batch; ``benchmarks/llm_served.py`` measures it.
"""

from __future__ import annotations

import contextlib
import os
import socket
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path

from scenariominer.llm.errors import INSTALL_LLM_HINT, BackendError, MissingDependencyError

__all__ = ["DEFAULT_ALIAS", "ServeSettings", "ServedModel", "free_port", "server_command"]

#: Model name the server answers to (``[llm] model`` of a client).
DEFAULT_ALIAS = "scenariominer"


@dataclass(frozen=True)
class ServeSettings:
    """How to serve a GGUF file.

    Attributes:
        model_path: the GGUF file.
        host: interface to listen on (loopback by default: the server has no authentication).
        port: TCP port.
        alias: model name the server answers to.
        n_ctx: context window in tokens.
        n_threads: CPU threads (0: every core the process may use).
    """

    model_path: Path
    host: str = "127.0.0.1"
    port: int = 8765
    alias: str = DEFAULT_ALIAS
    n_ctx: int = 8192
    n_threads: int = 0

    @property
    def base_url(self) -> str:
        """Root of the OpenAI-compatible API (with ``/v1``)."""
        return f"http://{self.host}:{self.port}/v1"


def server_command(settings: ServeSettings) -> list[str]:
    """The command line that runs llama-cpp-python's server with ``settings``.

    Raises:
        MissingDependencyError: llama-cpp-python's server extra is not installed.
    """
    try:
        import llama_cpp.server  # noqa: F401 - presence check only
    except ImportError:
        raise MissingDependencyError("llama_cpp.server", "llm serve", INSTALL_LLM_HINT) from None
    threads = settings.n_threads or max(1, len(os.sched_getaffinity(0)))
    return [
        sys.executable,
        "-m",
        "llama_cpp.server",
        "--model",
        str(settings.model_path),
        "--model_alias",
        settings.alias,
        "--host",
        settings.host,
        "--port",
        str(settings.port),
        "--n_ctx",
        str(settings.n_ctx),
        "--n_threads",
        str(threads),
        "--n_threads_batch",
        str(threads),
        "--n_gpu_layers",
        "0",
    ]


def free_port(host: str = "127.0.0.1") -> int:
    """A TCP port nothing listens on right now."""
    with socket.socket() as s:
        s.bind((host, 0))
        return int(s.getsockname()[1])


class ServedModel:
    """The server as a background subprocess, stopped on :meth:`stop` or at the end of a ``with``.

    Args:
        settings: what to serve and where.
        log_path: file receiving the server's output (``os.devnull`` by default).
        startup_timeout_s: seconds to wait for ``/v1/models`` to answer.
    """

    def __init__(
        self, settings: ServeSettings, *, log_path: Path | None = None, startup_timeout_s: float = 120.0
    ) -> None:
        self.settings = settings
        self.log_path = log_path
        self.startup_timeout_s = startup_timeout_s
        self._proc: subprocess.Popen[bytes] | None = None

    @property
    def base_url(self) -> str:
        """Root of the OpenAI-compatible API."""
        return self.settings.base_url

    def start(self) -> ServedModel:
        """Start the server and wait until it answers.

        Raises:
            BackendError: the server exited or did not answer within the timeout (the message
                ends with the last lines of its output).
        """
        cmd = server_command(self.settings)
        out = open(self.log_path or os.devnull, "wb")  # noqa: SIM115 - closed with the process
        env = {**os.environ, "OMP_WAIT_POLICY": os.environ.get("OMP_WAIT_POLICY", "PASSIVE")}
        self._proc = subprocess.Popen(cmd, stdout=out, stderr=subprocess.STDOUT, env=env)
        out.close()
        self._wait_ready()
        return self

    def _wait_ready(self) -> None:
        import httpx

        deadline = time.monotonic() + self.startup_timeout_s
        while time.monotonic() < deadline:
            if self._proc is None or self._proc.poll() is not None:
                raise BackendError(f"the model server exited at start{self._tail()}")
            with contextlib.suppress(httpx.HTTPError):
                if httpx.get(f"{self.base_url}/models", timeout=2.0).status_code == 200:
                    return
            time.sleep(0.25)
        self.stop()
        raise BackendError(
            f"the model server did not answer within {self.startup_timeout_s:g} s{self._tail()}"
        )

    def _tail(self) -> str:
        if self.log_path is None or not self.log_path.is_file():
            return ""
        lines = self.log_path.read_text(errors="replace").strip().splitlines()[-5:]
        return ": " + " | ".join(lines) if lines else ""

    def stop(self) -> None:
        """Terminate the server (killed after 10 s)."""
        if self._proc is None:
            return
        self._proc.terminate()
        try:
            self._proc.wait(timeout=10)
        except subprocess.TimeoutExpired:
            self._proc.kill()
            self._proc.wait()
        self._proc = None

    def __enter__(self) -> ServedModel:
        return self.start()

    def __exit__(self, *exc: object) -> None:
        self.stop()
