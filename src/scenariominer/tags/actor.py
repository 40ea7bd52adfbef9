"""Actor activity tags: LongitudeTag and LatitudeTag per track and timestamp (Table I).

Both are computed for every track (the ego included) from the smoothed kinematics of a
preprocessed :class:`~scenariominer.data.log.Log`, vectorised over ``tracks × timestamps``:

* **Longitude** — STANDING_STILL below a ground-speed threshold; REVERSING when the velocity
  points backwards along the box heading; otherwise ACCELERATING / DECELERATING from the
  acceleration projected on the heading, with hysteresis (enter and exit thresholds), else
  CRUISING. Segments shorter than ``min_segment_s`` are absorbed by their neighbour.
* **Latitude** — a moving actor is in a *turning segment* while its yaw rate keeps one sign above
  a small threshold. The heading change accumulated over the whole segment classifies every
  frame of it: VEERING between ``veer_angle_rad`` and ``turn_angle_rad`` (0.05-0.17 rad in the
  paper), TURNING above; left is counter-clockwise. A lane change thus reads VEERING_LEFT then
  VEERING_RIGHT, a 90° intersection turn TURNING for its whole duration.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from scenariominer.config.tags import TagConfig
from scenariominer.data.log import FloatArray, Log
from scenariominer.geometry import yaw_rate_radps
from scenariominer.tags.vocab import ABSENT, LatitudeTag, LongitudeTag, code_of

__all__ = [
    "classify_latitude",
    "classify_longitude",
    "frames_for",
    "hysteresis",
    "latitude_tags",
    "longitude_tags",
    "moving_average",
    "suppress_short_runs",
]

CodeArray = NDArray[np.int8]
BoolArray = NDArray[np.bool_]

_CRUISING = code_of(LongitudeTag.CRUISING)
_STANDING = code_of(LongitudeTag.STANDING_STILL)
_ACCEL = code_of(LongitudeTag.ACCELERATING)
_DECEL = code_of(LongitudeTag.DECELERATING)
_REVERSING = code_of(LongitudeTag.REVERSING)

# Turn-direction codes used internally by the latitude segmentation.
_STRAIGHT, _LEFT, _RIGHT = 0, 1, 2


def frames_for(duration_s: float, t_s: FloatArray) -> int:
    """Return the number of frames spanning ``duration_s`` at the log's median frame interval (at least 1)."""
    if t_s.size < 2 or duration_s <= 0:
        return 1
    dt_s = float(np.median(np.diff(t_s)))
    return max(1, int(round(duration_s / dt_s))) if dt_s > 0 else 1


def hysteresis(on: BoolArray, off: BoolArray) -> BoolArray:
    """Two-threshold switch along axis 1: True from an ``on`` cell until the next ``off`` cell.

    Vectorised by comparing, per cell, the index of the latest ``on`` and the latest ``off`` event
    at or before it. A cell that is both counts as ``off``.

    Args:
        on: ``(N, T)`` bool, cells that switch the state on.
        off: ``(N, T)`` bool, cells that switch it off.

    Returns:
        ``(N, T)`` bool state.
    """
    idx = np.arange(on.shape[1])
    last_on = np.maximum.accumulate(np.where(on & ~off, idx, -1), axis=1)
    last_off = np.maximum.accumulate(np.where(off, idx, -1), axis=1)
    return np.asarray(last_on > last_off, dtype=bool)


