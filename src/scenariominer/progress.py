"""Progress reporting: stages report through a small Protocol; the CLI renders it with Rich."""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from typing import TYPE_CHECKING, Protocol

if TYPE_CHECKING:
    from rich.progress import TaskID


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


class RichProgress:
    """A Rich progress bar on stderr; one bar per step."""

    def __init__(self, transient: bool = False) -> None:
        from rich.console import Console
        from rich.progress import (
            BarColumn,
            MofNCompleteColumn,
            SpinnerColumn,
            TextColumn,
            TimeElapsedColumn,
            TimeRemainingColumn,
        )
        from rich.progress import Progress as _RichProgress

        self._progress = _RichProgress(
            SpinnerColumn(),
            TextColumn("[bold]{task.description}"),
            BarColumn(),
            MofNCompleteColumn(),
            TimeElapsedColumn(),
            TimeRemainingColumn(),
            TextColumn("{task.fields[message]}"),
            console=Console(stderr=True),
            transient=transient,
        )
        self._task: TaskID | None = None

    def start(self, description: str, total: int | None) -> None:
        """Open a new bar."""
        if self._task is None and not self._progress.live.is_started:
            self._progress.start()
        self._task = self._progress.add_task(description, total=total, message="")

    def advance(self, n: int = 1, message: str | None = None) -> None:
        """Advance the current bar."""
        if self._task is not None:
            self._progress.update(self._task, advance=n, message=message or "")

    def finish(self) -> None:
        """Complete the current bar."""
        if self._task is not None:
            task = self._progress.tasks[-1]
            if task.total is not None:
                self._progress.update(self._task, completed=task.total)
            self._task = None

    def close(self) -> None:
        """Stop rendering."""
        self._progress.stop()


@contextmanager
def step(progress: Progress, description: str, total: int | None) -> Iterator[Progress]:
    """Context manager around :meth:`Progress.start` / :meth:`Progress.finish`."""
    progress.start(description, total)
    try:
        yield progress
    finally:
        progress.finish()
