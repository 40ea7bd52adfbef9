"""Canonical log model, dataset adapters, preprocessing and the synthetic generator.

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
    from scenariominer.data.av2 import Av2Reader, read_av2_log, write_av2_log
    from scenariominer.data.av2_map import Av2Map, read_av2_map, write_av2_map
    from scenariominer.data.highd import HighDReader, write_highd_recording
    from scenariominer.data.preprocess import preprocess
    from scenariominer.data.synth import ScenarioCategory, ScenarioLabel, generate, read_labels
    from scenariominer.data.tabular import TabularReader, write_tabular

_LAZY = {
    "Av2Reader": "av2",
    "read_av2_log": "av2",
    "write_av2_log": "av2",
    "Av2Map": "av2_map",
    "read_av2_map": "av2_map",
    "write_av2_map": "av2_map",
    "HighDReader": "highd",
    "write_highd_recording": "highd",
    "preprocess": "preprocess",
    "ScenarioCategory": "synth",
    "ScenarioLabel": "synth",
    "generate": "synth",
    "read_labels": "synth",
    "TabularReader": "tabular",
    "write_tabular": "tabular",
}


def __getattr__(name: str) -> Any:
    if name in _LAZY:
        return getattr(importlib.import_module(f"scenariominer.data.{_LAZY[name]}"), name)
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
    "ScenarioCategory",
    "ScenarioLabel",
    "TabularReader",
    "build_log",
    "canonical_category",
    "discover_sources",
    "expand_categories",
    "generate",
    "preprocess",
    "read_av2_log",
    "read_av2_map",
    "read_labels",
    "write_av2_log",
    "write_av2_map",
    "write_highd_recording",
    "write_tabular",
]
