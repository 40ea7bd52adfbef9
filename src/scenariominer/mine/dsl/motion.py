"""Predicates on an object's own motion: standing, speed, acceleration, turning, lane changes."""

from __future__ import annotations

import numpy as np

from scenariominer.data.log import BoolArray
from scenariominer.geometry import wrap_angle
from scenariominer.mine.context import IntArray, LogContext
from scenariominer.mine.dsl._common import (
    _choice,
    _long_runs,
    _not_stationary,
    _number,
    _runs,
    _runs_containing,
    _stationary_tracks,
    _unary_args,
    inf,
)
from scenariominer.mine.scenario import (
    Scenario,
)

# ====================================================================== motion state


def stationary(track_candidates: Scenario, log_dir: LogContext) -> Scenario:
    """Objects that stay in place for the WHOLE log (parked cars, poles), at all their timestamps.

    An object is stationary when all its observed box centres fit in a rectangle whose diagonal
    is shorter than 3 m (``MiningConfig.stationary_max_displacement_m``; box centres of parked
    objects jitter by up to a metre). Use this to separate parked from active objects; for an
    object that is only momentarily stopped use ``has_velocity(..., max_velocity=0.5)``, and for
    one that is stopped in either sense (parked included) the union of both.

    Args:
        track_candidates: subject objects (scenario).
        log_dir: the log (the predefined variable ``log_dir``).

    Returns:
        The subset of ``track_candidates`` that is stationary (all of their timestamps).

    Example:
        parked_vehicles = stationary(vehicles, log_dir)
        active_vehicles = scenario_not(stationary)(vehicles, log_dir)
    """
    tc, ctx = _unary_args(track_candidates, log_dir, "stationary", "stationary(vehicles, log_dir)")
    return tc.restrict(np.broadcast_to(_stationary_tracks(ctx)[:, None], tc.referred.shape))


def has_velocity(
    track_candidates: Scenario, log_dir: LogContext, min_velocity: float = 0.5, max_velocity: float = inf
) -> Scenario:
    """Timestamps at which an object's ground speed is within [min_velocity, max_velocity] m/s.

    Objects that are stationary for the whole log (see :func:`stationary`) never match, so
    ``has_velocity(vehicles, log_dir, max_velocity=0.5)`` finds vehicles that are momentarily
    stopped, not parked ones. Annotation jitter gives standing objects up to about 0.5 m/s.
    A plain "stopped" means at rest, parked included (as the Argoverse 2 scenario-mining ground
    truth labels "stopped car"): join both, as in the example below.

    Args:
        track_candidates: subject objects (scenario).
        log_dir: the log (the predefined variable ``log_dir``).
        min_velocity: lower speed bound, m/s, inclusive. Default 0.5.
        max_velocity: upper speed bound, m/s, inclusive. Default inf.

    Returns:
        The subset of ``track_candidates`` at the timestamps where the speed is in range.

    Example:
        fast_vehicles = has_velocity(vehicles, log_dir, min_velocity=15)
        momentarily_stopped = has_velocity(vehicles, log_dir, min_velocity=0, max_velocity=0.5)
        stopped_vehicles = scenario_or([stationary(vehicles, log_dir), momentarily_stopped])
    """
    func = "has_velocity"
    tc, ctx = _unary_args(track_candidates, log_dir, func, "has_velocity(vehicles, log_dir, min_velocity=5)")
    lo = _number(min_velocity, "min_velocity", func)
    hi = _number(max_velocity, "max_velocity", func)
    speed = ctx.speed_mps
    with np.errstate(invalid="ignore"):
        ok = (speed >= lo) & (speed <= hi)
    return tc.restrict(ok & _not_stationary(ctx))


def accelerating(
    track_candidates: Scenario, log_dir: LogContext, min_accel: float = 0.65, max_accel: float = inf
) -> Scenario:
    """Timestamps at which an object's acceleration ALONG ITS HEADING is in [min_accel, max_accel] m/s².

    Positive values speed the object up, negative values slow it down: above 1.0 reliably means
    accelerating, below -1.0 reliably means braking. Objects stationary for the whole log never match.

    Args:
        track_candidates: subject objects (scenario).
        log_dir: the log (the predefined variable ``log_dir``).
        min_accel: lower bound, m/s², inclusive. Default 0.65.
        max_accel: upper bound, m/s², inclusive. Default inf.

    Returns:
        The subset of ``track_candidates`` at the timestamps where the forward acceleration is in range.

    Example:
        accelerating_cars = accelerating(cars, log_dir, min_accel=1.0)
        braking_cars = accelerating(cars, log_dir, min_accel=-inf, max_accel=-1.0)
    """
    func = "accelerating"
    tc, ctx = _unary_args(track_candidates, log_dir, func, "accelerating(vehicles, log_dir, min_accel=1.0)")
    lo = _number(min_accel, "min_accel", func)
    hi = _number(max_accel, "max_accel", func)
    a = ctx.a_body_mps2[0]
    with np.errstate(invalid="ignore"):
        ok = (a >= lo) & (a <= hi)
    return tc.restrict(ok & _not_stationary(ctx))


