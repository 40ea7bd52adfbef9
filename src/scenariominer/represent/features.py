"""Scenario features of windows, mapped onto the embedding plots (the paper's Fig. 2-3).

All are computed from the window arrays, vectorised over windows; the chosen agent is row 0 and
velocities are in its frame at the window start (forward, left).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from scenariominer.represent.windows import WindowSet

__all__ = ["FEATURE_LABELS", "WindowFeatures", "window_features"]

FloatArray = NDArray[np.float64]

#: Plot titles of the features, with units.
FEATURE_LABELS: dict[str, str] = {
    "n_lanes": "number of lanes occupied",
    "lane_change": "lane change of the chosen agent (1 yes, 0 no)",
    "mean_speed_mps": "mean speed [m/s]",
    "n_road_users": "number of road users",
    "lateral_velocity_change_mps2": "peak lateral velocity change [m/s²]",
    "longitudinal_velocity_change_mps2": "longitudinal velocity change [m/s²]",
}


@dataclass(frozen=True)
class WindowFeatures:
    """Per-window features, each ``(W,)`` float64 (NaN where the data cannot tell).

    Attributes:
        n_lanes: distinct lane ids among the observed cells of all agents (NaN without lane ids).
        lane_change: 1.0 when the chosen agent's lane id changes within the window, else 0.0 (NaN
            without lane ids). Meaningful where lane ids are lanes (highD); Argoverse 2 lane
            *segments* also change along a lane.
        mean_speed_mps: the chosen agent's mean speed.
        n_road_users: agents observed at any step (the chosen one included).
        lateral_velocity_change_mps2: largest change of the chosen agent's lateral velocity
            between consecutive steps, per second.
        longitudinal_velocity_change_mps2: the chosen agent's forward velocity at the end minus at
            the start, divided by the window length (positive: it accelerated).
    """

    n_lanes: FloatArray
    lane_change: FloatArray
    mean_speed_mps: FloatArray
    n_road_users: FloatArray
    lateral_velocity_change_mps2: FloatArray
    longitudinal_velocity_change_mps2: FloatArray

    def as_dict(self) -> dict[str, FloatArray]:
        """Feature name → values."""
        return {name: getattr(self, name) for name in FEATURE_LABELS}


def window_features(windows: WindowSet) -> WindowFeatures:
    """Features of every window (see :class:`WindowFeatures`)."""
    lanes = np.where(windows.valid, windows.lane_ids, -1)
    known = lanes >= 0
    has_lanes = known.any(axis=(1, 2))
    flat = lanes.reshape(len(windows), -1)
    sorted_lanes = np.sort(flat, axis=1)
    distinct = (np.diff(sorted_lanes, axis=1) != 0) & (sorted_lanes[:, 1:] >= 0)
    n_lanes = distinct.sum(axis=1) + (sorted_lanes[:, -1] >= 0)
    own = lanes[:, 0]
    own_min = np.where(own >= 0, own, np.iinfo(np.int64).max).min(axis=1)
    own_max = own.max(axis=1)
    own_known = (own >= 0).any(axis=1)
    lane_change = np.where(own_known, (own_max != own_min).astype(float), np.nan)
    v = windows.vxy_mps[:, 0].astype(np.float64)  # (W, S, 2)
    speed = np.hypot(v[..., 0], v[..., 1])
    dt = windows.length_s / (windows.n_steps - 1)
    lat_change = np.abs(np.diff(v[..., 1], axis=1)).max(axis=1) / dt
    lon_change = (v[:, -1, 0] - v[:, 0, 0]) / windows.length_s
    return WindowFeatures(
        n_lanes=np.where(has_lanes, n_lanes, np.nan).astype(np.float64),
        lane_change=lane_change,
        mean_speed_mps=speed.mean(axis=1),
        n_road_users=windows.valid.any(axis=2).sum(axis=1).astype(np.float64),
        lateral_velocity_change_mps2=lat_change,
        longitudinal_velocity_change_mps2=lon_change,
    )
