"""Checking and running mining programs: an AST whitelist, then a resource-limited child process.

A mining program is a short Python text written by a language model (or a person) that calls
the functions of :mod:`scenariominer.mine.dsl` and ends with
``output_scenario(scenario, description, log_dir, output_dir)`` (RefAV's convention). The
program sees these predefined variables:

* ``log_dir``: the log being mined (a :class:`~scenariominer.mine.context.LogContext`; ``log`` is
  an alias), passed wherever RefAV passes its log folder;
* ``description``: the natural-language description being mined;
* ``output_dir``: ``None`` (accepted by ``output_scenario`` for compatibility);
* ``inf``; and ``np.inf``/``np.pi``/``math.inf``/``math.pi`` as the only attributes of ``np``/``math``.

Untrusted programs go through two barriers:

1. :func:`check_program` parses the text with :mod:`ast` and refuses, before anything runs,
   every construct outside a small whitelist: imports, function/class/lambda definitions,
   ``while`` loops, ``try``/``with``/``raise``/``global``/``nonlocal``/``del``, generators and
   ``await``, any name or attribute starting with ``__``, any attribute except a handful of
   container methods and ``np.inf``-style constants, and any name that is neither a mining
   function, a safe builtin (``len min max range abs sorted list dict set tuple enumerate zip
   bool int float str sum any all round print``), a predefined variable, nor assigned by the
   program itself. There is therefore no route to ``__class__``/``__subclasses__``,
   ``__globals__``, frames (``gi_frame``), ``str.format`` field look-ups, ``open``, ``eval``,
   ``exec``, ``getattr`` or modules. Definitions are refused rather than checked because mining
   programs are straight-line compositions: allowing ``def``/``lambda`` would only add
   recursion and hidden control flow.
2. :func:`run_program` executes the checked program in a separate process (``forkserver``,
   preloaded with the predicate library) with an address-space limit (``RLIMIT_AS``), a CPU
   limit, no file writes (``RLIMIT_FSIZE = 0``) and a wall-clock deadline enforced by the host,
   which kills the child. The child returns plain bytes (a JSON header and raw arrays), never a
   pickle, so even a compromised child cannot run code in the host.

Failures come back as a :class:`ProgramError` whose ``kind`` is one of :class:`ErrorKind`
(syntax, forbidden, runtime, timeout, memory, invalid_output) and whose message names the
line and the cause in words suited to feed back to a language model.

:func:`run_trusted_program` is the in-process fast path for TRUSTED, hand-written programs
(the example bank, benchmarks): same checks and namespace, no child process and no limits.
"""

from __future__ import annotations

import ast
import builtins
import contextlib
import json
import math
import multiprocessing
import multiprocessing.connection
import os
import signal
import sys
import threading
import time
import traceback
from collections.abc import Callable, Collection, Iterator
from dataclasses import dataclass
from enum import StrEnum
from types import SimpleNamespace
from typing import Any

import numpy as np

from scenariominer.config.mining import MiningConfig, SandboxConfig
from scenariominer.data.log import Log
from scenariominer.mine.context import LogContext, MapRequiredError
from scenariominer.mine.dsl import DSL_FUNCTIONS, OutputError, capture_output
from scenariominer.mine.scenario import Scenario, postprocess_scenario

__all__ = [
    "ALLOWED_ATTRIBUTES",
    "PREDEFINED_NAMES",
    "SAFE_BUILTIN_NAMES",
    "ErrorKind",
    "ProgramError",
    "ProgramResult",
    "check_program",
    "run_program",
    "run_trusted_program",
]

PROGRAM_FILENAME = "<program>"

#: Builtins available to programs (``range`` is capped, ``print`` discards its output).
SAFE_BUILTIN_NAMES: frozenset[str] = frozenset(
    {
        "len",
        "min",
        "max",
        "range",
        "abs",
        "sorted",
        "list",
        "dict",
        "set",
        "tuple",
        "enumerate",
        "zip",
        "bool",
        "int",
        "float",
        "str",
        "sum",
        "any",
        "all",
        "round",
        "print",
        "True",
        "False",
        "None",
    }
)

#: Variables every program starts with.
PREDEFINED_NAMES: frozenset[str] = frozenset(
    {"log_dir", "log", "description", "output_dir", "inf", "np", "math"}
)

#: Attribute names a program may read on any object (container methods).
ALLOWED_ATTRIBUTES: frozenset[str] = frozenset({"append", "extend", "items", "keys", "values", "get"})

#: ``name.attribute`` pairs allowed in addition (numeric constants).
ALLOWED_QUALIFIED: frozenset[tuple[str, str]] = frozenset(
    {("np", "inf"), ("np", "pi"), ("math", "inf"), ("math", "pi")}
)

