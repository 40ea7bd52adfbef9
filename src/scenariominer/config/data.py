"""Configuration of ingestion, preprocessing and the store."""

from __future__ import annotations

import math
from dataclasses import dataclass

from scenariominer.errors import ConfigError


def _check(ok: bool, key: str, message: str) -> None:
    """Raise a :class:`ConfigError` naming ``key`` unless ``ok``."""
    if not ok:
        raise ConfigError(f"{key} {message}")


@dataclass(frozen=True)
class PreprocessConfig:
    """Gap interpolation and Savitzky-Golay smoothing (braking paper, section III-A).

    Attributes:
        smooth_window_s: Savitzky-Golay window length in seconds, converted to the nearest odd
            number of samples at the log's frame rate (11 samples at 10 Hz, 25 at 25 Hz).
            One second is long enough to remove the ~0.1 m frame-to-frame jitter of 3D box
            annotations yet short enough that a hard braking manoeuvre (about 0.5 s to build
            up -6 m/s^2) keeps its onset: features lasting longer than roughly a third of the
            window survive a cubic fit, whereas spline fitting would flatten them.
        smooth_polyorder: polynomial order of the filter; 3 keeps a velocity step's shape
            (a quadratic would round it off more, a higher order lets jitter back in).
        max_gap_s: gaps inside a track's lifespan up to this length are interpolated linearly;
            longer gaps stay empty (the object was most likely occluded and re-identified).
        smooth_yaw: also smooth the heading (after unwrapping) with the same filter.
    """

    smooth_window_s: float = 1.0
    smooth_polyorder: int = 3
    max_gap_s: float = 2.0
    smooth_yaw: bool = True

    def __post_init__(self) -> None:
        _check(0.0 < self.smooth_window_s <= 60.0, "smooth_window_s", "must be in (0, 60] seconds")
        _check(1 <= self.smooth_polyorder <= 7, "smooth_polyorder", "must be an integer from 1 to 7")
        _check(0.0 <= self.max_gap_s <= 3600.0, "max_gap_s", "must be in [0, 3600] seconds")


@dataclass(frozen=True)
class IngestConfig:
    """How raw datasets are cut into logs.

    Attributes:
        highd_window_s: highD recordings are cut into windows of this many seconds (default 15 s,
            about the length of an Argoverse 2 log).
        highd_ego_ids: highD vehicle ids to treat as ego; empty means every vehicle whose track
            covers a full window.
        highd_max_egos_per_recording: cap on egos per recording (0 = no cap) to bound store size.
        highd_radius_m: other vehicles appear in a highD window while within this distance of the
            ego (a sensor-like range; highD covers about 420 m of road).
        min_track_frames: tracks with fewer observations are dropped with a note.
    """

    highd_window_s: float = 15.0
    highd_radius_m: float = 150.0
    highd_ego_ids: tuple[int, ...] = ()
    highd_max_egos_per_recording: int = 20
    min_track_frames: int = 2

    def __post_init__(self) -> None:
        _check(0.0 < self.highd_window_s <= 3600.0, "highd_window_s", "must be in (0, 3600] seconds")
        _check(
            self.highd_radius_m > 0.0 and math.isfinite(self.highd_radius_m), "highd_radius_m", "must be > 0"
        )
        _check(all(i >= 0 for i in self.highd_ego_ids), "highd_ego_ids", "must hold non-negative vehicle ids")
        _check(
            self.highd_max_egos_per_recording >= 0, "highd_max_egos_per_recording", "must be >= 0 (0: no cap)"
        )
        _check(self.min_track_frames >= 1, "min_track_frames", "must be at least 1")


@dataclass(frozen=True)
class StoreConfig:
    """Where the scenario store lives.

    Attributes:
        path: store directory; empty means the per-user data directory
            (``platformdirs.user_data_dir("scenariominer")/store``).
    """

    path: str = ""
