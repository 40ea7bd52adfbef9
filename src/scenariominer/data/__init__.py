"""Canonical log model, dataset adapters, preprocessing and the synthetic generator."""

from scenariominer.data.categories import AV2_CATEGORIES, CATEGORY_GROUPS, canonical_category
from scenariominer.data.log import STATE_FIELDS, Log, LogFormatError, build_log
from scenariominer.data.preprocess import preprocess

__all__ = [
    "AV2_CATEGORIES",
    "CATEGORY_GROUPS",
    "STATE_FIELDS",
    "Log",
    "LogFormatError",
    "build_log",
    "canonical_category",
    "preprocess",
]
