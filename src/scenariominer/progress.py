"""Progress reporting: stages report through a small Protocol; the CLI renders it (cli/progress.py)."""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from typing import Protocol


class Progress(Protocol):
    """Receives progress of a long step (a bar in the CLI, nothing in library use)."""

    def start(self, description: str, total: int | None) -> None:
        """Begin a step with ``total`` units of work (None when unknown)."""
        ...

    def advance(self, n: int = 1, message: str | None = None) -> None:
        """Mark ``n`` more units done, optionally with a status message."""
        ...

    def finish(self) -> None:
        """End the current step."""
        ...


class NullProgress:
    """Progress sink that ignores everything (the default outside the CLI)."""

    def start(self, description: str, total: int | None) -> None:
        """Ignore."""

    def advance(self, n: int = 1, message: str | None = None) -> None:
        """Ignore."""

    def finish(self) -> None:
        """Ignore."""


@contextmanager
def step(progress: Progress, description: str, total: int | None) -> Iterator[Progress]:
    """Context manager around :meth:`Progress.start` / :meth:`Progress.finish`."""
    progress.start(description, total)
    try:
        yield progress
    finally:
        progress.finish()
