"""Hand-built traffic for the representation tests: straight cruising and lane changes, a tiny model."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest

from scenariominer.config.represent import ClusterConfig, EmbedderConfig, RepresentConfig, WindowConfig
from scenariominer.data.log import Log
from scenariominer.store import ScenarioStore
from scenariominer.testing import LogBuilder, times

#: Short windows with overlap so that a 20 s log of 4 vehicles gives 36 windows.
TINY_WINDOWS = WindowConfig(lengths_s=(4.0,), overlap=0.5, n_steps=8, k_neighbours=3, agents="vehicles")
#: A network small enough to train in well under a second per epoch on tiny data.
TINY_EMBEDDER = EmbedderConfig(
    latent_dim=4, hidden_dim=8, attention_heads=2, epochs=3, batch_size=16, threads=1, position_scale_m=20.0
)
TINY = RepresentConfig(
    windows=TINY_WINDOWS,
    embedder=TINY_EMBEDDER,
    cluster=ClusterConfig(min_cluster_size=4, tsne_perplexity=5.0),
)


def lane_change_y(
    t_s: np.ndarray, start_s: float, width_m: float = 3.5, duration_s: float = 4.0
) -> np.ndarray:
    """Lateral position of a half-cosine lane change to the left starting at ``start_s``."""
    u = np.clip((t_s - start_s) / duration_s, 0.0, 1.0)
    return width_m * 0.5 * (1.0 - np.cos(np.pi * u))


def traffic_log(log_id: str, kind: str, speed_mps: float = 25.0) -> Log:
    """20 s of three-lane highway: ``cruise`` (everyone keeps lane) or ``weave`` (lane changes every 4 s)."""
    t = times(20.0)
    b = LogBuilder(t, log_id=log_id, dataset="synthetic")
    if kind == "cruise":
        b.ego(speed_mps=speed_mps)
        b.add("v1", "REGULAR_VEHICLE", speed_mps=speed_mps, x0_m=30.0)
        b.add("v2", "TRUCK", speed_mps=speed_mps - 3.0, x0_m=10.0, y0_m=3.5)
        b.add("v3", "REGULAR_VEHICLE", speed_mps=speed_mps + 2.0, x0_m=-20.0, y0_m=-3.5)
        return b.build()
    weave = sum(lane_change_y(t, s) * (-1) ** i for i, s in enumerate((1.0, 5.0, 9.0, 13.0)))
    x = speed_mps * t
    b.add_path("ego", "EGO_VEHICLE", x, weave, np.arctan2(np.gradient(weave), np.gradient(x)), length_m=4.8)
    for name, dx, dy in (("v1", 30.0, 0.0), ("v2", 10.0, 3.5), ("v3", -20.0, -3.5)):
        y = dy - weave
        b.add_path(name, "REGULAR_VEHICLE", x + dx, y, np.arctan2(np.gradient(y), np.gradient(x)))
    return b.build()


def put_logs(store: ScenarioStore, *logs: Log) -> None:
    """Store hand-built logs, one source each."""
    for log in logs:
        store.replace_source(f"src-{log.log_id}", "h1", [log.replace(source_hash="h1")])


@pytest.fixture
def make_log() -> Callable[..., Log]:
    """:func:`traffic_log`."""
    return traffic_log


@pytest.fixture
def tiny_store(tmp_path: Path) -> ScenarioStore:
    """A store with one cruising and one weaving log."""
    store = ScenarioStore.open(tmp_path / "store")
    put_logs(store, traffic_log("cruise-a", "cruise"), traffic_log("weave-a", "weave"))
    return store


@pytest.fixture
def tiny_config() -> RepresentConfig:
    """Tiny windows, network and clustering settings (:data:`TINY`)."""
    return TINY


@pytest.fixture
def add_to_store() -> Callable[..., None]:
    """:func:`put_logs`."""
    return put_logs
