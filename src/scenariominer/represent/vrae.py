"""Variational recurrent autoencoder of windows with a Hausdorff (L1) or MSE loss (section 3.1).

Network (PyTorch, CPU, imported lazily):

* **encoder**: at each of the ``S`` steps the window's ``A`` agents give ``(forward, left, valid)``
  (positions divided by ``position_scale_m`` forward and ``lateral_scale_m`` left), concatenated
  to ``3A`` inputs; an LSTM reads the steps, multi-head self-attention mixes its outputs across
  steps (with a residual), the mean over steps feeds two linear heads: the Gaussian latent's mean
  and log-variance;
* **decoder**: the latent sample, repeated at every step, drives an LSTM whose outputs a linear
  layer maps to ``2A`` positions per step;
* **loss**: reconstruction plus ``kl_weight`` times the KL divergence to a standard normal. The
  reconstruction is either the paper's **Hausdorff distance under L1** between each agent's input
  point set and its reconstructed point set (only the agent's valid steps, both ways; averaged over
  the agents present) or the **masked mean squared error** (the baseline).

:class:`TrajectoryEmbedder` follows the scikit-learn contract: ``fit(windows)``, ``transform``
(the latent means, ``(W, latent_dim)``), ``fit_transform``; ``to_bytes``/``from_bytes`` save and
restore it exactly. Training is deterministic on CPU for a given seed and thread count.
"""

from __future__ import annotations

import dataclasses
import hashlib
import io
import json
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from scenariominer._optional import require
from scenariominer.config.represent import EmbedderConfig
from scenariominer.progress import NullProgress, Progress, step
from scenariominer.represent.errors import NoWindowsError, RepresentError, WindowConfigMismatchError
from scenariominer.represent.windows import WindowSet

__all__ = ["TrainingSummary", "TrajectoryEmbedder", "hausdorff_l1", "masked_mse", "windows_data_hash"]

Float32Array = NDArray[np.float32]

#: Added to the distance of masked points so that they never win a minimum (scaled units).
_FAR = 1e6
#: Windows embedded per forward pass in :meth:`TrajectoryEmbedder.transform`.
_TRANSFORM_BATCH = 1024


def _torch() -> Any:
    return require("torch", extra="represent", purpose="the trajectory autoencoder (scenariominer embed)")


def hausdorff_l1(points: Any, recon: Any, valid: Any) -> Any:
    """Hausdorff distance under L1 between input and reconstructed point sets, per trajectory.

    Args:
        points: ``(..., S, D)`` tensor, the input trajectory's points.
        recon: ``(..., S, D)`` tensor, the reconstruction.
        valid: ``(..., S)`` bool tensor; only valid steps belong to either set.

    Returns:
        ``(...)`` tensor: ``max(sup_a inf_b |a - b|_1, sup_b inf_a |a - b|_1)`` over the valid
        points; 0 for a trajectory without valid points.
    """
    torch = _torch()
    d = (points.unsqueeze(-2) - recon.unsqueeze(-3)).abs().sum(-1)  # (..., S_in, S_rec)
    row_ok = valid.unsqueeze(-1)
    col_ok = valid.unsqueeze(-2)
    far = torch.where(row_ok & col_ok, d, d + _FAR)
    zero = torch.zeros((), dtype=d.dtype)
    in_to_rec = torch.where(valid, far.min(dim=-1).values, zero).max(dim=-1).values
    rec_to_in = torch.where(valid, far.min(dim=-2).values, zero).max(dim=-1).values
    return torch.maximum(in_to_rec, rec_to_in)


def masked_mse(points: Any, recon: Any, valid: Any) -> Any:
    """Mean squared error over the valid steps of each trajectory (``(..., S, D)`` → ``(...)``)."""
    torch = _torch()
    sq = ((points - recon) ** 2).sum(-1)
    n = valid.sum(-1).clamp(min=1)
    return torch.where(valid, sq, torch.zeros((), dtype=sq.dtype)).sum(-1) / n


def windows_data_hash(windows: WindowSet) -> str:
    """16-hex-digit hash of the windows' ids, positions and masks (what a model was trained on)."""
    h = hashlib.sha256()
    order = np.argsort(windows.window_ids, kind="stable")
    h.update("\n".join(windows.window_ids[order].tolist()).encode())
    h.update(np.ascontiguousarray(windows.xy_m[order]).tobytes())
    h.update(np.ascontiguousarray(windows.valid[order]).tobytes())
    return h.hexdigest()[:16]


