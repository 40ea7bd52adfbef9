"""The one ingestion loop: discover → read → validate → preprocess → hand to a sink.

The sink is where logs go: the scenario store (it implements :class:`LogSink`), or a
:class:`MemorySink` for commands that mine files without a store. Failures are isolated per source:
a source that cannot be read or fails validation is reported with the reason and the loop goes on;
the sink keeps what it had for that source.
"""

from __future__ import annotations

import hashlib
import json
import os
import stat
import time
from collections.abc import Callable, Iterable, Sequence
from concurrent.futures import Future, ThreadPoolExecutor
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Protocol

from scenariominer.config import Config
from scenariominer.data.log import LOG_SCHEMA_VERSION, Log, LogFormatError
from scenariominer.data.preprocess import preprocess
from scenariominer.data.sources import LogReader, LogSource, discover_sources, reader_for
from scenariominer.progress import NullProgress, Progress, step

if TYPE_CHECKING:
    from scenariominer.exec import Executor, ItemOutcome

__all__ = ["IngestTask", "LogSink", "MemorySink", "SourceResult", "ingest_sources", "pipeline_fingerprint"]


class LogSink(Protocol):
    """Where ingested logs go (the scenario store implements it)."""

    def needs_ingest(self, source_key: str, content_hash: str) -> bool:
        """Whether the source must be (re)read: new, or its content or settings changed."""
        ...

    def logs_of_source(self, source_key: str) -> list[str]:
        """Log ids held for a source."""
        ...

    def replace_source(self, source_key: str, content_hash: str, logs: Sequence[Log]) -> list[str]:
        """Replace the source's logs atomically; returns the log ids written."""
        ...

    def replace_sources(
        self, batch: Sequence[tuple[str, str, Sequence[Log]]]
    ) -> Sequence[list[str] | Exception]:
        """Several :meth:`replace_source` calls at once (each source atomic on its own).

        Returns, per source, its log ids or the error that kept it out; raises when the whole batch
        failed (the loop then commits the sources one by one).
        """
        ...


class MemorySink:
    """A sink that keeps the logs in memory (for a one-off run over files)."""

    def __init__(self) -> None:
        self.logs: dict[str, list[Log]] = {}

    def needs_ingest(self, source_key: str, content_hash: str) -> bool:
        """Always: nothing is kept between runs."""
        return True

    def logs_of_source(self, source_key: str) -> list[str]:
        """Log ids read from the source so far."""
        return [log.log_id for log in self.logs.get(source_key, [])]

    def replace_source(self, source_key: str, content_hash: str, logs: Sequence[Log]) -> list[str]:
        """Keep the logs under the source's key."""
        self.logs[source_key] = list(logs)
        return [log.log_id for log in logs]

    def replace_sources(
        self, batch: Sequence[tuple[str, str, Sequence[Log]]]
    ) -> Sequence[list[str] | Exception]:
        """Keep each source's logs under its key (a source whose ``replace_source`` raises gets its error)."""
        outcomes: list[list[str] | Exception] = []
        for key, content_hash, logs in batch:
            try:
                outcomes.append(self.replace_source(key, content_hash, logs))
            except Exception as exc:  # noqa: BLE001 - the source's outcome, as the store reports it
                outcomes.append(exc)
        return outcomes

    def all_logs(self) -> list[Log]:
        """Every log, in the order the sources were read."""
        return [log for logs in self.logs.values() for log in logs]


@dataclass(frozen=True)
class SourceResult:
    """Outcome of ingesting one source.

    Attributes:
        key: the source's stable key (its absolute path).
        format: reader that handled it.
        status: ``ingested``, ``skipped`` (unchanged content) or ``failed``.
        log_ids: logs written (or already present when skipped).
        error: the problem, for failed sources.
        notes: repairs applied while reading (dropped rows, interpolated cells, ...).
        seconds: wall time spent on this source.
        n_frames: valid (track, timestamp) cells of the logs written.
    """

    key: str
    format: str
    status: str
    log_ids: tuple[str, ...] = ()
    error: str = ""
    notes: tuple[str, ...] = ()
    seconds: float = 0.0
    n_frames: int = 0


def pipeline_fingerprint(config: Config) -> str:
    """Hash of what changes the stored logs (a change re-ingests): log schema, preprocess, ingest."""
    payload = json.dumps(
        {
            "log_schema": LOG_SCHEMA_VERSION,
            "preprocess": asdict(config.preprocess),
            "ingest": asdict(config.ingest),
        },
        sort_keys=True,
    )
    return hashlib.sha256(payload.encode()).hexdigest()[:16]


