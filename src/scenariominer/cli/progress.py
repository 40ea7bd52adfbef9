"""A Rich progress bar on stderr that implements :class:`scenariominer.progress.Progress`."""

from __future__ import annotations

import contextlib
from collections.abc import Iterator
from typing import TYPE_CHECKING

from scenariominer.cli._common import settings
from scenariominer.cli.text import plain

if TYPE_CHECKING:
    from rich.progress import TaskID


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
            TextColumn("{task.description}", markup=False, style="bold"),
            BarColumn(),
            MofNCompleteColumn(),
            TimeElapsedColumn(),
            TimeRemainingColumn(),
            TextColumn("{task.fields[message]}", markup=False),
            console=Console(stderr=True, emoji=False),
            transient=transient,
        )
        self._task: TaskID | None = None

    def start(self, description: str, total: int | None) -> None:
        """Open a new bar."""
        if self._task is None and not self._progress.live.is_started:
            self._progress.start()
        self._task = self._progress.add_task(plain(description), total=total, message="")

    def advance(self, n: int = 1, message: str | None = None) -> None:
        """Advance the current bar (the message is shown as data: no markup, no control characters)."""
        if self._task is not None:
            self._progress.update(self._task, advance=n, message=plain(message or ""))

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


@contextlib.contextmanager
def progress_bar(enabled: bool = True) -> Iterator[RichProgress | None]:
    """A :class:`RichProgress` for the duration of a command (``None`` when disabled, e.g. ``--json``)."""
    bar = RichProgress() if enabled and not settings.quiet else None
    try:
        yield bar
    finally:
        if bar is not None:
            bar.close()
