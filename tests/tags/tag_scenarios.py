"""Hand-built traffic scenes with known answers, shared by the tag tests.

Each scene is integrated exactly from a speed and yaw-rate profile (sub-stepped), turned into a
:class:`Log` through :func:`build_log` and preprocessed like real data.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from scenariominer.data.log import Log, build_log
from scenariominer.data.preprocess import preprocess

DT_S = 0.1


def times(duration_s: float, dt_s: float = DT_S) -> np.ndarray:
    return np.arange(int(round(duration_s / dt_s)) + 1) * dt_s


@dataclass
class Track:
    """A track sampled at the scene's timestamps (``present`` selects the observed frames)."""

    track_id: str
    category: str
    x_m: np.ndarray
    y_m: np.ndarray
    yaw_rad: np.ndarray
    length_m: float = 4.5
    width_m: float = 2.0
    present: np.ndarray | None = field(default=None)


def integrate(
    t_s: np.ndarray,
    speed_mps: np.ndarray | float,
    yaw_rate_radps: np.ndarray | float = 0.0,
    x0_m: float = 0.0,
    y0_m: float = 0.0,
    yaw0_rad: float = 0.0,
    substeps: int = 50,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Position and heading of a point moving along its heading (negative speed = backwards)."""
    speed = np.broadcast_to(np.asarray(speed_mps, dtype=float), t_s.shape)
    rate = np.broadcast_to(np.asarray(yaw_rate_radps, dtype=float), t_s.shape)
    fine = np.linspace(t_s[0], t_s[-1], (t_s.size - 1) * substeps + 1)
    v = np.interp(fine, t_s, speed)
    w = np.interp(fine, t_s, rate)
    h = np.diff(fine)
    yaw = yaw0_rad + np.concatenate([[0.0], np.cumsum(0.5 * (w[1:] + w[:-1]) * h)])
    vx, vy = v * np.cos(yaw), v * np.sin(yaw)
    x = x0_m + np.concatenate([[0.0], np.cumsum(0.5 * (vx[1:] + vx[:-1]) * h)])
    y = y0_m + np.concatenate([[0.0], np.cumsum(0.5 * (vy[1:] + vy[:-1]) * h)])
    return x[::substeps], y[::substeps], np.angle(np.exp(1j * yaw[::substeps]))


def braking_speed(t_s: np.ndarray, v0_mps: float, brake_at_s: float, decel_mps2: float) -> np.ndarray:
    """Constant speed, then constant deceleration from ``brake_at_s`` down to standstill."""
    return np.maximum(v0_mps - decel_mps2 * np.clip(t_s - brake_at_s, 0.0, None), 0.0)


def make_log(tracks: list[Track], t_s: np.ndarray, *, smooth: bool = True, log_id: str = "scene") -> Log:
    """Build (and by default preprocess) a log; the first track is the ego."""
    tid, cat, ts, cols = [], [], [], {k: [] for k in ("x_m", "y_m", "yaw_rad", "length_m", "width_m")}
    for tr in tracks:
        keep = np.ones(t_s.size, dtype=bool) if tr.present is None else tr.present
        k = int(keep.sum())
        tid += [tr.track_id] * k
        cat += [tr.category] * k
        ts.append(np.round(t_s[keep] * 1e9).astype(np.int64))
        cols["x_m"].append(tr.x_m[keep])
        cols["y_m"].append(tr.y_m[keep])
        cols["yaw_rad"].append(tr.yaw_rad[keep])
        cols["length_m"].append(np.full(k, tr.length_m))
        cols["width_m"].append(np.full(k, tr.width_m))
    log = build_log(
        log_id=log_id,
        track_id=tid,
        category=cat,
        timestamp_ns=np.concatenate(ts),
        fields={k: np.concatenate(v) for k, v in cols.items()},
        ego_track_id=tracks[0].track_id,
        source="<scene>",
        dataset="synthetic",
    )
    return preprocess(log) if smooth else log


# ---------------------------------------------------------------------- scenes


def braking_lead_scene() -> Log:
    """Ego follows a lead car at 10 m/s (15.5 m bumper gap); the lead brakes hard (-6 m/s^2) at 3 s,
    the ego reacts at 4 s (-5 m/s^2); both stop without touching. A car drives in parallel 30 m to
    the left and a car is parked at the kerb 5 m to the right of the ego's lane."""
    t = times(10.0)
    ego = integrate(t, braking_speed(t, 10.0, 4.0, 5.0))
    lead = integrate(t, braking_speed(t, 10.0, 3.0, 6.0), x0_m=20.0)
    far = integrate(t, 10.0, x0_m=0.0, y0_m=30.0)
    parked = integrate(t, 0.0, x0_m=30.0, y0_m=-5.0)
    return make_log(
        [
            Track("ego", "EGO_VEHICLE", *ego),
            Track("lead", "REGULAR_VEHICLE", *lead),
            Track("far", "REGULAR_VEHICLE", *far),
            Track("parked", "REGULAR_VEHICLE", *parked),
        ],
        t,
    )


def crossing_pedestrian_scene() -> Log:
    """Ego drives at 1.5 m/s; a pedestrian crosses its path 15 m ahead from right to left at 1.5 m/s,
    starting 9 m to the right, and clears the lane just before the ego passes."""
    t = times(12.0)
    ego = integrate(t, 1.5)
    ped = integrate(t, 1.5, x0_m=15.0, y0_m=-9.0, yaw0_rad=np.pi / 2)
    return make_log(
        [Track("ego", "EGO_VEHICLE", *ego), Track("ped", "PEDESTRIAN", *ped, length_m=0.6, width_m=0.6)], t
    )


def left_turn_scene() -> Log:
    """Ego drives +x at 8 m/s, turns left through 90° on a 10 m radius from 3.75 s, then drives +y.
    An oncoming car drives -x at 8 m/s in the opposite lane (y = +3.5 m)."""
    t = times(8.0)
    turn_s = (np.pi / 2) * 10.0 / 8.0
    rate = np.where((t >= 3.75) & (t < 3.75 + turn_s), 0.8, 0.0)
    ego = integrate(t, 8.0, rate, x0_m=-30.0)
    oncoming = integrate(t, 8.0, x0_m=25.0, y0_m=3.5, yaw0_rad=np.pi)
    return make_log([Track("ego", "EGO_VEHICLE", *ego), Track("oncoming", "REGULAR_VEHICLE", *oncoming)], t)
