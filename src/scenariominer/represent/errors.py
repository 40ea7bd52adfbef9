"""Errors of the representation stage (windows, embedder, clusters); all derive from the root error."""

from __future__ import annotations

from scenariominer import errors as _errors

__all__ = ["NoWindowsError", "RepresentError", "UnknownModelError", "WindowConfigMismatchError"]


class RepresentError(_errors.ScenarioMinerError):
    """A windowing, embedding or clustering step cannot run; the message names the cause."""


class NoWindowsError(RepresentError, ValueError):
    """There are no windows to work on (none built yet, or none matched the selection)."""


class WindowConfigMismatchError(RepresentError, ValueError):
    """Windows built with different settings (steps, neighbours) were about to be mixed."""


class UnknownModelError(RepresentError, KeyError):
    """No trained embedder (or clustering) is stored under the requested id."""

    def __str__(self) -> str:
        return str(self.args[0]) if self.args else "unknown model"
