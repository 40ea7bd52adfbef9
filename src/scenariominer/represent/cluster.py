"""HDBSCAN clusters of window embeddings (section 3.2), kept in the store, extended without refitting.

:func:`fit_clusters` runs HDBSCAN (the ``hdbscan`` package, ``prediction_data=True``) on a model's
embeddings; noise (label -1) is kept: those windows are the outliers. :func:`assign_clusters` gives
new windows a cluster of an existing clustering with ``hdbscan.approximate_predict`` (as the
density estimate of the fit would place them) until the user clusters again.

Store tables (schema 1):

* ``represent_clusterings``, key ``<model id>|hdbscan-<settings hash 6>``: JSON ``model_id``,
  ``min_cluster_size``, ``min_samples``, ``n_clusters``, ``n_noise``, ``n_windows``, ``created_at``;
  blob: the pickled fitted clusterer (this store's own artefact, read back only by this code).
* ``represent_cluster_labels``, key ``<clustering id>|<log id>``: JSON ``window_ids``, ``labels``,
  ``probabilities`` and ``method`` (``fit`` for windows of the fit, ``approximate`` for windows
  assigned later), per window.
"""

from __future__ import annotations

import hashlib
import pickle
from collections.abc import Sequence
from dataclasses import dataclass
from datetime import UTC, datetime
from typing import Any

import numpy as np
from numpy.typing import NDArray

from scenariominer._optional import require
from scenariominer.config.represent import ClusterConfig
from scenariominer.represent.errors import NoWindowsError, UnknownModelError
from scenariominer.store import ScenarioStore

__all__ = [
    "CLUSTERINGS_TABLE",
    "CLUSTER_LABELS_TABLE",
    "ClusterLabels",
    "ClusteringRecord",
    "approximate_labels",
    "fit_clusters",
    "lane_changes_by_cluster",
    "labelled_logs",
    "latest_clustering",
    "load_clusterer",
    "load_labels",
    "save_clustering",
    "save_labels",
]

CLUSTERINGS_TABLE = "represent_clusterings"
CLUSTER_LABELS_TABLE = "represent_cluster_labels"
SCHEMA = 1


def _hdbscan() -> Any:
    return require(
        "hdbscan", extra="represent", purpose="clustering window embeddings (scenariominer embed cluster)"
    )


@dataclass(frozen=True)
class ClusterLabels:
    """Cluster labels of windows.

    Attributes:
        window_ids: ``(W,)`` str.
        labels: ``(W,)`` int64 cluster index, -1 for noise (outliers).
        probabilities: ``(W,)`` float64 membership strength in ``[0, 1]``.
        method: ``(W,)`` str, ``fit`` or ``approximate``.
    """

    window_ids: NDArray[np.str_]
    labels: NDArray[np.int64]
    probabilities: NDArray[np.float64]
    method: NDArray[np.str_]

    @property
    def n_clusters(self) -> int:
        """Distinct clusters among the labels (noise not counted)."""
        return int(np.unique(self.labels[self.labels >= 0]).size)


@dataclass(frozen=True)
class ClusteringRecord:
    """A stored clustering's description.

    Attributes:
        clustering_id: its key.
        model_id: the embedder whose embeddings were clustered.
        n_clusters: clusters found by the fit.
        n_noise: windows of the fit labelled noise.
        n_windows: windows of the fit.
        created_at: ISO time (UTC).
    """

    clustering_id: str
    model_id: str
    n_clusters: int
    n_noise: int
    n_windows: int
    created_at: str


def fit_clusters(
    z: NDArray[np.float32], config: ClusterConfig
) -> tuple[Any, NDArray[np.int64], NDArray[np.float64]]:
    """Run HDBSCAN on embeddings ``z`` ``(W, D)``: the fitted clusterer, labels and probabilities.

    Raises:
        NoWindowsError: fewer windows than ``min_cluster_size``.
    """
    if z.shape[0] < config.min_cluster_size:
        raise NoWindowsError(
            f"{z.shape[0]} embedded windows are fewer than represent.cluster.min_cluster_size "
            f"({config.min_cluster_size}); embed more windows or lower it"
        )
    hdbscan = _hdbscan()
    clusterer = hdbscan.HDBSCAN(
        min_cluster_size=config.min_cluster_size,
        min_samples=config.min_samples or None,
        cluster_selection_method=config.selection,
        prediction_data=True,
    )
    clusterer.fit(np.asarray(z, dtype=np.float64))
    return (
        clusterer,
        np.asarray(clusterer.labels_, dtype=np.int64),
        np.asarray(clusterer.probabilities_, dtype=np.float64),
    )


def lane_changes_by_cluster(
    labels: NDArray[np.int64], lane_change: NDArray[np.float64]
) -> tuple[NDArray[np.int64], int]:
    """Lane-change windows per cluster (cluster 0 first) and among the noise.

    Args:
        labels: ``(W,)`` cluster labels, -1 noise.
        lane_change: ``(W,)`` 1.0 lane change, 0.0 none, NaN unknown.
    """
    change = np.isfinite(lane_change) & (np.nan_to_num(lane_change) > 0.5)
    n = int(labels.max(initial=-1)) + 1
    per = np.bincount(labels[change & (labels >= 0)], minlength=n).astype(np.int64)
    return per, int((change & (labels < 0)).sum())


