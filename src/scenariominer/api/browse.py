"""Use cases of the scenario browser: ``list_logs``, ``log_events`` and ``scene``.

What the web UI needs beyond search: the logs with their metadata and event counts, the events
of one log, and one scenario as arrays (tracks over the event's window, the map's lanes and
crossings around them, the key object's tags) for the animated bird's-eye view. Nothing here prints.
"""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pyarrow.compute as pc
from numpy.typing import NDArray

from scenariominer.data.log import LogFormatError
from scenariominer.explain.records import TAGS_TABLE, EventRecord, records_from_table
from scenariominer.explain.search import NoEventsError, load_events
from scenariominer.explain.show import UnknownEventError
from scenariominer.store import LogMeta, ScenarioStore, UnknownTableError
from scenariominer.tags.vocab import TAG_FAMILIES

__all__ = ["LogEntry", "Scene", "SceneRequest", "list_logs", "log_events", "scene"]

#: Margin around the tracks' extent inside which map elements are returned, metres.
MAP_MARGIN_M = 20.0

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class LogEntry:
    """One stored log for the browser's table.

    Attributes:
        meta: what the store records about the log.
        n_events: analysed braking events of the log (0 when not analysed).
        event_categories: number of events per category.
    """

    meta: LogMeta
    n_events: int
    event_categories: dict[str, int] = field(default_factory=dict)


def list_logs(store: ScenarioStore) -> list[LogEntry]:
    """Every log of the store with its metadata and its events per category, sorted by log id."""
    try:
        events = load_events(store)
        pairs = zip(events.column("log_id").to_pylist(), events.column("category").to_pylist(), strict=True)
        per_log: dict[str, Counter[str]] = {}
        for log_id, category in pairs:
            per_log.setdefault(str(log_id), Counter())[str(category)] += 1
    except NoEventsError:
        per_log = {}
    out = []
    for log_id in store.log_ids():
        counts = per_log.get(log_id, Counter())
        out.append(LogEntry(store.log_meta(log_id), sum(counts.values()), dict(sorted(counts.items()))))
    return out


def log_events(store: ScenarioStore, log_id: str) -> list[EventRecord]:
    """The analysed events of one log, in time order (empty when the log has none).

    Raises:
        UnknownLogError: the log is not in the store.
    """
    store.log_meta(log_id)
    try:
        records = records_from_table(load_events(store, [log_id]))
    except NoEventsError:
        return []
    return sorted(records, key=lambda r: (r.start_ns, r.guest_id))


@dataclass(frozen=True)
class SceneRequest:
    """Which scenario to draw.

    Attributes:
        log_id: the log.
        event_id: one of its events (``<log>:<guest>:<start_ns>``); ``None`` draws the whole log.
        max_timestamps: at most this many timestamps (evenly strided) in the answer.
    """

    log_id: str
    event_id: str | None = None
    max_timestamps: int = 400

    def __post_init__(self) -> None:
        if self.max_timestamps < 2:
            raise ValueError(f"max_timestamps must be at least 2, got {self.max_timestamps}")


@dataclass(frozen=True)
class Scene:
    """One scenario as arrays for a bird's-eye view (N tracks, T timestamps, city frame).

    Attributes:
        log_id: the log.
        event: the event drawn (``None`` for a whole log).
        timestamps_ns: ``(T,)`` timestamps.
        track_ids: ``(N,)`` track ids.
        categories: ``(N,)`` categories.
        ego_index: row of the ego.
        key_index: row of the event's key object (guest), -1 without an event.
        x_m, y_m, yaw_rad, length_m, width_m: ``(N, T)`` box centres, headings and sizes; NaN where
            the track is not observed.
        lanes: lane polygons ``(K_i, 2)`` near the tracks (empty without a map).
        crossings: pedestrian-crossing polygons ``(K_i, 2)`` near the tracks.
        tags: per tag family, the key object's ``(T,)`` tags (``None`` where undefined); the ego's
            actor tags under ``ego_<family>``. Empty when the log has no tags table.
    """

    log_id: str
    event: EventRecord | None
    timestamps_ns: NDArray[np.int64]
    track_ids: NDArray[np.str_]
    categories: NDArray[np.str_]
    ego_index: int
    key_index: int
    x_m: FloatArray
    y_m: FloatArray
    yaw_rad: FloatArray
    length_m: FloatArray
    width_m: FloatArray
    lanes: list[FloatArray]
    crossings: list[FloatArray]
    tags: dict[str, list[str | None]]