def ingest_sources(
    paths: Iterable[str | Path],
    sink: LogSink,
    config: Config,
    *,
    force: bool = False,
    readers: Sequence[LogReader] | None = None,
    progress: Progress | None = None,
    executor: Executor | None = None,
    reopen: Callable[[], LogSink] | None = None,
    min_pool_bytes: int = 0,
) -> list[SourceResult]:
    """Run the ingestion loop over every source found under ``paths``.

    Never raises for bad input: a path that does not exist or holds nothing recognisable, and a
    source that cannot be read or fails validation, each become a ``failed`` result naming the
    cause, and the other sources are still ingested.

    With an ``executor`` and ``reopen`` (a picklable function that opens the same sink in a worker,
    e.g. a :class:`~scenariominer.store.StoreRef`), each source is read, preprocessed and committed
    by a worker; discovery stays here. Custom ``readers`` always run in this process, and so does
    a batch whose files total fewer than ``min_pool_bytes`` (starting workers would take longer)
    and the in-process (``local``) executor. In this process, each source's commit runs in a
    writer thread while the next source is read, so ``sink.replace_source`` is called from that
    thread (one call at a time) while ``needs_ingest`` and ``logs_of_source`` run in this one.
    """
    progress = progress or NullProgress()
    results: list[SourceResult] = []
    sources: list[LogSource] = []
    seen: set[str] = set()
    for path in paths:
        # Discovery fails per path (missing, unreadable, a symlink loop, nothing recognisable): the
        # path is reported as a failed source and the rest of the batch goes on.
        try:
            found = [s for s in discover_sources([path], readers) if s.key not in seen]
        except (LogFormatError, OSError, ValueError) as exc:
            results.append(SourceResult(str(path), "-", "failed", error=str(exc)))
            continue
        seen.update(s.key for s in found)
        sources += found
    fingerprint = pipeline_fingerprint(config)
    small = min_pool_bytes > 0 and _total_bytes(sources) < min_pool_bytes
    # The in-process executor would gain nothing over the loop below, which overlaps commits with reads.
    in_process = readers is not None or small or (executor is not None and executor.name == "local")
    if executor is not None and reopen is not None and not in_process:
        task = IngestTask(reopen, _Reading(config, fingerprint, force))
        with step(progress, "ingest", len(sources)):
            outcomes = executor.map(
                task, sources, keys=[s.key for s in sources], on_outcome=lambda o: _advance(progress, o)
            )
        return results + [_source_result(source, o) for source, o in zip(sources, outcomes, strict=True)]
    with step(progress, "ingest", len(sources)):
        results += _ingest_pipelined(sources, sink, _Reading(config, fingerprint, force, readers), progress)
    return results


#: Sources committed in one catalog transaction at most, and the valid cells they may hold together
#: (what the loop keeps in memory while a commit runs: about 40 MB of preprocessed arrays).
_BATCH_SOURCES = 64
_BATCH_FRAMES = 250_000


def _ingest_pipelined(
    sources: Sequence[LogSource], sink: LogSink, reading: _Reading, progress: Progress
) -> list[SourceResult]:
    """Ingest ``sources`` in order, committing in a writer thread while the next sources are read.

    A commit (Parquet encoding, fsync, the catalog transaction) spends most of its time outside the
    GIL, so it overlaps reading and preprocessing. The sources read while a commit runs are committed
    together in the next one (one catalog transaction for the batch, each source atomic on its own:
    :meth:`LogSink.replace_sources`), up to :data:`_BATCH_SOURCES` sources or
    :data:`_BATCH_FRAMES` valid cells, which bounds the memory held: at most one batch in flight
    and one being gathered.
    """
    results: list[SourceResult] = []

    def done(batch_results: Sequence[SourceResult]) -> None:
        for result in batch_results:
            results.append(result)
            name = Path(result.key).name
            progress.advance(1, name if result.status == "ingested" else f"{result.status} {name}")

    with ThreadPoolExecutor(max_workers=1, thread_name_prefix="ingest-writer") as writer:
        in_flight: Future[list[SourceResult]] | None = None
        gathered: list[_Prepared] = []
        for source in sources:
            prepared = reading.prepare(source, sink)
            if isinstance(prepared, SourceResult):
                done([prepared])
            else:
                gathered.append(prepared)
            full = len(gathered) >= _BATCH_SOURCES or sum(p.n_frames for p in gathered) >= _BATCH_FRAMES
            if in_flight is not None and (in_flight.done() or full):
                done(in_flight.result())
                in_flight = None
            if in_flight is None and gathered:
                in_flight, gathered = writer.submit(_commit_batch, gathered, sink), []
        if in_flight is not None:
            done(in_flight.result())
        if gathered:
            done(writer.submit(_commit_batch, gathered, sink).result())
    return results


def _total_bytes(sources: Sequence[LogSource]) -> int:
    """Bytes of every regular file of ``sources`` (what an ingest reads; others count as 0)."""
    total = 0
    for source in sources:
        for path in source.files:
            try:
                st = path.stat()
            except OSError:
                continue
            if stat.S_ISREG(st.st_mode):
                total += st.st_size
    return total


@dataclass(frozen=True)
class IngestTask:
    """The worker side of the ingestion loop: read, preprocess and commit one source (picklable)."""

    reopen: Callable[[], LogSink]
    reading: _Reading

    def __call__(self, source: LogSource) -> SourceResult:
        """Ingest ``source`` into the sink ``reopen`` opens in this worker."""
        sink = self.reopen()
        prepared = self.reading.prepare(source, sink)
        return prepared if isinstance(prepared, SourceResult) else _commit(prepared, sink)