def _build_network(config: EmbedderConfig, n_agents: int, n_steps: int) -> Any:
    """The encoder-decoder module for windows of ``n_agents`` agents and ``n_steps`` steps."""
    torch = _torch()
    nn = torch.nn

    class _Vrae(nn.Module):  # type: ignore[misc,name-defined]
        def __init__(self) -> None:
            super().__init__()
            h, z = config.hidden_dim, config.latent_dim
            self.encoder = nn.LSTM(3 * n_agents, h, batch_first=True)
            self.attention = nn.MultiheadAttention(h, config.attention_heads, batch_first=True)
            self.norm = nn.LayerNorm(h)
            self.mu = nn.Linear(h, z)
            self.logvar = nn.Linear(h, z)
            self.decoder = nn.LSTM(z, h, batch_first=True)
            self.out = nn.Linear(h, 2 * n_agents)

        def encode(self, xy: Any, valid: Any) -> tuple[Any, Any]:
            b = xy.shape[0]
            feats = torch.cat([xy, valid.unsqueeze(-1).to(xy.dtype)], dim=-1)  # (B, A, S, 3)
            seq = feats.permute(0, 2, 1, 3).reshape(b, n_steps, 3 * n_agents)
            hidden, _ = self.encoder(seq)
            mixed, _ = self.attention(hidden, hidden, hidden, need_weights=False)
            pooled = self.norm(hidden + mixed).mean(dim=1)
            return self.mu(pooled), self.logvar(pooled)

        def decode(self, z: Any) -> Any:
            b = z.shape[0]
            hidden, _ = self.decoder(z.unsqueeze(1).expand(b, n_steps, z.shape[-1]))
            return self.out(hidden).reshape(b, n_steps, n_agents, 2).permute(0, 2, 1, 3)

    return _Vrae()


@dataclass(frozen=True)
class TrainingSummary:
    """What one :meth:`TrajectoryEmbedder.fit` did.

    Attributes:
        loss_history: mean training loss (reconstruction + weighted KL) per epoch.
        reconstruction_history: mean reconstruction loss per epoch (scaled units).
        n_windows: windows trained on.
        seconds: wall time of training.
    """

    loss_history: tuple[float, ...]
    reconstruction_history: tuple[float, ...]
    n_windows: int
    seconds: float


