"""Store-level stages after windowing: train, apply (embed + assign clusters), cluster, similar.

Each stage reads windows and embeddings from the store's corpus tables and writes its results back
per log, so that a new log only adds rows: ``apply`` embeds the windows of logs that have none for
the model yet (or whose windows changed) and assigns them to the model's latest clustering by
approximate prediction; everything already stored is left as it is.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from scenariominer.config.represent import ClusterConfig, RepresentConfig, WindowConfig
from scenariominer.progress import NullProgress, Progress, step
from scenariominer.represent.cluster import (
    ClusterLabels,
    approximate_labels,
    fit_clusters,
    labelled_logs,
    lane_changes_by_cluster,
    latest_clustering,
    load_clusterer,
    load_labels,
    save_clustering,
    save_labels,
)
from scenariominer.represent.errors import NoWindowsError
from scenariominer.represent.features import window_features
from scenariominer.represent.model_table import (
    ModelRecord,
    embedded_logs,
    load_embeddings,
    load_model,
    save_embeddings,
    save_model,
)
from scenariominer.represent.pipeline import build_store_windows
from scenariominer.represent.plots import tsne_projection, write_projection_plots
from scenariominer.represent.vrae import TrainingSummary, TrajectoryEmbedder
from scenariominer.represent.window_table import load_windows, log_window_records, window_config_hash
from scenariominer.store import ScenarioStore

__all__ = [
    "ApplyReport",
    "ClusterReport",
    "PlotReport",
    "TrainReport",
    "apply_store_embedder",
    "cluster_store",
    "plot_store",
    "current_window_logs",
    "stored_window_config",
    "train_store_embedder",
]


@dataclass(frozen=True)
class TrainReport:
    """Result of :func:`train_store_embedder`.

    Attributes:
        model: the stored model's record.
        summary: losses per epoch, windows, seconds.
        n_logs: logs whose windows were trained on.
        notes: what the user should know (too few windows to cluster).
    """

    model: ModelRecord
    summary: TrainingSummary
    n_logs: int
    notes: tuple[str, ...] = ()


@dataclass(frozen=True)
class ApplyReport:
    """Result of :func:`apply_store_embedder`.

    Attributes:
        model_id: the embedder used.
        n_logs_embedded: logs embedded in this run.
        n_windows_embedded: windows embedded in this run.
        clustering_id: the clustering new windows were assigned to ("" when the model has none).
        n_windows_assigned: windows given a cluster by approximate prediction in this run.
        n_assigned_noise: of those, how many fell outside every cluster (noise).
        skipped_logs: logs whose windows were cut with other settings than the model's.
        n_logs_cut: logs without windows that were cut in this run (with the model's settings).
        failed_logs: logs that could not be cut.
    """

    model_id: str
    n_logs_embedded: int
    n_windows_embedded: int
    clustering_id: str
    n_windows_assigned: int
    n_assigned_noise: int
    skipped_logs: tuple[str, ...]
    n_logs_cut: int = 0
    failed_logs: tuple[str, ...] = ()


@dataclass(frozen=True)
class ClusterReport:
    """Result of :func:`cluster_store`.

    Attributes:
        clustering_id: the stored clustering.
        model_id: the embedder whose embeddings were clustered.
        n_windows: windows clustered.
        n_clusters: clusters found.
        n_noise: windows labelled noise (outliers).
        sizes: windows per cluster, cluster 0 first.
        n_with_lanes: windows whose chosen agent has lane ids (lane changes can be told).
        lane_change_by_cluster: lane-change windows (the chosen agent's lane id changes) per
            cluster, cluster 0 first.
        lane_change_noise: lane-change windows labelled noise.
    """

    clustering_id: str
    model_id: str
    n_windows: int
    n_clusters: int
    n_noise: int
    sizes: tuple[int, ...]
    n_with_lanes: int = 0
    lane_change_by_cluster: tuple[int, ...] = ()
    lane_change_noise: int = 0

    @property
    def n_lane_change(self) -> int:
        """Lane-change windows among the clustered ones."""
        return sum(self.lane_change_by_cluster) + self.lane_change_noise


def current_window_logs(
    store: ScenarioStore, window_config: str, log_ids: Sequence[str] | None = None
) -> list[str]:
    """Logs with at least one window cut with the settings hashed as ``window_config``."""
    ids = list(log_ids) if log_ids is not None else store.log_ids()
    recs = log_window_records(store, ids)
    return [lid for lid in ids if lid in recs and recs[lid].config == window_config and recs[lid].window_ids]


def stored_window_config(
    store: ScenarioStore, preferred: WindowConfig, log_ids: Sequence[str] | None = None
) -> WindowConfig:
    """The window settings to train on: ``preferred`` if windows were cut with it, else the only ones.

    Raises:
        NoWindowsError: no windows at all, or windows of several settings none of which is ``preferred``.
    """
    ids = list(log_ids) if log_ids is not None else store.log_ids()
    recs = [r for r in log_window_records(store, ids).values() if r.window_ids]
    by_hash = {r.config: r for r in recs}
    if not by_hash:
        raise NoWindowsError("no windows in the store; run scenariominer embed windows")
    wanted = window_config_hash(preferred)
    if wanted in by_hash:
        return preferred
    if len(by_hash) == 1:
        return next(iter(by_hash.values())).window_config()
    raise NoWindowsError(
        f"the store holds windows of {len(by_hash)} different settings and none matches [represent.windows]; "
        "re-cut them with one setting (scenariominer embed windows --rebuild)"
    )


def train_store_embedder(
    store: ScenarioStore,
    config: RepresentConfig,
    *,
    log_ids: Sequence[str] | None = None,
    progress: Progress | None = None,
) -> TrainReport:
    """Train an embedder on the stored windows, store it and the windows' embeddings.

    The windows are those cut with ``config.windows``, or, when none were, with the one setting
    the store's windows share (:func:`stored_window_config`).

    Raises:
        NoWindowsError: no windows, or windows of several settings none of which is configured.
    """
    window_config = stored_window_config(store, config.windows, log_ids)
    logs = current_window_logs(store, window_config_hash(window_config), log_ids)
    windows = load_windows(store, log_ids=logs)
    embedder = TrajectoryEmbedder(config.embedder).fit(windows, progress)
    model_id = save_model(store, embedder, window_config)
    save_embeddings(store, model_id, windows.log_ids, windows.window_ids, embedder.transform(windows))
    record, _ = load_model(store, model_id)
    assert embedder.summary_ is not None
    notes: tuple[str, ...] = ()
    if len(windows.window_ids) < config.cluster.min_cluster_size:
        notes = (
            f"only {len(windows.window_ids)} windows: too few for the model to generalise, and fewer than "
            f"represent.cluster.min_cluster_size ({config.cluster.min_cluster_size}), so `embed cluster` "
            "cannot run; ingest and cut more logs (embed windows), then train again",
        )
    return TrainReport(record, embedder.summary_, len(logs), notes)


def apply_store_embedder(
    store: ScenarioStore,
    *,
    model_id: str | None = None,
    loss: str | None = None,
    log_ids: Sequence[str] | None = None,
    progress: Progress | None = None,
) -> ApplyReport:
    """Embed windows that have no embedding under the model yet, and assign them to its clusters.

    Logs without any windows yet are cut first with the model's window settings, so a newly
    ingested log needs this one call; logs whose windows were cut with other settings are skipped.
    """
    progress = progress or NullProgress()
    record, embedder = load_model(store, model_id, loss)
    ids = list(log_ids) if log_ids is not None else store.log_ids()
    uncut = [lid for lid in ids if lid not in log_window_records(store, ids)]
    new_windows = (
        build_store_windows(store, record.windows(), log_ids=uncut, progress=progress) if uncut else None
    )
    recs = log_window_records(store, ids)
    usable = current_window_logs(store, record.window_config, ids)
    skipped = tuple(lid for lid in ids if lid in recs and recs[lid].config != record.window_config)
    done = embedded_logs(store, record.model_id, usable)
    todo = [lid for lid in usable if set(done.get(lid, ())) != set(recs[lid].window_ids)]
    n_emb = 0
    with step(progress, "embedding windows", len(todo)):
        for start in range(0, len(todo), 64):
            chunk = todo[start : start + 64]
            windows = load_windows(store, log_ids=chunk)
            save_embeddings(
                store, record.model_id, windows.log_ids, windows.window_ids, embedder.transform(windows)
            )
            n_emb += len(windows)
            progress.advance(len(chunk))
    cid, n_assigned, n_noise = _assign_new(store, record.model_id, usable)
    return ApplyReport(
        model_id=record.model_id,
        n_logs_embedded=len(todo),
        n_windows_embedded=n_emb,
        clustering_id=cid,
        n_windows_assigned=n_assigned,
        n_assigned_noise=n_noise,
        skipped_logs=skipped,
        n_logs_cut=new_windows.n_built if new_windows else 0,
        failed_logs=tuple(r.log_id for r in new_windows.failed) if new_windows else (),
    )


def _assign_new(store: ScenarioStore, model_id: str, log_ids: Sequence[str]) -> tuple[str, int, int]:
    """Assign embedded windows without labels to the model's latest clustering (approximate predict)."""
    clustering = latest_clustering(store, model_id)
    if clustering is None:
        return "", 0, 0
    embedded = embedded_logs(store, model_id, log_ids)
    labelled = labelled_logs(store, clustering.clustering_id, list(embedded))
    todo = [lid for lid, wids in embedded.items() if set(labelled.get(lid, ())) != set(wids)]
    if not todo:
        return clustering.clustering_id, 0, 0
    _, clusterer = load_clusterer(store, clustering.clustering_id)
    wids, lids, z = load_embeddings(store, model_id, todo)
    labels, probs = approximate_labels(clusterer, z)
    method = np.full(wids.shape, "approximate", dtype=object).astype(str)
    save_labels(store, clustering.clustering_id, lids, ClusterLabels(wids, labels, probs, method))
    return clustering.clustering_id, int(wids.size), int((labels < 0).sum())


def cluster_store(
    store: ScenarioStore,
    config: ClusterConfig,
    *,
    model_id: str | None = None,
    loss: str | None = None,
    progress: Progress | None = None,
) -> ClusterReport:
    """Cluster every stored embedding of the model with HDBSCAN (re-clustering replaces the labels).

    Raises:
        UnknownModelError: no such model.
        NoWindowsError: too few embedded windows.
    """
    progress = progress or NullProgress()
    record, _ = load_model(store, model_id, loss)
    with step(progress, "clustering (HDBSCAN)", None):
        logs = current_window_logs(store, record.window_config)
        wids, lids, z = load_embeddings(store, record.model_id, logs)
        clusterer, labels, probs = fit_clusters(z, config)
        cid = save_clustering(store, record.model_id, config, clusterer, labels)
        method = np.full(wids.shape, "fit", dtype=object).astype(str)
        save_labels(store, cid, lids, ClusterLabels(wids, labels, probs, method))
    sizes = np.bincount(labels[labels >= 0]) if (labels >= 0).any() else np.zeros(0, dtype=np.int64)
    feats = window_features(load_windows(store, window_ids=wids.tolist()))
    known = np.isfinite(feats.lane_change)
    by_cluster, lc_noise = lane_changes_by_cluster(labels, feats.lane_change)
    return ClusterReport(
        clustering_id=cid,
        model_id=record.model_id,
        n_windows=int(labels.size),
        n_clusters=int(sizes.size),
        n_noise=int((labels < 0).sum()),
        sizes=tuple(int(v) for v in sizes),
        n_with_lanes=int(known.sum()),
        lane_change_by_cluster=tuple(int(v) for v in by_cluster),
        lane_change_noise=lc_noise,
    )


@dataclass(frozen=True)
class PlotReport:
    """Result of :func:`plot_store`.

    Attributes:
        model_id: the embedder.
        clustering_id: the clustering whose labels colour the plot ("" when none).
        n_windows: windows plotted.
        n_clusters: clusters among them.
        files: PNG files written.
    """

    model_id: str
    clustering_id: str
    n_windows: int
    n_clusters: int
    files: tuple[Path, ...]


def plot_store(
    store: ScenarioStore,
    config: ClusterConfig,
    out_dir: Path,
    *,
    model_id: str | None = None,
    loss: str | None = None,
    progress: Progress | None = None,
) -> PlotReport:
    """t-SNE projection of a model's embeddings as PNGs coloured by cluster and by scenario features."""
    progress = progress or NullProgress()
    record, _ = load_model(store, model_id, loss)
    logs = current_window_logs(store, record.window_config)
    wids, _lids, z = load_embeddings(store, record.model_id, logs)
    if wids.size == 0:
        raise NoWindowsError(f"no embeddings of model {record.model_id}; run scenariominer embed apply")
    clustering = latest_clustering(store, record.model_id)
    labels = np.full(wids.size, -1, dtype=np.int64)
    if clustering is not None:
        stored = load_labels(store, clustering.clustering_id, logs)
        pos = {w: i for i, w in enumerate(stored.window_ids.tolist())}
        have = np.asarray([pos.get(w, -1) for w in wids.tolist()], dtype=np.int64)
        labels = (
            np.where(have >= 0, stored.labels[np.clip(have, 0, None)], -1) if stored.labels.size else labels
        )
    windows = load_windows(store, window_ids=wids.tolist())
    with step(progress, "t-SNE projection", None):
        xy = tsne_projection(z, config)
    plots = write_projection_plots(
        xy, labels, window_features(windows), out_dir, f"{record.loss} ({record.model_id})"
    )
    files = (plots.clusters, *plots.features.values())
    return PlotReport(
        record.model_id,
        clustering.clustering_id if clustering else "",
        int(wids.size),
        int(np.unique(labels[labels >= 0]).size),
        files,
    )
