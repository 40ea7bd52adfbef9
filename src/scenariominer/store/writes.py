"""Replacing sources' logs in a store: several sources per catalog transaction, each atomic on its own.

:meth:`ScenarioStore.replace_source` and :meth:`ScenarioStore.replace_sources` call
:func:`replace_sources`. Every source is validated first (a bad one gets its error and the others
go on); the changed logs of all of them are written to one staging folder; then one catalog
transaction switches every source to its new logs, each inside its own savepoint, so a source that
turns out to conflict there (another source of the batch or another writer took one of its log ids)
is rolled back alone. One transaction for a batch of small logs costs what one costs for a single
log: the catalog's commit (a journal write and its fsyncs) is most of the time a small log takes to
store.
"""

from __future__ import annotations

import contextlib
import json
import os
import sqlite3
from collections import Counter
from collections.abc import Sequence
from dataclasses import dataclass, field
from datetime import datetime
from pathlib import Path
from typing import TYPE_CHECKING

from scenariominer.data.log import Log
from scenariominer.store.catalog import _delete_log_rows, _log_rows
from scenariominer.store.errors import InvalidLogError, InvalidNameError, LogConflictError
from scenariominer.store.layout import (
    _LOGS_DIR,
    TRACKS_TABLE,
    _remove_tree,
    _write_json_atomic,
    log_dir_name,
)
from scenariominer.store.records import LogMeta, _check_storable, _log_digest, _LogRow, _meta_file, _now

if TYPE_CHECKING:
    from scenariominer.store.store import ScenarioStore

__all__ = ["SourceContent", "replace_sources"]

#: One source's new content: (source key, content hash, every log it yields).
SourceContent = tuple[str, str, Sequence[Log]]


@dataclass
class _Write:
    """One source of a batch on its way into the catalog."""

    index: int
    source_key: str
    content_hash: str
    logs: list[Log]
    digests: dict[str, str]
    metas: dict[str, LogMeta]
    now: datetime
    staged: dict[str, Path] = field(default_factory=dict)
    moved: list[Path] = field(default_factory=list)
    garbage: list[Path] = field(default_factory=list)
    kept: list[tuple[Path, LogMeta]] = field(default_factory=list)

    @property
    def ids(self) -> list[str]:
        return [log.log_id for log in self.logs]


def replace_sources(store: ScenarioStore, batch: Sequence[SourceContent]) -> list[list[str] | Exception]:
    """Make each source's logs its complete, current content (see :meth:`ScenarioStore.replace_source`).

    Returns:
        Per source, in the order given: its log ids, or the :class:`InvalidLogError`,
        :class:`InvalidNameError` or :class:`LogConflictError` that kept it out (nothing of it
        was written; the other sources were).

    Raises:
        OSError, sqlite3.Error: writing files or the catalog failed; nothing of the batch is stored.
    """
    outcomes: list[list[str] | Exception] = [[] for _ in batch]
    writes: list[_Write] = []
    now = _now()
    for index, (source_key, content_hash, logs) in enumerate(batch):
        try:
            writes.append(_validated(index, source_key, content_hash, list(logs), now))
        except (InvalidLogError, InvalidNameError) as exc:
            outcomes[index] = exc
    with contextlib.closing(store._connect()) as con:
        before = {w.index: _log_rows(con, w.source_key, w.ids) for w in writes}
    live: list[_Write] = []
    for w in writes:
        try:
            store._check_owners(w.source_key, w.ids, before[w.index])
            live.append(w)
        except LogConflictError as exc:
            outcomes[w.index] = exc

    staging = store._new_staging()
    try:
        for w in live:
            for log in w.logs:
                row = before[w.index].get(log.log_id)
                if row is None or row.digest != w.digests[log.log_id]:
                    w.staged[log.log_id] = store._stage_log(
                        staging, log, w.metas[log.log_id], w.digests[log.log_id]
                    )
        with store._write_txn() as con:
            for w in live:
                con.execute("SAVEPOINT source")
                try:
                    _switch(store, con, w, staging)
                except LogConflictError as exc:
                    con.execute("ROLLBACK TO source")
                    for path in w.moved:
                        _remove_tree(path)
                    w.moved, w.garbage, w.kept = [], [], []
                    outcomes[w.index] = exc
                else:
                    outcomes[w.index] = w.ids
                con.execute("RELEASE source")
    except BaseException:
        for w in live:
            for path in w.moved:
                _remove_tree(path)
        raise
    finally:
        _remove_tree(staging)
    for w in live:
        for version_dir, meta in w.kept:
            with contextlib.suppress(OSError):
                _write_json_atomic(version_dir / "meta.json", _meta_file(meta, w.digests[meta.log_id]))
        store._discard(w.garbage)
    return outcomes


