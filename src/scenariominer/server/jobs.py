"""Long work as jobs: a bounded queue, worker processes, progress events, a persisted job table.

Each job runs in its own ``spawn``-ed process (so a cancelled job can be stopped at once and a
crashing one takes nothing else down); at most ``workers`` run at a time and at most
``max_queued`` wait (:class:`QueueFullError` beyond). Progress arrives over one multiprocessing
queue and is kept per job as numbered events (for Server-Sent Events). Every state change is
written to a small SQLite table, so a job the server did not finish before it stopped shows as
``interrupted`` after a restart, never disappears.

States: ``queued`` → ``running`` → ``succeeded`` | ``failed`` | ``cancelled``; ``interrupted``
for jobs found unfinished when the server starts (or still running when it stops).
"""

from __future__ import annotations

import contextlib
import json
import multiprocessing
import queue
import sqlite3
import threading
import uuid
from collections.abc import Iterator, Mapping
from dataclasses import dataclass, field, replace
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

from scenariominer.errors import ScenarioMinerError

__all__ = [
    "FINAL_STATES",
    "Job",
    "JobEvent",
    "JobManager",
    "JobTableBusyError",
    "QueueFullError",
    "UnknownJobError",
]

#: States a job never leaves.
FINAL_STATES = frozenset({"succeeded", "failed", "cancelled", "interrupted"})

#: Progress events kept per job (older ones are dropped; the newest state is always kept).
MAX_EVENTS = 500

#: Seconds the dispatcher waits for a finished process's last message.
_RESULT_GRACE_S = 10.0

_SCHEMA = """
CREATE TABLE IF NOT EXISTS jobs (
    id TEXT PRIMARY KEY, kind TEXT NOT NULL, params TEXT NOT NULL, state TEXT NOT NULL,
    created_at TEXT NOT NULL, started_at TEXT, finished_at TEXT,
    progress TEXT, result TEXT, error TEXT
)
"""


class QueueFullError(ScenarioMinerError):
    """The job queue is full; try again when a job has finished."""


class UnknownJobError(ScenarioMinerError, LookupError):
    """No job has this id."""


class JobTableBusyError(ScenarioMinerError):
    """Another server already runs the jobs of this job table (one server per store)."""


def _lock(path: Path) -> Any:
    """An exclusive lock on ``path`` held until the returned file is closed (or the process ends)."""
    import fcntl

    path.parent.mkdir(parents=True, exist_ok=True)
    handle = path.open("a")
    try:
        fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        handle.close()
        raise JobTableBusyError(
            f"another scenariominer server runs the jobs of {path.with_suffix('')} (one server per store); "
            "stop it, or give this one another store"
        ) from None
    return handle


@dataclass(frozen=True)
class JobEvent:
    """One numbered event of a job: ``state`` changes and ``progress`` of its current step."""

    seq: int
    type: str
    data: dict[str, Any]


@dataclass(frozen=True)
class Job:
    """A job as the API shows it.

    Attributes:
        id: job id (hex).
        kind: the use case (``ingest``, ``analyze``, ``mine`` ...).
        params: the validated request.
        state: see the module docstring.
        created_at, started_at, finished_at: ISO 8601 times (UTC).
        progress: the latest progress event's data (step, done, total, message).
        result: the use case's result as JSON (succeeded jobs).
        error: what went wrong (failed, cancelled and interrupted jobs).
    """

    id: str
    kind: str
    params: dict[str, Any]
    state: str
    created_at: str
    started_at: str | None = None
    finished_at: str | None = None
    progress: dict[str, Any] | None = None
    result: Any = None
    error: str | None = None


@dataclass
class _Live:
    job: Job
    events: list[JobEvent] = field(default_factory=list)
    seq: int = 0
    process: Any = None
    cancel_requested: bool = False


def _now() -> str:
    return datetime.now(UTC).isoformat(timespec="milliseconds")


