"""Configuration of the executor layer (how corpus-wide stages are spread over processes or a cluster)."""

from __future__ import annotations

from dataclasses import dataclass

from scenariominer.errors import ConfigError

#: The executors by name: ``local`` runs in this process (tests, debugging), ``process`` a pool of
#: local worker processes (the default), ``ray`` tasks on a Ray cluster.
EXECUTORS = ("local", "process", "ray")


@dataclass(frozen=True)
class ExecConfig:
    """How ``ingest``, ``analyze`` and ``mine`` spread their per-log work.

    Attributes:
        executor: ``local``, ``process`` (default) or ``ray``.
        workers: worker processes (``process``) or concurrent tasks (``ray``); 0 = every core of
            this machine (``process``) or of the cluster (``ray``).
        ray_address: the Ray cluster to join: ``auto`` (the cluster started on this machine with
            ``ray start``), ``HOST:PORT`` or ``ray://HOST:PORT``; empty starts a private local one.
        retries: extra attempts for an item whose worker died or that failed transiently.
        min_items: below this many items the ``process`` executor runs in this process (starting
            workers costs about a second, more than a handful of small items take).
        min_ingest_bytes: with the ``process`` executor, ``ingest`` reads sources whose files
            total fewer bytes than this in this process: their work (about 18 ms per MB of
            Argoverse 2 files, each commit overlapping the next read) is shorter than starting the
            workers. 0 = never. With two workers or fewer, ``ingest`` always runs in this process,
            which then does as well as the pool.
    """

    executor: str = "process"
    workers: int = 0
    ray_address: str = ""
    retries: int = 2
    min_items: int = 4
    min_ingest_bytes: int = 32 * 2**20

    def __post_init__(self) -> None:
        if self.executor not in EXECUTORS:
            raise ConfigError(f"executor must be one of {', '.join(EXECUTORS)}, got {self.executor!r}")
        if self.workers < 0:
            raise ConfigError("workers must be >= 0 (0: every core)")
        if self.retries < 0:
            raise ConfigError("retries must be >= 0")
        if self.min_items < 1:
            raise ConfigError("min_items must be >= 1")
        if self.min_ingest_bytes < 0:
            raise ConfigError("min_ingest_bytes must be >= 0")
