"""Use case ``mine``: find a described scenario in logs (files, a store, or both) and keep the results.

:func:`mine` is what the ``mine`` command and the HTTP server call: it loads the logs (reading
files in memory, or ingesting them into the store first), asks the mining stage
(:func:`scenariominer.mine.query.mine_logs`) for the matches, stores them when a store is given
(:func:`store_report`: rows of the same description in the same logs are replaced), and writes the
Argoverse 2 submission when asked. Nothing here prints.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
import pyarrow as pa

from scenariominer.api._exec import executor_for
from scenariominer.api.corpus import ingest
from scenariominer.config import Config
from scenariominer.data.log import Log, LogFormatError
from scenariominer.errors import MiningError
from scenariominer.llm.usage import UsageCounter
from scenariominer.mine.export import MATCHES_TABLE, RUNS_TABLE, LogMatches, matches_table, runs_table
from scenariominer.mine.query import LogFailure, QueryReport, av2_submission, make_synthesizer, mine_logs
from scenariominer.mine.synthesis import normalize_description
from scenariominer.store import ScenarioStore, StoreRef

if TYPE_CHECKING:
    from scenariominer.exec import Executor

#: Column of the mining tables holding the normalised description: the key of their upserts.
DESCRIPTION_KEY = "description_key"

__all__ = [
    "DESCRIPTION_KEY",
    "MineRequest",
    "MineResult",
    "StoreMatches",
    "load_logs",
    "mine",
    "raw_logs_for",
    "store_log_ids",
    "store_log_result",
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

    def __post_init__(self) -> None:
        if self.program is None and not self.description.strip():
            # it was read as "any object" and listed every track of every log
            raise MiningError(
                "the description is empty: say what to find (e.g. 'pedestrian crossing in front of the "
                "ego vehicle'), or give a program with --program"
            )


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


def mine(
    request: MineRequest, config: Config, usage: UsageCounter | None = None, executor: Executor | None = None
) -> MineResult:
    """Run one mining query end to end (see the module docstring).

    ``usage`` counts the model calls and tokens (for the command's usage table). With a store,
    the program runs on each log in the workers of ``executor`` (default: ``config.exec``), which
    load the log from the store and commit its result at once; logs read from files without a
    store, and the CLIP-filtered path, run in this process.

    Raises:
        MiningError: no logs to mine; a given program that does not pass the sandbox's checks
            (syntax, forbidden constructs, argument kinds); a bank, camera-frame or export problem.
        DataError, StoreError, LLMError: unreadable logs, store or model problems.
    """
    from scenariominer.mine.export import read_av2_submission, write_av2_submission
    from scenariominer.mine.sandbox.check import check_program

    if request.program is not None:
        # a program that cannot run anywhere failed once per log with the same message
        problem = check_program(request.program, config.mining.sandbox)
        if problem is not None:
            raise MiningError(f"the program was not run: {problem.feedback()}")
    store = request.store
    with executor_for(config, executor) as runner:
        if store is not None and request.camera_frames is None:
            ids = store_log_ids(list(request.logs), store, config, runner)
            if not ids:
                raise MiningError("no logs to mine: the paths and the store hold no log")
            ref = StoreRef.of(store)
            record = StoreMatches(ref, request.description)
            report = _mine(request, ids, config, usage, runner, ref.load_log, record)
            stored = sorted({m.log_id for m in report.matches} | {f.log_id for f in report.failures})
            mined: Sequence[Log] = [store.load_log(i) for i in ids] if request.export_av2 is not None else []
        else:
            mined = load_logs(list(request.logs), store, config)
            if not mined:
                raise MiningError("no logs to mine: the paths and the store hold no log")
            report = _mine(request, mined, config, usage, None, None, None)
            stored = store_report(store, report) if store is not None else []
    if request.export_av2 is not None:
        timestamps = None
        if request.align_to is not None:
            gt = read_av2_submission(request.align_to)
            timestamps = {lid: [int(f["timestamp_ns"]) for f in frames] for (lid, _), frames in gt.items()}
        submission = av2_submission(report, raw_logs_for(mined, config), timestamps=timestamps)
        write_av2_submission(submission, request.export_av2)
    return MineResult(report, stored, request.export_av2)


def _mine(
    request: MineRequest,
    logs: Sequence[Log] | Sequence[str],
    config: Config,
    usage: UsageCounter | None,
    executor: Executor | None,
    load: Callable[[str], Log] | None,
    record: Callable[[LogMatches | LogFailure, str], None] | None,
) -> QueryReport:
    """The mining stage with the request's program, bank, cache and CLIP settings."""
    from scenariominer.mine.loop import ProgramCache
    from scenariominer.mine.query import clip_candidates

    candidates = None
    if request.camera_frames is not None:
        in_memory = [x for x in logs if isinstance(x, Log)]
        candidates = clip_candidates(request.description, in_memory, request.camera_frames, config.mining)
    cache = ProgramCache.in_dir(config.llm.cache_dir) if config.mining.generation.cache_programs else None
    return mine_logs(
        request.description,
        logs,
        config=config.mining,
        program=request.program,
        synthesizer=lambda: make_synthesizer(config, usage=usage),
        examples=None,
        use_bank=request.use_bank,
        cache=cache,
        candidates=candidates,
        force=request.force,
        executor=executor,
        load=load,
        record=record,
    )


def store_log_ids(
    paths: Sequence[str | Path], store: ScenarioStore, config: Config, executor: Executor | None = None
) -> list[str]:
    """Ids of the logs to mine in ``store``: those under ``paths`` (ingested first), else every log.

    Raises:
        LogFormatError: a source failed to ingest.
    """
    if not paths:
        return store.log_ids()
    report = ingest(list(paths), store, config, executor=executor)
    if report.failed:
        first = report.failed[0]
        raise LogFormatError(first.key, first.error)
    return list(dict.fromkeys(log_id for r in report.sources for log_id in r.log_ids))


@dataclass(frozen=True)
class StoreMatches:
    """Commits one log's mining result to the store where it was mined (picklable, for workers)."""

    store: StoreRef
    description: str

    def __call__(self, result: LogMatches | LogFailure, program_sha256: str) -> None:
        """Replace the log's rows of this description with ``result``."""
        store_log_result(self.store.open(), self.description, program_sha256, result)


def store_log_result(
    store: ScenarioStore, description: str, program_sha256: str, result: LogMatches | LogFailure
) -> None:
    """Write one log's matches (or failure) to ``mining_runs`` / ``mining_results`` (keyed upserts)."""
    key = normalize_description(description)
    if isinstance(result, LogFailure):
        empty = LogMatches(
            result.log_id, description, program_sha256,
            np.zeros(0, dtype=np.int64), np.zeros(0, dtype=str), np.zeros(0, dtype=str),
            np.zeros((0, 0), dtype=bool), np.zeros((0, 3), dtype=np.int64),
        )  # fmt: skip
        error = result.error.feedback().encode("utf-8", "replace").decode("utf-8")
        runs = runs_table(empty, status="failed", error=error)
        store.upsert_table_rows(result.log_id, RUNS_TABLE, _keyed(runs, key), DESCRIPTION_KEY, [key])
        return
    store.upsert_table_rows(
        result.log_id, RUNS_TABLE, _keyed(runs_table(result), key), DESCRIPTION_KEY, [key]
    )
    cells = _keyed(matches_table(result), key)
    store.upsert_table_rows(result.log_id, MATCHES_TABLE, cells, DESCRIPTION_KEY, [key])


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
    everything: list[LogMatches | LogFailure] = [*report.matches, *report.failures]
    results = [r for r in everything if r.log_id in known]
    for result in sorted(results, key=lambda r: r.log_id):
        store_log_result(store, report.description, report.program_sha256, result)
    return sorted({r.log_id for r in results})


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
