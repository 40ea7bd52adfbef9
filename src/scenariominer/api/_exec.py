"""The executor a use case runs on: the caller's, or the configured one (closed afterwards)."""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from typing import TYPE_CHECKING

from scenariominer.config import Config

if TYPE_CHECKING:
    from scenariominer.exec import Executor

__all__ = ["executor_for"]


@contextmanager
def executor_for(config: Config, executor: Executor | None) -> Iterator[Executor]:
    """``executor`` as given (the caller closes it), else one built from ``config.exec`` and closed here."""
    if executor is not None:
        yield executor
        return
    from scenariominer.exec import make_executor

    made = make_executor(config.exec)
    try:
        yield made
    finally:
        made.close()