class JobTable:
    """The persisted job rows (one SQLite file; every write is its own transaction)."""

    def __init__(self, path: Path) -> None:
        path.parent.mkdir(parents=True, exist_ok=True)
        self._path = path
        with self._connect() as con:
            con.execute(_SCHEMA)

    @contextlib.contextmanager
    def _connect(self) -> Iterator[sqlite3.Connection]:
        con = sqlite3.connect(self._path, timeout=30.0)
        try:
            with con:
                yield con
        finally:
            con.close()

    def save(self, job: Job) -> None:
        """Insert or replace ``job``'s row."""
        row = (
            job.id, job.kind, json.dumps(job.params), job.state, job.created_at, job.started_at,
            job.finished_at, json.dumps(job.progress), json.dumps(job.result), job.error,
        )  # fmt: skip
        with self._connect() as con:
            con.execute("INSERT OR REPLACE INTO jobs VALUES (?,?,?,?,?,?,?,?,?,?)", row)

    def load_all(self) -> list[Job]:
        """Every job, oldest first."""
        with self._connect() as con:
            rows = con.execute("SELECT * FROM jobs ORDER BY created_at").fetchall()
        return [
            Job(r[0], r[1], json.loads(r[2]), r[3], r[4], r[5], r[6], json.loads(r[7] or "null"),
                json.loads(r[8] or "null"), r[9])
            for r in rows
        ]  # fmt: skip


