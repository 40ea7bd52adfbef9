"""What the scenario browser serves and how: store, data roots, address, token, job limits."""

from __future__ import annotations

import ipaddress
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

from scenariominer.errors import ConfigError, ScenarioMinerError

__all__ = ["LOOPBACK_HOST", "PathOutsideRootsError", "ServerSettings", "confine_path", "is_loopback"]

#: Address the server binds to unless told otherwise.
LOOPBACK_HOST = "127.0.0.1"


class PathOutsideRootsError(ScenarioMinerError, PermissionError):
    """A path in a request lies outside the data roots the server was started with."""


def is_loopback(host: str) -> bool:
    """Whether ``host`` is a loopback address (``localhost`` counts, ``0.0.0.0`` does not)."""
    if host == "localhost":
        return True
    try:
        return ipaddress.ip_address(host).is_loopback
    except ValueError:
        return False


@dataclass(frozen=True)
class ServerSettings:
    """Settings of ``scenariominer serve``.

    Attributes:
        store_path: the scenario store served (it must exist).
        config_path: TOML configuration handed to every use case (``None``: defaults and environment).
        data_roots: folders that request paths (ingest sources, synth output) must lie in.
        host: bind address; anything but loopback needs ``token``.
        port: TCP port (0: any free port).
        token: bearer token required on every API call when set.
        workers: job worker processes running at once.
        max_queued: jobs waiting beyond the running ones before a submission is refused (HTTP 429).
        max_results: the most search hits or listed rows one answer holds.
        read_concurrency: reads (logs, search, scene) computed at once; the others wait their turn.
        jobs_db: SQLite file of the job table (default ``<store>/server/jobs.sqlite``).
    """

    store_path: Path
    config_path: Path | None = None
    data_roots: tuple[Path, ...] = field(default_factory=tuple)
    host: str = LOOPBACK_HOST
    port: int = 8787
    token: str | None = None
    workers: int = 1
    max_queued: int = 8
    max_results: int = 500
    read_concurrency: int = 2
    jobs_db: Path | None = None

    def __post_init__(self) -> None:
        if not is_loopback(self.host) and not self.token:
            raise ConfigError(
                f"binding to {self.host} exposes the store beyond this machine: give --token "
                "(clients then send 'Authorization: Bearer <token>'), or bind to 127.0.0.1"
            )
        if self.token is not None and len(self.token) < 8:
            raise ConfigError("the token must be at least 8 characters long")
        if not 0 <= self.port <= 65535:
            raise ConfigError(f"port must be in 0..65535, got {self.port}")
        if self.workers < 1 or self.max_queued < 1 or self.read_concurrency < 1:
            raise ConfigError("workers, max_queued and read_concurrency must be at least 1")

    @property
    def jobs_db_path(self) -> Path:
        """Where the job table lives."""
        return self.jobs_db or self.store_path / "server" / "jobs.sqlite"

    @classmethod
    def create(cls, store_path: Path, data_roots: Sequence[Path] = (), **options: object) -> ServerSettings:
        """Settings with the store and data roots resolved to absolute paths (roots default to the cwd)."""
        roots = tuple(Path(r).expanduser().resolve() for r in (data_roots or [Path.cwd()]))
        return cls(Path(store_path).expanduser().resolve(), data_roots=roots, **options)  # type: ignore[arg-type]


def confine_path(path: str, roots: Sequence[Path]) -> Path:
    """``path`` resolved (symbolic links followed), checked to lie inside one of ``roots``.

    Raises:
        PathOutsideRootsError: it lies outside every root (the message names the roots).
    """
    resolved = Path(path).expanduser().resolve()
    if any(resolved == r or resolved.is_relative_to(r) for r in roots):
        return resolved
    listed = ", ".join(str(r) for r in roots) or "(none)"
    raise PathOutsideRootsError(f"path {path!r} is outside the server's data roots ({listed})")
