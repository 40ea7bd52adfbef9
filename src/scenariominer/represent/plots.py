"""t-SNE projections of window embeddings, coloured by cluster and by scenario features (Fig. 2-3).

The projection (scikit-learn's t-SNE) is computed apart from the drawing; drawing uses Matplotlib's
object API with the Agg canvas (no pyplot state, no backend switch at import).
"""

from __future__ import annotations

import textwrap
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from scenariominer._optional import require
from scenariominer.config.represent import ClusterConfig
from scenariominer.represent.features import FEATURE_LABELS, WindowFeatures

__all__ = ["ProjectionPlots", "tsne_projection", "write_projection_plots"]


@dataclass(frozen=True)
class ProjectionPlots:
    """PNG files written by :func:`write_projection_plots`.

    Attributes:
        clusters: the projection coloured by cluster (noise grey).
        features: feature name → its PNG.
    """

    clusters: Path
    features: dict[str, Path]


def tsne_projection(z: NDArray[np.float32], config: ClusterConfig) -> NDArray[np.float64]:
    """``(W, 2)`` t-SNE layout of embeddings ``z`` ``(W, D)`` (perplexity capped below ``W / 3``)."""
    if z.shape[0] < 3:
        return np.zeros((z.shape[0], 2))
    manifold = require("sklearn.manifold", extra="represent", purpose="t-SNE projections (embed plot)")
    perplexity = float(min(config.tsne_perplexity, max(1.0, (z.shape[0] - 1) / 3.0)))
    tsne = manifold.TSNE(n_components=2, perplexity=perplexity, init="pca", random_state=config.seed)
    return np.asarray(tsne.fit_transform(np.asarray(z, dtype=np.float64)), dtype=np.float64)


def _figure(title: str) -> tuple[Any, Any]:
    figure_mod = require("matplotlib.figure", extra="represent", purpose="embedding plots (embed plot)")
    fig = figure_mod.Figure(figsize=(7.0, 6.0), dpi=110)
    ax = fig.add_subplot(1, 1, 1)
    ax.set_title(textwrap.fill(title, 70), fontsize=9)  # long model ids would run off the figure
    ax.set_xticks([])
    ax.set_yticks([])
    return fig, ax


def _save(fig: Any, path: Path) -> Path:
    agg = require(
        "matplotlib.backends.backend_agg", extra="represent", purpose="embedding plots (embed plot)"
    )
    agg.FigureCanvasAgg(fig)
    fig.tight_layout()
    fig.savefig(path)
    return path


def write_projection_plots(
    xy: NDArray[np.float64],
    labels: NDArray[np.int64],
    features: WindowFeatures,
    out_dir: Path,
    title: str,
) -> ProjectionPlots:
    """Write ``clusters.png`` and one ``<feature>.png`` per feature of the projection ``xy`` ``(W, 2)``."""
    out_dir.mkdir(parents=True, exist_ok=True)
    n_clusters = int(np.unique(labels[labels >= 0]).size)
    fig, ax = _figure(f"{title}: {n_clusters} HDBSCAN clusters, {int((labels < 0).sum())} noise")
    noise = labels < 0
    ax.scatter(xy[noise, 0], xy[noise, 1], s=4, c="lightgrey", label="noise")
    if n_clusters:
        ax.scatter(xy[~noise, 0], xy[~noise, 1], s=5, c=labels[~noise], cmap="tab20")
    clusters = _save(fig, out_dir / "clusters.png")
    paths: dict[str, Path] = {}
    for name, values in features.as_dict().items():
        fig, ax = _figure(f"{title}: {FEATURE_LABELS[name]}")
        known = np.isfinite(values)
        ax.scatter(xy[~known, 0], xy[~known, 1], s=4, c="lightgrey")
        if known.any():
            sc = ax.scatter(xy[known, 0], xy[known, 1], s=5, c=values[known], cmap="viridis")
            fig.colorbar(sc, ax=ax)
        paths[name] = _save(fig, out_dir / f"{name}.png")
    return ProjectionPlots(clusters, paths)