_ALLOWED_NODES: tuple[type[ast.AST], ...] = (
    ast.Module,
    ast.Expr,
    ast.Assign,
    ast.AugAssign,
    ast.AnnAssign,
    ast.For,
    ast.If,
    ast.Pass,
    ast.Break,
    ast.Continue,
    ast.Assert,
    ast.Call,
    ast.keyword,
    ast.Name,
    ast.Constant,
    ast.Attribute,
    ast.Subscript,
    ast.Slice,
    ast.List,
    ast.Tuple,
    ast.Dict,
    ast.Set,
    ast.Starred,
    ast.ListComp,
    ast.SetComp,
    ast.DictComp,
    ast.comprehension,
    ast.BinOp,
    ast.UnaryOp,
    ast.BoolOp,
    ast.Compare,
    ast.IfExp,
    ast.JoinedStr,
    ast.FormattedValue,
    ast.Load,
    ast.Store,
    ast.operator,
    ast.unaryop,
    ast.boolop,
    ast.cmpop,
    ast.expr_context,
)

_FORBIDDEN_REASONS: dict[type[ast.AST], str] = {
    ast.Import: "imports are not allowed; every mining function is already available",
    ast.ImportFrom: "imports are not allowed; every mining function is already available",
    ast.FunctionDef: "defining functions is not allowed; write the program as a sequence of calls",
    ast.AsyncFunctionDef: "defining functions is not allowed; write the program as a sequence of calls",
    ast.Lambda: "lambda is not allowed; write the program as a sequence of calls",
    ast.ClassDef: "defining classes is not allowed",
    ast.While: "while loops are not allowed; predicates already cover all timestamps (or use a for loop)",
    ast.Try: "try/except is not allowed; the miner reports errors itself",
    ast.Raise: "raise is not allowed",
    ast.With: "with statements are not allowed",
    ast.AsyncWith: "with statements are not allowed",
    ast.AsyncFor: "async code is not allowed",
    ast.Global: "global is not allowed",
    ast.Nonlocal: "nonlocal is not allowed",
    ast.Delete: "del is not allowed",
    ast.Yield: "yield is not allowed",
    ast.YieldFrom: "yield is not allowed",
    ast.Await: "await is not allowed",
    ast.GeneratorExp: "generator expressions are not allowed; use a list comprehension [...]",
    ast.NamedExpr: "the := operator is not allowed",
    ast.Match: "match statements are not allowed",
}

_DENIED_CALL_HINTS: dict[str, str] = {
    name: "it is not available to mining programs"
    for name in (
        "open",
        "eval",
        "exec",
        "compile",
        "getattr",
        "setattr",
        "delattr",
        "hasattr",
        "globals",
        "locals",
        "vars",
        "dir",
        "input",
        "breakpoint",
        "type",
        "object",
        "memoryview",
        "help",
        "exit",
        "quit",
        "id",
        "format",
        "iter",
        "next",
        "super",
        "classmethod",
        "staticmethod",
        "property",
    )
}


class ErrorKind(StrEnum):
    """Why a program produced no scenario."""

    SYNTAX = "syntax"
    """The text is not valid Python."""
    FORBIDDEN = "forbidden"
    """The program uses a construct or name outside the whitelist (refused before running)."""
    RUNTIME = "runtime"
    """The program raised an exception while running (wrong arguments, missing map, ...)."""
    TIMEOUT = "timeout"
    """The program ran longer than the wall-clock or CPU limit and was killed."""
    MEMORY = "memory"
    """The program tried to allocate more memory than allowed."""
    INVALID_OUTPUT = "invalid_output"
    """The program finished without calling ``output_scenario`` exactly once with a scenario."""


@dataclass(frozen=True)
class ProgramError:
    """A structured failure of a mining program.

    Attributes:
        kind: category of the failure.
        message: one or two sentences naming the cause, with the line when known.
        line: 1-based program line the failure is attributed to, if known.
    """

    kind: ErrorKind
    message: str
    line: int | None = None

    def feedback(self) -> str:
        """The error as text to show a language model that should repair the program."""
        return f"{self.kind.value} error: {self.message}"

    def __str__(self) -> str:
        return self.feedback()


@dataclass(frozen=True)
class ProgramResult:
    """Outcome of running one program on one log.

    Attributes:
        scenario: the (post-processed) scenario the program output, or ``None`` on failure.
        error: the failure, or ``None`` on success.
        elapsed_s: wall-clock seconds spent, checks and process start-up included.
        description: the description the program passed to ``output_scenario``, if any.
    """

    scenario: Scenario | None
    error: ProgramError | None
    elapsed_s: float
    description: str | None = None

    @property
    def ok(self) -> bool:
        """Whether the program produced a scenario."""
        return self.error is None and self.scenario is not None


# ---------------------------------------------------------------------- static checks


