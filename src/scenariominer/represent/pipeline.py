"""Store-level stages of the representation: cut windows of stored logs (incrementally)."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

from scenariominer import errors as _errors
from scenariominer.config.represent import WindowConfig
from scenariominer.progress import NullProgress, Progress, step
from scenariominer.represent.lanes import log_lane_ids
from scenariominer.represent.window_table import log_window_records, save_logs_windows, window_config_hash
from scenariominer.represent.windows import WindowSet, extract_windows
from scenariominer.store import ScenarioStore, StoreRef

if TYPE_CHECKING:
    from scenariominer.exec import Executor, ItemOutcome

__all__ = ["LogWindowsResult", "WindowTask", "WindowsReport", "build_store_windows"]

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


@dataclass(frozen=True)
class WindowTask:
    """The worker side of window cutting: load one stored log and cut its windows (picklable)."""

    store: StoreRef
    config: WindowConfig

    def __call__(self, log_id: str) -> tuple[WindowSet, bool]:
        """The log's windows and whether lane ids were found for it."""
        log = self.store.open().load_log(log_id)
        lanes = log_lane_ids(log)
        return extract_windows(log, self.config, lanes), lanes is not None


def build_store_windows(
    store: ScenarioStore,
    config: WindowConfig,
    *,
    log_ids: Sequence[str] | None = None,
    rebuild: bool = False,
    progress: Progress | None = None,
    executor: Executor | None = None,
) -> WindowsReport:
    """Cut the windows of stored logs whose windows are missing or stale; keep the others.

    A log's windows are current when they were cut with the same settings from the same source
    hash. A log that cannot be read or windowed is reported as failed; the others go on. Windows
    are written in batches of logs (one transaction per table and batch). With an ``executor``
    (not ``local``), the logs are loaded and cut in its workers and written here as they return.
    """
    progress = progress or NullProgress()
    ids = list(log_ids) if log_ids is not None else store.log_ids()
    chash = window_config_hash(config)
    records = log_window_records(store, ids)
    results: dict[str, LogWindowsResult] = {}
    hashes: dict[str, str] = {}
    stale: list[str] = []
    for log_id in ids:
        try:
            meta = store.log_meta(log_id)
        except (_errors.ScenarioMinerError, ValueError, OSError) as exc:
            results[log_id] = LogWindowsResult(log_id, "failed", 0, error=f"{type(exc).__name__}: {exc}")
            continue
        rec = records.get(log_id)
        if rec is not None and rec.config == chash and rec.source_hash == meta.source_hash and not rebuild:
            results[log_id] = LogWindowsResult(log_id, "current", len(rec.window_ids))
        else:
            hashes[log_id] = meta.source_hash
            stale.append(log_id)
    pending: dict[str, tuple[WindowSet, str]] = {}

    def keep(log_id: str, windows: WindowSet | None, has_lanes: bool, error: str) -> None:
        nonlocal pending
        if windows is None:
            results[log_id] = LogWindowsResult(log_id, "failed", 0, error=error)
        else:
            pending[log_id] = (windows, hashes[log_id])
            results[log_id] = LogWindowsResult(log_id, "built", len(windows), has_lanes)
        if len(pending) >= _WRITE_BATCH_LOGS:
            save_logs_windows(store, pending, config)
            pending = {}
        progress.advance(1, log_id)

    with step(progress, "cutting windows", len(ids)):
        progress.advance(len(ids) - len(stale))
        task = WindowTask(StoreRef.of(store), config)
        if executor is not None and executor.name != "local":

            def on_outcome(outcome: ItemOutcome[tuple[WindowSet, bool]]) -> None:
                windows, has_lanes = outcome.value if outcome.value is not None else (None, False)
                keep(outcome.key, windows, has_lanes, outcome.error)

            executor.map(task, stale, keys=stale, on_outcome=on_outcome)
        else:
            for log_id in stale:
                try:
                    windows, has_lanes = task(log_id)
                except (_errors.ScenarioMinerError, ValueError, OSError) as exc:
                    keep(log_id, None, False, f"{type(exc).__name__}: {exc}")
                else:
                    keep(log_id, windows, has_lanes, "")
        save_logs_windows(store, pending, config)
    return WindowsReport(tuple(results[i] for i in ids), chash)
