"""Atomic mining predicates: the functions a mining program may call.

These functions are the vocabulary of the mining DSL. Their signatures follow RefAV's atomic
functions (Davidson et al., 2025) so that programs written for RefAV read the same, and their
docstrings are the reference text given to the language model, so each one states exactly:

* which argument is the SUBJECT: ``track_candidates``, the objects the result refers to;
* which argument is the REFERENCE: ``related_candidates``, the objects a relation is measured
  against (they become the *related objects* of the result);
* units, defaults and thresholds, and what is returned.

Conventions shared by every predicate:

* A *scenario* (:class:`~scenariominer.mine.scenario.Scenario`) is the set of (object,
  timestamp) pairs where something holds, plus related objects. Predicates take scenarios and
  return a scenario that is a SUBSET of ``track_candidates``: same objects, fewer timestamps.
* ``log_dir`` is the log being mined. In a program it is the predefined variable ``log_dir``
  (a :class:`~scenariominer.mine.context.LogContext`, not a path); pass it where RefAV passes
  its log folder.
* Distances are metres, speeds m/s, accelerations m/s², angles degrees. An object's frame has
  ``x`` forward along its heading and ``y`` to its left; "left"/"right"/"forward"/"backward"
  are always seen from the object named as the frame's owner.
* Map predicates (crossings, lanes, intersections, drivable area, stop signs) need the log's
  HD map and raise :class:`~scenariominer.mine.context.MapRequiredError` without one.

Everything is vectorised over tracks × timestamps with arrays shared through the log's
:class:`~scenariominer.mine.context.LogContext`.
"""

from __future__ import annotations

import contextlib
import inspect
import math
from collections.abc import Callable, Iterator
from contextvars import ContextVar
from dataclasses import dataclass
from typing import Any

import numpy as np

from scenariominer import errors as _errors
from scenariominer.data.log import BoolArray, FloatArray, time_derivative
from scenariominer.geometry import wrap_angle
from scenariominer.mine.context import IntArray, LogContext
from scenariominer.mine.scenario import (
    Scenario,
    reverse_relationship,
    scenario_and,
    scenario_not,
    scenario_or,
)

__all__ = [
    "DSL_FUNCTIONS",
    "OutputError",
    "OutputSink",
    "accelerating",
    "at_pedestrian_crossing",
    "at_stop_sign",
    "being_crossed_by",
    "capture_output",
    "changing_lanes",
    "facing_toward",
    "following",
    "get_objects_in_relative_direction",
    "get_objects_of_category",
    "has_lateral_acceleration",
    "has_objects_in_relative_direction",
    "has_velocity",
    "heading_in_relative_direction_to",
    "heading_toward",
    "in_drivable_area",
    "in_same_lane",
    "is_category",
    "library_reference",
    "near_intersection",
    "near_objects",
    "on_intersection",
    "on_lane_type",
    "on_relative_side_of_road",
    "on_road",
    "output_scenario",
    "reverse_relationship",
    "scenario_and",
    "scenario_not",
    "scenario_or",
    "stationary",
    "turning",
]

inf = math.inf

_DIRECTIONS = ("forward", "backward", "left", "right")
_DIRECTION_ALIASES = {"front": "forward", "ahead": "forward", "behind": "backward", "back": "backward"}

# ---------------------------------------------------------------------- argument checking


def _context(log_dir: Any, func: str, example: str) -> LogContext:
    if not isinstance(log_dir, LogContext):
        got = (
            f"{type(log_dir).__name__} {log_dir!r}"
            if isinstance(log_dir, str | int | float)
            else type(log_dir).__name__
        )
        raise TypeError(
            f"{func}(): the log argument must be the predefined variable log_dir, got {got}. "
            f"Example: {example}"
        )
    return log_dir


def _scenario(value: Any, name: str, func: str, ctx: LogContext | None, example: str) -> Scenario:
    if not isinstance(value, Scenario):
        if isinstance(value, LogContext):
            hint = " (log_dir comes after the scenario arguments)"
        elif isinstance(value, str):
            hint = " (did you forget to call get_objects_of_category first?)"
        else:
            hint = ""
        raise TypeError(
            f"{func}(): {name} must be a scenario, got {type(value).__name__}{hint}. Example: {example}"
        )
    if ctx is not None and value.context is not ctx:
        raise ValueError(f"{func}(): {name} belongs to another log than log_dir")
    return value


def _choice(value: Any, allowed: tuple[Any, ...], name: str, func: str) -> Any:
    """Return the allowed value equal to ``value`` (strings compared case-insensitively)."""
    for option in allowed:
        if value == option or (
            isinstance(value, str) and isinstance(option, str) and value.lower() == option.lower()
        ):
            return option
    raise ValueError(f"{func}(): {name} must be one of {list(allowed)}, got {value!r}")


def _number(value: Any, name: str, func: str, minimum: float | None = None) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise TypeError(f"{func}(): {name} must be a number, got {type(value).__name__} {value!r}")
    x = float(value)
    if math.isnan(x) or (minimum is not None and x < minimum):
        raise ValueError(f"{func}(): {name} must be a number >= {minimum}, got {value!r}")
    return x


def _unary_args(track_candidates: Any, log_dir: Any, func: str, example: str) -> tuple[Scenario, LogContext]:
    _scenario(track_candidates, "track_candidates", func, None, example)
    ctx = _context(log_dir, func, example)
    return _scenario(track_candidates, "track_candidates", func, ctx, example), ctx


def _binary_args(
    track_candidates: Any, related_candidates: Any, log_dir: Any, func: str, example: str
) -> tuple[Scenario, Scenario, LogContext]:
    _scenario(track_candidates, "track_candidates", func, None, example)
    _scenario(related_candidates, "related_candidates", func, None, example)
    ctx = _context(log_dir, func, example)
    tc = _scenario(track_candidates, "track_candidates", func, ctx, example)
    rc = _scenario(related_candidates, "related_candidates", func, ctx, example)
    return tc, rc, ctx


# ---------------------------------------------------------------------- relational plumbing


@dataclass(frozen=True)
class _Pairs:
    rows: IntArray  # (R,) subject tracks
    cols: IntArray  # (C,) reference tracks
    active: BoolArray  # (R, C, T) both candidates present, distinct tracks


def _pairs(tc: Scenario, rc: Scenario) -> _Pairs:
    rows, cols = tc.referred_tracks, rc.referred_tracks
    active = tc.referred[rows][:, None, :] & rc.referred[cols][None, :, :]
    active &= (rows[:, None] != cols[None, :])[:, :, None]
    return _Pairs(rows, cols, active)


def _relational_result(
    tc: Scenario, pairs: _Pairs, related: BoolArray, holds: BoolArray | None = None
) -> Scenario:
    """Subject cells where ``holds`` ``(R, T)`` (default: any related pair), with the relations."""
    related = related & pairs.active
    cells: BoolArray = np.asarray(related.any(axis=1) if holds is None else holds, dtype=bool)
    mask = np.zeros_like(tc.referred)
    mask[pairs.rows] = cells
    r, c, t = np.nonzero(related & cells[:, None, :])
    rel = np.stack([pairs.rows[r], t, pairs.cols[c]], axis=1).astype(np.int64)
    return tc.restrict(mask).with_relations(rel)