class JobManager:
    """Runs jobs in worker processes; see the module docstring.

    Args:
        db_path: SQLite file of the job table.
        store_path: the store every job opens.
        config_path: configuration file every job loads (``None``: defaults and environment).
        workers: jobs running at once.
        max_queued: jobs waiting at most.
    """

    def __init__(
        self,
        db_path: Path,
        store_path: Path,
        config_path: Path | None = None,
        *,
        workers: int = 1,
        max_queued: int = 8,
    ) -> None:
        self._lock_file = _lock(db_path.with_suffix(db_path.suffix + ".lock"))
        self._table = JobTable(db_path)
        self._store_path = str(store_path)
        self._config_path = str(config_path) if config_path is not None else None
        self._ctx = multiprocessing.get_context("spawn")
        self._messages: Any = self._ctx.Queue()
        self._pending: queue.Queue[str | None] = queue.Queue(maxsize=max_queued)
        self._lock = threading.Condition()
        self._live: dict[str, _Live] = {}
        self._closed = False
        for job in self._table.load_all():
            if job.state not in FINAL_STATES:
                note = f"the server stopped while the job was {job.state}; submit it again"
                job = replace(job, state="interrupted", error=note, finished_at=job.finished_at or _now())
                self._table.save(job)
            self._live[job.id] = _Live(job)
        self._threads = [threading.Thread(target=self._read_messages, name="jobs-reader", daemon=True)]
        self._threads += [
            threading.Thread(target=self._dispatch, name=f"jobs-worker-{i}", daemon=True)
            for i in range(workers)
        ]
        for t in self._threads:
            t.start()

    # ------------------------------------------------------------------ public
    def submit(self, kind: str, params: Mapping[str, Any]) -> Job:
        """Queue a job; returns it in state ``queued``.

        Raises:
            QueueFullError: ``max_queued`` jobs are already waiting.
        """
        job = Job(uuid.uuid4().hex, kind, dict(params), "queued", _now())
        with self._lock:
            if self._closed:
                raise QueueFullError("the server is shutting down")
            try:
                self._pending.put_nowait(job.id)
            except queue.Full:
                raise QueueFullError(
                    f"{self._pending.maxsize} jobs are already waiting; try again when one has finished"
                ) from None
            self._live[job.id] = _Live(job)
            self._event(job.id, "state", {"state": "queued"})
        self._table.save(job)
        return job

    def get(self, job_id: str) -> Job:
        """The job with this id.

        Raises:
            UnknownJobError: no such job.
        """
        with self._lock:
            return self._get(job_id).job

    def recent(self, limit: int = 100) -> list[Job]:
        """The newest ``limit`` jobs, newest first."""
        with self._lock:
            jobs = [live.job for live in self._live.values()]
        return sorted(jobs, key=lambda j: j.created_at, reverse=True)[:limit]

    def events_after(self, job_id: str, seq: int, timeout_s: float) -> tuple[list[JobEvent], Job]:
        """Events numbered above ``seq`` (waiting up to ``timeout_s`` for one) and the job now."""
        with self._lock:
            live = self._get(job_id)
            if live.seq <= seq and live.job.state not in FINAL_STATES:
                self._lock.wait(timeout_s)
            return [e for e in live.events if e.seq > seq], live.job

    def cancel(self, job_id: str) -> Job:
        """Cancel a queued or running job (a running one's process is terminated)."""
        with self._lock:
            live = self._get(job_id)
            if live.job.state in FINAL_STATES:
                return live.job
            live.cancel_requested = True
            if live.job.state == "queued":
                self._finish(live, "cancelled", error="cancelled before it started")
            elif live.process is not None:
                live.process.terminate()
            return live.job

    def close(self) -> None:
        """Stop taking jobs, terminate running ones (they become ``interrupted``) and the threads."""
        with self._lock:
            self._closed = True
            for live in self._live.values():
                if live.job.state == "running" and live.process is not None:
                    live.process.terminate()
                    self._finish(live, "interrupted", error="the server stopped while the job ran")
        for _ in self._threads[1:]:
            with contextlib.suppress(queue.Full):
                self._pending.put(None, timeout=1.0)
        self._messages.put(None)
        for t in self._threads:
            t.join(timeout=10.0)
        self._messages.close()
        self._messages.join_thread()
        self._lock_file.close()

    # ------------------------------------------------------------------ internals
    def _get(self, job_id: str) -> _Live:
        live = self._live.get(job_id)
        if live is None:
            raise UnknownJobError(f"no job {job_id!r}")
        return live

    def _event(self, job_id: str, type_: str, data: dict[str, Any]) -> None:
        """Append an event (lock held) and wake the waiting streams."""
        live = self._live[job_id]
        live.seq += 1
        live.events.append(JobEvent(live.seq, type_, data))
        del live.events[:-MAX_EVENTS]
        self._lock.notify_all()

    def _finish(self, live: _Live, state: str, *, result: Any = None, error: str | None = None) -> None:
        """Move a job to a final state (lock held) and persist it."""
        live.job = replace(live.job, state=state, result=result, error=error, finished_at=_now())
        self._event(live.job.id, "state", {"state": state, "error": error})
        self._table.save(live.job)

    def _dispatch(self) -> None:
        from scenariominer.server.worker import run_job

        while True:
            job_id = self._pending.get()
            if job_id is None:
                return
            with self._lock:
                live = self._live[job_id]
                if live.job.state != "queued" or self._closed:
                    continue
                live.process = self._ctx.Process(
                    target=run_job,
                    args=(
                        job_id,
                        live.job.kind,
                        live.job.params,
                        self._store_path,
                        self._config_path,
                        self._messages,
                    ),
                    name=f"scenariominer-job-{job_id[:8]}",
                    daemon=False,  # the mining sandbox starts processes of its own
                )
                live.job = replace(live.job, state="running", started_at=_now())
                self._event(job_id, "state", {"state": "running"})
                live.process.start()
            self._table.save(live.job)
            live.process.join()
            self._settle(live)

    def _settle(self, live: _Live) -> None:
        """After the process ended: wait for its last message, else record why it ended."""
        with self._lock:
            self._lock.wait_for(lambda: live.job.state in FINAL_STATES, timeout=_RESULT_GRACE_S)
            if live.job.state in FINAL_STATES:
                return
            if live.cancel_requested:
                self._finish(live, "cancelled", error="cancelled while running")
            else:
                code = live.process.exitcode if live.process is not None else None
                self._finish(live, "failed", error=f"the worker process ended with exit code {code}")

    def _read_messages(self) -> None:
        while True:
            message = self._messages.get()
            if message is None:
                return
            job_id, type_, payload = message
            with self._lock:
                live = self._live.get(job_id)
                if live is None or live.job.state in FINAL_STATES:
                    continue
                if type_ == "progress":
                    live.job = replace(live.job, progress=payload)
                    self._event(job_id, "progress", payload)
                elif type_ == "result":
                    self._finish(live, "succeeded", result=payload)
                else:
                    self._finish(live, "failed", error=str(payload))
