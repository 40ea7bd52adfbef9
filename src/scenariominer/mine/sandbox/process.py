"""The second line of defence: running an untrusted program in a resource-limited child process."""

from __future__ import annotations

import contextlib
import json
import multiprocessing
import multiprocessing.connection
import os
import signal
import sys
import threading
import time
from collections.abc import Iterator
from dataclasses import dataclass
from typing import Any

import numpy as np

from scenariominer.config.mining import MiningConfig, SandboxConfig
from scenariominer.data.log import Log
from scenariominer.mine.context import LogContext
from scenariominer.mine.sandbox.check import (
    ErrorKind,
    ProgramError,
    ProgramResult,
    check_program,
)
from scenariominer.mine.sandbox.execute import (
    _execute,
)
from scenariominer.mine.scenario import Scenario

# ---------------------------------------------------------------------- the child process

_HEADER_LIMIT = 1 << 16


def _address_space_bytes() -> int:
    try:
        with open("/proc/self/statm", encoding="ascii") as fh:
            pages = int(fh.read().split()[0])
        return pages * os.sysconf("SC_PAGE_SIZE")
    except (OSError, ValueError, IndexError):
        return 0


def _limit_resources(config: SandboxConfig) -> None:
    try:
        import resource
    except ImportError:  # pragma: no cover - non-POSIX
        return
    base = _address_space_bytes()
    if base:
        limit = base + config.memory_mb * 1024 * 1024
        resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
    cpu = int(config.cpu_s)
    resource.setrlimit(resource.RLIMIT_CPU, (cpu, cpu + 1))
    resource.setrlimit(resource.RLIMIT_FSIZE, (0, 0))
    resource.setrlimit(resource.RLIMIT_CORE, (0, 0))


def _send(conn: multiprocessing.connection.Connection, header: dict[str, Any], *blobs: bytes) -> None:
    conn.send_bytes(json.dumps(header).encode("utf-8"))
    for blob in blobs:
        conn.send_bytes(blob)


def _child_main(
    conn: multiprocessing.connection.Connection,
    source: str,
    log: Log,
    config: MiningConfig,
    hd_map: Any,
    description: str,
    postprocess: bool,
    host_pid: int,
) -> None:
    """Entry point of the sandbox child: limit, run, reply with bytes, exit."""
    try:
        signal.signal(signal.SIGINT, signal.SIG_IGN)
        _exit_with_host(host_pid)
        context = LogContext(log, config, hd_map)
        if log.map_dir is not None or hd_map is not None:
            try:
                _ = context.has_map  # read the map before file access is restricted
            except Exception as exc:
                _send(
                    conn, {"status": "error", "kind": "runtime", "message": f"cannot read the HD map: {exc}"}
                )
                return
        _limit_resources(config.sandbox)
        scenario, error, desc = _execute(source, context, description, config, postprocess)
        if error is not None:
            _send(
                conn,
                {"status": "error", "kind": error.kind.value, "message": error.message, "line": error.line},
            )
            return
        assert scenario is not None
        referred = np.ascontiguousarray(scenario.referred, dtype=np.bool_)
        relations = np.ascontiguousarray(scenario.relations, dtype="<i8")
        header = {
            "status": "ok",
            "shape": list(referred.shape),
            "relations": int(relations.shape[0]),
            "description": None if desc is None else desc[:1000],
        }
        _send(conn, header, referred.tobytes(), relations.tobytes())
    except MemoryError:
        with contextlib.suppress(Exception):
            _send(conn, {"status": "error", "kind": "memory", "message": "the program ran out of memory"})
    except BaseException as exc:  # the child must always answer or die quietly
        with contextlib.suppress(Exception):
            _send(conn, {"status": "error", "kind": "runtime", "message": f"{type(exc).__name__}: {exc}"})
    finally:
        try:
            conn.close()
        finally:
            sys.stdout.flush()