def _validated(index: int, source_key: str, content_hash: str, logs: list[Log], now: datetime) -> _Write:
    """The source's write, once its logs are known to be storable.

    Raises:
        InvalidLogError: a log cannot be stored losslessly, or log ids repeat.
        InvalidNameError: a log id cannot be a directory name.
    """
    ids = [log.log_id for log in logs]
    dupes = sorted(i for i, c in Counter(ids).items() if c > 1)
    if dupes:
        raise InvalidLogError(f"source {source_key}: log id(s) {dupes[:5]} occur more than once")
    for log in logs:
        log_dir_name(log.log_id)
        _check_storable(log)
    digests = {log.log_id: _log_digest(log) for log in logs}
    metas = {log.log_id: LogMeta.of_log(log, source_key, now) for log in logs}
    return _Write(index, source_key, content_hash, logs, digests, metas, now)


def _switch(store: ScenarioStore, con: sqlite3.Connection, w: _Write, staging: Path) -> None:
    """Point the catalog at the source's new logs (inside the caller's transaction).

    Raises:
        LogConflictError: one of its log ids now belongs to another source.
    """
    current: dict[str, _LogRow] = _log_rows(con, w.source_key, w.ids)
    store._check_owners(w.source_key, w.ids, current)
    for log in w.logs:
        log_id = log.log_id
        row = current.get(log_id)
        meta_json = json.dumps(w.metas[log_id].to_json_dict())
        if log_id not in w.staged and (row is None or row.digest != w.digests[log_id]):
            # Another writer changed the log since our first look: write it now.
            w.staged[log_id] = store._stage_log(staging, log, w.metas[log_id], w.digests[log_id])
        if log_id not in w.staged:
            assert row is not None
            con.execute("UPDATE logs SET meta = ? WHERE log_id = ?", (meta_json, log_id))
            w.kept.append((store.root / row.dir, w.metas[log_id]))
            continue
        final = store.root / _LOGS_DIR / log_dir_name(log_id) / w.staged[log_id].name
        final.parent.mkdir(parents=True, exist_ok=True)
        os.replace(w.staged[log_id], final)
        w.moved.append(final)
        if row is not None:
            w.garbage.append(store.root / row.dir)
        rel_dir = final.relative_to(store.root).as_posix()
        con.execute("DELETE FROM log_tables WHERE log_id = ?", (log_id,))
        con.execute(
            "INSERT OR REPLACE INTO logs (log_id, source_key, dir, digest, meta) VALUES (?, ?, ?, ?, ?)",
            (log_id, w.source_key, rel_dir, w.digests[log_id], meta_json),
        )
        con.execute(
            "INSERT INTO log_tables (log_id, name, file, n_rows) VALUES (?, ?, ?, ?)",
            (log_id, TRACKS_TABLE, f"{rel_dir}/{TRACKS_TABLE}.parquet", log.n_frames),
        )
    wanted = set(w.ids)
    for row in current.values():
        if row.source_key == w.source_key and row.log_id not in wanted:
            _delete_log_rows(con, row.log_id)
            w.garbage.append(store.root / row.dir)
    con.execute(
        "INSERT OR REPLACE INTO sources (source_key, content_hash, ingested_at) VALUES (?, ?, ?)",
        (w.source_key, w.content_hash, w.now.isoformat()),
    )
