"""Canonical log model, dataset adapters, preprocessing and the synthetic generator."""

from scenariominer.data.av2 import Av2Reader, read_av2_log, write_av2_log
from scenariominer.data.av2_map import Av2Map, read_av2_map, write_av2_map
from scenariominer.data.categories import (
    AV2_CATEGORIES,
    CATEGORY_GROUPS,
    canonical_category,
    expand_categories,
)
from scenariominer.data.highd import HighDReader, write_highd_recording
from scenariominer.data.log import STATE_FIELDS, Log, LogFormatError, build_log
from scenariominer.data.preprocess import preprocess
from scenariominer.data.sources import InMemoryReader, LogReader, LogSource, discover_sources
from scenariominer.data.synth import ScenarioCategory, ScenarioLabel, generate, read_labels
from scenariominer.data.tabular import TabularReader, write_tabular

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