def _find(records: list[EventRecord], log_id: str, event_id: str) -> EventRecord:
    for r in records:
        if r.event_id == event_id:
            return r
    raise UnknownEventError(f"event {event_id!r} is not in log {log_id}")


def scene(store: ScenarioStore, request: SceneRequest) -> Scene:
    """The arrays of one scenario: the event's analysis window (or the whole log), map and tags.

    Raises:
        UnknownLogError: the log is not in the store.
        UnknownEventError: the event is not in the log.
    """
    log = store.load_log(request.log_id)
    event = None
    key = -1
    cols = np.arange(log.n_timestamps)
    if request.event_id is not None:
        event = _find(log_events(store, request.log_id), request.log_id, request.event_id)
        key = log.track_index(event.guest_id)
        ts = log.timestamps_ns
        cols = np.flatnonzero((ts >= event.window_start_ns) & (ts <= event.window_end_ns))
    if cols.size > request.max_timestamps:
        cols = cols[np.linspace(0, cols.size - 1, request.max_timestamps).round().astype(np.int64)]
    valid = log.valid[:, cols]
    rows = np.flatnonzero(valid.any(axis=1) | (np.arange(log.n_tracks) == log.ego_index))

    def pick(values: FloatArray) -> FloatArray:
        return np.where(valid[rows], values[np.ix_(rows, cols)], np.nan)

    x_m, y_m = pick(log.x_m), pick(log.y_m)
    lanes, crossings = _map_near(log.map_dir, x_m, y_m) if log.map_dir is not None else ([], [])
    new_row = {int(r): i for i, r in enumerate(rows)}
    tags = _tags(store, request.log_id, log.timestamps_ns[cols], log.track_ids[log.ego_index], event)
    return Scene(
        log_id=log.log_id,
        event=event,
        timestamps_ns=log.timestamps_ns[cols],
        track_ids=log.track_ids[rows],
        categories=log.categories[rows],
        ego_index=new_row[log.ego_index],
        key_index=new_row.get(key, -1),
        x_m=x_m,
        y_m=y_m,
        yaw_rad=pick(log.yaw_rad),
        length_m=pick(log.length_m),
        width_m=pick(log.width_m),
        lanes=lanes,
        crossings=crossings,
        tags=tags,
    )


def _map_near(map_dir: Path, x_m: FloatArray, y_m: FloatArray) -> tuple[list[FloatArray], list[FloatArray]]:
    """Lane and crossing outlines within :data:`MAP_MARGIN_M` of the tracks (none if unreadable)."""
    import shapely

    from scenariominer.data.adapters.av2.map import read_av2_map

    if not np.isfinite(x_m).any():
        return [], []
    try:
        av2_map = read_av2_map(map_dir)
    except LogFormatError:
        return [], []  # the scene is still useful without its map
    view = shapely.box(
        np.nanmin(x_m) - MAP_MARGIN_M,
        np.nanmin(y_m) - MAP_MARGIN_M,
        np.nanmax(x_m) + MAP_MARGIN_M,
        np.nanmax(y_m) + MAP_MARGIN_M,
    )

    def outlines(polygons: NDArray[np.object_]) -> list[FloatArray]:
        out = []
        for poly in polygons:
            if poly is None or poly.is_empty or not poly.intersects(view):
                continue
            for part in getattr(poly, "geoms", [poly]):
                if part.geom_type == "Polygon":
                    out.append(np.asarray(part.exterior.coords, dtype=np.float64)[:, :2])
        return out

    return outlines(av2_map.lane_polygons), outlines(av2_map.crosswalk_polygons)


def _tags(
    store: ScenarioStore,
    log_id: str,
    timestamps_ns: NDArray[np.int64],
    ego_id: str,
    event: EventRecord | None,
) -> dict[str, list[str | None]]:
    """The key object's tags and the ego's actor tags at ``timestamps_ns`` (see :class:`Scene`)."""
    if event is None:
        return {}
    try:
        table = store.read_table(TAGS_TABLE, [log_id])
    except UnknownTableError:
        return {}
    out: dict[str, list[str | None]] = {}
    wanted = (("", event.guest_id, list(TAG_FAMILIES)), ("ego_", ego_id, ["longitude", "latitude"]))
    for prefix, track_id, families in wanted:
        rows = table.filter(pc.equal(table.column("track_id"), track_id))
        at = {int(t): i for i, t in enumerate(rows.column("timestamp_ns").to_pylist())}
        for family in families:
            values = rows.column(family).cast("string").to_pylist()
            out[prefix + family] = [values[at[int(t)]] if int(t) in at else None for t in timestamps_ns]
    return out
