"""The ingestion loop never stops for one source: not for bad data, nor for a bug an odd input meets."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

from scenariominer.config import Config
from scenariominer.data.ingest import MemorySink, ingest_sources
from scenariominer.data.log import Log
from scenariominer.data.sources import InMemoryReader, LogSource
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
