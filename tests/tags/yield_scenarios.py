"""Hand-built early smooth yields, where the ego stops well short of the object it yields to.

Geometry (metres, seconds, 10 Hz):

* **Pedestrian yield**: the ego drives +x at 10 m/s from x = -30, brakes gently (0.97 m/s²) from
  t = 1 s and stops with its front bumper 6 m short of a crosswalk at x = 40. A pedestrian walks +y
  across the crosswalk at 1.4 m/s from y = -9.8 (it is in the ego's lane from about t = 6 s). Had
  the ego kept 10 m/s it would have reached the crosswalk at about t = 6.7 s, with the pedestrian
  in its lane. Distractors: a car parked beside the road and a car in the oncoming lane.
* **Left-turn yield**: the ego drives +x at 10 m/s, brakes (1.35 m/s²) from t = 1 s to a stop at
  x = -3 before a left turn (arc of radius 12 m starting at x = 0), waits until t = 11 s and turns.
  A car in the oncoming lane (y = 3.5, heading -x, 12 m/s) passes the point where the turn crosses
  its lane at about t = 6.2 s; the ego gets there 8 s later, so recorded paths never overlap
  within the tags' 3 s window.
"""

from __future__ import annotations

import numpy as np

from scenariominer.data.log import Log
from scenariominer.testing import LogBuilder, times

CROSSWALK_X_M = 40.0
EGO_LENGTH_M = 4.877
TURN_RADIUS_M = 12.0


def _brake_profile(t: np.ndarray, v0: float, brake_at_s: float, stop_distance_m: float) -> np.ndarray:
    """Speed: ``v0`` until ``brake_at_s``, then constant deceleration to stop after ``stop_distance_m``."""
    decel = v0 * v0 / (2.0 * stop_distance_m)
    return np.maximum(v0 - decel * np.clip(t - brake_at_s, 0.0, None), 0.0)


def pedestrian_yield(*, ped_present: np.ndarray | None = None, split_at_s: float | None = None) -> LogBuilder:
    """Builder of the pedestrian yield (see the module docstring); the pedestrian is ``ped``.

    Args:
        ped_present: ``(T,)`` observed samples of the pedestrian (default all).
        split_at_s: when given, the pedestrian's track id switches from ``ped`` to ``ped_b`` at
            this time, with two dropped frames in between.
    """
    t = times(14.0)
    x0 = -30.0
    x_start_brake = x0 + 10.0 * 1.0
    stop_centre = CROSSWALK_X_M - 6.0 - EGO_LENGTH_M / 2.0
    ego_speed = _brake_profile(t, 10.0, 1.0, stop_centre - x_start_brake)
    b = LogBuilder(t, log_id="ped_yield").ego(speed_mps=ego_speed, x0_m=x0)
    present = np.ones(t.size, dtype=bool) if ped_present is None else ped_present
    ped_kw = {
        "speed_mps": 1.4,
        "x0_m": CROSSWALK_X_M,
        "y0_m": -9.8,
        "yaw0_rad": np.pi / 2,
        "length_m": 0.6,
        "width_m": 0.6,
    }
    if split_at_s is None:
        b.add("ped", "PEDESTRIAN", present=present, **ped_kw)  # type: ignore[arg-type]
    else:
        first = present & (t < split_at_s - 1e-9)
        second = present & (t >= split_at_s + 0.2 - 1e-9)
        b.add("ped", "PEDESTRIAN", present=first, **ped_kw)  # type: ignore[arg-type]
        b.add("ped_b", "PEDESTRIAN", present=second, **ped_kw)  # type: ignore[arg-type]
    b.add("parked", "REGULAR_VEHICLE", x0_m=25.0, y0_m=-4.5)
    b.add("oncoming", "REGULAR_VEHICLE", speed_mps=10.0, x0_m=120.0, y0_m=3.5, yaw0_rad=np.pi)
    return b


def _turn_path(s_m: np.ndarray, to_turn_m: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Straight +x ending at x = 0 after ``to_turn_m``, a left quarter circle of radius R, then +y."""
    r = TURN_RADIUS_M
    arc = np.pi / 2 * r
    d = s_m - to_turn_m  # distance past the turn start (negative: before it)
    phi = np.clip(d / r, 0.0, np.pi / 2)
    x = np.where(d < 0, d, np.where(d <= arc, r * np.sin(phi), r))
    y = np.where(d < 0, 0.0, np.where(d <= arc, r * (1 - np.cos(phi)), r + (d - arc)))
    return x, y, np.where(d < 0, 0.0, phi)


def left_turn_yield() -> Log:
    """The left-turn yield (see the module docstring), preprocessed; the oncoming car is ``oncoming``."""
    t = times(18.0)
    x0 = -50.0
    speed = _brake_profile(t, 10.0, 1.0, 37.0)
    go = np.clip(t - 11.0, 0.0, None)
    speed = np.where(t >= 11.0, np.minimum(2.0 * go, 6.0), speed)
    s = np.concatenate([[0.0], np.cumsum(0.5 * (speed[1:] + speed[:-1]) * np.diff(t))])
    x, y, yaw = _turn_path(s, -x0)
    b = LogBuilder(t, log_id="left_yield")
    b.add_path("ego", "EGO_VEHICLE", x, y, yaw, length_m=EGO_LENGTH_M, width_m=2.0)
    b.add("oncoming", "REGULAR_VEHICLE", speed_mps=12.0, x0_m=82.9, y0_m=3.5, yaw0_rad=np.pi)
    b.add("parked", "REGULAR_VEHICLE", x0_m=20.0, y0_m=-5.0)
    return b.build(smooth=True)