def has_lateral_acceleration(
    track_candidates: Scenario, log_dir: LogContext, min_accel: float = -inf, max_accel: float = inf
) -> Scenario:
    """Timestamps at which an object's SIDEWAYS acceleration is in [min_accel, max_accel] m/s².

    Positive values accelerate toward the object's left, negative toward its right; objects with
    a large magnitude are usually turning or swerving. Objects stationary for the whole log never match.

    Args:
        track_candidates: subject objects (scenario).
        log_dir: the log (the predefined variable ``log_dir``).
        min_accel: lower bound, m/s², inclusive. Default -inf.
        max_accel: upper bound, m/s², inclusive. Default inf.

    Returns:
        The subset of ``track_candidates`` at the timestamps where the lateral acceleration is in range.

    Example:
        swerving_left = has_lateral_acceleration(vehicles, log_dir, min_accel=2)
        swerving_right = has_lateral_acceleration(vehicles, log_dir, max_accel=-2)
    """
    func = "has_lateral_acceleration"
    tc, ctx = _unary_args(
        track_candidates, log_dir, func, "has_lateral_acceleration(vehicles, log_dir, min_accel=2)"
    )
    lo = _number(min_accel, "min_accel", func)
    hi = _number(max_accel, "max_accel", func)
    a = ctx.a_body_mps2[1]
    with np.errstate(invalid="ignore"):
        ok = (a >= lo) & (a <= hi)
    return tc.restrict(ok & _not_stationary(ctx))


def _turning_masks(ctx: LogContext) -> tuple[BoolArray, BoolArray]:
    cfg = ctx.config
    rate = ctx.yaw_rate_deg_s
    valid = ctx.valid
    dt = np.gradient(ctx.t_s) if ctx.n_timestamps > 1 else np.ones(ctx.n_timestamps)
    dead = cfg.turn_yaw_rate_deadband_deg_s
    with np.errstate(invalid="ignore"):
        pos = valid & (rate > dead)
        neg = valid & (rate < -dead)
    first = np.argmax(valid, axis=1)
    last = valid.shape[1] - 1 - np.argmax(valid[:, ::-1], axis=1)
    near_int: BoolArray | None = None
    if ctx.has_map:
        x, y = ctx.center_xy_m
        near_int = ctx.require_map("turning").near_intersection(x, y, 5.0)
    out = []
    for sign_mask, sign in ((pos, 1.0), (neg, -1.0)):
        run_id, n = _runs(sign_mask)
        n_runs = int(n)
        ids = run_id[sign_mask]
        change = np.bincount(ids, weights=(np.nan_to_num(rate) * dt)[sign_mask], minlength=n_runs) * sign
        count = np.bincount(ids, minlength=n_runs)
        rows, cols = np.nonzero(sign_mask)
        touches = np.zeros(n_runs, dtype=bool)
        np.logical_or.at(touches, ids, (cols == first[rows]) | (cols == last[rows]))
        near = np.ones(n_runs, dtype=bool)
        if near_int is not None:
            near = np.zeros(n_runs, dtype=bool)
            np.logical_or.at(near, ids, near_int[sign_mask])
        mean_rate = change / np.maximum(count, 1) / np.maximum(float(np.mean(dt)), 1e-9)
        full = change > cfg.turn_min_heading_change_deg
        partial = (
            touches
            & near
            & (change > cfg.turn_partial_min_heading_change_deg)
            & (mean_rate > cfg.turn_min_yaw_rate_deg_s)
        )
        is_turn = full | partial
        mask = np.zeros_like(sign_mask)
        mask[sign_mask] = is_turn[ids]
        out.append(mask)
    return out[0], out[1]


