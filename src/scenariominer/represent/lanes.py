"""Lane ids of a log's tracks, where the data has them (highD ``laneId``, Argoverse 2 lane segments).

The canonical :class:`~scenariominer.data.log.Log` carries no lanes, so they are looked up in the
log's source: a highD log's recording (its ``laneId`` column, per vehicle and frame), or an
Argoverse 2 log's vector map (the lane segment under each box centre, chosen as mining does,
:meth:`scenariominer.mine.context.MapIndex.lanes_at`). Logs of other formats, or whose source is no
longer on disk, have no lanes (``None``); windows then carry -1.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from scenariominer.data.adapters.highd import HighDFiles, read_highd_recording
from scenariominer.data.log import Log, LogFormatError

__all__ = ["log_lane_ids"]

IntArray = NDArray[np.int64]


def log_lane_ids(log: Log) -> IntArray | None:
    """``(N, T)`` lane id of each track and timestamp of ``log`` (-1 unknown), or ``None`` if it has none."""
    try:
        if log.dataset == "highd" and log.source_path is not None and Path(log.source_path).is_file():
            return _highd_lanes(
                log, _recording(str(log.source_path), Path(log.source_path).stat().st_mtime_ns)
            )
        if log.map_dir is not None and Path(log.map_dir).is_dir():
            return _map_lanes(log)
    except (LogFormatError, OSError):
        return None
    return None


@dataclass(frozen=True)
class _LaneLookup:
    """A highD recording's ``laneId`` per (vehicle id, frame), sorted for binary search."""

    frame_rate_hz: float
    span: int
    sorted_codes: IntArray
    sorted_lanes: IntArray


@functools.lru_cache(maxsize=4)
def _recording(path: str, mtime_ns: int) -> _LaneLookup | None:
    """The lane look-up of a tracks file (cached: all windows of a recording share it)."""
    files = HighDFiles.from_path(Path(path))
    if files is None:
        return None
    rec = read_highd_recording(files)
    if bool(np.all(rec.lane_id < 0)):
        return None
    span = int(rec.frame.max()) + 2
    codes = rec.vehicle_ids[rec.row_vehicle] * span + rec.frame
    order = np.argsort(codes, kind="stable")
    return _LaneLookup(rec.meta.frame_rate_hz, span, codes[order], rec.lane_id[order])


def _highd_lanes(log: Log, lookup: _LaneLookup | None) -> IntArray | None:
    """Look each (vehicle id, frame) of the log up among the recording's rows."""
    if lookup is None:
        return None
    try:
        vids = log.track_ids.astype(np.int64)
    except ValueError:
        return None
    frames = np.round(log.timestamps_ns.astype(np.float64) * 1e-9 * lookup.frame_rate_hz).astype(np.int64)
    if frames.size == 0 or frames.max() >= lookup.span or frames.min() < 0:
        return None
    query = vids[:, None] * lookup.span + frames[None, :]
    pos = np.clip(np.searchsorted(lookup.sorted_codes, query), 0, lookup.sorted_codes.size - 1)
    hit = (lookup.sorted_codes[pos] == query) & log.valid
    return np.where(hit, lookup.sorted_lanes[pos], -1).astype(np.int64)


def _map_lanes(log: Log) -> IntArray | None:
    """Lane segment id under each box centre from the log's Argoverse 2 vector map."""
    from scenariominer.data.adapters.av2.map import read_av2_map
    from scenariominer.mine.context import MapIndex

    assert log.map_dir is not None
    index = MapIndex(read_av2_map(Path(log.map_dir)))
    if index.n_lanes == 0:
        return None
    lane_idx, _direction = index.lanes_at(log.x_m, log.y_m, log.yaw_rad, log.categories)
    out: IntArray = np.where(lane_idx >= 0, index.lane_ids[np.clip(lane_idx, 0, None)], -1).astype(np.int64)
    return out
