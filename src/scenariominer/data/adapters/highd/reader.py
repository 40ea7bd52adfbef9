"""highD recordings cut into ego-centred windows, and the adapter that reads them into logs."""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from scenariominer.config import Config
from scenariominer.data.adapters.highd.format import (
    DEFAULT_RADIUS_M,
    HighDFiles,
    HighDRecording,
    read_highd_recording,
)
from scenariominer.data.log import Log, LogFormatError, build_log
from scenariominer.data.sources import LogSource

IntArray = NDArray[np.int64]


# ---------------------------------------------------------------------------------------- windows


@dataclass(frozen=True)
class HighDWindow:
    """One (ego, window) cut of a recording.

    Attributes:
        ego_id: highD id of the ego vehicle.
        index: window number ``k`` within the ego's span (0-based).
        first_frame: first highD frame of the window (inclusive).
        stop_frame: frame after the last one (exclusive).
    """

    ego_id: int
    index: int
    first_frame: int
    stop_frame: int

    def log_id(self, recording_id: int) -> str:
        """Return the log id ``highd-<recording:02d>-ego<id>-w<k>``."""
        return f"highd-{recording_id:02d}-ego{self.ego_id}-w{self.index}"


def plan_windows(
    recording: HighDRecording,
    window_s: float,
    ego_ids: Sequence[int] = (),
    max_egos: int = 0,
) -> list[HighDWindow]:
    """Choose egos and cut each one's visible span into full windows of ``window_s``.

    Args:
        recording: the recording.
        window_s: window length in seconds (``round(window_s * frameRate)`` frames).
        ego_ids: explicit egos; ids absent from the recording or visible for less than one window
            are skipped (so one id list can serve many recordings). Empty: every vehicle visible for
            at least one window, thinned to ``max_egos`` evenly spread over the ascending ids
            (highD ids grow with entry time, so the choice spreads over the recording).
        max_egos: cap on automatically chosen egos; 0 means no cap.

    Returns:
        Windows ordered by ego id, then window index.

    Raises:
        ValueError: ``window_s`` is not positive.
    """
    if not window_s > 0:
        raise ValueError(f"highd_window_s must be positive, got {window_s}")
    n_win_frames = max(2, round(window_s * recording.meta.frame_rate_hz))
    first = recording.frame[recording.track_start]
    last = recording.frame[recording.track_start + recording.track_count - 1]
    span = last - first + 1
    eligible = span >= n_win_frames
    if ego_ids:
        wanted = np.isin(recording.vehicle_ids, np.asarray(list(ego_ids), dtype=np.int64))
        chosen = np.flatnonzero(wanted & eligible)
    else:
        chosen = np.flatnonzero(eligible)
        if max_egos > 0 and chosen.size > max_egos:
            picks = np.unique(np.round(np.linspace(0, chosen.size - 1, max_egos)).astype(np.int64))
            chosen = chosen[picks]
    windows: list[HighDWindow] = []
    for v in chosen.tolist():
        start = int(first[v])
        for k in range(int(span[v]) // n_win_frames):
            f0 = start + k * n_win_frames
            windows.append(HighDWindow(int(recording.vehicle_ids[v]), k, f0, f0 + n_win_frames))
    return windows


def window_log(
    recording: HighDRecording,
    window: HighDWindow,
    *,
    radius_m: float | None = DEFAULT_RADIUS_M,
    source_hash: str = "",
    min_track_frames: int = 2,
) -> Log:
    """Build the :class:`Log` of one (ego, window).

    The ego is row 0 (category ``EGO_VEHICLE``); another vehicle's cell is kept when the ego is
    observed at that frame and the two box centres are at most ``radius_m`` apart (``None``: no
    limit). Vectorised: one slice of the frame-sorted rows and a distance mask.
    """
    rec = recording
    lo, hi = np.searchsorted(rec.frame_sorted, [window.first_frame, window.stop_frame])
    rows = rec.frame_order[lo:hi]
    ego_rows = rec.vehicle_rows(window.ego_id)
    ego_frames = rec.frame[ego_rows]
    idx = np.clip(np.searchsorted(ego_frames, rec.frame[rows]), 0, ego_frames.size - 1)
    keep = ego_frames[idx] == rec.frame[rows]
    if radius_m is not None:
        dist = np.hypot(rec.x_m[rows] - rec.x_m[ego_rows][idx], rec.y_m[rows] - rec.y_m[ego_rows][idx])
        keep &= dist <= radius_m
    rows = rows[keep]
    veh = rec.row_vehicle[rows]
    fields = {
        "x_m": rec.x_m[rows],
        "y_m": rec.y_m[rows],
        "z_m": np.zeros(rows.size),
        "yaw_rad": rec.yaw_rad[rows],
        "length_m": rec.length_m[rows],
        "width_m": rec.width_m[rows],
        "height_m": rec.height_m[rows],
        "vx_mps": rec.vx_mps[rows],
        "vy_mps": rec.vy_mps[rows],
        "ax_mps2": rec.ax_mps2[rows],
        "ay_mps2": rec.ay_mps2[rows],
    }
    log = build_log(
        log_id=window.log_id(rec.files.recording_id),
        track_id=rec.vehicle_ids.astype(str)[veh],
        category=rec.vehicle_categories[veh],
        timestamp_ns=rec.t_ns[rows],
        fields=fields,
        ego_track_id=str(window.ego_id),
        source=rec.files.tracks,
        dataset="highd",
        source_hash=source_hash,
        min_track_frames=min_track_frames,
    )
    return log.replace(notes=rec.notes + log.notes) if rec.notes else log


# ---------------------------------------------------------------------------------------- reader


#: Sentinel for :class:`HighDReader`: take the radius from ``config.ingest.highd_radius_m``.
RADIUS_FROM_CONFIG = -1.0


class HighDReader:
    """Reads highD recordings (``NN_tracks.csv`` + meta files) as ego-centred windowed logs.

    Args:
        radius_m: other vehicles appear in a log while within this distance of the ego (metres);
            ``None`` keeps every vehicle of the window; the default (:data:`RADIUS_FROM_CONFIG`)
            uses ``config.ingest.highd_radius_m`` at read time.
    """

    format = "highd"

    def __init__(self, radius_m: float | None = RADIUS_FROM_CONFIG) -> None:
        self.radius_m = radius_m

    def discover(self, path: Path) -> list[LogSource]:
        """Find recordings at ``path``: one highD file, or a folder (or its ``data/`` subfolder) of them.

        Raises:
            LogFormatError: a tracks file lacks one of its meta files (naming the missing file).
        """
        if path.is_file():
            found = HighDFiles.from_path(path)
            return [] if found is None else [self._source(found)]
        if not path.is_dir():
            return []
        sources: list[LogSource] = []
        for folder in (path, path / "data"):
            if not folder.is_dir():
                continue
            for tracks in sorted(folder.glob("*_tracks.csv")):
                found = HighDFiles.from_path(tracks)
                if found is not None:
                    sources.append(self._source(found))
        return sources

    def _source(self, files: HighDFiles) -> LogSource:
        tracks = files.tracks.resolve()
        return LogSource(
            key=str(tracks),
            format=self.format,
            path=tracks,
            files=tuple(f.resolve() for f in files.all),
        )

    def read(self, source: LogSource, config: Config) -> Iterator[Log]:
        """Yield one log per (ego, window) of the recording, ordered by ego id then window."""
        files = HighDFiles.from_path(source.path)
        if files is None:
            raise LogFormatError(source.path, "not a highD file name (expected NN_tracks.csv)")
        recording = read_highd_recording(files)
        ingest = config.ingest
        windows = plan_windows(
            recording, ingest.highd_window_s, ingest.highd_ego_ids, ingest.highd_max_egos_per_recording
        )
        if not windows:
            who = "chosen ego (ingest.highd_ego_ids)" if ingest.highd_ego_ids else "vehicle"
            raise LogFormatError(
                source.path,
                f"no {who} of highD recording {files.recording_id:02d} is visible for a full "
                f"{ingest.highd_window_s:g} s window (ingest.highd_window_s); nothing to ingest",
            )
        source_hash = source.content_hash()
        for window in windows:
            yield window_log(
                recording,
                window,
                radius_m=ingest.highd_radius_m if self.radius_m == RADIUS_FROM_CONFIG else self.radius_m,
                source_hash=source_hash,
                min_track_frames=ingest.min_track_frames,
            )
