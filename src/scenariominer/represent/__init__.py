"""Trajectory representation (seed 001): windows, a trajectory autoencoder, clusters, projections.

* :mod:`.windows`: :func:`extract_windows` cuts a log into :class:`WindowSet` samples (one chosen
  agent and its K nearest road users, in the agent's frame, resampled, padded and masked).
* :mod:`.window_table`: windows as the store's corpus table ``represent_windows``.
* :mod:`.lanes`: lane ids where the data has them (highD ``laneId``, Argoverse 2 map lanes).
* :mod:`.pipeline`: incremental window building over a store.
* :mod:`.vrae`: :class:`~.vrae.TrajectoryEmbedder`, the variational recurrent autoencoder with a
  Hausdorff (L1) or MSE loss; :mod:`.model_table`: models and embeddings in the store.
* :mod:`.cluster`: HDBSCAN clusters, approximate assignment of new windows, their store tables.
* :mod:`.features`, :mod:`.plots`: scenario features and t-SNE projection PNGs.
* :mod:`.stages`: train, apply, cluster and plot over a store; :mod:`.similar`: query by example.

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
