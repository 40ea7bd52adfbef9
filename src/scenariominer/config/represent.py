"""Configuration of trajectory windows, the trajectory autoencoder and clustering (seed 001).

The paper cuts highD into 15 s sequences (section 4.1), trains a variational recurrent autoencoder
with a Hausdorff (L1) reconstruction loss (section 3.1) and clusters the embeddings with HDBSCAN
(section 3.2). It states no network sizes or HDBSCAN parameters; the defaults below are chosen for
2-core CPU training and are explained per field.
"""

from __future__ import annotations

from dataclasses import dataclass, field

#: Agents a window can be centred on.
AGENT_CHOICES = ("ego", "vehicles")
#: Reconstruction losses of the autoencoder.
LOSS_CHOICES = ("hausdorff", "mse")


@dataclass(frozen=True)
class WindowConfig:
    """How logs are cut into samples of one agent and its neighbours.

    Attributes:
        lengths_s: window lengths in seconds; several give multi-scale windows (e.g. 5, 15, 45).
            15 s is the paper's sequence length.
        overlap: fraction of a window shared with the next one of the same agent (0 = back to back,
            0.5 = a new window every half length); must be in ``[0, 1)``.
        n_steps: samples per window after resampling (positions at ``n_steps`` evenly spaced times
            from the window start to its end); 30 is one sample per 0.5 s for a 15 s window.
        k_neighbours: surrounding agents per sample (nearest by mean distance over the window);
            missing ones are padded and masked. 8 covers the highD 8-neighbourhood (preceding,
            following, alongside on both sides).
        neighbour_radius_m: only road users whose mean distance over the window is within this
            radius (metres) count as neighbours.
        agents: ``ego``: one window series per log, centred on the log's ego; ``vehicles``: every
            vehicle observed over a whole window is a chosen agent.
        end_tolerance_s: a window may end up to this many seconds after the log's last timestamp
            (its last samples repeat the last position); lets a 15 s window fit a log of 15 s at
            25 Hz, whose first and last timestamps are 14.96 s apart.
    """

    lengths_s: tuple[float, ...] = (15.0,)
    overlap: float = 0.0
    n_steps: int = 30
    k_neighbours: int = 8
    neighbour_radius_m: float = 100.0
    agents: str = "ego"
    end_tolerance_s: float = 0.1

    def __post_init__(self) -> None:
        if not self.lengths_s or any(not (length > 0) for length in self.lengths_s):
            raise ValueError("represent.windows: lengths_s must be positive seconds, at least one")
        if not 0.0 <= self.overlap < 1.0:
            raise ValueError(f"represent.windows: overlap must be in [0, 1), got {self.overlap}")
        if self.n_steps < 2:
            raise ValueError(f"represent.windows: n_steps must be at least 2, got {self.n_steps}")
        if self.k_neighbours < 0:
            raise ValueError(f"represent.windows: k_neighbours must be >= 0, got {self.k_neighbours}")
        if not self.neighbour_radius_m > 0:
            raise ValueError("represent.windows: neighbour_radius_m must be positive")
        if self.agents not in AGENT_CHOICES:
            raise ValueError(f"represent.windows: agents must be one of {AGENT_CHOICES}, got {self.agents!r}")
        if self.end_tolerance_s < 0:
            raise ValueError("represent.windows: end_tolerance_s must be >= 0")


@dataclass(frozen=True)
class EmbedderConfig:
    """Variational recurrent autoencoder (section 3.1) and its training.

    Attributes:
        loss: ``hausdorff`` (the paper's: Hausdorff distance under L1 between each agent's input
            and reconstructed point sets) or ``mse`` (the baseline).
        latent_dim: size of the Gaussian latent (the embedding).
        hidden_dim: LSTM hidden size of encoder and decoder.
        attention_heads: heads of the encoder's self-attention over the LSTM outputs.
        epochs: passes over the training windows.
        batch_size: windows per optimiser step.
        learning_rate: Adam step size.
        kl_weight: weight of the KL term against the reconstruction loss.
        position_scale_m: forward positions are divided by this (metres) before entering the
            network (and the loss is measured in these units).
        lateral_scale_m: left positions are divided by this (metres); 0 means
            ``position_scale_m``. A smaller lateral scale makes a lane's width count as much as a
            longer forward distance in the loss.
        seed: seed of parameter initialisation and batch order (training is deterministic on CPU).
        threads: torch CPU threads (0: leave torch's default).
    """

    loss: str = "hausdorff"
    latent_dim: int = 16
    hidden_dim: int = 64
    attention_heads: int = 4
    epochs: int = 40
    batch_size: int = 64
    learning_rate: float = 2e-3
    kl_weight: float = 1e-3
    position_scale_m: float = 50.0
    lateral_scale_m: float = 0.0
    seed: int = 0
    threads: int = 2

    def __post_init__(self) -> None:
        if self.loss not in LOSS_CHOICES:
            raise ValueError(f"represent.embedder: loss must be one of {LOSS_CHOICES}, got {self.loss!r}")
        if self.latent_dim < 1 or self.hidden_dim < 1 or self.attention_heads < 1:
            raise ValueError("represent.embedder: latent_dim, hidden_dim and attention_heads must be >= 1")
        if self.hidden_dim % self.attention_heads:
            raise ValueError("represent.embedder: hidden_dim must be a multiple of attention_heads")
        if self.epochs < 1 or self.batch_size < 1:
            raise ValueError("represent.embedder: epochs and batch_size must be >= 1")
        if not (self.learning_rate > 0 and self.position_scale_m > 0 and self.kl_weight >= 0):
            raise ValueError("represent.embedder: learning_rate and position_scale_m > 0, kl_weight >= 0")
        if self.lateral_scale_m < 0:
            raise ValueError("represent.embedder: lateral_scale_m must be >= 0 (0: position_scale_m)")
        if self.threads < 0:
            raise ValueError("represent.embedder: threads must be >= 0")


@dataclass(frozen=True)
class ClusterConfig:
    """HDBSCAN over the embeddings (section 3.2) and the t-SNE projection of the plots.

    Attributes:
        min_cluster_size: smallest group HDBSCAN calls a cluster.
        min_samples: HDBSCAN's density smoothing; 0 means equal to ``min_cluster_size``.
        selection: HDBSCAN's ``cluster_selection_method``: ``eom`` (excess of mass, the library's
            default: fewer, larger clusters) or ``leaf`` (the finest clusters of the tree).
        tsne_perplexity: t-SNE perplexity (capped below the number of windows).
        seed: seed of the t-SNE layout.
    """

    min_cluster_size: int = 10
    min_samples: int = 0
    selection: str = "eom"
    tsne_perplexity: float = 30.0
    seed: int = 0

    def __post_init__(self) -> None:
        if self.min_cluster_size < 2:
            raise ValueError("represent.cluster: min_cluster_size must be at least 2")
        if self.min_samples < 0 or not self.tsne_perplexity > 0:
            raise ValueError("represent.cluster: min_samples >= 0 and tsne_perplexity > 0")
        if self.selection not in ("eom", "leaf"):
            raise ValueError(f"represent.cluster: selection must be eom or leaf, got {self.selection!r}")


@dataclass(frozen=True)
class RepresentConfig:
    """Windows, embedder and clustering settings (``[represent.windows]`` and so on)."""

    windows: WindowConfig = field(default_factory=WindowConfig)
    embedder: EmbedderConfig = field(default_factory=EmbedderConfig)
    cluster: ClusterConfig = field(default_factory=ClusterConfig)