def _exit_with_host(host_pid: int, period_s: float = 0.2) -> None:
    """End this child as soon as the host process is gone.

    The child's parent is the fork server, not the host, so the kernel's parent-death signal does
    not reach it; without this watchdog a busy program would run on until its CPU limit.
    """

    def watch() -> None:
        while True:
            time.sleep(period_s)
            try:
                os.kill(host_pid, 0)
            except ProcessLookupError:
                os._exit(70)
            except PermissionError:
                continue

    threading.Thread(target=watch, daemon=True, name="scenariominer-host-watchdog").start()


def _mp_context() -> Any:
    methods = multiprocessing.get_all_start_methods()
    if "forkserver" in methods:
        ctx = multiprocessing.get_context("forkserver")
        ctx.set_forkserver_preload(["scenariominer.mine.sandbox"])
        return ctx
    return multiprocessing.get_context("spawn")


def _recv_header(conn: multiprocessing.connection.Connection) -> dict[str, Any]:
    raw = conn.recv_bytes(_HEADER_LIMIT)
    header = json.loads(raw.decode("utf-8"))
    if not isinstance(header, dict):
        raise ValueError("malformed reply header")
    return header


def _decode_reply(
    conn: multiprocessing.connection.Connection, context: LogContext, deadline: float
) -> tuple[Scenario | None, ProgramError | None, str | None]:
    header = _recv_header(conn)
    if header.get("status") == "error":
        try:
            kind = ErrorKind(str(header.get("kind")))
        except ValueError:
            kind = ErrorKind.RUNTIME
        line = header.get("line")
        return (
            None,
            ProgramError(
                kind, str(header.get("message", ""))[:2000], line if isinstance(line, int) else None
            ),
            None,
        )
    n, t = context.n_tracks, context.n_timestamps
    if header.get("shape") != [n, t]:
        return None, ProgramError(ErrorKind.INVALID_OUTPUT, "the output has the wrong shape"), None
    k = int(header.get("relations", -1))
    if k < 0 or k > 64 * n * n * max(t, 1):
        return None, ProgramError(ErrorKind.INVALID_OUTPUT, "the output has an invalid relation count"), None
    if not conn.poll(max(0.0, deadline - time.monotonic())):
        raise TimeoutError
    referred_raw = conn.recv_bytes(n * t + 1)
    if not conn.poll(max(0.0, deadline - time.monotonic())):
        raise TimeoutError
    relations_raw = conn.recv_bytes(k * 3 * 8 + 1)
    if len(referred_raw) != n * t or len(relations_raw) != k * 3 * 8:
        return None, ProgramError(ErrorKind.INVALID_OUTPUT, "the output arrays have the wrong size"), None
    referred = np.frombuffer(referred_raw, dtype=np.uint8).reshape(n, t)
    if referred.max(initial=0) > 1:
        return None, ProgramError(ErrorKind.INVALID_OUTPUT, "the output mask is not boolean"), None
    relations = np.frombuffer(relations_raw, dtype="<i8").reshape(k, 3).astype(np.int64)
    try:
        scenario = Scenario.from_arrays(context, referred.astype(bool), relations)
    except ValueError as exc:
        return None, ProgramError(ErrorKind.INVALID_OUTPUT, f"the output scenario is invalid ({exc})"), None
    desc = header.get("description")
    return scenario, None, desc if isinstance(desc, str) else None


def _exit_error(exitcode: int | None) -> ProgramError:
    if exitcode is not None and exitcode < 0:
        sig = -exitcode
        if sig == getattr(signal, "SIGXCPU", -1):
            return ProgramError(
                ErrorKind.TIMEOUT, "the program used more CPU time than allowed and was stopped"
            )
        if sig == signal.SIGKILL:
            return ProgramError(ErrorKind.MEMORY, "the program was killed (most likely out of memory)")
        name = signal.Signals(sig).name if sig in signal.valid_signals() else str(sig)
        return ProgramError(ErrorKind.RUNTIME, f"the program crashed (signal {name})")
    return ProgramError(
        ErrorKind.RUNTIME, f"the program's process ended without a result (exit code {exitcode})"
    )


@dataclass
class _Child:
    process: Any
    conn: multiprocessing.connection.Connection

    def stop(self) -> None:
        if self.process.is_alive():
            self.process.kill()
        self.process.join(5)
        self.conn.close()


