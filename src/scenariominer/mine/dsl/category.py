"""Predicates that select objects by category."""

from __future__ import annotations

import numpy as np

from scenariominer.mine.context import LogContext
from scenariominer.mine.dsl._common import (
    _context,
    _unary_args,
)
from scenariominer.mine.scenario import (
    Scenario,
)

# ====================================================================== selection


def get_objects_of_category(log_dir: LogContext, category: str) -> Scenario:
    """All objects of one category, at every timestamp they are observed.

    Args:
        log_dir: the log (the predefined variable ``log_dir``).
        category: an Argoverse 2 category name such as ``"REGULAR_VEHICLE"``, ``"PEDESTRIAN"``,
            ``"BICYCLE"``, ``"BUS"``, ``"EGO_VEHICLE"``, or a group: ``"VEHICLE"`` (every motor
            vehicle incl. the ego: REGULAR_VEHICLE, LARGE_VEHICLE, BUS, BOX_TRUCK, TRUCK,
            TRUCK_CAB, SCHOOL_BUS, ARTICULATED_BUS, RAILED_VEHICLE, MOTORCYCLE, EGO_VEHICLE),
            ``"VULNERABLE_ROAD_USER"`` or ``"ANY"``. Case-insensitive. ``"VEHICLE"`` has no
            BICYCLE and no VEHICULAR_TRAILER (not motorised); where a description's "vehicle"
            includes them, combine them with ``scenario_or``.

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