def _not_stationary(ctx: LogContext) -> BoolArray:
    return np.asarray(~_stationary_tracks(ctx))[:, None]


def _stationary_tracks(ctx: LogContext) -> BoolArray:
    result: BoolArray = ctx.memo(
        ("stationary",),
        lambda: (
            ctx.valid.any(axis=1) & (ctx.displacement_extent_m < ctx.config.stationary_max_displacement_m)
        ),
    )
    return result


def _runs(mask: BoolArray) -> tuple[IntArray, IntArray]:
    """Label runs of True along the last axis of ``mask`` (any leading shape).

    Returns:
        ``run_id`` of ``mask``'s shape (-1 outside runs; ids are unique over the whole array) and
        the number of runs.
    """
    flat = mask.reshape(-1, mask.shape[-1])
    prev = np.zeros_like(flat)
    prev[:, 1:] = flat[:, :-1]
    start = flat & ~prev
    ids = np.cumsum(start.ravel()).reshape(flat.shape) - 1
    run_id = np.where(flat, ids, -1).reshape(mask.shape)
    return run_id.astype(np.int64), np.asarray(int(start.sum()), dtype=np.int64)


def _runs_containing(run_mask: BoolArray, seeds: BoolArray) -> BoolArray:
    """Cells of the runs of ``run_mask`` (along the last axis) that contain a ``seeds`` cell."""
    run_id, n = _runs(run_mask)
    hit = np.zeros(int(n) + 1, dtype=bool)
    hit[run_id[seeds & run_mask]] = True
    return np.asarray((run_id >= 0) & hit[np.where(run_id >= 0, run_id, n)])


def _long_runs(mask: BoolArray, step: FloatArray, minimum: float) -> BoolArray:
    """Runs of ``mask`` (along the last axis) whose summed ``step`` reaches ``minimum``."""
    run_id, n = _runs(mask)
    total = np.bincount(run_id[mask], weights=step[mask], minlength=int(n))
    keep = np.append(total >= minimum, False)
    return np.asarray(keep[np.where(run_id >= 0, run_id, int(n))])


def _deriv_last_axis(values: FloatArray, t_s: FloatArray) -> FloatArray:
    shape = values.shape
    return time_derivative(values.reshape(-1, shape[-1]), t_s).reshape(shape)


# ====================================================================== selection


def get_objects_of_category(log_dir: LogContext, category: str) -> Scenario:
    """All objects of one category, at every timestamp they are observed.

    Args:
        log_dir: the log (the predefined variable ``log_dir``).
        category: an Argoverse 2 category name such as ``"REGULAR_VEHICLE"``, ``"PEDESTRIAN"``,
            ``"BICYCLE"``, ``"BUS"``, ``"EGO_VEHICLE"``, or a group: ``"VEHICLE"`` (every motor
            vehicle incl. the ego: REGULAR_VEHICLE, LARGE_VEHICLE, BUS, BOX_TRUCK, TRUCK,
            VEHICULAR_TRAILER, TRUCK_CAB, SCHOOL_BUS, ARTICULATED_BUS, RAILED_VEHICLE, MOTORCYCLE,
            EGO_VEHICLE), ``"VULNERABLE_ROAD_USER"`` or ``"ANY"``. Case-insensitive.
            ``"VEHICLE"`` has no BICYCLE; where a description's "vehicle" includes bicycles,
            combine both with ``scenario_or``.

    Returns:
        A scenario whose referred objects are all objects of the category, each at all of its
        timestamps; no related objects.

    Example:
        trucks = get_objects_of_category(log_dir, category='TRUCK')
    """
    example = "get_objects_of_category(log_dir, category='VEHICLE')"
    ctx = _context(log_dir, "get_objects_of_category", example)
    if not isinstance(category, str):
        raise TypeError(
            f"get_objects_of_category(): category must be a string such as 'VEHICLE', got {category!r}"
        )
    return Scenario.from_mask(ctx, ctx.category_mask(category)[:, None] & ctx.valid)


def is_category(track_candidates: Scenario, log_dir: LogContext, category: str) -> Scenario:
    """The track candidates that belong to a category (or category group).

    Args:
        track_candidates: subject objects (scenario).
        log_dir: the log (the predefined variable ``log_dir``).
        category: a category or group name as for :func:`get_objects_of_category`.

    Returns:
        The subset of ``track_candidates`` whose category matches, with their timestamps and
        related objects unchanged.

    Example:
        moving_buses = is_category(moving_vehicles, log_dir, category='BUS')
    """
    example = "is_category(vehicles, log_dir, category='BUS')"
    tc, ctx = _unary_args(track_candidates, log_dir, "is_category", example)
    if not isinstance(category, str):
        raise TypeError(f"is_category(): category must be a string such as 'BUS', got {category!r}")
    return tc.restrict(np.broadcast_to(ctx.category_mask(category)[:, None], tc.referred.shape))


# ====================================================================== motion state


