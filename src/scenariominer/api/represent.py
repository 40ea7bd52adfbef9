"""Use cases of the trajectory representation (seed 001): windows, embedder, clusters, similar.

Each function takes a store, a typed request and the configuration, calls the stage in
:mod:`scenariominer.represent` and returns its typed result. Nothing here prints.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from scenariominer.api._exec import executor_for
from scenariominer.config import Config
from scenariominer.progress import Progress
from scenariominer.represent.pipeline import WindowsReport, build_store_windows
from scenariominer.represent.similar import SimilarResult, similar_windows
from scenariominer.represent.stages import (
    ApplyReport,
    ClusterReport,
    PlotReport,
    TrainReport,
    apply_store_embedder,
    cluster_store,
    plot_store,
    train_store_embedder,
)
from scenariominer.store import ScenarioStore

if TYPE_CHECKING:
    from scenariominer.exec import Executor

__all__ = [
    "ApplyRequest",
    "ClusterRequest",
    "PlotRequest",
    "SimilarRequest",
    "TrainRequest",
    "WindowsRequest",
    "apply_embedder",
    "build_windows",
    "cluster_windows",
    "plot_embeddings",
    "similar",
    "train_embedder",
]


@dataclass(frozen=True)
class WindowsRequest:
    """Which logs to cut into windows and how (``None`` fields keep ``[represent.windows]``).

    Attributes:
        log_ids: only these logs (``None``: every log in the store).
        lengths_s: window lengths, seconds (multi-scale when several).
        overlap: fraction of a window shared with the next one of the same agent.
        agents: ``ego`` or ``vehicles``.
        rebuild: re-cut logs whose stored windows are current.
    """

    log_ids: Sequence[str] | None = None
    lengths_s: Sequence[float] | None = None
    overlap: float | None = None
    agents: str | None = None
    rebuild: bool = False


def window_config(request: WindowsRequest, config: Config) -> Config:
    """``config`` with the request's window settings applied (validated by the config section)."""
    changes: dict[str, object] = {}
    if request.lengths_s is not None:
        changes["lengths_s"] = tuple(float(v) for v in request.lengths_s)
    if request.overlap is not None:
        changes["overlap"] = float(request.overlap)
    if request.agents is not None:
        changes["agents"] = request.agents
    if not changes:
        return config
    from scenariominer.config import ConfigError

    try:
        windows = dataclasses.replace(config.represent.windows, **changes)  # type: ignore[arg-type]
    except ValueError as exc:
        raise ConfigError(str(exc)) from None
    return dataclasses.replace(config, represent=dataclasses.replace(config.represent, windows=windows))


def build_windows(
    store: ScenarioStore,
    request: WindowsRequest,
    config: Config,
    progress: Progress | None = None,
    executor: Executor | None = None,
) -> WindowsReport:
    """Cut stored logs into windows (only logs whose windows are missing or stale, unless rebuilding).

    Logs are loaded and cut on ``executor`` (default: ``config.exec``).

    Raises:
        ConfigError: invalid window settings in the request.
    """
    cfg = window_config(request, config)
    with executor_for(config, executor) as runner:
        return build_store_windows(
            store,
            cfg.represent.windows,
            log_ids=request.log_ids,
            rebuild=request.rebuild,
            progress=progress,
            executor=runner,
        )


def _replace_section(config: Config, section: str, **changes: object) -> Config:
    """``config`` with fields of ``[represent.<section>]`` replaced (``None`` values are ignored)."""
    from scenariominer.config import ConfigError

    changes = {k: v for k, v in changes.items() if v is not None}
    if not changes:
        return config
    try:
        new = dataclasses.replace(getattr(config.represent, section), **changes)
    except (TypeError, ValueError) as exc:
        raise ConfigError(str(exc)) from None
    return dataclasses.replace(config, represent=dataclasses.replace(config.represent, **{section: new}))


