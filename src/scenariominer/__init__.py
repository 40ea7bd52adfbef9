"""scenariominer: turn recorded driving logs into a searchable, explainable scenario database.

The programmatic entry points live in :mod:`scenariominer.api`; the ``scenariominer`` command is a
thin layer over them. Submodules are imported lazily, so ``import scenariominer`` is cheap.
"""

__version__ = "0.1.0"

__all__ = ["__version__"]