def _start_child(source: str, context: LogContext, description: str, postprocess: bool) -> _Child:
    mp = _mp_context()
    recv_end, send_end = mp.Pipe(duplex=False)
    hd_map = context._map_given  # noqa: SLF001 - forward a map given in memory to the child
    process = mp.Process(
        target=_child_main,
        args=(send_end, source, context.log, context.config, hd_map, description, postprocess, os.getpid()),
        daemon=True,
        name="scenariominer-sandbox",
    )
    process.start()
    send_end.close()
    return _Child(process, recv_end)


def _iter_wait(child: _Child, deadline: float) -> Iterator[bool]:
    """Yield once the child has something to read (True) or the deadline passed (False)."""
    while True:
        remaining = deadline - time.monotonic()
        if remaining <= 0:
            yield False
            return
        ready = multiprocessing.connection.wait(
            [child.conn, child.process.sentinel], timeout=min(remaining, 0.5)
        )
        if child.conn in ready:
            yield True
            return
        if child.process.sentinel in ready and not child.conn.poll():
            yield True
            return


def run_program(
    source: str,
    log: Log | LogContext,
    *,
    description: str = "",
    config: MiningConfig | None = None,
    postprocess: bool = True,
) -> ProgramResult:
    """Check an UNTRUSTED program and run it on one log in a resource-limited child process.

    The host survives anything the program does: the child is killed at the deadline, its
    address space and CPU time are capped, and its reply is parsed as raw bytes.

    Args:
        source: the program text.
        log: the log to mine, or its :class:`LogContext` (whose config and in-memory map are used).
        description: value of the program's ``description`` variable.
        config: thresholds and sandbox limits; defaults to the context's or :class:`MiningConfig`.
        postprocess: apply :func:`~scenariominer.mine.scenario.postprocess_scenario` in the child.

    Returns:
        The scenario (rebuilt on the host's context) or a :class:`ProgramError`.
    """
    start = time.perf_counter()
    if isinstance(log, LogContext):
        context = (
            log if config is None or config is log.config else LogContext(log.log, config, log._map_given)
        )  # noqa: SLF001
    else:
        context = LogContext(log, config)
    cfg = context.config
    problem = check_program(source, cfg.sandbox)
    if problem is not None:
        return ProgramResult(None, problem, time.perf_counter() - start)
    try:
        child = _start_child(source, context, description, postprocess)
    except Exception as exc:  # e.g. an unpicklable map object
        return ProgramResult(
            None,
            ProgramError(ErrorKind.RUNTIME, f"the sandbox could not start ({type(exc).__name__}: {exc})"),
            time.perf_counter() - start,
        )
    deadline = time.monotonic() + cfg.sandbox.timeout_s  # the child runs from here
    try:
        got = next(_iter_wait(child, deadline))
        if not got:
            slow = ProgramError(
                ErrorKind.TIMEOUT,
                f"the program did not finish within {cfg.sandbox.timeout_s:g} s and was stopped; avoid loops "
                "over timestamps or objects, the predicates already work on all of them",
            )
            return ProgramResult(None, slow, time.perf_counter() - start)
        if not child.conn.poll():
            child.process.join(1)
            return ProgramResult(None, _exit_error(child.process.exitcode), time.perf_counter() - start)
        try:
            scenario, error, desc = _decode_reply(child.conn, context, deadline)
        except TimeoutError:
            late = ProgramError(ErrorKind.TIMEOUT, "the program's result did not arrive in time")
            return ProgramResult(None, late, time.perf_counter() - start)
        except (EOFError, OSError, ValueError, UnicodeDecodeError) as exc:
            child.process.join(1)
            if child.process.exitcode not in (None, 0):
                return ProgramResult(None, _exit_error(child.process.exitcode), time.perf_counter() - start)
            unreadable = ProgramError(
                ErrorKind.INVALID_OUTPUT, f"the program's reply could not be read ({type(exc).__name__})"
            )
            return ProgramResult(None, unreadable, time.perf_counter() - start)
        return ProgramResult(scenario, error, time.perf_counter() - start, desc)
    finally:
        child.stop()
