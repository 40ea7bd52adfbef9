"""Use case ``mine``: find a described scenario in logs (files, a store, or both) and keep the results.

:func:`mine` is what the ``mine`` command and the HTTP server call: it loads the logs (reading
files in memory, or ingesting them into the store first), asks the mining stage
(:func:`scenariominer.mine.query.mine_logs`) for the matches, stores them when a store is given
(:func:`store_report`: rows of the same description in the same logs are replaced), and writes the
Argoverse 2 submission when asked. Nothing here prints.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pyarrow as pa

from scenariominer.api.corpus import ingest
from scenariominer.config import Config
from scenariominer.data.log import Log, LogFormatError
from scenariominer.errors import MiningError
from scenariominer.llm.usage import UsageCounter
from scenariominer.mine.export import MATCHES_TABLE, RUNS_TABLE, LogMatches, matches_table, runs_table
from scenariominer.mine.query import QueryReport, make_synthesizer, mine_logs
from scenariominer.mine.synthesis import normalize_description
from scenariominer.store import ScenarioStore

#: Column of the mining tables holding the normalised description: the key of their upserts.
DESCRIPTION_KEY = "description_key"

__all__ = [
    "DESCRIPTION_KEY",
    "MineRequest",
    "MineResult",
    "load_logs",
    "mine",
    "raw_logs_for",
    "store_report",
]


@dataclass(frozen=True)
class MineRequest:
    """One mining query.

    Attributes:
        description: the scenario to find, in plain English.
        logs: log folders or files (any supported format); may be empty when ``store`` is given.
        store: the store to ingest ``logs`` into and to keep the results in; ``None`` mines in memory.
        program: a program text to run instead of generating one (run in the sandbox).
        use_bank: use a hand-written bank program with exactly this description, if any.
        camera_frames: camera-frame crops folder; enables the CLIP candidate filter.
        export_av2: write the Argoverse 2 submission pickle here.
        align_to: ground-truth pickle whose evaluation timestamps the export uses.
        force: regenerate even if the program is cached.
    """

    description: str
    logs: Sequence[Path] = ()
    store: ScenarioStore | None = None
    program: str | None = None
    use_bank: bool = True
    camera_frames: Path | None = None
    export_av2: Path | None = None
    align_to: Path | None = None
    force: bool = False


@dataclass(frozen=True)
class MineResult:
    """What :func:`mine` did: the query report, the logs stored and the export written."""

    report: QueryReport
    stored_logs: list[str] = field(default_factory=list)
    export_path: Path | None = None

    @property
    def all_failed(self) -> bool:
        """True when the program failed on every log it was run on."""
        r = self.report
        return bool(r.failures) and not r.matches


def mine(request: MineRequest, config: Config, usage: UsageCounter | None = None) -> MineResult:
    """Run one mining query end to end (see the module docstring).

    ``usage`` counts the model calls and tokens (for the command's usage table).

    Raises:
        MiningError: no logs to mine; a bank, camera-frame or export problem.
        DataError, StoreError, LLMError: unreadable logs, store or model problems.
    """
    from scenariominer.mine.export import read_av2_submission, write_av2_submission
    from scenariominer.mine.loop import ProgramCache
    from scenariominer.mine.query import av2_submission, clip_candidates

    mined = load_logs(list(request.logs), request.store, config)
    if not mined:
        raise MiningError("no logs to mine: the paths and the store hold no log")
    candidates = (
        clip_candidates(request.description, mined, request.camera_frames, config.mining)
        if request.camera_frames is not None
        else None
    )
    cache = ProgramCache.in_dir(config.llm.cache_dir) if config.mining.generation.cache_programs else None
    report = mine_logs(
        request.description,
        mined,
        config=config.mining,
        program=request.program,
        synthesizer=lambda: make_synthesizer(config, usage=usage),
        examples=None,
        use_bank=request.use_bank,
        cache=cache,
        candidates=candidates,
        force=request.force,
    )
    stored = store_report(request.store, report) if request.store is not None else []
    if request.export_av2 is not None:
        timestamps = None
        if request.align_to is not None:
            gt = read_av2_submission(request.align_to)
            timestamps = {lid: [int(f["timestamp_ns"]) for f in frames] for (lid, _), frames in gt.items()}
        submission = av2_submission(report, raw_logs_for(mined, config), timestamps=timestamps)
        write_av2_submission(submission, request.export_av2)
    return MineResult(report, stored, request.export_av2)


def store_report(store: ScenarioStore, report: QueryReport) -> list[str]:
    """Write a query's matches to ``mining_results`` and ``mining_runs`` of the logs in the store.

    Rows of the same description (normalised) in those logs are replaced, rows of other
    descriptions are kept: a keyed upsert under the store's write lock, so processes mining
    different descriptions at once never lose each other's rows. Logs the store does not hold
    are skipped. Text from the program (error messages) is stored as valid UTF-8.

    Returns:
        The log ids written.
    """
    known = set(store.log_ids())
    key = normalize_description(report.description)
    runs: dict[str, pa.Table] = {m.log_id: runs_table(m) for m in report.matches if m.log_id in known}
    cells = {m.log_id: matches_table(m) for m in report.matches if m.log_id in known}
    for failure in report.failures:
        if failure.log_id in known:
            empty = LogMatches(
                failure.log_id, report.description, report.program_sha256,
                np.zeros(0, dtype=np.int64), np.zeros(0, dtype=str), np.zeros(0, dtype=str),
                np.zeros((0, 0), dtype=bool), np.zeros((0, 3), dtype=np.int64),
            )  # fmt: skip
            error = failure.error.feedback().encode("utf-8", "replace").decode("utf-8")
            runs[failure.log_id] = runs_table(empty, status="failed", error=error)
    for log_id in sorted(runs):
        store.upsert_table_rows(log_id, RUNS_TABLE, _keyed(runs[log_id], key), DESCRIPTION_KEY, [key])
        if log_id in cells:
            store.upsert_table_rows(log_id, MATCHES_TABLE, _keyed(cells[log_id], key), DESCRIPTION_KEY, [key])
    return sorted(runs)


def _keyed(table: pa.Table, key: str) -> pa.Table:
    """``table`` with the normalised description as its :data:`DESCRIPTION_KEY` column."""
    return table.append_column(DESCRIPTION_KEY, pa.array([key] * table.num_rows, pa.string()))


def load_logs(
    paths: Sequence[str | Path] = (),
    store: ScenarioStore | None = None,
    config: Config | None = None,
) -> list[Log]:
    """The preprocessed logs to mine.

    * ``paths`` only: read every log under the paths (any supported format) and preprocess it in
      memory (nothing is written);
    * ``paths`` and ``store``: ingest the paths into the store (incremental: unchanged sources
      are skipped) and load those logs from it, so results can be stored beside them;
    * ``store`` only: every log in the store.

    Raises:
        LogFormatError: a path holds no readable log, or a source failed to ingest.
        ValueError: neither paths nor a store.
    """
    from scenariominer.config import load_config
    from scenariominer.data.ingest import MemorySink, ingest_sources

    cfg = config or load_config()
    if paths and store is not None:
        report = ingest(list(paths), store, cfg)
        if report.failed:
            first = report.failed[0]
            raise LogFormatError(first.key, first.error)
        ids = [log_id for r in report.sources for log_id in r.log_ids]
        return [store.load_log(i) for i in dict.fromkeys(ids)]
    if paths:
        sink = MemorySink()
        for result in ingest_sources(list(paths), sink, cfg):
            if result.status == "failed":
                raise LogFormatError(result.key, result.error)
        return sink.all_logs()
    if store is not None:
        return [store.load_log(i) for i in store.log_ids()]
    raise ValueError("give log paths, a store, or both")


def raw_logs_for(logs: Sequence[Log], config: Config | None = None) -> dict[str, Log]:
    """The RAW (unsmoothed) version of each log, for the Argoverse 2 export.

    Each log is re-read from its source with the reader of its format (the ground truth uses the
    raw annotation boxes); a log whose source is gone or no longer yields it is used as it is.
    """
    from scenariominer.config import load_config

    cfg = config or load_config()
    return {log.log_id: _reread(log, cfg) or log for log in logs}


def _reread(log: Log, config: Config) -> Log | None:
    """``log`` read again from ``log.source_path`` by the reader of ``log.dataset``, if possible."""
    from scenariominer.data.log import LogFormatError
    from scenariominer.data.sources import default_readers, discover_sources

    readers = [r for r in default_readers() if r.format == log.dataset]
    if log.source_path is None or not readers or not Path(log.source_path).exists():
        return None
    try:
        for source in discover_sources([log.source_path], readers):
            for raw in readers[0].read(source, config):
                if raw.log_id == log.log_id:
                    return raw
    except LogFormatError:
        return None
    return None
