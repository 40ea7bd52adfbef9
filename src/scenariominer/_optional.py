"""Lazy import of optional extras, with the command that installs them."""

from __future__ import annotations

import importlib
from types import ModuleType

from scenariominer.errors import MissingExtraError

__all__ = ["require"]


def require(module: str, *, extra: str, purpose: str) -> ModuleType:
    """Import ``module``, or raise :class:`MissingExtraError` with the ``pip install`` command."""
    try:
        return importlib.import_module(module)
    except ImportError as exc:
        raise MissingExtraError(module, extra, purpose) from exc