def _advance(progress: Progress, outcome: ItemOutcome[SourceResult]) -> None:
    """Progress after one source came back from a worker."""
    status = outcome.value.status if outcome.value is not None else "failed"
    name = Path(outcome.key).name
    progress.advance(1, name if status == "ingested" else f"{status} {name}")


def _source_result(source: LogSource, outcome: ItemOutcome[SourceResult]) -> SourceResult:
    """The worker's result, or a failed result naming why the worker gave none."""
    if outcome.value is not None:
        return outcome.value
    return SourceResult(source.key, source.format, "failed", error=outcome.error, seconds=outcome.seconds)


def _check_utf8_paths(source: LogSource) -> None:
    """Refuse a source whose path is not valid UTF-8: Arrow cannot open it and a store cannot name it."""
    for path in (source.path, *source.files):
        try:
            str(path).encode("utf-8")
        except UnicodeEncodeError:
            raw = os.fsencode(path)
            raise LogFormatError(
                ascii(raw)[2:-1],
                "the path is not valid UTF-8 (undecodable bytes shown as \\xNN); rename it to ingest it",
            ) from None


@dataclass(frozen=True)
class _Prepared:
    """A source read and preprocessed, ready to commit."""

    source: LogSource
    content_hash: str
    logs: list[Log]
    t0: float

    @property
    def n_frames(self) -> int:
        return sum(log.n_frames for log in self.logs)


@dataclass(frozen=True)
class _Reading:
    """How sources are read: the settings, their fingerprint, ``force`` and the readers to try."""

    config: Config
    fingerprint: str
    force: bool
    readers: Sequence[LogReader] | None = None

    def prepare(self, source: LogSource, sink: LogSink) -> _Prepared | SourceResult:
        """The source's preprocessed logs, or its result when it is skipped (unchanged) or fails."""
        t0 = time.perf_counter()
        try:
            _check_utf8_paths(source)
            content_hash = f"{source.content_hash()}:{self.fingerprint}"
            if not self.force and not sink.needs_ingest(source.key, content_hash):
                return SourceResult(
                    source.key, source.format, "skipped", tuple(sink.logs_of_source(source.key))
                )
            reader = reader_for(source, self.readers)
            logs = [preprocess(log, self.config.preprocess) for log in reader.read(source, self.config)]
            if not logs:
                raise LogFormatError(source.path, "the source yielded no logs")
        except Exception as exc:  # noqa: BLE001 - see _failed
            return _failed(source, exc, t0)
        return _Prepared(source, content_hash, logs, t0)


def _commit(prepared: _Prepared, sink: LogSink) -> SourceResult:
    """Hand the prepared logs to the sink; the source's result."""
    try:
        written = sink.replace_source(prepared.source.key, prepared.content_hash, prepared.logs)
    except Exception as exc:  # noqa: BLE001 - see _failed
        return _failed(prepared.source, exc, prepared.t0)
    return _ingested(prepared, written)


def _commit_batch(batch: Sequence[_Prepared], sink: LogSink) -> list[SourceResult]:
    """Hand several sources' logs to the sink at once; their results, in order.

    When the batch as a whole fails (a disk error, a catalog error), each source is committed on its
    own, so the error is reported against the source that meets it and the others still land.
    """
    if len(batch) == 1:
        return [_commit(batch[0], sink)]
    try:
        outcomes = sink.replace_sources([(p.source.key, p.content_hash, p.logs) for p in batch])
    except Exception:  # noqa: BLE001 - retried source by source, which reports each error
        return [_commit(p, sink) for p in batch]
    return [
        _failed(p.source, o, p.t0) if isinstance(o, Exception) else _ingested(p, o)
        for p, o in zip(batch, outcomes, strict=True)
    ]


def _ingested(prepared: _Prepared, written: Sequence[str]) -> SourceResult:
    """The result of a source whose logs the sink took."""
    source, logs = prepared.source, prepared.logs
    return SourceResult(
        source.key,
        source.format,
        "ingested",
        tuple(written),
        notes=tuple(f"{log.log_id}: {note}" for log in logs for note in log.notes),
        seconds=time.perf_counter() - prepared.t0,
        n_frames=sum(log.n_frames for log in logs),
    )


def _failed(source: LogSource, exc: Exception, t0: float) -> SourceResult:
    """The failed result of a source.

    Bad input names its cause; a bug met by one odd input is reported as unexpected (and must not
    abort the batch either).
    """
    seconds = time.perf_counter() - t0
    if isinstance(exc, LogFormatError | OSError | ValueError):
        return SourceResult(source.key, source.format, "failed", error=str(exc), seconds=seconds)
    error = f"{source.path}: unexpected {type(exc).__name__} while reading ({exc}); please report it"
    return SourceResult(source.key, source.format, "failed", error=error, seconds=seconds)
