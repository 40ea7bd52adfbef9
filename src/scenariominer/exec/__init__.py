"""Executors: how corpus-wide stages spread their per-item work (see :mod:`scenariominer.exec.base`).

``local`` runs in this process, ``process`` in a pool of local worker processes (the default),
``ray`` as tasks on a Ray cluster. Stages take an :class:`Executor` and never start a pool
themselves; :func:`make_executor` builds the configured one::

    from scenariominer.exec import make_executor
    executor = make_executor(config.exec)             # or make_executor(config.exec, "ray")
    outcomes = executor.map(task, log_ids, keys=log_ids)
"""

from __future__ import annotations

from scenariominer.config.exec import EXECUTORS, ExecConfig
from scenariominer.errors import ExecutorError
from scenariominer.exec.base import (
    CANCELLED,
    Executor,
    ItemOutcome,
    OnOutcome,
    is_transient,
    progress_callback,
)
from scenariominer.exec.local import InlineExecutor, ProcessExecutor

__all__ = [
    "CANCELLED",
    "EXECUTORS",
    "Executor",
    "InlineExecutor",
    "ItemOutcome",
    "OnOutcome",
    "ProcessExecutor",
    "is_transient",
    "make_executor",
    "progress_callback",
]


def make_executor(
    config: ExecConfig | None = None, name: str | None = None, *, ray_address: str | None = None
) -> Executor:
    """The executor named by ``name`` (default ``config.executor``), set up from ``config``.

    Raises:
        ExecutorError: an unknown name, or Ray cannot be started or joined.
        MissingExtraError: ``ray`` without the ``ray`` extra installed.
    """
    cfg = config or ExecConfig()
    which = name or cfg.executor
    if which == "local":
        return InlineExecutor(retries=cfg.retries)
    if which == "process":
        return ProcessExecutor(cfg.workers, retries=cfg.retries, min_items=cfg.min_items)
    if which == "ray":
        from scenariominer.exec.ray_executor import RayExecutor

        address = cfg.ray_address if ray_address is None else ray_address
        return RayExecutor(address, cfg.workers, retries=cfg.retries)
    raise ExecutorError(f"unknown executor {which!r}: use one of {', '.join(EXECUTORS)}")
