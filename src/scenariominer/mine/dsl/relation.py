"""Relational predicates: objects in a direction, facing, heading toward, crossing, near, following."""

from __future__ import annotations

import math

import numpy as np

from scenariominer.data.log import BoolArray, FloatArray
from scenariominer.geometry import wrap_angle
from scenariominer.mine.context import LogContext
from scenariominer.mine.dsl._common import (
    _DIRECTION_ALIASES,
    _binary_args,
    _choice,
    _deriv_last_axis,
    _number,
    _Pairs,
    _pairs,
    _relational_result,
    _runs_containing,
    inf,
)
from scenariominer.mine.scenario import (
    Scenario,
)

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
    within_distance: float = 50,
    lateral_thresh: float = inf,
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

    The defaults (RefAV's) cover the whole half-plane on that side up to 50 m. Narrow them for
    "beside"/"just ahead": ``within_distance=4, lateral_thresh=1`` keeps "a bicycle to its
    right" beside the subject, at most about a lane away; ``lateral_thresh=1`` keeps "in front"
    inside a corridor of about one lane.

    Args:
        track_candidates: subject objects (scenario), e.g. vehicles.
        related_candidates: reference objects to look for (scenario), e.g. bicycles.
        log_dir: the log (the predefined variable ``log_dir``).
        direction: ``'forward'``, ``'backward'``, ``'left'`` or ``'right'`` of the subject
            (``'front'`` and ``'behind'``/``'back'`` are accepted as aliases).
        min_number: least number of related objects needed at a timestamp. Default 1.
        max_number: at most this many nearest related objects are kept as related. Default inf.
        within_distance: maximum box-to-box distance, metres. Default 50.
        lateral_thresh: how far (m) the related object's centre may lie outside the subject's
            extent perpendicular to ``direction``. Default inf (the whole half-plane); 1 keeps
            it beside the subject for left/right, inside about one lane for forward/backward.

    Returns:
        The subset of ``track_candidates`` at the timestamps where enough related candidates are
        in the direction, with those related candidates as related objects.

    Example:
        vehicles_with_bicycle_right = has_objects_in_relative_direction(
            vehicles, bicycles, log_dir, direction='right', within_distance=4, lateral_thresh=1)
        cars_with_2_peds_ahead = has_objects_in_relative_direction(
            cars, peds, log_dir, direction='forward', min_number=2, within_distance=20)
    """
    func = "has_objects_in_relative_direction"
    example = "has_objects_in_relative_direction(vehicles, bicycles, log_dir, direction='right')"
    tc, rc, ctx = _binary_args(track_candidates, related_candidates, log_dir, func, example)
    direction = _choice(_DIRECTION_ALIASES.get(str(direction).lower(), direction), "direction", func)
    lo = _number(min_number, "min_number", func, minimum=0)
    hi = _number(max_number, "max_number", func, minimum=0)
    dist_max = _number(within_distance, "within_distance", func, minimum=0)
    lat = _number(lateral_thresh, "lateral_thresh", func, minimum=0)
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
    within_distance: float = 50,
    lateral_thresh: float = inf,
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
        within_distance: maximum box-to-box distance, metres. Default 50.
        lateral_thresh: as in :func:`has_objects_in_relative_direction`, metres. Default inf
            (the whole half-plane); 1 keeps about one lane.

    Returns:
        A scenario whose referred objects are subsets of ``related_candidates``.

    Example:
        peds_in_front_of_vehicles = get_objects_in_relative_direction(
            vehicles, peds, log_dir, direction='forward', within_distance=15, lateral_thresh=1)
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
    that side and keeps moving across: from ``lateral_thresh`` m before the subject's side it
    approaches (``'forward'``: its left or right side) until ``lateral_thresh`` m past the
    subject's centre line.

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
        lateral_thresh: the crossing is tracked from this far before the subject's side it
            comes from until this far past the subject's centre line, metres. Default 5.

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
    direction = _choice(_DIRECTION_ALIASES.get(str(direction).lower(), direction), "direction", func)
    in_direction = _choice(in_direction, "in_direction", func)
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
        ahead = pairs.active & (u >= hu) & (u <= hu + reach)
        passed_up = (v_prev < 0) & (v >= 0)
        passed_down = (v_prev > 0) & (v <= 0)
        # approach: from lateral_thresh beyond the subject's side; departure: until lateral_thresh
        # past its centre line (RefAV); the cell of the pass itself always counts
        up = ahead & (dv > thr) & (v >= -(hv + lat)) & ((v < lat) | passed_up)
        down = ahead & (dv < -thr) & (v <= hv + lat) & ((v > -lat) | passed_down)
        up_event = up & passed_up
        down_event = down & passed_down
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
    the follower's lane: with an HD map the lead's lane segment is in the follower's semantic
    lane (as in :func:`in_same_lane`) or a successor of the follower's segment (and the lead is
    within 5 m sideways); without a map the lead's centre is at most 1.75 m to either side of
    the follower's centre line. Thresholds: ``MiningConfig.following_*``.

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
            # the lead's lane is in the follower's semantic lane, or a successor of its lane
            succ = np.zeros((hd.n_lanes + 1, hd.n_lanes + 1), dtype=bool)
            for i, ss in enumerate(hd.successors):
                succ[i, ss] = True
            same = hd.in_semantic_lane[lr, lc] | succ[lr, lc]
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
    direction = _choice(direction, "direction", func)
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