def turning(track_candidates: Scenario, log_dir: LogContext, direction: str | None = None) -> Scenario:
    """Timestamps at which an object is making a turn to its left or right.

    A turn is a stretch of time during which the object's heading keeps rotating the same way
    (yaw rate beyond ±1 deg/s) and changes by more than 45 degrees in total; the whole stretch is
    returned. A stretch cut off by the start or end of the recording counts when it already
    changes the heading by more than 15 degrees at a mean rate above 5 deg/s (and, when the log
    has an HD map, happens within 5 m of an intersection). Thresholds: ``MiningConfig.turn_*``.

    Args:
        track_candidates: subject objects (scenario).
        log_dir: the log (the predefined variable ``log_dir``).
        direction: ``'left'``, ``'right'`` (from the object's own point of view), or ``None``
            for either. Default None.

    Returns:
        The subset of ``track_candidates`` at the timestamps of their turns.

    Example:
        left_turning_vehicles = turning(vehicles, log_dir, direction='left')
    """
    func = "turning"
    tc, ctx = _unary_args(track_candidates, log_dir, func, "turning(vehicles, log_dir, direction='left')")
    direction = _choice(direction, "direction", func)
    left, right = ctx.memo(("turning",), lambda: _turning_masks(ctx))
    mask = left if direction == "left" else right if direction == "right" else left | right
    return tc.restrict(mask)


def _lane_change_masks(ctx: LogContext) -> tuple[BoolArray, BoolArray]:
    cfg = ctx.config
    hd = ctx.require_map("changing_lanes")
    lane = ctx.lane_index("changing_lanes")
    lane_dir = ctx.lane_direction_rad("changing_lanes")
    in_lane = hd.in_semantic_lane
    n, t = lane.shape
    vx, vy = ctx.log.vx_mps, ctx.log.vy_mps
    # velocity across the lane, positive toward the lane's left
    v_across = -np.sin(lane_dir) * vx + np.cos(lane_dir) * vy
    travel = np.arctan2(vy, vx)
    with np.errstate(invalid="ignore"):
        aligned = np.abs(wrap_angle(travel - lane_dir)) <= np.radians(cfg.lane_change_max_heading_deg)
    prev = np.full((n, t), -1, dtype=np.int64)
    prev[:, 1:] = lane[:, :-1]
    both = (prev >= 0) & (lane >= 0) & (prev != lane)
    p = np.where(both, prev, 0)
    c = np.where(both, lane, 0)

    def into_neighbour(nb: IntArray) -> BoolArray:
        # the new lane and the old lane's neighbour belong to one semantic lane (either way round)
        target = nb[p]  # -1 (no neighbour) indexes the all-False last row/column
        return np.asarray(both & (in_lane[target, c] | in_lane[c, target]))

    to_left = into_neighbour(hd.left_neighbor)
    to_right = into_neighbour(hd.right_neighbor)
    thr = cfg.lane_change_min_lateral_speed_mps
    with np.errstate(invalid="ignore"):
        moving_left = ctx.valid & (v_across >= thr) & aligned
        moving_right = ctx.valid & (v_across <= -thr) & aligned
    left_ev = to_left & moving_left
    right_ev = to_right & moving_right
    dt = np.gradient(ctx.t_s) if t > 1 else np.ones(t)
    step = np.nan_to_num(np.abs(v_across)) * dt
    left = _long_runs(_runs_containing(moving_left, left_ev), step, cfg.lane_change_min_lateral_m)
    right = _long_runs(_runs_containing(moving_right, right_ev), step, cfg.lane_change_min_lateral_m)
    tl, tr = ctx.memo(("turning",), lambda: _turning_masks(ctx))
    turning_any = tl | tr
    return left & ~turning_any, right & ~turning_any


def changing_lanes(track_candidates: Scenario, log_dir: LogContext, direction: str | None = None) -> Scenario:
    """Timestamps at which an object is changing lanes (needs the HD map).

    A lane change happens when the lane under the object's centre switches to the lane's left
    or right neighbour while the object moves across the lane at ≥ 0.1 m/s and travels within
    60 degrees of the lane direction; the whole sideways movement around the switch is returned
    if it shifts the object by at least 1 m across the lane (so drifting inside a lane near its
    edge is not a lane change). Timestamps at which the object is turning (see :func:`turning`)
    are excluded. Thresholds: ``MiningConfig.lane_change_*``.

    Args:
        track_candidates: subject objects (scenario).
        log_dir: the log (the predefined variable ``log_dir``).
        direction: ``'left'``, ``'right'`` (from the object's point of view) or ``None`` for
            either. Default None.

    Returns:
        The subset of ``track_candidates`` at the timestamps of their lane changes.

    Example:
        left_lane_changes = changing_lanes(vehicles, log_dir, direction='left')
    """
    func = "changing_lanes"
    tc, ctx = _unary_args(
        track_candidates, log_dir, func, "changing_lanes(vehicles, log_dir, direction='left')"
    )
    direction = _choice(direction, "direction", func)
    ctx.require_map(func)
    left, right = ctx.memo(("changing_lanes",), lambda: _lane_change_masks(ctx))
    mask = left if direction == "left" else right if direction == "right" else left | right
    return tc.restrict(mask)
