"""Windows in the store: corpus table ``represent_windows`` keyed by window id, plus a per-log index.

``represent_windows`` (schema 1) has one row per window, key :func:`~.windows.window_id`. Its JSON
holds ``log_id``, ``agent_id``, ``start_ns``, ``start_s``, ``length_s``, ``track_ids`` and
``categories`` (``A`` strings each, ``""`` for padding) and ``config`` (hash of the window settings);
its blob is an uncompressed ``.npz`` with ``xy_m`` ``(A, S, 2)`` float32, ``vxy_mps`` ``(A, S, 2)``
float32, ``valid`` ``(A, S)`` bool and ``lane_ids`` ``(A, S)`` int64 (see
:class:`~.windows.WindowSet`).

``represent_window_logs`` (schema 1) has one row per log, key the log id: ``config``, ``settings``
(the window settings themselves), ``source_hash`` (of the log when its windows were cut) and
``window_ids``. A log whose row matches the current settings and source hash is up to date;
adding a log writes that log's rows only.
"""

from __future__ import annotations

import hashlib
import io
import json
from collections.abc import Mapping, Sequence
from dataclasses import asdict, dataclass
from typing import Any

import numpy as np

from scenariominer.config.represent import WindowConfig
from scenariominer.represent.errors import NoWindowsError, WindowConfigMismatchError
from scenariominer.represent.windows import WindowSet
from scenariominer.store import ScenarioStore

__all__ = [
    "WINDOWS_SCHEMA",
    "WINDOWS_TABLE",
    "WINDOW_LOGS_TABLE",
    "LogWindowsRecord",
    "load_windows",
    "log_window_records",
    "save_log_windows",
    "save_logs_windows",
    "window_config_from",
    "window_config_hash",
]

WINDOWS_TABLE = "represent_windows"
WINDOW_LOGS_TABLE = "represent_window_logs"
WINDOWS_SCHEMA = 1


def window_config_hash(config: WindowConfig) -> str:
    """16-hex-digit hash of the settings that shape a window's content."""
    text = json.dumps(asdict(config), sort_keys=True)
    return hashlib.sha256(text.encode()).hexdigest()[:16]


@dataclass(frozen=True)
class LogWindowsRecord:
    """What the store holds about one log's windows.

    Attributes:
        log_id: the log.
        config: :func:`window_config_hash` of the settings they were cut with.
        source_hash: the log's source hash when they were cut.
        window_ids: ids of its windows (possibly none).
        settings: the window settings themselves (:class:`WindowConfig` fields).
    """

    log_id: str
    config: str
    source_hash: str
    window_ids: tuple[str, ...]
    settings: dict[str, Any]

    def window_config(self) -> WindowConfig:
        """The :class:`WindowConfig` the windows were cut with."""
        return window_config_from(self.settings)


def window_config_from(settings: Mapping[str, Any]) -> WindowConfig:
    """A :class:`WindowConfig` from its stored fields (lists back to tuples)."""
    fields = dict(settings)
    fields["lengths_s"] = tuple(float(v) for v in fields.get("lengths_s", (15.0,)))
    return WindowConfig(**fields)


def _pack(ws: WindowSet, i: int) -> bytes:
    buf = io.BytesIO()
    np.savez(buf, xy_m=ws.xy_m[i], vxy_mps=ws.vxy_mps[i], valid=ws.valid[i], lane_ids=ws.lane_ids[i])
    return buf.getvalue()


def save_log_windows(
    store: ScenarioStore, log_id: str, windows: WindowSet, config: WindowConfig, source_hash: str
) -> None:
    """Replace the windows of ``log_id`` by ``windows`` (cut with ``config``; all from that log)."""
    save_logs_windows(store, {log_id: (windows, source_hash)}, config)


