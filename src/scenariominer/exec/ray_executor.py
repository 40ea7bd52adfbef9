"""The Ray executor: the same stages as tasks on a Ray cluster (``pip install 'scenariominer[ray]'``).

Each item becomes one Ray task running the stage's function; the function itself is put in the
object store once and shared by all tasks. Ray retries a task whose worker died (``max_retries``)
and :meth:`RayExecutor.map` resubmits one that raised a transient error. Workers must see the same store
root and input paths as the driver (a shared file system) and have scenariominer installed (the
cluster's image, or a ``runtime_env``).
"""

from __future__ import annotations

import threading
import time
from collections import deque
from collections.abc import Callable, Sequence
from typing import Any, TypeVar

from scenariominer._optional import require
from scenariominer.errors import ExecutorError
from scenariominer.exec.base import CANCELLED, ItemOutcome, OnOutcome, default_keys, describe, is_transient

__all__ = ["RayExecutor"]

T = TypeVar("T")
R = TypeVar("R")

_POLL_S = 0.2


def _call(fn: Callable[[Any], Any], item: Any) -> Any:
    """The one remote function: apply the stage's function to one item on a worker."""
    return fn(item)


class RayExecutor:
    """Tasks on a Ray cluster.

    Args:
        address: ``auto``, ``HOST:PORT`` or ``ray://HOST:PORT`` of an existing cluster; empty starts
            a private local cluster with ``workers`` CPUs (tests, one machine).
        workers: tasks running at once (0: every CPU of the cluster).
        retries: extra attempts of a task whose worker died or that raised a transient error.
        init_kwargs: passed on to ``ray.init`` (e.g. ``runtime_env``).
    """

    name = "ray"

    def __init__(
        self,
        address: str = "",
        workers: int = 0,
        *,
        retries: int = 2,
        init_kwargs: dict[str, Any] | None = None,
    ) -> None:
        self._ray = require("ray", extra="ray", purpose="running stages on a Ray cluster (--executor ray)")
        self.retries = retries
        self._cancelled = threading.Event()
        if not self._ray.is_initialized():
            kwargs: dict[str, Any] = {"include_dashboard": False, "log_to_driver": False}
            kwargs.update(init_kwargs or {})
            try:
                if address:
                    self._ray.init(address=address, **kwargs)
                else:
                    cpus = {"num_cpus": workers} if workers else {}
                    self._ray.init(**cpus, **kwargs)
            except (ConnectionError, RuntimeError, ValueError) as exc:
                where = address or "a local cluster"
                raise ExecutorError(f"cannot start or join Ray at {where}: {exc}") from exc
        total = int(self._ray.cluster_resources().get("CPU", 1))
        self._workers = workers or max(1, total)
        # Ray re-runs a task whose worker died (max_retries); transient errors are retried by map().
        self._remote = self._ray.remote(num_cpus=1, max_retries=retries)(_call)

    @property
    def workers(self) -> int:
        """Tasks running at once."""
        return self._workers

    def map(
        self,
        fn: Callable[[T], R],
        items: Sequence[T],
        *,
        keys: Sequence[str] | None = None,
        on_outcome: OnOutcome | None = None,
        max_in_flight: int | None = None,
    ) -> list[ItemOutcome[R]]:
        """Run ``fn`` on the items as Ray tasks (see :class:`~scenariominer.exec.base.Executor`)."""
        ray = self._ray
        self._cancelled.clear()
        names = default_keys(items, keys)
        limit = max_in_flight or self._workers
        fn_ref = ray.put(fn)
        outcomes: list[ItemOutcome[R] | None] = [None] * len(items)
        started: dict[int, float] = {}
        attempts = [0] * len(items)
        running: dict[Any, int] = {}
        queue: deque[int] = deque(range(len(items)))
        try:
            while True:
                while queue and len(running) < limit and not self._cancelled.is_set():
                    i = queue.popleft()
                    attempts[i] += 1
                    started[i] = time.perf_counter()
                    running[self._remote.remote(fn_ref, items[i])] = i
                if not running:
                    break
                if self._cancelled.is_set():
                    for ref in running:
                        ray.cancel(ref, force=True)
                    break
                done, _ = ray.wait(list(running), num_returns=1, timeout=_POLL_S)
                for ref in done:
                    i = running.pop(ref)
                    seconds = time.perf_counter() - started[i]
                    try:
                        value = ray.get(ref)
                    except Exception as exc:  # noqa: BLE001 - one failing item must not stop the batch
                        if _transient(exc) and attempts[i] <= self.retries:
                            queue.append(i)
                            continue
                        error = _ray_error(exc)
                        outcome: ItemOutcome[R] = ItemOutcome(
                            names[i], error=error, attempts=attempts[i], seconds=seconds
                        )
                    else:
                        outcome = ItemOutcome(names[i], value, attempts=attempts[i], seconds=seconds)
                    outcomes[i] = outcome
                    if on_outcome is not None:
                        on_outcome(outcome)
        except KeyboardInterrupt:
            for ref in running:
                ray.cancel(ref, force=True)
            raise
        return [
            o if o is not None else ItemOutcome(names[i], error=CANCELLED, attempts=attempts[i])
            for i, o in enumerate(outcomes)
        ]

    def cancel(self) -> None:
        """Stop submitting and cancel the running tasks."""
        self._cancelled.set()

    def close(self) -> None:
        """Leave the cluster running (it belongs to the user); nothing to release here."""


def _transient(exc: BaseException) -> bool:
    """Whether the user's exception inside a Ray task error is worth retrying."""
    cause = getattr(exc, "cause", None)
    return isinstance(cause, BaseException) and is_transient(cause)


def _ray_error(exc: BaseException) -> str:
    """The user's exception inside a Ray task error (Ray wraps it), else Ray's own failure."""
    cause = getattr(exc, "cause", None)
    if isinstance(cause, BaseException):
        return describe(cause)
    first = str(exc).strip().splitlines()
    return f"{type(exc).__name__}: {first[0] if first else ''}".rstrip(": ")
