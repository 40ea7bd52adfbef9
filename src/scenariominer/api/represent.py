"""Use cases of the trajectory representation (seed 001): windows, embedder, clusters, similar.

Each function takes a store, a typed request and the configuration, calls the stage in
:mod:`scenariominer.represent` and returns its typed result. Nothing here prints.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from dataclasses import dataclass

from scenariominer.config import Config
from scenariominer.progress import Progress
from scenariominer.represent.pipeline import WindowsReport, build_store_windows
from scenariominer.store import ScenarioStore

__all__ = ["WindowsRequest", "build_windows"]


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
    store: ScenarioStore, request: WindowsRequest, config: Config, progress: Progress | None = None
) -> WindowsReport:
    """Cut stored logs into windows (only logs whose windows are missing or stale, unless rebuilding).

    Raises:
        ConfigError: invalid window settings in the request.
    """
    cfg = window_config(request, config)
    return build_store_windows(
        store, cfg.represent.windows, log_ids=request.log_ids, rebuild=request.rebuild, progress=progress
    )