def save_logs_windows(
    store: ScenarioStore, by_log: Mapping[str, tuple[WindowSet, str]], config: WindowConfig
) -> None:
    """Replace the windows of several logs at once: ``log id -> (its windows, its source hash)``.

    Three writes in all (windows, stale windows, per-log records), whatever the number of logs.

    Raises:
        ValueError: a log's windows include windows of another log.
    """
    config_hash = window_config_hash(config)
    rows: dict[str, dict[str, object]] = {}
    blobs: dict[str, bytes] = {}
    records: dict[str, dict[str, object]] = {}
    for log_id, (windows, source_hash) in by_log.items():
        if len(windows) and set(windows.log_ids.tolist()) != {log_id}:
            raise ValueError(f"windows given for log {log_id!r} include windows of other logs")
        ids = windows.window_ids.tolist()
        for i, wid in enumerate(ids):
            rows[wid] = {
                "log_id": log_id,
                "agent_id": str(windows.agent_ids[i]),
                "start_ns": int(windows.start_ns[i]),
                "start_s": float(windows.start_s[i]),
                "length_s": float(windows.length_s[i]),
                "track_ids": windows.track_ids[i].tolist(),
                "categories": windows.categories[i].tolist(),
                "config": config_hash,
            }
            blobs[wid] = _pack(windows, i)
        records[log_id] = {
            "config": config_hash,
            "settings": asdict(config),
            "source_hash": source_hash,
            "window_ids": ids,
        }
    if not records:
        return
    old = log_window_records(store, list(records))
    table = store.corpus(WINDOWS_TABLE, WINDOWS_SCHEMA)
    if rows:
        table.upsert(rows, blobs)
    stale = {w for rec in old.values() for w in rec.window_ids} - set(rows)
    if stale:
        table.delete(sorted(stale))
    store.corpus(WINDOW_LOGS_TABLE, WINDOWS_SCHEMA).upsert(records)


def log_window_records(
    store: ScenarioStore, log_ids: Sequence[str] | None = None
) -> dict[str, LogWindowsRecord]:
    """The per-log window records (all, or those of ``log_ids`` that exist)."""
    rows = store.corpus(WINDOW_LOGS_TABLE, WINDOWS_SCHEMA).rows(None if log_ids is None else list(log_ids))
    return {
        r.key: LogWindowsRecord(
            r.key,
            str(r.data["config"]),
            str(r.data["source_hash"]),
            tuple(r.data["window_ids"]),
            dict(r.data.get("settings") or {}),
        )
        for r in rows
    }


def load_windows(
    store: ScenarioStore, *, log_ids: Sequence[str] | None = None, window_ids: Sequence[str] | None = None
) -> WindowSet:
    """Stored windows (all, those of ``log_ids``, or those under ``window_ids``), in window-id order.

    Raises:
        NoWindowsError: none match.
        WindowConfigMismatchError: the matching windows differ in agents per window or steps.
    """
    keys: list[str] | None = None
    if window_ids is not None:
        keys = sorted(set(window_ids))
    elif log_ids is not None:
        recs = log_window_records(store, log_ids)
        keys = sorted({w for rec in recs.values() for w in rec.window_ids})
    rows = store.corpus(WINDOWS_TABLE, WINDOWS_SCHEMA).rows(keys, with_blobs=True)
    if not rows:
        raise NoWindowsError(
            "no windows in the store for this selection; build them first (scenariominer embed windows)"
        )
    arrays = [np.load(io.BytesIO(r.blob or b"")) for r in rows]
    shapes = {a["valid"].shape for a in arrays}
    if len(shapes) > 1:
        raise WindowConfigMismatchError(
            f"stored windows have different (agents, steps) shapes {sorted(shapes)}; rebuild them "
            "(scenariominer embed windows --rebuild)"
        )
    return WindowSet(
        window_ids=np.asarray([r.key for r in rows], dtype=str),
        log_ids=np.asarray([r.data["log_id"] for r in rows], dtype=str),
        agent_ids=np.asarray([r.data["agent_id"] for r in rows], dtype=str),
        start_ns=np.asarray([r.data["start_ns"] for r in rows], dtype=np.int64),
        start_s=np.asarray([r.data["start_s"] for r in rows], dtype=np.float64),
        length_s=np.asarray([r.data["length_s"] for r in rows], dtype=np.float64),
        track_ids=np.asarray([r.data["track_ids"] for r in rows], dtype=str),
        categories=np.asarray([r.data["categories"] for r in rows], dtype=str),
        xy_m=np.stack([a["xy_m"] for a in arrays]),
        vxy_mps=np.stack([a["vxy_mps"] for a in arrays]),
        valid=np.stack([a["valid"] for a in arrays]),
        lane_ids=np.stack([a["lane_ids"] for a in arrays]),
    )
