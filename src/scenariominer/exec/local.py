"""The two executors that need nothing beyond the standard library: in-process and a process pool."""

from __future__ import annotations

import multiprocessing
import os
import threading
import time
from collections import deque
from collections.abc import Callable, Sequence
from concurrent.futures import FIRST_COMPLETED, Future, ProcessPoolExecutor, wait
from concurrent.futures.process import BrokenProcessPool
from typing import Any, TypeVar

from scenariominer.exec.base import (
    CANCELLED,
    ItemOutcome,
    OnOutcome,
    default_keys,
    describe,
    is_transient,
    run_serially,
)

__all__ = ["InlineExecutor", "ProcessExecutor"]

T = TypeVar("T")
R = TypeVar("R")

#: How often the driver wakes up to look for cancellation while waiting on workers.
_POLL_S = 0.2


class InlineExecutor:
    """Runs every item in the calling process, one after the other (tests, debugging, tiny runs)."""

    name = "local"

    def __init__(self, *, retries: int = 2) -> None:
        self.retries = retries
        self._cancelled = threading.Event()

    @property
    def workers(self) -> int:
        """One item at a time."""
        return 1

    def map(
        self,
        fn: Callable[[T], R],
        items: Sequence[T],
        *,
        keys: Sequence[str] | None = None,
        on_outcome: OnOutcome | None = None,
        max_in_flight: int | None = None,
    ) -> list[ItemOutcome[R]]:
        """Run ``fn`` on each item in turn (see :class:`~scenariominer.exec.base.Executor`)."""
        self._cancelled.clear()
        names = default_keys(items, keys)
        return run_serially(
            fn, items, names, retries=self.retries, cancelled=self._cancelled, on_outcome=on_outcome
        )

    def cancel(self) -> None:
        """Skip the items not started yet."""
        self._cancelled.set()

    def close(self) -> None:
        """Nothing to release."""


def _start_method() -> multiprocessing.context.BaseContext:
    """``forkserver`` where available (workers start from a clean, small parent), else ``spawn``."""
    if "forkserver" in multiprocessing.get_all_start_methods():
        return multiprocessing.get_context("forkserver")
    return multiprocessing.get_context("spawn")


class ProcessExecutor:
    """A pool of local worker processes (the default executor).

    A worker that dies (killed, out of memory, a crash in native code) breaks the pool: the items
    that were running are counted as an attempt and resubmitted to a fresh pool, up to ``retries``
    more times each; items already finished keep their outcome.

    Args:
        workers: worker processes (0: every core).
        retries: extra attempts per item (worker death or a transient error).
        min_items: fewer items than this run in the calling process instead (no start-up cost).
    """

    name = "process"

    def __init__(self, workers: int = 0, *, retries: int = 2, min_items: int = 4) -> None:
        self._workers = workers or os.cpu_count() or 1
        self.retries = retries
        self.min_items = min_items
        self._cancelled = threading.Event()
        self._pool: ProcessPoolExecutor | None = None

    @property
    def workers(self) -> int:
        """Worker processes."""
        return self._workers

    def worker_pids(self) -> list[int]:
        """Process ids of the current pool's workers (empty when no pool is running)."""
        processes = getattr(self._pool, "_processes", None) or {}
        return [p.pid for p in processes.values() if p.pid is not None]

    def map(
        self,
        fn: Callable[[T], R],
        items: Sequence[T],
        *,
        keys: Sequence[str] | None = None,
        on_outcome: OnOutcome | None = None,
        max_in_flight: int | None = None,
    ) -> list[ItemOutcome[R]]:
        """Run ``fn`` on the items in the pool (see :class:`~scenariominer.exec.base.Executor`)."""
        self._cancelled.clear()
        names = default_keys(items, keys)
        if len(items) < self.min_items:
            return run_serially(
                fn, items, names, retries=self.retries, cancelled=self._cancelled, on_outcome=on_outcome
            )
        try:
            return self._map_pool(fn, items, names, on_outcome, max_in_flight or self._workers)
        except KeyboardInterrupt:
            self.cancel()
            self.close()
            raise

    def _map_pool(
        self,
        fn: Callable[[T], R],
        items: Sequence[T],
        names: list[str],
        on_outcome: OnOutcome | None,
        limit: int,
    ) -> list[ItemOutcome[R]]:
        outcomes: list[ItemOutcome[R] | None] = [None] * len(items)
        attempts = [0] * len(items)
        started: dict[int, float] = {}
        pending: deque[int] = deque(range(len(items)))
        running: dict[Future[Any], int] = {}

        def finish(i: int, outcome: ItemOutcome[R]) -> None:
            outcomes[i] = outcome
            if on_outcome is not None:
                on_outcome(outcome)

        while pending or running:
            if self._cancelled.is_set():
                for fut in running:
                    fut.cancel()
                break
            pool = self._ensure_pool()
            while pending and len(running) < limit:
                i = pending.popleft()
                try:
                    future = pool.submit(fn, items[i])
                except BrokenProcessPool:  # a worker died between two rounds: start a fresh pool
                    pending.appendleft(i)
                    self.close()
                    pool = self._ensure_pool()
                    continue
                attempts[i] += 1
                started[i] = time.perf_counter()
                running[future] = i
            done, _ = wait(list(running), timeout=_POLL_S, return_when=FIRST_COMPLETED)
            broken = False
            for fut in done:
                i = running.pop(fut)
                seconds = time.perf_counter() - started[i]
                try:
                    value = fut.result()
                except BrokenProcessPool:
                    broken = True
                    if attempts[i] <= self.retries:
                        pending.appendleft(i)
                    else:
                        error = f"WorkerDied: a worker process died {attempts[i]} times running this item"
                        finish(i, ItemOutcome(names[i], error=error, attempts=attempts[i], seconds=seconds))
                except Exception as exc:  # noqa: BLE001 - one failing item must not stop the batch
                    if is_transient(exc) and attempts[i] <= self.retries:
                        pending.append(i)
                    else:
                        finish(
                            i,
                            ItemOutcome(names[i], error=describe(exc), attempts=attempts[i], seconds=seconds),
                        )
                else:
                    finish(i, ItemOutcome(names[i], value, attempts=attempts[i], seconds=seconds))
            if broken:
                self.close()  # a fresh pool is started on the next round
        return [
            o if o is not None else ItemOutcome(names[i], error=CANCELLED, attempts=attempts[i])
            for i, o in enumerate(outcomes)
        ]

    def _ensure_pool(self) -> ProcessPoolExecutor:
        if self._pool is None:
            self._pool = ProcessPoolExecutor(max_workers=self._workers, mp_context=_start_method())
        return self._pool

    def cancel(self) -> None:
        """Stop submitting; running items are abandoned when the pool is closed."""
        self._cancelled.set()

    def close(self) -> None:
        """Shut the pool down (workers of a broken pool are already gone)."""
        pool, self._pool = self._pool, None
        if pool is not None:
            pool.shutdown(wait=True, cancel_futures=True)