@dataclass(frozen=True)
class TrainRequest:
    """How to train an embedder (``None`` fields keep ``[represent.embedder]``).

    Attributes:
        loss: ``hausdorff`` or ``mse``.
        epochs: passes over the windows.
        seed: training seed.
        log_ids: train on the windows of these logs only (``None``: every log with current windows).
    """

    loss: str | None = None
    epochs: int | None = None
    seed: int | None = None
    log_ids: Sequence[str] | None = None


def train_embedder(
    store: ScenarioStore, request: TrainRequest, config: Config, progress: Progress | None = None
) -> TrainReport:
    """Train the trajectory autoencoder on stored windows; store the model and the windows' embeddings.

    Raises:
        ConfigError: invalid settings in the request.
        NoWindowsError: no windows cut with the current window settings.
    """
    cfg = _replace_section(config, "embedder", loss=request.loss, epochs=request.epochs, seed=request.seed)
    return train_store_embedder(store, cfg.represent, log_ids=request.log_ids, progress=progress)


@dataclass(frozen=True)
class ApplyRequest:
    """Which model to apply (default: the most recently trained, with ``loss`` if given)."""

    model_id: str | None = None
    loss: str | None = None


def apply_embedder(
    store: ScenarioStore, request: ApplyRequest, config: Config, progress: Progress | None = None
) -> ApplyReport:
    """Embed windows of logs not yet embedded by the model (no retraining) and assign them to its clusters.

    Raises:
        UnknownModelError: no such model.
    """
    return apply_store_embedder(store, model_id=request.model_id, loss=request.loss, progress=progress)


@dataclass(frozen=True)
class ClusterRequest:
    """Which model's embeddings to cluster, with optional HDBSCAN overrides of ``[represent.cluster]``."""

    model_id: str | None = None
    loss: str | None = None
    min_cluster_size: int | None = None
    min_samples: int | None = None
    selection: str | None = None


def cluster_windows(
    store: ScenarioStore, request: ClusterRequest, config: Config, progress: Progress | None = None
) -> ClusterReport:
    """Cluster every stored embedding of the model with HDBSCAN (replaces earlier labels of these settings).

    Raises:
        ConfigError: invalid settings in the request.
        UnknownModelError: no such model.
        NoWindowsError: too few embedded windows.
    """
    cfg = _replace_section(
        config,
        "cluster",
        min_cluster_size=request.min_cluster_size,
        min_samples=request.min_samples,
        selection=request.selection,
    )
    return cluster_store(
        store, cfg.represent.cluster, model_id=request.model_id, loss=request.loss, progress=progress
    )


@dataclass(frozen=True)
class PlotRequest:
    """Where to write the projection PNGs and for which model."""

    out_dir: Path
    model_id: str | None = None
    loss: str | None = None


def plot_embeddings(
    store: ScenarioStore, request: PlotRequest, config: Config, progress: Progress | None = None
) -> PlotReport:
    """Write t-SNE projections of the model's embeddings coloured by cluster and scenario features.

    Raises:
        UnknownModelError: no such model.
        NoWindowsError: nothing embedded.
    """
    return plot_store(
        store,
        config.represent.cluster,
        request.out_dir,
        model_id=request.model_id,
        loss=request.loss,
        progress=progress,
    )


@dataclass(frozen=True)
class SimilarRequest:
    """A query by example: the agent ``track_id`` of ``log_id`` around ``t_s`` seconds after the log start."""

    log_id: str
    track_id: str
    t_s: float
    k: int = 10
    model_id: str | None = None


def similar(store: ScenarioStore, request: SimilarRequest, config: Config) -> SimilarResult:
    """The stored windows nearest in embedding space to the query window.

    Raises:
        UnknownModelError: no model.
        NoWindowsError: the agent has no window there, or nothing is embedded.
        UnknownLogError: the log is not in the store.
    """
    if request.k < 1:
        from scenariominer.config import ConfigError

        raise ConfigError(f"k must be at least 1, got {request.k}")
    return similar_windows(
        store,
        request.log_id,
        request.track_id,
        request.t_s,
        k=request.k,
        model_id=request.model_id,
    )
