"""Work-item functions with injected faults, for testing executors (picklable: they run in workers).

Each keeps its state in files under a folder, so a fault happens once across processes and
retries: :class:`FailOnce` raises a transient error the first time it sees an item,
:class:`DieOnce` kills its own worker process the first time it sees one given item.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

from scenariominer.errors import TransientError

__all__ = ["DieOnce", "FailOnce", "Square"]


def _first_time(folder: str, item: object) -> bool:
    """True the first time ``item`` is seen under ``folder`` (an exclusive file creation)."""
    try:
        Path(folder, f"seen-{item}").touch(exist_ok=False)
    except FileExistsError:
        return False
    return True


@dataclass(frozen=True)
class Square:
    """``item ** 2``; raises ``ValueError`` for the items in ``bad`` (a permanent failure)."""

    bad: tuple[int, ...] = ()

    def __call__(self, item: int) -> int:
        """Square the item or fail for a bad one."""
        if item in self.bad:
            raise ValueError(f"item {item} is bad")
        return item * item


@dataclass(frozen=True)
class FailOnce:
    """``item ** 2`` after raising :class:`TransientError` on the first attempt of every item."""

    folder: str

    def __call__(self, item: int) -> int:
        """Fail transiently once per item, then succeed."""
        if _first_time(self.folder, item):
            raise TransientError(f"item {item}: busy, try again")
        return item * item


@dataclass(frozen=True)
class DieOnce:
    """``item ** 2``; the first attempt at ``victim`` kills the worker process (``os._exit``)."""

    folder: str
    victim: int

    def __call__(self, item: int) -> int:
        """Kill this process on the victim's first attempt; square otherwise."""
        if item == self.victim and _first_time(self.folder, item):
            os._exit(17)
        return item * item
