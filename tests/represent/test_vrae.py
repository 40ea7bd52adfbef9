"""The Hausdorff loss on point sets with known distances, and the autoencoder as an estimator."""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest
import torch

from scenariominer.config.represent import RepresentConfig
from scenariominer.data.log import Log
from scenariominer.represent.errors import RepresentError, WindowConfigMismatchError
from scenariominer.represent.model_table import load_model, save_model
from scenariominer.represent.vrae import TrajectoryEmbedder, hausdorff_l1, masked_mse
from scenariominer.represent.windows import WindowSet, extract_windows
from scenariominer.store import ScenarioStore


def _t(points: list[tuple[float, float]]) -> torch.Tensor:
    return torch.tensor(points, dtype=torch.float64)


def test_hausdorff_under_l1_of_known_point_sets() -> None:
    a = _t([(0, 0), (1, 0), (2, 0)])
    b = _t([(0, 0), (1, 0), (2, 3)])
    ok = torch.ones(3, dtype=torch.bool)
    # a -> b: (2,0) is 1 from (1,0); b -> a: (2,3) is 3 from (2,0): the larger, 3, is the distance
    assert float(hausdorff_l1(a, b, ok)) == pytest.approx(3.0)
    assert float(hausdorff_l1(b, a, ok)) == pytest.approx(3.0)
    # L1, not Euclidean: (1,1) is 2 from the origin
    assert float(hausdorff_l1(_t([(0, 0)]), _t([(1, 1)]), torch.ones(1, dtype=torch.bool))) == pytest.approx(
        2.0
    )
    # a set distance: the order of the points does not matter
    assert float(hausdorff_l1(a, b.flip(0), ok)) == pytest.approx(hausdorff_l1(a, b, ok).item())


def test_masked_points_belong_to_neither_set() -> None:
    a = _t([(0, 0), (1, 0), (100, 100)])
    b = _t([(0, 0), (1, 0.5), (-50, 7)])
    mask = torch.tensor([True, True, False])
    assert float(hausdorff_l1(a, b, mask)) == pytest.approx(0.5)
    assert float(hausdorff_l1(a, b, torch.zeros(3, dtype=torch.bool))) == 0.0
    # batched: (..., S, D) with a different answer per row
    batch = hausdorff_l1(torch.stack([a, a]), torch.stack([b, a]), torch.stack([mask, mask]))
    assert batch.tolist() == pytest.approx([0.5, 0.0])


def test_hausdorff_loss_has_a_gradient_at_the_farthest_point() -> None:
    a = _t([(0, 0), (1, 0), (2, 0)])
    b = _t([(0, 0), (1, 0), (2, 3)]).requires_grad_(True)
    hausdorff_l1(a, b, torch.ones(3, dtype=torch.bool)).backward()
    assert b.grad is not None
    # only the point that sets the distance moves, towards a: d/dy of |3 - 0| is +1
    assert b.grad[2].tolist() == pytest.approx([0.0, 1.0])
    assert b.grad[:2].abs().sum().item() == 0.0


def test_masked_mse() -> None:
    a = _t([(0, 0), (1, 0), (5, 5)])
    b = _t([(0, 1), (1, 0), (0, 0)])
    assert float(masked_mse(a, b, torch.tensor([True, True, False]))) == pytest.approx(0.5)


@pytest.fixture
def windows(make_log: Callable[..., Log], tiny_config: RepresentConfig) -> WindowSet:
    """Windows of one cruising and one weaving log (72 windows of 4 agents x 8 steps)."""
    parts = [
        extract_windows(make_log(i, k), tiny_config.windows) for i, k in (("c", "cruise"), ("w", "weave"))
    ]
    return WindowSet.concat(parts)


@pytest.mark.parametrize("loss", ["hausdorff", "mse"])
def test_a_tiny_model_learns_and_is_deterministic(
    windows: WindowSet, tiny_config: RepresentConfig, loss: str
) -> None:
    cfg = dataclasses.replace(tiny_config.embedder, loss=loss, epochs=25)
    first = TrajectoryEmbedder(cfg).fit(windows)
    assert first.summary_ is not None
    history = first.summary_.reconstruction_history
    assert history[-1] < 0.7 * history[0]
    z = first.transform(windows)
    assert z.shape == (len(windows), cfg.latent_dim) and np.isfinite(z).all()
    again = TrajectoryEmbedder(cfg).fit(windows)
    np.testing.assert_array_equal(again.transform(windows), z)


def test_save_and_load_give_identical_embeddings(
    windows: WindowSet, tiny_config: RepresentConfig, tmp_path: Path
) -> None:
    est = TrajectoryEmbedder(tiny_config.embedder).fit(windows)
    restored = TrajectoryEmbedder.from_bytes(est.to_bytes())
    np.testing.assert_array_equal(restored.transform(windows), est.transform(windows))
    assert restored.data_hash_ == est.data_hash_ and restored.summary_ == est.summary_
    store = ScenarioStore.open(tmp_path / "store")
    model_id = save_model(store, est, tiny_config.windows)
    record, loaded = load_model(store)
    assert record.model_id == model_id and record.loss == "hausdorff" and record.n_windows == len(windows)
    assert record.windows() == tiny_config.windows
    np.testing.assert_array_equal(loaded.transform(windows), est.transform(windows))


def test_windows_of_other_settings_are_refused(windows: WindowSet, tiny_config: RepresentConfig) -> None:
    with pytest.raises(RepresentError, match="not fitted"):
        TrajectoryEmbedder(tiny_config.embedder).transform(windows)
    est = TrajectoryEmbedder(tiny_config.embedder).fit(windows.select([0, 1, 2]))
    other = WindowSet.empty(n_agents=2, n_steps=8)
    with pytest.raises(WindowConfigMismatchError, match="2 agents x 8 steps"):
        est.transform(other)