@dataclass
class TrajectoryEmbedder:
    """Scikit-learn-style estimator embedding windows with a VRAE (see the module docstring).

    Attributes:
        config: network and training settings.
        n_agents_: agents per window it was fitted on (after :meth:`fit`).
        n_steps_: steps per window it was fitted on.
        data_hash_: :func:`windows_data_hash` of the training windows.
        summary_: the training summary.
    """

    config: EmbedderConfig = field(default_factory=EmbedderConfig)
    n_agents_: int = 0
    n_steps_: int = 0
    data_hash_: str = ""
    summary_: TrainingSummary | None = None
    _net: Any = field(default=None, repr=False)

    # ------------------------------------------------------------------ fitting
    def fit(
        self,
        windows: WindowSet,
        progress: Progress | None = None,
        on_epoch: Callable[[int, float], None] | None = None,
    ) -> TrajectoryEmbedder:
        """Train on ``windows``; progress advances once per epoch with the epoch's mean loss.

        Raises:
            NoWindowsError: ``windows`` is empty.
        """
        if len(windows) == 0:
            raise NoWindowsError("no windows to train on; build them first (scenariominer embed windows)")
        torch = _torch()
        cfg = self.config
        progress = progress or NullProgress()
        if cfg.threads:
            torch.set_num_threads(cfg.threads)
        torch.manual_seed(cfg.seed)
        self.n_agents_, self.n_steps_ = windows.n_agents, windows.n_steps
        self.data_hash_ = windows_data_hash(windows)
        net = _build_network(cfg, self.n_agents_, self.n_steps_)
        xy, valid = self._tensors(windows)
        opt = torch.optim.Adam(net.parameters(), lr=cfg.learning_rate)
        gen = torch.Generator().manual_seed(cfg.seed)
        n = xy.shape[0]
        losses: list[float] = []
        recons: list[float] = []
        t0 = time.perf_counter()
        net.train()
        with step(progress, f"training ({cfg.loss} loss)", cfg.epochs):
            for epoch in range(cfg.epochs):
                perm = torch.randperm(n, generator=gen)
                total = total_rec = 0.0
                for s in range(0, n, cfg.batch_size):
                    idx = perm[s : s + cfg.batch_size]
                    loss, rec = self._loss(net, xy[idx], valid[idx], gen)
                    opt.zero_grad()
                    loss.backward()
                    opt.step()
                    total += float(loss.detach()) * idx.numel()
                    total_rec += float(rec.detach()) * idx.numel()
                losses.append(total / n)
                recons.append(total_rec / n)
                progress.advance(1, f"epoch {epoch + 1} loss {losses[-1]:.4f}")
                if on_epoch is not None:
                    on_epoch(epoch, losses[-1])
        net.eval()
        self._net = net
        self.summary_ = TrainingSummary(tuple(losses), tuple(recons), n, time.perf_counter() - t0)
        return self

    def _loss(self, net: Any, xy: Any, valid: Any, gen: Any) -> tuple[Any, Any]:
        """Training loss (reconstruction + weighted KL) and the reconstruction part of one batch."""
        torch = _torch()
        mu, logvar = net.encode(xy, valid)
        eps = torch.randn(mu.shape, generator=gen)
        recon = net.decode(mu + eps * torch.exp(0.5 * logvar))
        per = (hausdorff_l1 if self.config.loss == "hausdorff" else masked_mse)(xy, recon, valid)  # (B, A)
        present = valid.any(dim=-1)
        rec = (per * present).sum() / present.sum().clamp(min=1)
        kl = -0.5 * (1 + logvar - mu**2 - logvar.exp()).sum(dim=-1).mean()
        return rec + self.config.kl_weight * kl, rec

    def _scale(self) -> Float32Array:
        """``(2,)`` metres per network unit, forward and left."""
        cfg = self.config
        return np.asarray(
            [cfg.position_scale_m, cfg.lateral_scale_m or cfg.position_scale_m], dtype=np.float32
        )

    def _tensors(self, windows: WindowSet) -> tuple[Any, Any]:
        torch = _torch()
        xy = torch.from_numpy(np.ascontiguousarray(windows.xy_m, dtype=np.float32) / self._scale())
        return xy, torch.from_numpy(np.ascontiguousarray(windows.valid))

    # ------------------------------------------------------------------ using
    def _check_fitted(self, windows: WindowSet) -> Any:
        if self._net is None:
            raise RepresentError("the embedder is not fitted; call fit() or load a trained model")
        if (windows.n_agents, windows.n_steps) != (self.n_agents_, self.n_steps_):
            raise WindowConfigMismatchError(
                f"windows have {windows.n_agents} agents x {windows.n_steps} steps, the model was trained "
                f"on {self.n_agents_} x {self.n_steps_}; cut windows with the model's settings"
            )
        return self._net

    def transform(self, windows: WindowSet) -> Float32Array:
        """``(W, latent_dim)`` float32 latent means of ``windows`` (deterministic)."""
        net = self._check_fitted(windows)
        torch = _torch()
        if self.config.threads:
            torch.set_num_threads(self.config.threads)
        xy, valid = self._tensors(windows)
        out = np.empty((len(windows), self.config.latent_dim), dtype=np.float32)
        with torch.inference_mode():
            for s in range(0, len(windows), _TRANSFORM_BATCH):
                mu, _ = net.encode(xy[s : s + _TRANSFORM_BATCH], valid[s : s + _TRANSFORM_BATCH])
                out[s : s + mu.shape[0]] = mu.numpy()
        return out

    def fit_transform(self, windows: WindowSet, progress: Progress | None = None) -> Float32Array:
        """:meth:`fit` then :meth:`transform` on the same windows."""
        return self.fit(windows, progress).transform(windows)

    def reconstruct(self, windows: WindowSet) -> Float32Array:
        """``(W, A, S, 2)`` reconstructed positions (metres, agent frame) from the latent means."""
        net = self._check_fitted(windows)
        torch = _torch()
        xy, valid = self._tensors(windows)
        with torch.inference_mode():
            mu, _ = net.encode(xy, valid)
            recon = net.decode(mu).numpy() * self._scale()
        return np.asarray(recon, dtype=np.float32)

    # ------------------------------------------------------------------ persistence
    def to_bytes(self) -> bytes:
        """Weights, settings and training record as one byte string (see :meth:`from_bytes`)."""
        if self._net is None:
            raise RepresentError("cannot save an embedder that is not fitted")
        torch = _torch()
        buf = io.BytesIO()
        meta = {
            "config": dataclasses.asdict(self.config),
            "n_agents": self.n_agents_,
            "n_steps": self.n_steps_,
            "data_hash": self.data_hash_,
            "summary": dataclasses.asdict(self.summary_) if self.summary_ else None,
        }
        torch.save({"meta": json.dumps(meta), "state": self._net.state_dict()}, buf)
        return buf.getvalue()

    @classmethod
    def from_bytes(cls, data: bytes) -> TrajectoryEmbedder:
        """The embedder saved by :meth:`to_bytes` (same weights: same embeddings)."""
        torch = _torch()
        saved = torch.load(io.BytesIO(data), weights_only=True)
        meta = json.loads(saved["meta"])
        cfg_dict = dict(meta["config"])
        config = EmbedderConfig(**cfg_dict)
        summary = meta.get("summary")
        est = cls(
            config=config,
            n_agents_=int(meta["n_agents"]),
            n_steps_=int(meta["n_steps"]),
            data_hash_=str(meta["data_hash"]),
            summary_=None
            if summary is None
            else TrainingSummary(
                tuple(summary["loss_history"]),
                tuple(summary["reconstruction_history"]),
                int(summary["n_windows"]),
                float(summary["seconds"]),
            ),
        )
        net = _build_network(config, est.n_agents_, est.n_steps_)
        net.load_state_dict(saved["state"])
        net.eval()
        est._net = net
        return est