def _line(node: ast.AST) -> int | None:
    return getattr(node, "lineno", None)


def _forbidden(node: ast.AST, reason: str) -> ProgramError:
    line = _line(node)
    prefix = f"line {line}: " if line is not None else ""
    return ProgramError(ErrorKind.FORBIDDEN, prefix + reason, line)


def _is_dunder(name: str) -> bool:
    return name.startswith("__")


def check_program(
    source: str,
    config: SandboxConfig | None = None,
    functions: Collection[str] | None = None,
) -> ProgramError | None:
    """Check a program against the whitelist without running it.

    Args:
        source: the program text.
        config: size limits; defaults to :class:`SandboxConfig`.
        functions: names of the callable mining functions; defaults to every DSL function.

    Returns:
        ``None`` if the program may run, else the first problem found (``syntax`` or ``forbidden``).
    """
    cfg = config or SandboxConfig()
    if not isinstance(source, str):
        return ProgramError(ErrorKind.SYNTAX, f"the program must be text, got {type(source).__name__}")
    if len(source) > cfg.max_program_chars:
        return ProgramError(
            ErrorKind.FORBIDDEN,
            f"the program has {len(source)} characters; at most {cfg.max_program_chars} are allowed",
        )
    try:
        tree = ast.parse(source, filename=PROGRAM_FILENAME, mode="exec")
    except SyntaxError as exc:
        return ProgramError(ErrorKind.SYNTAX, f"line {exc.lineno}: {exc.msg}", exc.lineno)
    except (ValueError, RecursionError, MemoryError) as exc:
        return ProgramError(ErrorKind.SYNTAX, f"the program cannot be parsed ({type(exc).__name__}: {exc})")

    allowed_funcs = frozenset(functions) if functions is not None else frozenset(DSL_FUNCTIONS)
    known = allowed_funcs | SAFE_BUILTIN_NAMES | PREDEFINED_NAMES
    nodes = list(ast.walk(tree))
    if len(nodes) > cfg.max_ast_nodes:
        return ProgramError(
            ErrorKind.FORBIDDEN,
            f"the program has {len(nodes)} syntax nodes; at most {cfg.max_ast_nodes} are allowed",
        )
    assigned = {n.id for n in nodes if isinstance(n, ast.Name) and isinstance(n.ctx, ast.Store)}

    for node in nodes:
        reason = _FORBIDDEN_REASONS.get(type(node))
        if reason is not None:
            return _forbidden(node, reason)
        if not isinstance(node, _ALLOWED_NODES):
            return _forbidden(node, f"{type(node).__name__} is not allowed in mining programs")
        if isinstance(node, ast.Name):
            if _is_dunder(node.id):
                return _forbidden(node, f"the name {node.id!r} is not allowed (no names starting with '__')")
            if isinstance(node.ctx, ast.Store) and node.id in PREDEFINED_NAMES | allowed_funcs:
                return _forbidden(node, f"do not assign to {node.id!r}; it is predefined")
            if isinstance(node.ctx, ast.Load) and node.id not in known and node.id not in assigned:
                hint = _DENIED_CALL_HINTS.get(node.id) or (
                    "it is neither a mining function, an allowed builtin, nor a variable the program assigns"
                )
                return _forbidden(node, f"the name {node.id!r} cannot be used: {hint}")
        elif isinstance(node, ast.Attribute):
            if _is_dunder(node.attr) or node.attr.startswith("_"):
                return _forbidden(
                    node, f"the attribute {node.attr!r} is not allowed (no attributes starting with '_')"
                )
            if not isinstance(node.ctx, ast.Load):
                return _forbidden(node, "assigning to attributes is not allowed")
            qualified = isinstance(node.value, ast.Name) and (node.value.id, node.attr) in ALLOWED_QUALIFIED
            if not qualified and node.attr not in ALLOWED_ATTRIBUTES:
                return _forbidden(
                    node,
                    f"the attribute '.{node.attr}' is not allowed; mining programs only call the mining "
                    "functions directly (np.inf and inf are available)",
                )
        elif isinstance(node, ast.Call):
            problem = _check_call(node, known, assigned)
            if problem is not None:
                return problem
        elif isinstance(node, ast.Constant) and isinstance(node.value, bytes):
            return _forbidden(node, "bytes literals are not allowed")
    return None


def _check_call(node: ast.Call, known: frozenset[str], assigned: set[str]) -> ProgramError | None:
    func = node.func
    if isinstance(func, ast.Name):
        return None  # names are checked on their own (unknown names get a specific message)
    if isinstance(func, ast.Call) and isinstance(func.func, ast.Name):
        if func.func.id in ("scenario_not", "reverse_relationship"):
            return None
        return _forbidden(
            node, "only scenario_not(...)(...) and reverse_relationship(...)(...) may be called twice"
        )
    if isinstance(func, ast.Attribute):
        return None  # attributes are whitelisted separately
    return _forbidden(node, "only mining functions and allowed builtins may be called")


