"""Trajectory representation (seed 001): windows, a trajectory autoencoder, clusters, projections.

* :mod:`.windows`: :func:`extract_windows` cuts a log into :class:`WindowSet` samples (one chosen
  agent and its K nearest road users, in the agent's frame, resampled, padded and masked).
* :mod:`.window_table`: windows as the store's corpus table ``represent_windows``.
* :mod:`.lanes`: lane ids where the data has them (highD ``laneId``, Argoverse 2 map lanes).
* :mod:`.pipeline`: incremental window building over a store.

Torch, hdbscan and scikit-learn are imported lazily inside the functions that need them.
"""

from scenariominer.represent.errors import (
    NoWindowsError,
    RepresentError,
    UnknownModelError,
    WindowConfigMismatchError,
)
from scenariominer.represent.windows import WindowSet, extract_windows, window_id

__all__ = [
    "NoWindowsError",
    "RepresentError",
    "UnknownModelError",
    "WindowConfigMismatchError",
    "WindowSet",
    "extract_windows",
    "window_id",
]
