"""The ingestion loop never stops for one source: not for bad data, nor for a bug an odd input meets."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

from scenariominer.config import Config
from scenariominer.data.ingest import MemorySink, ingest_sources
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
    """Runs items here, counting how often the loop handed it work."""

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