def suppress_short_runs(codes: CodeArray, min_frames: int) -> CodeArray:
    """Absorb runs of equal codes shorter than ``min_frames`` into a neighbouring run.

    Along each row, a run (maximal stretch of one code) shorter than ``min_frames`` takes the code
    of the nearest preceding kept run of the same observed span; at the start of a span, the
    following one. :data:`ABSENT` runs are never changed and never spread; a span consisting only
    of short runs is left as it is. Vectorised over runs, not frames.

    Args:
        codes: ``(N, T)`` int codes with :data:`ABSENT` where unobserved.
        min_frames: minimum run length in frames; ``<= 1`` returns ``codes`` unchanged.

    Returns:
        ``(N, T)`` codes of the same dtype.
    """
    if min_frames <= 1 or codes.size == 0:
        return codes
    n, t = codes.shape
    flat = codes.ravel()
    start = np.ones((n, t), dtype=bool)
    start[:, 1:] = codes[:, 1:] != codes[:, :-1]
    start_flat = start.ravel()
    run_start = np.flatnonzero(start_flat)
    run_of_cell = np.cumsum(start_flat) - 1
    run_len = np.diff(np.append(run_start, flat.size))
    run_val = flat[run_start]
    run_row = run_start // t
    absent = run_val == ABSENT
    kept = absent | (run_len >= min_frames)
    if kept.all():
        return codes
    ids = np.arange(run_start.size)
    prev_kept = np.maximum.accumulate(np.where(kept, ids, -1))
    next_kept = np.minimum.accumulate(np.where(kept, ids, ids.size)[::-1])[::-1]
    prev_ok = (prev_kept >= 0) & (run_row[np.maximum(prev_kept, 0)] == run_row)
    prev_ok &= ~absent[np.maximum(prev_kept, 0)]
    next_ok = (next_kept < ids.size) & (run_row[np.minimum(next_kept, ids.size - 1)] == run_row)
    next_ok &= ~absent[np.minimum(next_kept, ids.size - 1)]
    new_val = run_val.copy()
    short = ~kept
    use_prev = short & prev_ok
    use_next = short & ~prev_ok & next_ok
    new_val[use_prev] = run_val[prev_kept[use_prev]]
    new_val[use_next] = run_val[next_kept[use_next]]
    return np.asarray(new_val[run_of_cell].reshape(n, t), dtype=codes.dtype)


def moving_average(values: FloatArray, valid: BoolArray, window: int) -> FloatArray:
    """Centred moving average along axis 1 over ``window`` frames, using only valid cells.

    Near the ends of the array and next to absent cells the window shrinks to the valid cells
    it covers. Vectorised with cumulative sums.

    Args:
        values: ``(N, T)`` values (ignored where not ``valid``).
        valid: ``(N, T)`` mask.
        window: window length in frames; ``<= 1`` returns the values unchanged.

    Returns:
        ``(N, T)`` averages, NaN where not valid.
    """
    if window <= 1:
        return np.where(valid, values, np.nan)
    n, t = values.shape
    filled = np.where(valid, values, 0.0)
    csum = np.zeros((n, t + 1))
    csum[:, 1:] = np.cumsum(filled, axis=1)
    ccount = np.zeros((n, t + 1))
    ccount[:, 1:] = np.cumsum(valid, axis=1)
    half = window // 2
    lo = np.clip(np.arange(t) - half, 0, t)
    hi = np.clip(np.arange(t) + (window - half), 0, t)
    count = ccount[:, hi] - ccount[:, lo]
    with np.errstate(invalid="ignore", divide="ignore"):
        mean = (csum[:, hi] - csum[:, lo]) / count
    return np.where(valid, mean, np.nan)


def classify_longitude(
    speed_mps: FloatArray,
    v_lon_mps: FloatArray,
    a_lon_mps2: FloatArray,
    valid: BoolArray,
    t_s: FloatArray,
    cfg: TagConfig,
) -> CodeArray:
    """LongitudeTag codes from speed, heading-projected velocity and acceleration.

    Precedence: absent, STANDING_STILL, REVERSING, ACCELERATING / DECELERATING (with hysteresis,
    on the acceleration averaged over ``cfg.accel_window_s``), CRUISING; then segments shorter
    than ``cfg.min_segment_s`` are absorbed.

    Args:
        speed_mps: ``(N, T)`` ground speed.
        v_lon_mps: ``(N, T)`` velocity component along the heading (negative when reversing).
        a_lon_mps2: ``(N, T)`` acceleration component along the heading.
        valid: ``(N, T)`` observation mask.
        t_s: ``(T,)`` seconds.
        cfg: thresholds.

    Returns:
        ``(N, T)`` int8 :class:`LongitudeTag` codes, :data:`ABSENT` where not valid.
    """
    with np.errstate(invalid="ignore"):
        standing = valid & ~(speed_mps >= cfg.standing_speed_mps)
        reversing = valid & ~standing & (v_lon_mps < -cfg.reversing_speed_mps)
        forward = valid & ~standing & ~reversing
        a = moving_average(a_lon_mps2, valid & np.isfinite(a_lon_mps2), frames_for(cfg.accel_window_s, t_s))
        a = np.where(forward, a, 0.0)
        accel = hysteresis(forward & (a > cfg.accel_enter_mps2), ~forward | (a < cfg.accel_exit_mps2))
        decel = hysteresis(forward & (a < -cfg.decel_enter_mps2), ~forward | (a > -cfg.decel_exit_mps2))
    codes = np.full(valid.shape, _CRUISING, dtype=np.int8)
    codes[accel] = _ACCEL
    codes[decel] = _DECEL
    codes[reversing] = _REVERSING
    codes[standing] = _STANDING
    codes[~valid] = ABSENT
    return suppress_short_runs(codes, frames_for(cfg.min_segment_s, t_s))


