"""Lane ids of a log's tracks, where the data has them (highD ``laneId``, Argoverse 2 lane segments).

The canonical :class:`~scenariominer.data.log.Log` carries no lanes, so they are looked up in the
log's source: a highD log's recording (its ``laneId`` column, per vehicle and frame), or an
Argoverse 2 log's vector map (the lane segment under each box centre, chosen as mining does,
:meth:`scenariominer.mine.context.MapIndex.lanes_at`). Logs of other formats, or whose source is no
longer on disk, have no lanes (``None``); windows then carry -1.
"""

from __future__ import annotations

import functools
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from scenariominer.data.adapters.highd import HighDFiles, HighDRecording, read_highd_recording
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


@functools.lru_cache(maxsize=4)
def _recording(path: str, mtime_ns: int) -> HighDRecording | None:
    """The highD recording of a tracks file (cached: all windows of a recording share it)."""
    files = HighDFiles.from_path(Path(path))
    return None if files is None else read_highd_recording(files)


def _highd_lanes(log: Log, rec: HighDRecording | None) -> IntArray | None:
    """Look each (vehicle id, frame) of the log up among the recording's rows."""
    if rec is None or bool(np.all(rec.lane_id < 0)):
        return None
    try:
        vids = log.track_ids.astype(np.int64)
    except ValueError:
        return None
    frames = np.round(log.timestamps_ns.astype(np.float64) * 1e-9 * rec.meta.frame_rate_hz).astype(np.int64)
    span = int(max(rec.frame.max(), frames.max())) + 1
    row_codes = rec.vehicle_ids[rec.row_vehicle] * span + rec.frame
    order = np.argsort(row_codes, kind="stable")
    sorted_codes = row_codes[order]
    query = vids[:, None] * span + frames[None, :]
    pos = np.clip(np.searchsorted(sorted_codes, query), 0, sorted_codes.size - 1)
    hit = (sorted_codes[pos] == query) & log.valid
    return np.where(hit, rec.lane_id[order[pos]], -1).astype(np.int64)


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