def approximate_labels(
    clusterer: Any, z: NDArray[np.float32]
) -> tuple[NDArray[np.int64], NDArray[np.float64]]:
    """Labels and probabilities of new embeddings ``z`` under a fitted clusterer (no refit)."""
    if z.shape[0] == 0 or int(np.max(clusterer.labels_, initial=-1)) < 0:
        return np.full(z.shape[0], -1, dtype=np.int64), np.zeros(z.shape[0])
    labels, probs = _hdbscan().approximate_predict(clusterer, np.asarray(z, dtype=np.float64))
    return np.asarray(labels, dtype=np.int64), np.asarray(probs, dtype=np.float64)


# ------------------------------------------------------------------------------------------ store


def clustering_id_for(model_id: str, config: ClusterConfig) -> str:
    """Key of a clustering of ``model_id``'s embeddings with ``config``."""
    text = f"{config.min_cluster_size}/{config.min_samples}/{config.selection}"
    return f"{model_id}|hdbscan-{hashlib.sha256(text.encode()).hexdigest()[:6]}"


def save_clustering(
    store: ScenarioStore, model_id: str, config: ClusterConfig, clusterer: Any, labels: NDArray[np.int64]
) -> str:
    """Store a fitted clusterer; returns its clustering id."""
    cid = clustering_id_for(model_id, config)
    row = {
        "model_id": model_id,
        "min_cluster_size": config.min_cluster_size,
        "min_samples": config.min_samples,
        "selection": config.selection,
        "n_clusters": int(np.unique(labels[labels >= 0]).size),
        "n_noise": int((labels < 0).sum()),
        "n_windows": int(labels.size),
        "created_at": datetime.now(UTC).isoformat(),
    }
    store.corpus(CLUSTERINGS_TABLE, SCHEMA).upsert({cid: row}, {cid: pickle.dumps(clusterer)})
    return cid


def _clustering_record(key: str, d: Any) -> ClusteringRecord:
    return ClusteringRecord(
        key,
        str(d["model_id"]),
        int(d["n_clusters"]),
        int(d["n_noise"]),
        int(d["n_windows"]),
        str(d["created_at"]),
    )


def latest_clustering(store: ScenarioStore, model_id: str) -> ClusteringRecord | None:
    """The most recent clustering of ``model_id``'s embeddings, if any."""
    rows = [r for r in store.corpus(CLUSTERINGS_TABLE, SCHEMA).rows() if r.data.get("model_id") == model_id]
    if not rows:
        return None
    best = max(rows, key=lambda r: str(r.data["created_at"]))
    return _clustering_record(best.key, best.data)


def load_clusterer(store: ScenarioStore, clustering_id: str) -> tuple[ClusteringRecord, Any]:
    """A stored clustering and its fitted clusterer.

    Raises:
        UnknownModelError: no such clustering.
    """
    row = store.corpus(CLUSTERINGS_TABLE, SCHEMA).get(clustering_id)
    if row is None or row.blob is None:
        raise UnknownModelError(
            f"no clustering {clustering_id!r} in the store; run scenariominer embed cluster"
        )
    _hdbscan()  # the pickle refers to hdbscan's classes
    return _clustering_record(row.key, row.data), pickle.loads(row.blob)  # noqa: S301 (our own artefact)


def save_labels(
    store: ScenarioStore, clustering_id: str, log_ids: NDArray[np.str_], labels: ClusterLabels
) -> None:
    """Store labels of windows (from ``log_ids``), one row per log (replacing that log's row)."""
    rows: dict[str, dict[str, object]] = {}
    for log_id in sorted(set(log_ids.tolist())):
        sel = np.flatnonzero(log_ids == log_id)
        rows[f"{clustering_id}|{log_id}"] = {
            "window_ids": labels.window_ids[sel].tolist(),
            "labels": labels.labels[sel].tolist(),
            "probabilities": labels.probabilities[sel].tolist(),
            "method": labels.method[sel].tolist(),
        }
    if rows:
        store.corpus(CLUSTER_LABELS_TABLE, SCHEMA).upsert(rows)


def labelled_logs(
    store: ScenarioStore, clustering_id: str, log_ids: Sequence[str]
) -> dict[str, tuple[str, ...]]:
    """For each of ``log_ids`` with labels under ``clustering_id``: its labelled window ids."""
    rows = store.corpus(CLUSTER_LABELS_TABLE, SCHEMA).rows([f"{clustering_id}|{lid}" for lid in log_ids])
    return {r.key.rsplit("|", 1)[1]: tuple(r.data["window_ids"]) for r in rows}


def load_labels(store: ScenarioStore, clustering_id: str, log_ids: Sequence[str]) -> ClusterLabels:
    """Labels of the windows of ``log_ids`` under ``clustering_id``, sorted by window id."""
    rows = store.corpus(CLUSTER_LABELS_TABLE, SCHEMA).rows([f"{clustering_id}|{lid}" for lid in log_ids])
    wids = np.asarray([w for r in rows for w in r.data["window_ids"]], dtype=str)
    order = np.argsort(wids, kind="stable")
    return ClusterLabels(
        window_ids=wids[order],
        labels=np.asarray([v for r in rows for v in r.data["labels"]], dtype=np.int64)[order],
        probabilities=np.asarray([v for r in rows for v in r.data["probabilities"]], dtype=np.float64)[order],
        method=np.asarray([v for r in rows for v in r.data["method"]], dtype=str)[order],
    )
