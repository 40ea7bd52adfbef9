"""Running a checked program: its restricted namespace and the trusted in-process runner."""

from __future__ import annotations

import builtins
import math
import time
import traceback
from collections.abc import Callable
from types import SimpleNamespace
from typing import Any

from scenariominer.config.mining import MiningConfig, SandboxConfig
from scenariominer.mine.context import LogContext, MapRequiredError
from scenariominer.mine.dsl import DSL_FUNCTIONS, OutputError, capture_output
from scenariominer.mine.sandbox.check import (
    PROGRAM_FILENAME,
    SAFE_BUILTIN_NAMES,
    ErrorKind,
    ProgramError,
    ProgramResult,
    check_program,
)
from scenariominer.mine.scenario import Scenario, postprocess_scenario

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
