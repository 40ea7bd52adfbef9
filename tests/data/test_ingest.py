"""The ingestion loop never stops for one source: not for bad data, nor for a bug an odd input meets."""

from __future__ import annotations

import threading
import time
from collections.abc import Iterator, Sequence
from pathlib import Path

import pytest

from scenariominer.config import Config
from scenariominer.data.ingest import _BATCH_SOURCES, MemorySink, ingest_sources
from scenariominer.data.log import Log
from scenariominer.data.sources import InMemoryReader, LogSource
from scenariominer.exec.local import InlineExecutor
from scenariominer.testing import LogBuilder, times


class _BuggyReader(InMemoryReader):
    """Reads the held logs, except one on which it fails with an error that is no format error."""

    def read(self, source: LogSource, config: Config) -> Iterator[Log]:
        if source.path.name == "odd":
            raise TypeError("unsupported operand type(s) for +: 'int' and 'str'")
        yield from super().read(source, config)


def test_an_unexpected_error_fails_its_source_alone_and_names_it(tmp_path: Path) -> None:
    t = times(2.0)
    logs = [LogBuilder(t, log_id=name).ego(speed_mps=5.0).build() for name in ("odd", "fine")]
    for name in ("odd", "fine"):
        (tmp_path / name).mkdir()
    sink = MemorySink()
    paths = [tmp_path / "odd", tmp_path / "fine"]
    results = ingest_sources(paths, sink, Config(), readers=[_BuggyReader(logs)])
    status = {r.key: (r.status, r.error) for r in results}
    assert status["memory:fine"] == ("ingested", "")
    assert status["memory:odd"][0] == "failed"
    assert "unexpected TypeError while reading (unsupported operand" in status["memory:odd"][1]
    assert [log.log_id for log in sink.all_logs()] == ["fine"]


class _CountingExecutor(InlineExecutor):
    """Runs items here, counting how often the loop handed it work (named as a pool would be)."""

    name = "counting"

    def __init__(self) -> None:
        super().__init__()
        self.calls = 0

    def map(self, fn, items, **kwargs):  # type: ignore[no-untyped-def, override]
        self.calls += 1
        return super().map(fn, items, **kwargs)


def test_a_batch_under_min_pool_bytes_is_ingested_here_without_the_executor(tmp_path: Path) -> None:
    from scenariominer import api

    api.synth(tmp_path / "logs", 2, seed=1)
    size = sum(f.stat().st_size for f in (tmp_path / "logs").rglob("*") if f.is_file())
    for threshold, expected_calls in ((size * 10, 0), (size // 10, 1), (0, 1)):
        sink = MemorySink()
        executor = _CountingExecutor()
        results = ingest_sources(
            [tmp_path / "logs"], sink, Config(), executor=executor, reopen=lambda s=sink: s,
            min_pool_bytes=threshold,
        )  # fmt: skip
        assert executor.calls == expected_calls, threshold
        assert [r.status for r in results] == ["ingested", "ingested"]
        assert len(sink.all_logs()) == 2
    assert Config().exec.min_ingest_bytes > 0  # on by default for the process executor


@pytest.mark.parametrize("fail", ["", "memory:c"])
def test_commits_run_one_at_a_time_in_a_writer_thread_each_source_once(tmp_path: Path, fail: str) -> None:
    t = times(2.0)
    names = ["a", "b", "c", "d", "e"]
    reader = _ProbeReader([LogBuilder(t, log_id=n).ego(speed_mps=5.0).build() for n in names])
    sink = _ProbeSink(reader, fail=fail)
    for name in names:
        (tmp_path / name).mkdir()
    results = ingest_sources([tmp_path / n for n in names], sink, Config(), readers=[reader])
    keys = [f"memory:{n}" for n in names]
    assert [r.key for r in results] == keys  # the sources' order, whatever finished first
    assert [c[0] for c in sink.commits] == keys  # each source committed once, in order
    assert all(writer for _, _, writer in sink.commits)
    # a source is committed after it was read, and at most one batch is gathered ahead
    assert all(i + 1 <= read <= i + 1 + _BATCH_SOURCES for i, (_, read, _) in enumerate(sink.commits))
    status = {r.key: (r.status, r.error) for r in results}
    for key in keys:
        if key == fail:
            assert status[key] == ("failed", "memory:c: the store refused it")
        else:
            assert status[key] == ("ingested", "")
    assert [log.log_id for log in sink.all_logs()] == [n for n in names if f"memory:{n}" != fail]


def test_sources_read_while_a_commit_runs_are_committed_together(tmp_path: Path) -> None:
    names = ["a", "b", "c", "d", "e"]
    reader = _ProbeReader([LogBuilder(times(2.0), log_id=n).ego(speed_mps=5.0).build() for n in names])
    sink = _ProbeSink(reader, first_commit_s=1.0)  # reading the other four takes milliseconds
    for name in names:
        (tmp_path / name).mkdir()
    results = ingest_sources([tmp_path / n for n in names], sink, Config(), readers=[reader])
    assert [r.status for r in results] == ["ingested"] * 5
    assert sink.batches == [["memory:a"], ["memory:b", "memory:c", "memory:d", "memory:e"]]


class _ProbeSink(MemorySink):
    """Records the thread of each commit, how many sources had been read when it started, the batches."""

    def __init__(self, reader: _ProbeReader, fail: str = "", first_commit_s: float = 0.0) -> None:
        super().__init__()
        self.reader, self.fail, self.first_commit_s = reader, fail, first_commit_s
        self.commits: list[tuple[str, int, bool]] = []  # (source, sources read by then, writer thread)
        self.batches: list[list[str]] = []
        self._busy = threading.Lock()

    def replace_sources(
        self, batch: Sequence[tuple[str, str, Sequence[Log]]]
    ) -> Sequence[list[str] | Exception]:
        self.batches.append([key for key, _, _ in batch])
        if len(self.batches) == 1:
            time.sleep(self.first_commit_s)
        return super().replace_sources(batch)

    def replace_source(self, source_key: str, content_hash: str, logs: Sequence[Log]) -> list[str]:
        if not self.batches or source_key not in self.batches[-1]:
            self.batches.append([source_key])  # a batch of one goes here directly
            if len(self.batches) == 1:
                time.sleep(self.first_commit_s)
        assert self._busy.acquire(blocking=False), "two commits ran at once"
        try:
            writer = threading.current_thread() is not threading.main_thread()
            self.commits.append((source_key, self.reader.reads, writer))
            if source_key == self.fail:
                raise ValueError(f"{source_key}: the store refused it")
            return super().replace_source(source_key, content_hash, logs)
        finally:
            self._busy.release()


class _ProbeReader(InMemoryReader):
    """Counts the sources read so far."""

    def __init__(self, logs: Sequence[Log]) -> None:
        super().__init__(logs)
        self.reads = 0

    def read(self, source: LogSource, config: Config) -> Iterator[Log]:
        self.reads += 1
        yield from super().read(source, config)