# ---------------------------------------------------------------------- execution namespace


def _safe_range_factory(limit: int) -> Callable[..., range]:
    def safe_range(*args: Any) -> range:
        r = range(*args)
        if len(r) > limit:
            raise ValueError(f"range() of {len(r)} values is too long; at most {limit} are allowed")
        return r

    return safe_range


def _discard(*_args: Any, **_kwargs: Any) -> None:
    return None


def _namespace(context: LogContext, description: str, config: SandboxConfig) -> dict[str, Any]:
    safe = {name: getattr(builtins, name) for name in SAFE_BUILTIN_NAMES if hasattr(builtins, name)}
    safe["range"] = _safe_range_factory(config.max_range_len)
    safe["print"] = _discard
    constants = SimpleNamespace(inf=math.inf, pi=math.pi)
    ns: dict[str, Any] = {"__builtins__": safe, **DSL_FUNCTIONS}
    ns.update(log_dir=context, log=context, description=description, output_dir=None, inf=math.inf)
    ns.update(np=constants, math=constants)
    return ns


def _program_line(exc: BaseException) -> int | None:
    line = None
    for frame in traceback.extract_tb(exc.__traceback__):
        if frame.filename == PROGRAM_FILENAME:
            line = frame.lineno
    return line


def _runtime_error(exc: BaseException) -> ProgramError:
    line = _program_line(exc)
    prefix = f"line {line}: " if line is not None else ""
    if isinstance(exc, MemoryError):
        return ProgramError(
            ErrorKind.MEMORY, prefix + "the program tried to allocate more memory than allowed", line
        )
    if isinstance(exc, RecursionError):
        return ProgramError(ErrorKind.RUNTIME, prefix + "RecursionError: the program nests too deeply", line)
    text = str(exc) or type(exc).__name__
    if isinstance(exc, OutputError):
        return ProgramError(ErrorKind.INVALID_OUTPUT, prefix + text, line)
    if isinstance(exc, MapRequiredError):
        return ProgramError(ErrorKind.RUNTIME, prefix + text, line)
    return ProgramError(ErrorKind.RUNTIME, f"{prefix}{type(exc).__name__}: {text}", line)


def _execute(
    source: str, context: LogContext, description: str, config: MiningConfig, postprocess: bool
) -> tuple[Scenario | None, ProgramError | None, str | None]:
    """Compile and run a checked program in this process; never raises for program faults."""
    if not isinstance(description, str):
        description = str(description)
    try:
        code = compile(source, PROGRAM_FILENAME, "exec", dont_inherit=True)
    except (SyntaxError, ValueError, RecursionError, MemoryError) as exc:
        return (
            None,
            ProgramError(ErrorKind.SYNTAX, f"the program cannot be compiled ({type(exc).__name__}: {exc})"),
            None,
        )
    ns = _namespace(context, description, config.sandbox)
    with capture_output() as sink:
        try:
            exec(code, ns)  # noqa: S102 - the program passed check_program; see module docstring
        except Exception as exc:  # every program fault becomes a structured error
            return None, _runtime_error(exc), None
    if sink.calls == 0 or sink.scenario is None:
        return (
            None,
            ProgramError(
                ErrorKind.INVALID_OUTPUT,
                "the program never called output_scenario(scenario, description, log_dir, output_dir)",
            ),
            None,
        )
    scenario = sink.scenario
    if scenario.context is not context:
        return (
            None,
            ProgramError(ErrorKind.INVALID_OUTPUT, "the output scenario belongs to another log"),
            None,
        )
    try:
        if postprocess:
            scenario = postprocess_scenario(scenario, config)
    except Exception as exc:
        return None, ProgramError(ErrorKind.INVALID_OUTPUT, f"the output scenario is malformed ({exc})"), None
    return scenario, None, sink.description


def run_trusted_program(
    source: str, context: LogContext, *, description: str = "", postprocess: bool = True
) -> ProgramResult:
    """Run a TRUSTED program in this process (no child process, no resource limits).

    For hand-written programs shipped with the package and for benchmarks. The whitelist check
    still runs (it is cheap and catches typos); never use this for model-written programs.

    Args:
        source: the program text.
        context: the log to mine.
        description: value of the program's ``description`` variable.
        postprocess: apply :func:`~scenariominer.mine.scenario.postprocess_scenario`.
    """
    start = time.perf_counter()
    problem = check_program(source, context.config.sandbox)
    if problem is not None:
        return ProgramResult(None, problem, time.perf_counter() - start)
    scenario, error, desc = _execute(source, context, description, context.config, postprocess)
    return ProgramResult(scenario, error, time.perf_counter() - start, desc)


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