def longitude_tags(log: Log, cfg: TagConfig) -> CodeArray:
    """``(N, T)`` int8 :class:`LongitudeTag` codes for every track of a preprocessed log."""
    c, s = np.cos(log.yaw_rad), np.sin(log.yaw_rad)
    v_lon = log.vx_mps * c + log.vy_mps * s
    a_lon = log.ax_mps2 * c + log.ay_mps2 * s
    return classify_longitude(log.speed_mps, v_lon, a_lon, log.valid, log.t_s, cfg)


def classify_latitude(
    yaw_rate: FloatArray,
    moving: BoolArray,
    valid: BoolArray,
    t_s: FloatArray,
    cfg: TagConfig,
) -> tuple[CodeArray, FloatArray]:
    """LatitudeTag codes from yaw rate by accumulating the heading change of each turning segment.

    Args:
        yaw_rate: ``(N, T)`` yaw rate, rad/s (counter-clockwise positive).
        moving: ``(N, T)`` True where the actor moves (stationary actors face forward).
        valid: ``(N, T)`` observation mask.
        t_s: ``(T,)`` seconds.
        cfg: thresholds.

    Returns:
        ``(N, T)`` int8 :class:`LatitudeTag` codes (:data:`ABSENT` where not valid), and ``(N, T)``
        the signed heading change accumulated over the segment each cell belongs to (rad; 0 outside
        turning segments, NaN where not valid).
    """
    n, t = valid.shape
    rate = np.where(valid & moving, np.nan_to_num(yaw_rate), 0.0)
    direction = np.full((n, t), _STRAIGHT, dtype=np.int8)
    direction[rate > cfg.turn_min_yaw_rate_radps] = _LEFT
    direction[rate < -cfg.turn_min_yaw_rate_radps] = _RIGHT
    direction[~valid] = ABSENT
    direction = suppress_short_runs(direction, frames_for(cfg.min_segment_s, t_s))

    frame_s = np.gradient(t_s) if t >= 2 else np.zeros(t)
    increment = rate * frame_s  # rad swept during each frame
    start = np.ones((n, t), dtype=bool)
    start[:, 1:] = direction[:, 1:] != direction[:, :-1]
    run_of_cell = np.cumsum(start.ravel()) - 1
    total = np.bincount(run_of_cell, weights=increment.ravel())
    turning = (direction == _LEFT) | (direction == _RIGHT)
    accumulated = np.where(turning, total[run_of_cell].reshape(n, t), 0.0)
    magnitude = np.abs(accumulated)
    left = accumulated > 0

    codes = np.full((n, t), code_of(LatitudeTag.FACING_FORWARD), dtype=np.int8)
    veer = turning & (magnitude >= cfg.veer_angle_rad) & (magnitude <= cfg.turn_angle_rad)
    turn = turning & (magnitude > cfg.turn_angle_rad)
    codes[veer & left] = code_of(LatitudeTag.VEERING_LEFT)
    codes[veer & ~left] = code_of(LatitudeTag.VEERING_RIGHT)
    codes[turn & left] = code_of(LatitudeTag.TURNING_LEFT)
    codes[turn & ~left] = code_of(LatitudeTag.TURNING_RIGHT)
    codes[~valid] = ABSENT
    accumulated[~valid] = np.nan
    return codes, accumulated


def latitude_tags(log: Log, cfg: TagConfig) -> CodeArray:
    """``(N, T)`` int8 :class:`LatitudeTag` codes for every track of a preprocessed log."""
    rate = yaw_rate_radps(log.yaw_rad, log.t_s)
    with np.errstate(invalid="ignore"):
        moving = log.speed_mps >= cfg.standing_speed_mps
    codes, _ = classify_latitude(rate, moving, log.valid, log.t_s, cfg)
    return codes