def stationary(track_candidates: Scenario, log_dir: LogContext) -> Scenario:
    """Objects that stay in place for the WHOLE log (parked cars, poles), at all their timestamps.

    An object is stationary when all its observed box centres fit in a rectangle whose diagonal
    is shorter than 3 m (``MiningConfig.stationary_max_displacement_m``; box centres of parked
    objects jitter by up to a metre). Use this to separate parked from active objects; for an
    object that is only momentarily stopped use ``has_velocity(..., max_velocity=0.5)``.

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

    Args:
        track_candidates: subject objects (scenario).
        log_dir: the log (the predefined variable ``log_dir``).
        min_velocity: lower speed bound, m/s, inclusive. Default 0.5.
        max_velocity: upper speed bound, m/s, inclusive. Default inf.

    Returns:
        The subset of ``track_candidates`` at the timestamps where the speed is in range.

    Example:
        fast_vehicles = has_velocity(vehicles, log_dir, min_velocity=15)
        stopped_vehicles = has_velocity(vehicles, log_dir, min_velocity=0, max_velocity=0.5)
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
    direction = _choice(direction, ("left", "right", None), "direction", func)
    left, right = ctx.memo(("turning",), lambda: _turning_masks(ctx))
    mask = left if direction == "left" else right if direction == "right" else left | right
    return tc.restrict(mask)


def _lane_change_masks(ctx: LogContext) -> tuple[BoolArray, BoolArray]:
    cfg = ctx.config
    hd = ctx.require_map("changing_lanes")
    lane = ctx.lane_index("changing_lanes")
    lane_dir = ctx.lane_direction_rad("changing_lanes")
    sem = hd.semantic_lane
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

    def neighbour_group(nb: IntArray) -> IntArray:
        target = nb[p]
        return np.where(target >= 0, sem[np.maximum(target, 0)], -2)

    to_left = both & (neighbour_group(hd.left_neighbor) == sem[c])
    to_right = both & (neighbour_group(hd.right_neighbor) == sem[c])
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
    direction = _choice(direction, ("left", "right", None), "direction", func)
    ctx.require_map(func)
    left, right = ctx.memo(("changing_lanes",), lambda: _lane_change_masks(ctx))
    mask = left if direction == "left" else right if direction == "right" else left | right
    return tc.restrict(mask)


# ====================================================================== relations


def _direction_geometry(
    ctx: LogContext, pairs: _Pairs, direction: str
) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """Reference centres in the subject frame rotated so ``u`` points along ``direction``.

    Returns ``u``, ``v`` (R, C, T) and the subject's half extents along ``u`` and ``v`` (R, 1, T).
    """
    x, y = ctx.relative_position(pairs.rows, pairs.cols)
    hl = (ctx.length_m[pairs.rows] / 2)[:, None, :]
    hw = (ctx.width_m[pairs.rows] / 2)[:, None, :]
    if direction == "forward":
        return x, y, hl, hw
    if direction == "backward":
        return -x, -y, hl, hw
    if direction == "left":
        return y, -x, hw, hl
    return -y, x, hw, hl


def _in_direction(
    ctx: LogContext, pairs: _Pairs, direction: str, lateral_thresh: float
) -> tuple[BoolArray, FloatArray]:
    u, v, hu, hv = _direction_geometry(ctx, pairs, direction)
    with np.errstate(invalid="ignore"):
        inside = (u > hu) & (np.abs(v) < hv + lateral_thresh)
    return inside, ctx.box_distance(pairs.rows, pairs.cols)


def has_objects_in_relative_direction(
    track_candidates: Scenario,
    related_candidates: Scenario,
    log_dir: LogContext,
    direction: str,
    min_number: int = 1,
    max_number: float = inf,
    within_distance: float | None = None,
    lateral_thresh: float | None = None,
) -> Scenario:
    """Track candidates that have related candidates in a direction SEEN FROM THE TRACK CANDIDATE.

    SUBJECT = ``track_candidates`` (returned, referred). REFERENCE = ``related_candidates`` (the
    objects that must lie in ``direction`` of the subject; they become its related objects).
    "vehicle with a bicycle to its right" is
    ``has_objects_in_relative_direction(vehicles, bicycles, log_dir, direction='right')``.

    A related object is in ``direction`` of the subject at a timestamp when its centre lies
    beyond the subject's box on that side, within a corridor that extends ``lateral_thresh``
    metres past the subject's box on both sides:

    * ``'forward'``/``'backward'``: ahead of the front / behind the rear bumper, at most
      ``lateral_thresh`` m sideways beyond the subject's left and right sides;
    * ``'left'``/``'right'``: beyond the subject's left / right side, at most ``lateral_thresh``
      m ahead of its front or behind its rear;

    and its box is at most ``within_distance`` m from the subject's box (closest points). At
    every timestamp the in-direction objects are ranked by that distance and the nearest
    ``max_number`` are kept; the subject matches when at least ``min_number`` are kept.

    Args:
        track_candidates: subject objects (scenario), e.g. vehicles.
        related_candidates: reference objects to look for (scenario), e.g. bicycles.
        log_dir: the log (the predefined variable ``log_dir``).
        direction: ``'forward'``, ``'backward'``, ``'left'`` or ``'right'`` of the subject
            (``'front'`` and ``'behind'``/``'back'`` are accepted as aliases).
        min_number: least number of related objects needed at a timestamp. Default 1.
        max_number: at most this many nearest related objects are kept as related. Default inf.
        within_distance: maximum box-to-box distance, metres. Default None: 4 m for
            ``'left'``/``'right'`` (beside it, at most about a lane away) and 25 m for
            ``'forward'``/``'backward'``. Pass a number (e.g. 50) to search farther.
        lateral_thresh: how far (m) the related object's centre may lie outside the subject's
            extent perpendicular to ``direction``. Default None: 1 m (beside the subject for
            left/right, inside about one lane for forward/backward). Pass ``inf`` for the whole
            half-plane.

    Returns:
        The subset of ``track_candidates`` at the timestamps where enough related candidates are
        in the direction, with those related candidates as related objects.

    Example:
        vehicles_with_bicycle_right = has_objects_in_relative_direction(
            vehicles, bicycles, log_dir, direction='right')
        cars_with_2_peds_ahead = has_objects_in_relative_direction(
            cars, peds, log_dir, direction='forward', min_number=2, within_distance=20)
    """
    func = "has_objects_in_relative_direction"
    example = "has_objects_in_relative_direction(vehicles, bicycles, log_dir, direction='right')"
    tc, rc, ctx = _binary_args(track_candidates, related_candidates, log_dir, func, example)
    direction = _choice(
        _DIRECTION_ALIASES.get(str(direction).lower(), direction), _DIRECTIONS, "direction", func
    )
    lo = _number(min_number, "min_number", func, minimum=0)
    hi = _number(max_number, "max_number", func, minimum=0)
    cfg = ctx.config
    if within_distance is None:
        within_distance = (
            cfg.side_max_distance_m if direction in ("left", "right") else cfg.front_back_max_distance_m
        )
    dist_max = _number(within_distance, "within_distance", func, minimum=0)
    lat = _number(
        cfg.direction_lateral_m if lateral_thresh is None else lateral_thresh, "lateral_thresh", func, 0
    )
    pairs = _pairs(tc, rc)
    if pairs.rows.size == 0 or pairs.cols.size == 0:
        return tc.restrict(np.zeros_like(tc.referred)) if lo > 0 else tc
    inside, dist = _in_direction(ctx, pairs, direction, lat)
    with np.errstate(invalid="ignore"):
        cand = inside & pairs.active & (dist <= dist_max)
    if math.isfinite(hi):
        ranked = np.where(cand, dist, np.inf)
        order = np.argsort(ranked, axis=1, kind="stable")
        rank = np.empty_like(order)
        np.put_along_axis(rank, order, np.arange(order.shape[1])[None, :, None], axis=1)
        cand &= rank < hi
    count = cand.sum(axis=1)
    holds = count >= lo
    return _relational_result(tc, pairs, cand, holds)


def get_objects_in_relative_direction(
    track_candidates: Scenario,
    related_candidates: Scenario,
    log_dir: LogContext,
    direction: str,
    min_number: int = 0,
    max_number: float = inf,
    within_distance: float | None = None,
    lateral_thresh: float | None = None,
) -> Scenario:
    """The RELATED candidates that lie in a direction of the track candidates (roles reversed).

    Same test as :func:`has_objects_in_relative_direction` with the same arguments, the
    direction still SEEN FROM ``track_candidates``, but the RETURNED referred objects are the
    ``related_candidates`` found there, each with the track candidate as its related object.
    "pedestrian in front of a vehicle" is
    ``get_objects_in_relative_direction(vehicles, peds, log_dir, direction='forward')``.

    Args:
        track_candidates: the objects whose frame defines the direction (scenario), e.g. vehicles.
        related_candidates: the objects to return when they lie in the direction (scenario).
        log_dir: the log (the predefined variable ``log_dir``).
        direction: ``'forward'``, ``'backward'``, ``'left'`` or ``'right'`` of the track candidate.
        min_number: a track candidate contributes only at timestamps where it has at least this
            many related candidates in the direction. Default 0.
        max_number: per track candidate and timestamp, only the nearest ``max_number`` related
            candidates are returned. Default inf.
        within_distance: maximum box-to-box distance, metres. Default None: 4 m for
            ``'left'``/``'right'``, 25 m for ``'forward'``/``'backward'``.
        lateral_thresh: as in :func:`has_objects_in_relative_direction`, metres. Default None: 1 m.

    Returns:
        A scenario whose referred objects are subsets of ``related_candidates``.

    Example:
        peds_in_front_of_vehicles = get_objects_in_relative_direction(
            vehicles, peds, log_dir, direction='forward', within_distance=15)
    """
    result = has_objects_in_relative_direction(
        track_candidates,
        related_candidates,
        log_dir,
        direction,
        min_number=min_number,
        max_number=max_number,
        within_distance=within_distance,
        lateral_thresh=lateral_thresh,
    )
    return result.reversed()


def facing_toward(
    track_candidates: Scenario,
    related_candidates: Scenario,
    log_dir: LogContext,
    within_angle: float = 22.5,
    max_distance: float = 50,
) -> Scenario:
    """Track candidates whose heading POINTS AT a related candidate (the track candidate does the facing).

    SUBJECT = ``track_candidates`` (returned): their box heading is used. REFERENCE =
    ``related_candidates``: the objects looked at. Holds when the direction from the subject's
    centre to the related centre is within ``within_angle`` degrees of the subject's heading
    (either side) and the boxes are at most ``max_distance`` m apart. Motion is not needed:
    use :func:`heading_toward` for objects moving toward something.

    Args:
        track_candidates: subject objects (scenario).
        related_candidates: objects that may be faced (scenario).
        log_dir: the log (the predefined variable ``log_dir``).
        within_angle: half-angle of the viewing cone, degrees. Default 22.5.
        max_distance: maximum box-to-box distance, metres. Default 50.

    Returns:
        The subset of ``track_candidates`` facing at least one related candidate, with the faced
        objects as related objects.

    Example:
        peds_facing_ego = facing_toward(peds, ego_vehicle, log_dir, within_angle=30)
    """
    func = "facing_toward"
    tc, rc, ctx = _binary_args(
        track_candidates, related_candidates, log_dir, func, "facing_toward(peds, ego, log_dir)"
    )
    angle = _number(within_angle, "within_angle", func, minimum=0)
    dmax = _number(max_distance, "max_distance", func, minimum=0)
    pairs = _pairs(tc, rc)
    if pairs.rows.size == 0 or pairs.cols.size == 0:
        return tc.restrict(np.zeros_like(tc.referred))
    x, y = ctx.relative_position(pairs.rows, pairs.cols)
    with np.errstate(invalid="ignore"):
        ok = (np.abs(np.degrees(np.arctan2(y, x))) <= angle) & (
            ctx.box_distance(pairs.rows, pairs.cols) <= dmax
        )
    return _relational_result(tc, pairs, ok)


def heading_toward(
    track_candidates: Scenario,
    related_candidates: Scenario,
    log_dir: LogContext,
    angle_threshold: float = 22.5,
    minimum_speed: float = 0.5,
    max_distance: float = inf,
) -> Scenario:
    """Track candidates MOVING TOWARD a related candidate (the track candidate does the moving).

    SUBJECT = ``track_candidates`` (returned): their velocity is used. REFERENCE =
    ``related_candidates``: the objects approached. Holds when the subject's velocity direction
    is within ``angle_threshold`` degrees of the direction from the subject's centre to the
    related centre, the distance between the two centres shrinks by at least ``minimum_speed``
    m/s (a car driving behind another at the same speed is not heading toward it), and the
    boxes are at most ``max_distance`` m apart.

    Args:
        track_candidates: subject objects (scenario).
        related_candidates: objects that may be approached (scenario).
        log_dir: the log (the predefined variable ``log_dir``).
        angle_threshold: maximum angle between velocity and direction to the object, degrees. Default 22.5.
        minimum_speed: minimum closing speed (decrease of the centre distance), m/s. Default 0.5.
        max_distance: maximum box-to-box distance, metres. Default inf.

    Returns:
        The subset of ``track_candidates`` moving toward at least one related candidate, with
        those as related objects.

    Example:
        vehicles_heading_toward_ego = heading_toward(vehicles, ego_vehicle, log_dir, max_distance=30)
    """
    func = "heading_toward"
    tc, rc, ctx = _binary_args(
        track_candidates, related_candidates, log_dir, func, "heading_toward(vehicles, ego, log_dir)"
    )
    angle = _number(angle_threshold, "angle_threshold", func, minimum=0)
    vmin = _number(minimum_speed, "minimum_speed", func)
    dmax = _number(max_distance, "max_distance", func, minimum=0)
    pairs = _pairs(tc, rc)
    if pairs.rows.size == 0 or pairs.cols.size == 0:
        return tc.restrict(np.zeros_like(tc.referred))
    x, y = ctx.relative_position(pairs.rows, pairs.cols)
    vf, vl = ctx.v_body_mps
    vx = vf[pairs.rows][:, None, :]
    vy = vl[pairs.rows][:, None, :]
    dist_c = np.hypot(x, y)
    closing = -_deriv_last_axis(dist_c, ctx.t_s)
    with np.errstate(invalid="ignore", divide="ignore"):
        cos_angle = (vx * x + vy * y) / (dist_c * np.hypot(vx, vy))
        ok = (
            (closing >= vmin)
            & (cos_angle >= np.cos(np.radians(angle)))
            & (ctx.box_distance(pairs.rows, pairs.cols) <= dmax)
        )
    return _relational_result(tc, pairs, ok)


def being_crossed_by(
    track_candidates: Scenario,
    related_candidates: Scenario,
    log_dir: LogContext,
    direction: str = "forward",
    in_direction: str = "either",
    forward_thresh: float = 10,
    lateral_thresh: float = 5,
) -> Scenario:
    """Track candidates that a related candidate is crossing (e.g. a pedestrian crossing in front of a car).

    SUBJECT = ``track_candidates`` (returned): the object being crossed. REFERENCE =
    ``related_candidates``: the objects that cross. ``direction`` names the side of the SUBJECT
    where the crossing happens, seen from the subject.

    The subject's *half-midplane* on side ``direction`` is its centre line extended beyond its
    box on that side by ``forward_thresh`` m (``'forward'``: the line straight ahead of the front
    bumper, up to ``forward_thresh`` m away; ``'left'``: the line straight out of its left side,
    ...). A crossing happens when the related object's centre passes through that line while
    the related object itself moves across it at more than 0.2 m/s (its own ground velocity, so
    a parked car the subject drives past does not cross it). The returned timestamps cover the
    related object's pass while it stays within ``forward_thresh`` m of the subject's box on
    that side and within ``lateral_thresh`` m beyond the subject's sides, moving across.

    Args:
        track_candidates: subject objects that are crossed (scenario), e.g. vehicles.
        related_candidates: objects that cross (scenario), e.g. pedestrians.
        log_dir: the log (the predefined variable ``log_dir``).
        direction: ``'forward'``, ``'backward'``, ``'left'`` or ``'right'`` side of the subject.
            Default ``'forward'``.
        in_direction: which way the crossing object must move, seen from above:
            ``'clockwise'`` around the subject (for ``'forward'``: from the subject's left to its
            right across its front; for ``'left'``: from behind to ahead along its left side),
            ``'counterclockwise'`` (the reverse) or ``'either'``. Default ``'either'``.
        forward_thresh: how far the half-midplane extends beyond the subject's box, metres. Default 10.
        lateral_thresh: how far before/after the subject's sides the crossing is tracked, metres. Default 5.

    Returns:
        The subset of ``track_candidates`` at the timestamps of being crossed, with the crossing
        objects as related objects.

    Example:
        vehicles_crossed_by_peds = being_crossed_by(vehicles, peds, log_dir)
        overtaken_on_left = being_crossed_by(
            vehicles, moving_vehicles, log_dir, direction='left', in_direction='clockwise', forward_thresh=4)
    """
    func = "being_crossed_by"
    tc, rc, ctx = _binary_args(
        track_candidates, related_candidates, log_dir, func, "being_crossed_by(vehicles, peds, log_dir)"
    )
    direction = _choice(
        _DIRECTION_ALIASES.get(str(direction).lower(), direction), _DIRECTIONS, "direction", func
    )
    in_direction = _choice(in_direction, ("clockwise", "counterclockwise", "either"), "in_direction", func)
    reach = _number(forward_thresh, "forward_thresh", func, minimum=0)
    lat = _number(lateral_thresh, "lateral_thresh", func, minimum=0)
    pairs = _pairs(tc, rc)
    if pairs.rows.size == 0 or pairs.cols.size == 0:
        return tc.restrict(np.zeros_like(tc.referred))
    u, v, hu, hv = _direction_geometry(ctx, pairs, direction)
    vx, vy = ctx.relative_velocity(pairs.rows, pairs.cols)
    dv = {"forward": vy, "backward": -vy, "left": -vx, "right": vx}[direction]
    thr = ctx.config.crossing_min_speed_mps
    v_prev = np.full_like(v, np.nan)
    v_prev[..., 1:] = v[..., :-1]
    with np.errstate(invalid="ignore"):
        in_band = pairs.active & (u >= hu) & (u <= hu + reach) & (np.abs(v) <= hv + lat)
        up = in_band & (dv > thr)
        down = in_band & (dv < -thr)
        up_event = up & (v_prev < 0) & (v >= 0)
        down_event = down & (v_prev > 0) & (v <= 0)
    crossing = np.zeros_like(up)
    if in_direction in ("counterclockwise", "either"):
        crossing |= _runs_containing(up, up_event)
    if in_direction in ("clockwise", "either"):
        crossing |= _runs_containing(down, down_event)
    return _relational_result(tc, pairs, crossing)


def near_objects(
    track_candidates: Scenario,
    related_candidates: Scenario,
    log_dir: LogContext,
    distance_thresh: float = 10,
    min_objects: int | None = 1,
    include_self: bool = False,
) -> Scenario:
    """Track candidates with at least ``min_objects`` related candidates nearby.

    SUBJECT = ``track_candidates`` (returned). REFERENCE = ``related_candidates`` (the nearby
    objects, returned as related objects). A related object is near when the two boxes are at
    most ``distance_thresh`` m apart (closest points; 0 when touching), in any direction.

    Args:
        track_candidates: subject objects (scenario).
        related_candidates: objects that must be nearby (scenario).
        log_dir: the log (the predefined variable ``log_dir``).
        distance_thresh: maximum box-to-box distance, metres. Default 10.
        min_objects: least number of nearby related objects at a timestamp; ``None`` or 0 means
            all related candidate objects. Default 1.
        include_self: count the subject itself when it is also a related candidate. Default False.

    Returns:
        The subset of ``track_candidates`` at the timestamps with enough related objects nearby,
        with the nearby ones as related objects.

    Example:
        vehicles_near_ped_group = near_objects(vehicles, peds, log_dir, distance_thresh=5, min_objects=3)
    """
    func = "near_objects"
    tc, rc, ctx = _binary_args(
        track_candidates, related_candidates, log_dir, func, "near_objects(vehicles, peds, log_dir)"
    )
    dmax = _number(distance_thresh, "distance_thresh", func, minimum=0)
    pairs = _pairs(tc, rc)
    need = float(pairs.cols.size) if not min_objects else _number(min_objects, "min_objects", func, minimum=0)
    if pairs.rows.size == 0 or pairs.cols.size == 0:
        return tc.restrict(np.zeros_like(tc.referred))
    with np.errstate(invalid="ignore"):
        near = pairs.active & (ctx.box_distance(pairs.rows, pairs.cols) <= dmax)
    count = near.sum(axis=1)
    if include_self:
        count = count + (rc.referred[pairs.rows] & tc.referred[pairs.rows])
    holds = (count >= need) & (count > 0)
    return _relational_result(tc, pairs, near, holds)


def following(track_candidates: Scenario, related_candidates: Scenario, log_dir: LogContext) -> Scenario:
    """Track candidates driving behind a related candidate in the same lane and direction.

    SUBJECT = ``track_candidates`` (returned): the FOLLOWER. REFERENCE = ``related_candidates``:
    the LEAD objects (returned as related objects). Holds at a timestamp when both move
    (≥ 0.5 m/s), the lead's centre is ahead of the follower's front bumper by at most 25 m, both
    travel in similar directions (cosine of the angle between them > 0.5), and the lead is in
    the follower's lane: with an HD map the lead's lane is the follower's lane, the lane
    continuing it, or a successor of it (and the lead is within 5 m sideways); without a map
    the lead's centre is at most 1.75 m to either side of the follower's centre line.
    Thresholds: ``MiningConfig.following_*``.

    Args:
        track_candidates: follower candidates (scenario).
        related_candidates: lead candidates (scenario).
        log_dir: the log (the predefined variable ``log_dir``).

    Returns:
        The subset of ``track_candidates`` at the timestamps where they follow a lead, with the
        lead as related object.

    Example:
        vehicles_following_bus = following(vehicles, buses, log_dir)
    """
    func = "following"
    tc, rc, ctx = _binary_args(
        track_candidates, related_candidates, log_dir, func, "following(vehicles, buses, log_dir)"
    )
    cfg = ctx.config
    pairs = _pairs(tc, rc)
    if pairs.rows.size == 0 or pairs.cols.size == 0:
        return tc.restrict(np.zeros_like(tc.referred))
    x, y = ctx.relative_position(pairs.rows, pairs.cols)
    hl = (ctx.length_m[pairs.rows] / 2)[:, None, :]
    travel = ctx.travel_direction_rad
    cos_dir = np.cos(travel[pairs.cols][None, :, :] - travel[pairs.rows][:, None, :])
    fast = ctx.speed_mps >= cfg.moving_min_speed_mps
    moving = fast[pairs.rows][:, None, :] & fast[pairs.cols][None, :, :]
    with np.errstate(invalid="ignore"):
        ahead = (x > hl) & (x < hl + cfg.following_max_gap_m)
        ok = ahead & moving & (cos_dir > cfg.following_min_heading_cos)
        if ctx.has_map:
            hd = ctx.require_map(func)
            lane = ctx.lane_index(func)
            lr = lane[pairs.rows][:, None, :]
            lc = lane[pairs.cols][None, :, :]
            sem = hd.semantic_lane
            known = (lr >= 0) & (lc >= 0)
            same = known & (sem[np.maximum(lr, 0)] == sem[np.maximum(lc, 0)])
            succ = np.zeros((hd.n_lanes, hd.n_lanes), dtype=bool)
            for i, ss in enumerate(hd.successors):
                succ[i, ss] = True
            same |= known & succ[np.maximum(lr, 0), np.maximum(lc, 0)]
            ok &= same & (np.abs(y) < 5.0)
        else:
            ok &= np.abs(y) <= cfg.following_max_lateral_m
    return _relational_result(tc, pairs, ok)


def heading_in_relative_direction_to(
    track_candidates: Scenario, related_candidates: Scenario, log_dir: LogContext, direction: str
) -> Scenario:
    """Track candidates travelling in a given direction RELATIVE TO a related candidate's travel direction.

    SUBJECT = ``track_candidates`` (returned). REFERENCE = ``related_candidates`` (returned as
    related objects). Each object's direction of travel is its velocity direction when it moves
    at ≥ 1 m/s, else its box heading if it is an agent (vehicle, pedestrian, rider); at least one
    of the two must move at ≥ 1 m/s. With the angle between the two directions:

    * ``'same'``: 0 to 45 degrees;
    * ``'perpendicular'``: more than 45 and less than 135 degrees;
    * ``'opposite'``: 135 to 180 degrees.

    Args:
        track_candidates: subject objects (scenario).
        related_candidates: objects whose travel direction is the reference (scenario).
        log_dir: the log (the predefined variable ``log_dir``).
        direction: ``'same'``, ``'opposite'`` or ``'perpendicular'``.

    Returns:
        The subset of ``track_candidates`` at the timestamps where the relation holds for at
        least one related candidate, with those as related objects.

    Example:
        oncoming_vehicles = heading_in_relative_direction_to(
            vehicles, ego_vehicle, log_dir, direction='opposite')
    """
    func = "heading_in_relative_direction_to"
    example = "heading_in_relative_direction_to(vehicles, ego, log_dir, direction='opposite')"
    tc, rc, ctx = _binary_args(track_candidates, related_candidates, log_dir, func, example)
    direction = _choice(direction, ("same", "opposite", "perpendicular"), "direction", func)
    cfg = ctx.config
    pairs = _pairs(tc, rc)
    if pairs.rows.size == 0 or pairs.cols.size == 0:
        return tc.restrict(np.zeros_like(tc.referred))
    travel = ctx.travel_direction_rad
    angle = np.degrees(np.abs(wrap_angle(travel[pairs.rows][:, None, :] - travel[pairs.cols][None, :, :])))
    fast = ctx.speed_mps >= cfg.heading_min_speed_mps
    some_moving = fast[pairs.rows][:, None, :] | fast[pairs.cols][None, :, :]
    with np.errstate(invalid="ignore"):
        if direction == "same":
            ok = angle <= cfg.same_direction_max_deg
        elif direction == "opposite":
            ok = angle >= cfg.opposite_direction_min_deg
        else:
            ok = (angle > cfg.same_direction_max_deg) & (angle < cfg.opposite_direction_min_deg)
    return _relational_result(tc, pairs, ok & some_moving)


# ====================================================================== map-aware


def at_pedestrian_crossing(
    track_candidates: Scenario, log_dir: LogContext, within_distance: float = 1
) -> Scenario:
    """Timestamps at which an object's box is within ``within_distance`` m of a pedestrian crossing (HD map).

    Args:
        track_candidates: subject objects (scenario).
        log_dir: the log (the predefined variable ``log_dir``).
        within_distance: maximum distance between the object's box and the crossing polygon,
            metres; 0 means the box must overlap the crossing. Default 1.

    Returns:
        The subset of ``track_candidates`` at the timestamps they are at a crossing.

    Example:
        peds_at_crossing = at_pedestrian_crossing(peds, log_dir, within_distance=0)
    """
    func = "at_pedestrian_crossing"
    tc, ctx = _unary_args(track_candidates, log_dir, func, "at_pedestrian_crossing(peds, log_dir)")
    dmax = _number(within_distance, "within_distance", func, minimum=0)
    hd = ctx.require_map(func)
    dist = ctx.memo(("crosswalk_distance",), lambda: _crosswalk_distance(ctx, hd))
    with np.errstate(invalid="ignore"):
        return tc.restrict(dist <= dmax)


def _crosswalk_distance(ctx: LogContext, hd: Any) -> FloatArray:
    polys = ctx.box_polygons
    out = np.full(polys.shape, np.nan)
    ok = ctx.valid
    if ok.any():
        out[ok] = hd.crosswalk_distance(polys[ok])
    return out


def on_lane_type(track_candidates: Scenario, log_dir: LogContext, lane_type: str) -> Scenario:
    """Timestamps at which an object's centre is on a lane of the given type (needs the HD map).

    Args:
        track_candidates: subject objects (scenario).
        log_dir: the log (the predefined variable ``log_dir``).
        lane_type: ``'VEHICLE'``, ``'BIKE'`` or ``'BUS'``.

    Returns:
        The subset of ``track_candidates`` at the timestamps they are on such a lane.

    Example:
        vehicles_in_bus_lane = on_lane_type(vehicles, log_dir, lane_type='BUS')
    """
    func = "on_lane_type"
    tc, ctx = _unary_args(track_candidates, log_dir, func, "on_lane_type(vehicles, log_dir, lane_type='BUS')")
    if not isinstance(lane_type, str):
        raise TypeError(f"on_lane_type(): lane_type must be 'VEHICLE', 'BIKE' or 'BUS', got {lane_type!r}")
    kind = _choice(lane_type, ("VEHICLE", "BIKE", "BUS"), "lane_type", func)
    hd = ctx.require_map(func)
    lane = ctx.lane_index(func)
    types = np.append(hd.lane_types, "")
    return tc.restrict((lane >= 0) & (types[lane] == kind))


def near_intersection(track_candidates: Scenario, log_dir: LogContext, threshold: float = 5) -> Scenario:
    """Timestamps at which an object's centre is within ``threshold`` m of an intersection (needs the HD map).

    The intersection is the union of the map's lane segments marked as inside an intersection;
    an object on the intersection is near it as well.

    Args:
        track_candidates: subject objects (scenario).
        log_dir: the log (the predefined variable ``log_dir``).
        threshold: maximum distance from the centre to the intersection area, metres. Default 5.

    Returns:
        The subset of ``track_candidates`` at the timestamps they are near an intersection.

    Example:
        bicycles_near_intersection = near_intersection(bicycles, log_dir, threshold=10)
    """
    func = "near_intersection"
    tc, ctx = _unary_args(
        track_candidates, log_dir, func, "near_intersection(bicycles, log_dir, threshold=10)"
    )
    d = _number(threshold, "threshold", func, minimum=0)
    hd = ctx.require_map(func)
    x, y = ctx.center_xy_m

    return tc.restrict(ctx.memo(("near_intersection", d), lambda: hd.near_intersection(x, y, d)))


def on_intersection(track_candidates: Scenario, log_dir: LogContext) -> Scenario:
    """Timestamps at which an object's centre is on a lane segment inside an intersection (needs the HD map).

    Args:
        track_candidates: subject objects (scenario).
        log_dir: the log (the predefined variable ``log_dir``).

    Returns:
        The subset of ``track_candidates`` at the timestamps they are on an intersection.

    Example:
        strollers_on_intersection = on_intersection(strollers, log_dir)
    """
    func = "on_intersection"
    tc, ctx = _unary_args(track_candidates, log_dir, func, "on_intersection(vehicles, log_dir)")
    hd = ctx.require_map(func)
    lane = ctx.lane_index(func)
    flags = np.append(hd.lane_is_intersection, False)
    return tc.restrict(flags[lane])


def in_drivable_area(track_candidates: Scenario, log_dir: LogContext) -> Scenario:
    """Timestamps at which an object's centre is inside the map's drivable area (needs the HD map).

    The drivable area includes roads, parking lots and driveways; use :func:`on_road` for roads only.

    Args:
        track_candidates: subject objects (scenario).
        log_dir: the log (the predefined variable ``log_dir``).

    Returns:
        The subset of ``track_candidates`` at the timestamps they are in the drivable area.

    Example:
        buses_in_drivable_area = in_drivable_area(buses, log_dir)
    """
    func = "in_drivable_area"
    tc, ctx = _unary_args(track_candidates, log_dir, func, "in_drivable_area(peds, log_dir)")
    hd = ctx.require_map(func)
    x, y = ctx.center_xy_m
    return tc.restrict(ctx.memo(("drivable",), lambda: hd.in_drivable_area(x, y)))


def on_road(track_candidates: Scenario, log_dir: LogContext) -> Scenario:
    """Timestamps at which an object's centre is on a mapped lane of any type (needs the HD map).

    Roads here are the lanes of the map (vehicle, bike and bus lanes, intersections included);
    parking lots and driveways are not roads. Prefer this over :func:`in_drivable_area` for
    "on the road".

    Args:
        track_candidates: subject objects (scenario).
        log_dir: the log (the predefined variable ``log_dir``).

    Returns:
        The subset of ``track_candidates`` at the timestamps they are on a road.

    Example:
        animals_on_road = on_road(animals, log_dir)
    """
    func = "on_road"
    tc, ctx = _unary_args(track_candidates, log_dir, func, "on_road(peds, log_dir)")
    return tc.restrict(ctx.lane_index(func) >= 0)


def in_same_lane(track_candidates: Scenario, related_candidates: Scenario, log_dir: LogContext) -> Scenario:
    """Track candidates that are in the same lane as a related candidate (needs the HD map).

    SUBJECT = ``track_candidates`` (returned). REFERENCE = ``related_candidates`` (returned as
    related objects). Two objects share a lane when the lane segments under their centres belong
    to the same lane: the chain of segments continuing each other straight ahead (a turning lane
    inside an intersection is a lane of its own).

    Args:
        track_candidates: subject objects (scenario).
        related_candidates: objects that may share the lane (scenario).
        log_dir: the log (the predefined variable ``log_dir``).

    Returns:
        The subset of ``track_candidates`` at the timestamps they share a lane with a related
        candidate, with those as related objects.

    Example:
        bicycles_in_same_lane_as_vehicle = in_same_lane(bicycles, vehicles, log_dir)
    """
    func = "in_same_lane"
    tc, rc, ctx = _binary_args(
        track_candidates, related_candidates, log_dir, func, "in_same_lane(bicycles, vehicles, log_dir)"
    )
    hd = ctx.require_map(func)
    lane = ctx.lane_index(func)
    pairs = _pairs(tc, rc)
    if pairs.rows.size == 0 or pairs.cols.size == 0:
        return tc.restrict(np.zeros_like(tc.referred))
    sem = np.append(hd.semantic_lane, -1)
    gr = sem[lane[pairs.rows]][:, None, :]
    gc = sem[lane[pairs.cols]][None, :, :]
    return _relational_result(tc, pairs, (gr >= 0) & (gr == gc))


def on_relative_side_of_road(
    track_candidates: Scenario, related_candidates: Scenario, log_dir: LogContext, side: str = "same"
) -> Scenario:
    """Track candidates on the same or the opposite side of the road as a related candidate (HD map).

    SUBJECT = ``track_candidates`` (returned). REFERENCE = ``related_candidates`` (returned as
    related objects). A side of the road is the set of adjacent lanes with the same direction of
    travel; the opposite side is the adjacent set with the other direction.

    Args:
        track_candidates: subject objects (scenario).
        related_candidates: reference objects (scenario).
        log_dir: the log (the predefined variable ``log_dir``).
        side: ``'same'`` or ``'opposite'``. Default ``'same'``.

    Returns:
        The subset of ``track_candidates`` at the timestamps the relation holds, with the
        matching related candidates as related objects.

    Example:
        vehicles_on_other_side = on_relative_side_of_road(vehicles, ego_vehicle, log_dir, side='opposite')
    """
    func = "on_relative_side_of_road"
    example = "on_relative_side_of_road(vehicles, ego, log_dir, side='opposite')"
    tc, rc, ctx = _binary_args(track_candidates, related_candidates, log_dir, func, example)
    side = _choice(side, ("same", "opposite"), "side", func)
    hd = ctx.require_map(func)
    lane = ctx.lane_index(func)
    pairs = _pairs(tc, rc)
    if pairs.rows.size == 0 or pairs.cols.size == 0:
        return tc.restrict(np.zeros_like(tc.referred))
    own = np.append(hd.road_side if side == "same" else hd.opposite_road_side, -1)
    other = np.append(hd.road_side, -2)
    gr = own[lane[pairs.rows]][:, None, :]
    gc = other[lane[pairs.cols]][None, :, :]
    return _relational_result(tc, pairs, (gr >= 0) & (gr == gc))


def at_stop_sign(track_candidates: Scenario, log_dir: LogContext, forward_thresh: float = 10) -> Scenario:
    """Timestamps at which an object is in the lane a stop sign controls, in front of the sign (HD map).

    Uses the log's STOP_SIGN objects. The object's centre must lie in front of the sign (on the
    side its face points to) by at most ``forward_thresh`` m and at least 1 m behind the sign's
    plane, at most 7 m to the right of the sign; the object must face the sign (heading more
    than 90 degrees from the sign's); and its lane must be the lane the sign controls (the
    nearest vehicle lane within 5 m of the sign that runs toward the sign's face). This may also
    match vehicles parked near a stop sign. Thresholds: ``MiningConfig.stop_sign_*``.

    Args:
        track_candidates: subject objects (scenario).
        log_dir: the log (the predefined variable ``log_dir``).
        forward_thresh: maximum distance in front of the sign, metres. Default 10.

    Returns:
        The subset of ``track_candidates`` at those timestamps, with the stop sign as related object.

    Example:
        vehicles_at_stop_sign = at_stop_sign(vehicles, log_dir)
    """
    func = "at_stop_sign"
    tc, ctx = _unary_args(track_candidates, log_dir, func, "at_stop_sign(vehicles, log_dir)")
    reach = _number(forward_thresh, "forward_thresh", func, minimum=0)
    cfg = ctx.config
    hd = ctx.require_map(func)
    lane = ctx.lane_index(func)
    signs = get_objects_of_category(log_dir, "STOP_SIGN")
    pairs = _pairs(tc, signs)
    if pairs.rows.size == 0 or pairs.cols.size == 0:
        return tc.restrict(np.zeros_like(tc.referred))
    # object centres in each sign's frame
    x, y = ctx.relative_position(pairs.cols, pairs.rows)
    x, y = np.swapaxes(x, 0, 1), np.swapaxes(y, 0, 1)
    yaw = ctx.yaw_rad
    dyaw = np.degrees(np.abs(wrap_angle(yaw[pairs.rows][:, None, :] - yaw[pairs.cols][None, :, :])))
    sign_lane = ctx.memo(("stop_sign_lanes",), lambda: _stop_sign_lanes(ctx, hd))
    sem = np.append(hd.semantic_lane, -1)
    obj_group = sem[lane[pairs.rows]][:, None, :]
    sign_group = sem[sign_lane[pairs.cols]][None, :, None]
    with np.errstate(invalid="ignore"):
        ok = (
            (x > -cfg.stop_sign_min_behind_m)
            & (x < reach)
            & (y < 0)
            & (y > -cfg.stop_sign_max_right_m)
            & (dyaw >= 90)
            & (obj_group >= 0)
            & (obj_group == sign_group)
        )
    return _relational_result(tc, pairs, ok)


def _stop_sign_lanes(ctx: LogContext, hd: Any) -> IntArray:
    """``(N,)`` lane index of the lane each STOP_SIGN track controls (-1 for other tracks)."""
    import shapely

    out = np.full(ctx.n_tracks, -1, dtype=np.int64)
    x, y = ctx.center_xy_m
    for i in np.flatnonzero(ctx.category_mask("STOP_SIGN")):
        t = int(np.argmax(ctx.valid[i]))
        p = shapely.points(x[i, t], y[i, t])
        near = np.flatnonzero(shapely.dwithin(hd.lane_polygons, p, 5.0))
        if near.size == 0:
            continue
        # prefer vehicle lanes outside intersections that run toward the sign's face
        toward = np.cos(hd.lane_direction_rad[near] - ctx.yaw_rad[i, t]) < 0
        rank = (
            1000.0 * hd.lane_is_intersection[near]
            + 100.0 * (hd.lane_types[near] != "VEHICLE")
            + 10.0 * ~toward
            + shapely.distance(hd.lane_polygons[near], p)
        )
        out[i] = near[int(np.argmin(rank))]
    return out


# ====================================================================== output


class OutputError(_errors.MiningError, RuntimeError):
    """``output_scenario`` was misused (not a scenario, wrong log, called twice)."""


@dataclass
class OutputSink:
    """Receives the scenario a program passes to :func:`output_scenario`.

    Attributes:
        scenario: the scenario output by the program, if any.
        description: the description the program gave.
        calls: how many times output_scenario was called.
    """

    scenario: Scenario | None = None
    description: str | None = None
    calls: int = 0


_SINK: ContextVar[OutputSink | None] = ContextVar("scenariominer_output_sink", default=None)


@contextlib.contextmanager
def capture_output() -> Iterator[OutputSink]:
    """Collect what a program passes to :func:`output_scenario` while the block runs."""
    sink = OutputSink()
    token = _SINK.set(sink)
    try:
        yield sink
    finally:
        _SINK.reset(token)


def output_scenario(
    scenario: Scenario,
    description: str | None = None,
    log_dir: LogContext | None = None,
    output_dir: Any = None,
    visualize: bool = False,
    **visualization_kwargs: Any,
) -> None:
    """Hand the program's final scenario back to the miner. Call it exactly ONCE, at the end.

    Args:
        scenario: the final scenario; its referred objects are the answer.
        description: the description being mined (pass the predefined variable ``description``).
        log_dir: the log (the predefined variable ``log_dir``); optional.
        output_dir: accepted for compatibility with RefAV programs (pass ``output_dir``); unused.
        visualize: accepted for compatibility; unused.
        **visualization_kwargs: accepted for compatibility; unused.

    Returns:
        None. The miner post-processes and stores the scenario.

    Example:
        output_scenario(vehicles_with_bicycle_right, description, log_dir, output_dir)
    """
    sink = _SINK.get()
    if sink is None:
        raise RuntimeError("output_scenario() can only be called inside a mining program run")
    if not isinstance(scenario, Scenario):
        raise OutputError(
            f"output_scenario(): the first argument must be the final scenario, got {type(scenario).__name__}"
        )
    if log_dir is not None and isinstance(log_dir, LogContext) and log_dir is not scenario.context:
        raise OutputError("output_scenario(): the scenario belongs to another log than log_dir")
    sink.calls += 1
    if sink.calls > 1:
        raise OutputError(
            "output_scenario() was called more than once; call it exactly once with the final scenario"
        )
    sink.scenario = scenario
    sink.description = None if description is None else str(description)


# ====================================================================== the DSL

#: Every function a mining program may call, in the order they are presented to the model.
DSL_FUNCTIONS: dict[str, Callable[..., Any]] = {
    f.__name__: f
    for f in (
        get_objects_of_category,
        is_category,
        has_objects_in_relative_direction,
        get_objects_in_relative_direction,
        being_crossed_by,
        near_objects,
        following,
        facing_toward,
        heading_toward,
        heading_in_relative_direction_to,
        turning,
        changing_lanes,
        has_lateral_acceleration,
        accelerating,
        has_velocity,
        stationary,
        at_pedestrian_crossing,
        on_lane_type,
        near_intersection,
        on_intersection,
        at_stop_sign,
        in_drivable_area,
        on_road,
        in_same_lane,
        on_relative_side_of_road,
        scenario_and,
        scenario_or,
        scenario_not,
        reverse_relationship,
        output_scenario,
    )
}


def library_reference(names: list[str] | None = None) -> str:
    """The signatures and docstrings of the DSL functions as one text (for prompts and docs).

    Args:
        names: functions to include, in this order; default all of :data:`DSL_FUNCTIONS`.
    """
    chosen = names if names is not None else list(DSL_FUNCTIONS)
    parts = []
    for name in chosen:
        f = DSL_FUNCTIONS[name]
        sig = str(inspect.signature(f)).replace("'", "")
        doc = inspect.getdoc(f) or ""
        parts.append(
            f"def {name}{sig}:\n"
            + "\n".join(f"    {line}" if line else "" for line in ['"""', *doc.splitlines(), '"""'])
        )
    return "\n\n".join(parts)
