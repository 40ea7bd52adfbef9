"""Log readers: the Protocol every dataset adapter implements, discovery, and content hashing.

A *source* is the unit of incremental ingestion: a set of files whose content hash decides
whether the logs read from them must be re-ingested. One source yields one or more logs
(an Argoverse 2 log folder yields one; a highD recording yields one log per ego and window).
"""

from __future__ import annotations

import hashlib
import stat
from collections.abc import Iterable, Iterator, Sequence
from dataclasses import dataclass, field
from functools import cached_property
from pathlib import Path
from typing import Protocol, runtime_checkable

from scenariominer.config import Config
from scenariominer.data.log import Log, LogFormatError

_HASH_CHUNK = 1 << 20


@dataclass(frozen=True)
class LogSource:
    """Files that together define one or more logs.

    Attributes:
        key: stable identifier of the source (absolute path of its folder or main file).
        format: reader name (``av2``, ``highd``, ``tabular``, ``memory``).
        path: folder or main file handed to the reader.
        files: every file whose bytes define the logs (hashed for incremental ingestion).
    """

    key: str
    format: str
    path: Path
    files: tuple[Path, ...] = field(default_factory=tuple)

    def content_hash(self) -> str:
        """SHA-256 over the names and bytes of :attr:`files` (sorted), hex-encoded.

        Computed once per object (the ingestion loop and the reader both ask for it); a new
        :class:`LogSource` from discovery hashes the files again.
        """
        return self._content_hash

    @cached_property
    def _content_hash(self) -> str:
        h = hashlib.sha256(self.format.encode())
        for f in sorted(self.files):
            h.update(f.name.encode())
            try:
                if not stat.S_ISREG(f.stat().st_mode):
                    # A FIFO or a device would block or never end: refused without opening it.
                    raise LogFormatError(f, "not a regular file (a folder, FIFO, device or socket); refused")
                with f.open("rb") as fh:
                    while chunk := fh.read(_HASH_CHUNK):
                        h.update(chunk)
            except OSError as exc:
                raise LogFormatError(f, f"cannot read file ({exc.strerror or exc})") from None
        return h.hexdigest()


def check_delimiter(path: Path, header: str) -> None:
    """Refuse a CSV header line without commas that another delimiter splits, saying which."""
    if "," in header:
        return
    for sep in (";", "\t", "|"):
        if sep in header:
            raise LogFormatError(
                path, f"the header has no ',' but {sep!r}: expected a comma-separated file (save it with ',')"
            )


@runtime_checkable
class LogReader(Protocol):
    """A dataset adapter: finds sources under a path and reads logs from a source."""

    #: Short name used in :attr:`LogSource.format` and on the command line.
    format: str

    def discover(self, path: Path) -> list[LogSource]:
        """Sources of this format at or under ``path``; an empty list if there are none."""
        ...

    def read(self, source: LogSource, config: Config) -> Iterator[Log]:
        """Read the logs of ``source``; raise :class:`LogFormatError` naming the file on bad input."""
        ...


class InMemoryReader:
    """A reader over logs already in memory (tests, notebooks, the synthetic generator).

    Its sources have no files; the content hash is the logs' own ``source_hash`` (or log id).
    """

    format = "memory"

    def __init__(self, logs: Sequence[Log]) -> None:
        self._logs = {log.log_id: log for log in logs}

    def discover(self, path: Path) -> list[LogSource]:
        """One source per held log whose id equals ``path.name`` (or all for ``path == Path('*')``)."""
        ids = list(self._logs) if str(path) == "*" else [i for i in self._logs if i == path.name]
        return [LogSource(key=f"memory:{i}", format=self.format, path=Path(i)) for i in ids]

    def read(self, source: LogSource, config: Config) -> Iterator[Log]:
        """Yield the held log named by the source."""
        yield self._logs[source.path.name]


def default_readers() -> list[LogReader]:
    """One instance of every registered adapter, most specific first (see :mod:`.adapters`)."""
    from scenariominer.data.adapters import adapter_names, load_adapter

    readers: list[LogReader] = []
    for name in adapter_names():
        reader = load_adapter(name)
        if not isinstance(reader, LogReader):
            raise LogFormatError(name, "the registered adapter does not implement the LogReader protocol")
        readers.append(reader)
    return readers


def discover_sources(
    paths: Iterable[str | Path], readers: Sequence[LogReader] | None = None
) -> list[LogSource]:
    """Find every source under ``paths`` with the first reader that recognises it.

    Raises:
        LogFormatError: a path does not exist or no reader recognises anything under it.
    """
    readers = list(readers) if readers is not None else default_readers()
    out: list[LogSource] = []
    seen: set[str] = set()
    for raw in paths:
        path = Path(raw).expanduser()
        if not path.exists():
            raise LogFormatError(path, "no such file or directory")
        found: list[LogSource] = []
        for reader in readers:
            found = reader.discover(path)
            if found:
                break
        if not found:
            raise LogFormatError(
                path,
                "not a recognised log: expected an Argoverse 2 log folder (annotations*.feather + "
                "city_SE3_egovehicle.feather) or dataset root, a highD recording (NN_tracks.csv with its "
                "meta files), or a tabular file (.parquet/.csv, see docs/tabular-schema.md)",
            )
        for src in found:
            if src.key not in seen:
                seen.add(src.key)
                out.append(src)
    return out


def reader_for(source: LogSource, readers: Sequence[LogReader] | None = None) -> LogReader:
    """The reader that handles ``source.format``."""
    for reader in readers if readers is not None else default_readers():
        if reader.format == source.format:
            return reader
    raise LogFormatError(source.path, f"no reader for format {source.format!r}")
