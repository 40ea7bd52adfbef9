"""Dataset adapters and their registry.

An adapter is a :class:`~scenariominer.data.sources.LogReader` (``format``, ``discover``, ``read``).
The registry maps a format name to ``"module:attribute"`` and imports an adapter only when it is
used, so a command that reads only Argoverse 2 data never imports the highD or tabular code.
Third-party packages add adapters through the entry-point group ``scenariominer.adapters``
(``name = "package.module:ReaderClass"``); :func:`register_adapter` does the same at run time.
Discovery tries the adapters in registration order, most specific first.
"""

from __future__ import annotations

import importlib
from importlib.metadata import entry_points

from scenariominer.errors import DataError

__all__ = ["ENTRY_POINT_GROUP", "adapter_names", "load_adapter", "register_adapter"]

#: Entry-point group through which other packages register adapters.
ENTRY_POINT_GROUP = "scenariominer.adapters"

_BUILT_IN: dict[str, str] = {
    "av2": "scenariominer.data.adapters.av2.logs:Av2Reader",
    "highd": "scenariominer.data.adapters.highd.reader:HighDReader",
    "tabular": "scenariominer.data.adapters.tabular:TabularReader",
}
_registry: dict[str, str] = dict(_BUILT_IN)
_entry_points_loaded = False


def register_adapter(name: str, target: str) -> None:
    """Register (or replace) the adapter ``name`` as ``"module:ReaderClass"`` (imported when used)."""
    if ":" not in target:
        raise ValueError(f"adapter target must be 'module:attribute', got {target!r}")
    _registry[name] = target


def adapter_names() -> list[str]:
    """Registered format names, built-in ones first, then those of installed plug-ins."""
    _load_entry_points()
    return list(_registry)


def load_adapter(name: str) -> object:
    """A new instance of the adapter registered as ``name``.

    Raises:
        DataError: no adapter has that name, or its module cannot be imported.
    """
    _load_entry_points()
    target = _registry.get(name)
    if target is None:
        raise DataError(f"no adapter for format {name!r}; known formats: {', '.join(_registry)}")
    module_name, _, attr = target.partition(":")
    try:
        cls = getattr(importlib.import_module(module_name), attr)
    except (ImportError, AttributeError) as exc:
        raise DataError(f"adapter {name!r} ({target}) cannot be loaded: {exc}") from None
    return cls()


def _load_entry_points() -> None:
    global _entry_points_loaded
    if _entry_points_loaded:
        return
    _entry_points_loaded = True
    for ep in entry_points(group=ENTRY_POINT_GROUP):
        _registry.setdefault(ep.name, ep.value)
