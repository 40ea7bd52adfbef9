"""Hand-built traffic scenes with known answers, shared by the tag tests.

Each scene is integrated exactly from a speed and yaw-rate profile (sub-stepped), turned into a
:class:`Log` through :func:`build_log` and preprocessed like real data.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from scenariominer.data.log import Log, build_log
from scenariominer.data.preprocess import preprocess
from scenariominer.testing import braking_speed, integrate, times

DT_S = 0.1


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
