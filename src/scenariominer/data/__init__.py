"""Canonical log model, dataset adapters, preprocessing and the one ingestion loop.

The adapters pull in scipy and shapely, so they are imported on first attribute access
(``scenariominer.data.Av2Reader``) rather than with the package.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

from scenariominer.data.categories import (
    AV2_CATEGORIES,
    CATEGORY_GROUPS,
    canonical_category,
    expand_categories,
)
from scenariominer.data.log import STATE_FIELDS, Log, LogFormatError, build_log
from scenariominer.data.sources import InMemoryReader, LogReader, LogSource, discover_sources

if TYPE_CHECKING:
    from scenariominer.data.adapters.av2 import Av2Reader, read_av2_log, write_av2_log
    from scenariominer.data.adapters.av2.map import Av2Map, read_av2_map, write_av2_map
    from scenariominer.data.adapters.highd import HighDReader, write_highd_recording
    from scenariominer.data.adapters.tabular import TabularReader, write_tabular
    from scenariominer.data.preprocess import preprocess

_LAZY = {
    "Av2Reader": "scenariominer.data.adapters.av2",
    "read_av2_log": "scenariominer.data.adapters.av2",
    "write_av2_log": "scenariominer.data.adapters.av2",
    "Av2Map": "scenariominer.data.adapters.av2.map",
    "read_av2_map": "scenariominer.data.adapters.av2.map",
    "write_av2_map": "scenariominer.data.adapters.av2.map",
    "HighDReader": "scenariominer.data.adapters.highd",
    "write_highd_recording": "scenariominer.data.adapters.highd",
    "preprocess": "scenariominer.data.preprocess",
    "TabularReader": "scenariominer.data.adapters.tabular",
    "write_tabular": "scenariominer.data.adapters.tabular",
}


def __getattr__(name: str) -> Any:
    if name in _LAZY:
        return getattr(importlib.import_module(_LAZY[name]), name)
    raise AttributeError(f"module 'scenariominer.data' has no attribute {name!r}")


__all__ = [
    "AV2_CATEGORIES",
    "CATEGORY_GROUPS",
    "STATE_FIELDS",
    "Av2Map",
    "Av2Reader",
    "HighDReader",
    "InMemoryReader",
    "Log",
    "LogFormatError",
    "LogReader",
    "LogSource",
    "TabularReader",
    "build_log",
    "canonical_category",
    "discover_sources",
    "expand_categories",
    "preprocess",
    "read_av2_log",
    "read_av2_map",
    "write_av2_log",
    "write_av2_map",
    "write_highd_recording",
    "write_tabular",
]
