"""Store-level stages of the representation: cut windows of stored logs (incrementally)."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

from scenariominer import errors as _errors
from scenariominer.config.represent import WindowConfig
from scenariominer.progress import NullProgress, Progress, step
from scenariominer.represent.lanes import log_lane_ids
from scenariominer.represent.window_table import log_window_records, save_logs_windows, window_config_hash
from scenariominer.represent.windows import WindowSet, extract_windows
from scenariominer.store import ScenarioStore

__all__ = ["LogWindowsResult", "WindowsReport", "build_store_windows"]

#: Logs whose windows are written to the store in one transaction (bounds memory and lost work).
_WRITE_BATCH_LOGS = 64


@dataclass(frozen=True)
class LogWindowsResult:
    """Outcome for one log.

    Attributes:
        log_id: the log.
        status: ``built`` (windows cut now), ``current`` (stored windows were up to date) or
            ``failed``.
        n_windows: windows the log has now (0 when failed).
        has_lanes: whether lane ids were found for it.
        error: why it failed (empty otherwise).
    """

    log_id: str
    status: str
    n_windows: int
    has_lanes: bool = False
    error: str = ""


@dataclass(frozen=True)
class WindowsReport:
    """Result of :func:`build_store_windows`: one entry per log and the totals."""

    logs: tuple[LogWindowsResult, ...]
    config_hash: str

    @property
    def n_built(self) -> int:
        """Logs whose windows were cut in this run."""
        return sum(r.status == "built" for r in self.logs)

    @property
    def n_windows(self) -> int:
        """Windows of the selected logs in the store now."""
        return sum(r.n_windows for r in self.logs)

    @property
    def failed(self) -> tuple[LogWindowsResult, ...]:
        """Logs that could not be windowed."""
        return tuple(r for r in self.logs if r.status == "failed")


def build_store_windows(
    store: ScenarioStore,
    config: WindowConfig,
    *,
    log_ids: Sequence[str] | None = None,
    rebuild: bool = False,
    progress: Progress | None = None,
) -> WindowsReport:
    """Cut the windows of stored logs whose windows are missing or stale; keep the others.

    A log's windows are current when they were cut with the same settings from the same source
    hash. A log that cannot be read or windowed is reported as failed; the others go on. Windows
    are written in batches of logs (one transaction per table and batch).
    """
    progress = progress or NullProgress()
    ids = list(log_ids) if log_ids is not None else store.log_ids()
    chash = window_config_hash(config)
    records = log_window_records(store, ids)
    results: list[LogWindowsResult] = []
    pending: dict[str, tuple[WindowSet, str]] = {}
    with step(progress, "cutting windows", len(ids)):
        for log_id in ids:
            try:
                meta = store.log_meta(log_id)
                rec = records.get(log_id)
                current = rec is not None and rec.config == chash and rec.source_hash == meta.source_hash
                if current and not rebuild:
                    assert rec is not None
                    results.append(LogWindowsResult(log_id, "current", len(rec.window_ids)))
                else:
                    log = store.load_log(log_id)
                    lanes = log_lane_ids(log)
                    windows = extract_windows(log, config, lanes)
                    pending[log_id] = (windows, meta.source_hash)
                    results.append(LogWindowsResult(log_id, "built", len(windows), lanes is not None))
            except (_errors.ScenarioMinerError, ValueError, OSError) as exc:
                results.append(LogWindowsResult(log_id, "failed", 0, error=f"{type(exc).__name__}: {exc}"))
            if len(pending) >= _WRITE_BATCH_LOGS:
                save_logs_windows(store, pending, config)
                pending = {}
            progress.advance(1, log_id)
        save_logs_windows(store, pending, config)
    return WindowsReport(tuple(results), chash)
