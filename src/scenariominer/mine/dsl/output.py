"""``output_scenario``: how a program hands its result back to the host."""

from __future__ import annotations

import contextlib
from collections.abc import Iterator
from contextvars import ContextVar
from dataclasses import dataclass
from typing import Any

from scenariominer import errors as _errors
from scenariominer.mine.context import LogContext
from scenariominer.mine.scenario import (
    Scenario,
)

# ====================================================================== output


class OutputError(_errors.MiningError, RuntimeError):
    """``output_scenario`` was misused (not a scenario, wrong log, called twice)."""


@dataclass
class OutputSink:
    """Receives the scenario a program passes to :func:`output_scenario`.

    Attributes:
        scenario: the scenario output by the program, if any.
        description: the description the program gave.
        calls: how many times output_scenario was called.
    """

    scenario: Scenario | None = None
    description: str | None = None
    calls: int = 0


_SINK: ContextVar[OutputSink | None] = ContextVar("scenariominer_output_sink", default=None)


@contextlib.contextmanager
def capture_output() -> Iterator[OutputSink]:
    """Collect what a program passes to :func:`output_scenario` while the block runs."""
    sink = OutputSink()
    token = _SINK.set(sink)
    try:
        yield sink
    finally:
        _SINK.reset(token)


def output_scenario(
    scenario: Scenario,
    description: str | None = None,
    log_dir: LogContext | None = None,
    output_dir: Any = None,
    visualize: bool = False,
    **visualization_kwargs: Any,
) -> None:
    """Hand the program's final scenario back to the miner. Call it exactly ONCE, at the end.

    Args:
        scenario: the final scenario; its referred objects are the answer.
        description: the description being mined (pass the predefined variable ``description``).
        log_dir: the log (the predefined variable ``log_dir``); optional.
        output_dir: accepted for compatibility with RefAV programs (pass ``output_dir``); unused.
        visualize: accepted for compatibility; unused.
        **visualization_kwargs: accepted for compatibility; unused.

    Returns:
        None. The miner post-processes and stores the scenario.

    Example:
        output_scenario(vehicles_with_bicycle_right, description, log_dir, output_dir)
    """
    sink = _SINK.get()
    if sink is None:
        raise RuntimeError("output_scenario() can only be called inside a mining program run")
    if not isinstance(scenario, Scenario):
        raise OutputError(
            f"output_scenario(): the first argument must be the final scenario, got {type(scenario).__name__}"
        )
    if log_dir is not None and isinstance(log_dir, LogContext) and log_dir is not scenario.context:
        raise OutputError("output_scenario(): the scenario belongs to another log than log_dir")
    sink.calls += 1
    if sink.calls > 1:
        raise OutputError(
            "output_scenario() was called more than once; call it exactly once with the final scenario"
        )
    sink.scenario = scenario
    sink.description = None if description is None else str(description)
