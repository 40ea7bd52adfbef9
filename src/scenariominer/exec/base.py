"""The executor protocol: map one stage's function over work items, isolating every item.

A *work item* is small and picklable: a log source, a log id, a batch of window ids. The function
is a picklable callable (a top-level function or an instance of a top-level class) that opens what
it needs itself (the store from its root, a model from the configuration) and commits its result
through the store's atomic writes. So a task carries references, never arrays, and a worker that
dies mid-task loses nothing already committed.

Every executor gives the same guarantees:

* one :class:`ItemOutcome` per item, in the order of the items;
* an item that raises is reported (type and message) and the other items go on;
* an item whose worker died, or that raised :class:`~scenariominer.errors.TransientError` (or a
  connection or time-out error), is retried up to ``retries`` more times;
* :meth:`Executor.cancel` (from any thread) stops submitting; items not finished are reported as
  cancelled; a ``KeyboardInterrupt`` in the caller cancels too, then propagates.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any, Generic, Protocol, TypeVar

from scenariominer.errors import TransientError
from scenariominer.progress import NullProgress, Progress

__all__ = [
    "CANCELLED",
    "Executor",
    "ItemOutcome",
    "OnOutcome",
    "is_transient",
    "run_serially",
]

T = TypeVar("T")
R = TypeVar("R")

#: The error text of an item that never finished because the run was cancelled.
CANCELLED = "cancelled before it finished"


@dataclass(frozen=True)
class ItemOutcome(Generic[R]):
    """What became of one work item.

    Attributes:
        key: the item's name (a source path, a log id).
        value: the function's return value (``None`` when it failed).
        error: ``""`` on success, else the cause (``TypeName: message``).
        attempts: how many times the item was started (more than 1 after retries).
        seconds: wall time of the last attempt, as the driver saw it.
    """

    key: str
    value: R | None = None
    error: str = ""
    attempts: int = 1
    seconds: float = 0.0

    @property
    def ok(self) -> bool:
        """True when the item finished without an error."""
        return not self.error


#: Called in the driver after each item finishes (progress, logging).
OnOutcome = Callable[[ItemOutcome[Any]], None]


class Executor(Protocol):
    """Runs a function over work items (see the module docstring for the guarantees)."""

    name: str
    """``local``, ``process`` or ``ray``."""

    @property
    def workers(self) -> int:
        """How many items run at once."""
        ...

    def map(
        self,
        fn: Callable[[T], R],
        items: Sequence[T],
        *,
        keys: Sequence[str] | None = None,
        on_outcome: OnOutcome | None = None,
        max_in_flight: int | None = None,
    ) -> list[ItemOutcome[R]]:
        """Run ``fn`` on every item; one outcome per item, in order.

        Args:
            fn: picklable callable (the worker side of a stage).
            items: picklable work items.
            keys: a name per item for the outcomes (default: the item's position).
            on_outcome: called in the calling thread after each item finishes.
            max_in_flight: at most this many items running at once (e.g. a served model's
                concurrency limit); default: :attr:`workers`.
        """
        ...

    def cancel(self) -> None:
        """Stop the current :meth:`map` (safe from another thread)."""
        ...

    def close(self) -> None:
        """Release workers (a later :meth:`map` starts new ones)."""
        ...


def is_transient(exc: BaseException) -> bool:
    """Whether a failure is worth retrying: a declared transient error, a connection or a time-out."""
    return isinstance(exc, TransientError | ConnectionError | TimeoutError)


def describe(exc: BaseException) -> str:
    """``TypeName: message`` of an exception (what an outcome records)."""
    text = str(exc)
    return f"{type(exc).__name__}: {text}" if text else type(exc).__name__


def run_serially(
    fn: Callable[[T], R],
    items: Sequence[T],
    keys: Sequence[str],
    *,
    retries: int,
    cancelled: threading.Event,
    on_outcome: OnOutcome | None,
    backoff_s: float = 0.05,
) -> list[ItemOutcome[R]]:
    """The in-process loop: each item in turn, retrying transient failures (the ``local`` executor)."""
    outcomes: list[ItemOutcome[R]] = []
    for item, key in zip(items, keys, strict=True):
        if cancelled.is_set():
            outcomes.append(ItemOutcome(key, error=CANCELLED, attempts=0))
            continue
        attempt = 0
        while True:
            attempt += 1
            t0 = time.perf_counter()
            try:
                outcome: ItemOutcome[R] = ItemOutcome(key, fn(item), attempts=attempt)
            except Exception as exc:  # noqa: BLE001 - one failing item must not stop the batch
                if is_transient(exc) and attempt <= retries and not cancelled.is_set():
                    time.sleep(backoff_s * attempt)
                    continue
                outcome = ItemOutcome(key, error=describe(exc), attempts=attempt)
            outcome = ItemOutcome(
                outcome.key, outcome.value, outcome.error, attempt, time.perf_counter() - t0
            )
            break
        outcomes.append(outcome)
        if on_outcome is not None:
            on_outcome(outcome)
    return outcomes


def default_keys(items: Sequence[Any], keys: Sequence[str] | None) -> list[str]:
    """``keys`` checked against ``items``, or the items' positions."""
    if keys is None:
        return [str(i) for i in range(len(items))]
    if len(keys) != len(items):
        raise ValueError(f"{len(keys)} keys for {len(items)} items")
    return [str(k) for k in keys]


def progress_callback(progress: Progress | None, message: Callable[[ItemOutcome[Any]], str]) -> OnOutcome:
    """An :data:`OnOutcome` that advances ``progress`` by one with ``message(outcome)``."""
    sink = progress or NullProgress()

    def on_outcome(outcome: ItemOutcome[Any]) -> None:
        sink.advance(1, message(outcome))

    return on_outcome
