"""Map-aware predicates: crossings, lane types, intersections, drivable area, lanes, stop signs."""

from __future__ import annotations

from typing import Any

import numpy as np

from scenariominer.data.log import FloatArray
from scenariominer.geometry import wrap_angle
from scenariominer.mine.context import IntArray, LogContext
from scenariominer.mine.dsl._common import (
    _binary_args,
    _choice,
    _number,
    _pairs,
    _relational_result,
    _unary_args,
)
from scenariominer.mine.dsl.category import (
    get_objects_of_category,
)
from scenariominer.mine.scenario import (
    Scenario,
)

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
    kind = _choice(lane_type, "lane_type", func)
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
    related objects). The subject's lane is the chain of lane segments continuing the segment
    under its centre straight backwards and forwards (one best-aligned segment at a time; a
    turning lane inside an intersection is a lane of its own); the relation holds when the
    segment under the related object's centre is in that chain. As in RefAV it is directed:
    where lanes merge or split, ``in_same_lane(a, b)`` may hold while ``in_same_lane(b, a)``
    does not. Objects in the neighbouring lane are never in the same lane.

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
    same = hd.in_semantic_lane[lane[pairs.rows][:, None, :], lane[pairs.cols][None, :, :]]
    return _relational_result(tc, pairs, same)


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
    side = _choice(side, "side", func)
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
    than 90 degrees from the sign's); and its lane segment must be in the semantic lane (see
    :func:`in_same_lane`) of the lane the sign controls (the nearest vehicle lane within 5 m of
    the sign that runs toward the sign's face). This may also
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
    # the object's lane is in the semantic lane of the lane the sign controls
    in_sign_lane = hd.in_semantic_lane[sign_lane[pairs.cols][None, :, None], lane[pairs.rows][:, None, :]]
    with np.errstate(invalid="ignore"):
        ok = (
            (x > -cfg.stop_sign_min_behind_m)
            & (x < reach)
            & (y < 0)
            & (y > -cfg.stop_sign_max_right_m)
            & (dyaw >= 90)
            & in_sign_lane
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
