"""A fake clock: code that waits (retry back-off, polling) runs instantly and the waits are recorded."""

from __future__ import annotations

__all__ = ["FakeClock"]


class FakeClock:
    """``time()`` and ``sleep()`` over a virtual time that only :meth:`sleep` and :meth:`advance` move.

    Example:
        >>> clock = FakeClock()
        >>> clock.sleep(0.5); clock.sleep(1.0)
        >>> clock.sleeps, clock.time()
        ([0.5, 1.0], 1.5)
    """

    def __init__(self, start_s: float = 0.0) -> None:
        self._now = float(start_s)
        self.sleeps: list[float] = []

    def time(self) -> float:
        """The virtual time, seconds."""
        return self._now

    def sleep(self, seconds: float) -> None:
        """Record the wait and move the virtual time on; returns at once."""
        if seconds < 0:
            raise ValueError(f"sleep length must be non-negative, got {seconds}")
        self.sleeps.append(float(seconds))
        self._now += float(seconds)

    def advance(self, seconds: float) -> None:
        """Move the virtual time on without recording a wait."""
        self._now += float(seconds)
