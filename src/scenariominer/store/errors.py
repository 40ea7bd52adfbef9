"""Errors of the scenario store (the StoreError family)."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from scenariominer import errors as _errors


class StoreError(_errors.StoreError):
    """Base class of every error raised by the store."""


class NotAStoreError(StoreError):
    """A directory cannot be opened as a store; the message names the path and the reason.

    Attributes:
        path: the directory that was to be opened.
        problem: one-line description of what is wrong.
    """

    def __init__(self, path: str | Path, problem: str) -> None:
        self.path = str(path)
        self.problem = problem
        super().__init__(f"{self.path}: {problem}")


class StoreVersionError(StoreError):
    """The store was written by a newer scenariominer with an unknown layout version."""


class UnknownLogError(StoreError, LookupError):
    """A log id is not in the store."""

    def __init__(self, log_id: str) -> None:
        self.log_id = log_id
        super().__init__(f"log {log_id!r} is not in the store")

    def __str__(self) -> str:
        return str(self.args[0])


class UnknownTableError(StoreError, LookupError):
    """A table name is not present in the store; the message lists the tables that are."""

    def __init__(self, name: str, available: Sequence[str]) -> None:
        self.name = name
        self.available = tuple(available)
        super().__init__(f"no table {name!r} in the store; available: {', '.join(self.available) or 'none'}")

    def __str__(self) -> str:
        return str(self.args[0])


class InvalidNameError(StoreError, ValueError):
    """A table name or log id cannot be used (the message says why)."""


class InvalidLogError(StoreError, ValueError):
    """A log cannot be stored without losing information (the message names the log and the cell)."""


class LogConflictError(StoreError, ValueError):
    """A source tried to write a log id that another source already owns."""


class QueryError(StoreError):
    """A SQL query failed; the message carries DuckDB's explanation and the available tables."""
