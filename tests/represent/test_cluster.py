"""HDBSCAN clusters, approximate assignment of new windows, and a store extended log by log."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest

from scenariominer.config.represent import ClusterConfig, RepresentConfig
from scenariominer.represent.cluster import (
    CLUSTER_LABELS_TABLE,
    approximate_labels,
    fit_clusters,
    lane_changes_by_cluster,
    latest_clustering,
    load_labels,
)
from scenariominer.represent.errors import NoWindowsError
from scenariominer.represent.features import window_features
from scenariominer.represent.model_table import EMBEDDINGS_TABLE
from scenariominer.represent.pipeline import build_store_windows
from scenariominer.represent.stages import (
    apply_store_embedder,
    cluster_store,
    plot_store,
    train_store_embedder,
)
from scenariominer.represent.window_table import WINDOWS_TABLE, load_windows
from scenariominer.store import ScenarioStore


def _blobs(n: int, seed: int) -> np.ndarray:
    """Three tight groups of ``n`` points around (0,0), (10,0) and (0,10) in 2-D."""
    rng = np.random.default_rng(seed)
    centres = np.asarray([[0.0, 0.0], [10.0, 0.0], [0.0, 10.0]])
    return np.concatenate([c + 0.3 * rng.standard_normal((n, 2)) for c in centres]).astype(np.float32)


def test_hdbscan_finds_groups_and_places_new_points_without_refitting() -> None:
    z = _blobs(20, seed=0)
    clusterer, labels, probs = fit_clusters(z, ClusterConfig(min_cluster_size=5))
    assert len(set(labels.tolist()) - {-1}) == 3
    assert ((probs >= 0) & (probs <= 1)).all()
    group_label = [
        int(np.bincount(labels[i * 20 : (i + 1) * 20][labels[i * 20 : (i + 1) * 20] >= 0]).argmax())
        for i in range(3)
    ]
    new = np.asarray([[0.1, -0.1], [9.9, 0.2], [0.2, 10.1], [50.0, 50.0]], dtype=np.float32)
    new_labels, new_probs = approximate_labels(clusterer, new)
    assert new_labels[:3].tolist() == group_label
    assert new_labels[3] == -1  # far from every group: an outlier
    assert new_probs[3] == 0.0


def test_too_few_windows_to_cluster_is_a_clear_error() -> None:
    with pytest.raises(NoWindowsError, match="min_cluster_size"):
        fit_clusters(_blobs(1, 0), ClusterConfig(min_cluster_size=10))


def test_features_of_hand_built_windows(tiny_store: ScenarioStore, tiny_config: RepresentConfig) -> None:
    build_store_windows(tiny_store, tiny_config.windows)
    ws = load_windows(tiny_store, log_ids=["cruise-a"])
    f = window_features(ws)
    ego = ws.agent_ids == "ego"
    np.testing.assert_allclose(f.mean_speed_mps[ego], 25.0, atol=0.05)
    np.testing.assert_allclose(f.longitudinal_velocity_change_mps2[ego], 0.0, atol=0.05)
    assert (f.n_road_users == 4).all()
    assert np.isnan(f.lane_change).all() and np.isnan(f.n_lanes).all()  # no lane ids in built logs
    weave = window_features(load_windows(tiny_store, log_ids=["weave-a"]))
    assert weave.lateral_velocity_change_mps2.max() > 0.5 > f.lateral_velocity_change_mps2.max()


def test_adding_a_log_extends_windows_embeddings_and_clusters_without_recomputing(
    tiny_store: ScenarioStore,
    tiny_config: RepresentConfig,
    make_log: Callable[..., object],
    add_to_store: Callable[..., None],
    tmp_path: Path,
) -> None:
    store = tiny_store
    build_store_windows(store, tiny_config.windows)
    trained = train_store_embedder(store, tiny_config)
    model_id = trained.model.model_id
    clustered = cluster_store(store, tiny_config.cluster, model_id=model_id)
    assert clustered.n_windows == 72
    versions = {
        name: {r.key: r.version for r in store.corpus(name).rows()}
        for name in (WINDOWS_TABLE, EMBEDDINGS_TABLE, CLUSTER_LABELS_TABLE)
    }
    labels_before = load_labels(store, clustered.clustering_id, ["cruise-a", "weave-a"])

    add_to_store(store, make_log("cruise-b", "cruise", speed_mps=24.0))
    applied = apply_store_embedder(store, model_id=model_id)  # cuts, embeds and assigns the new log
    assert applied.n_logs_cut == 1
    assert (applied.n_logs_embedded, applied.n_windows_embedded) == (1, 36)
    windows = build_store_windows(store, tiny_config.windows)
    assert {r.status for r in windows.logs} == {"current"}
    assert applied.clustering_id == clustered.clustering_id and applied.n_windows_assigned == 36

    for name, before in versions.items():
        after = {r.key: r.version for r in store.corpus(name).rows()}
        kept = {k: v for k, v in after.items() if "cruise-b" not in k}
        assert kept == before, f"{name}: rows of the old logs were rewritten"
        assert any("cruise-b" in k for k in after), f"{name}: nothing stored for the new log"
    # the old labels stand; the new windows carry approximate labels of the same clustering
    assert latest_clustering(store, model_id) is not None
    again = load_labels(store, clustered.clustering_id, ["cruise-a", "weave-a"])
    np.testing.assert_array_equal(again.labels, labels_before.labels)
    new = load_labels(store, clustered.clustering_id, ["cruise-b"])
    assert set(new.method.tolist()) == {"approximate"} and new.window_ids.size == 36
    # a second apply has nothing left to do
    assert apply_store_embedder(store, model_id=model_id).n_windows_embedded == 0

    plots = plot_store(store, tiny_config.cluster, tmp_path / "plots", model_id=model_id)
    assert plots.n_windows == 108
    assert sorted(p.name for p in plots.files)[:2] == ["clusters.png", "lane_change.png"]
    assert all(p.stat().st_size > 1000 for p in plots.files)


def test_lane_changes_are_counted_per_cluster_and_in_the_noise() -> None:
    labels = np.asarray([0, 0, 1, 1, 1, -1, -1, 2])
    lane_change = np.asarray([1.0, 0.0, 1.0, 1.0, np.nan, 1.0, 0.0, 0.0])
    per, noise = lane_changes_by_cluster(labels, lane_change)
    assert per.tolist() == [1, 2, 0]
    assert noise == 1
