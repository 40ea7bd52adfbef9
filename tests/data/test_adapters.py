"""The adapter registry: built-ins load lazily, third parties plug in, bad registrations are named."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from scenariominer.config import Config
from scenariominer.data import adapters
from scenariominer.data.log import Log
from scenariominer.data.sources import LogSource, default_readers, discover_sources, reader_for
from scenariominer.errors import DataError
from scenariominer.testing import LogBuilder, times


class DotLogReader:
    """A toy third-party adapter: any ``*.dotlog`` file is one log with an ego driving at 5 m/s."""

    format = "dotlog"

    def discover(self, path: Path) -> list[LogSource]:
        files = [path] if path.is_file() else sorted(path.glob("*.dotlog"))
        return [LogSource(str(f.resolve()), self.format, f, (f,)) for f in files if f.suffix == ".dotlog"]

    def read(self, source: LogSource, config: Config) -> list[Log]:
        return [LogBuilder(times(2.0), log_id=source.path.stem).ego(speed_mps=5.0).build()]


def test_built_in_adapters_are_registered_most_specific_first() -> None:
    assert adapters.adapter_names()[:3] == ["av2", "highd", "tabular"]
    assert [r.format for r in default_readers()][:3] == ["av2", "highd", "tabular"]


def test_a_registered_adapter_discovers_and_reads(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(adapters, "_registry", dict(adapters._registry))
    adapters.register_adapter("dotlog", f"{__name__}:DotLogReader")
    (tmp_path / "run7.dotlog").write_text("x")
    (source,) = discover_sources([tmp_path])
    assert source.format == "dotlog"
    (log,) = reader_for(source).read(source, Config())
    assert log.log_id == "run7"


def test_unknown_or_broken_adapters_are_named() -> None:
    with pytest.raises(DataError, match="no adapter for format 'nope'"):
        adapters.load_adapter("nope")
    with pytest.raises(ValueError, match="module:attribute"):
        adapters.register_adapter("bad", "no_colon")


def test_importing_the_data_package_imports_no_adapter() -> None:
    code = (
        "import sys, scenariominer.data, scenariominer.data.sources; "
        "print([m for m in sys.modules if m.startswith('scenariominer.data.adapters.')])"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "[]"
