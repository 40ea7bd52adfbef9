"""Argument checking and array helpers shared by the predicate families."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from scenariominer.data.log import BoolArray, FloatArray, time_derivative
from scenariominer.mine.context import IntArray, LogContext
from scenariominer.mine.scenario import (
    Scenario,
)

inf = math.inf

_DIRECTIONS = ("forward", "backward", "left", "right")
_DIRECTION_ALIASES = {"front": "forward", "ahead": "forward", "behind": "backward", "back": "backward"}

#: The values each text argument of a predicate accepts, by function and argument name: the one
#: list that the predicates check against and the program grammar (``mine/grammar.py``) offers
#: the model. ``None`` means the argument may be left out or passed as ``None``. Category
#: arguments accept the Argoverse 2 names and groups of :mod:`scenariominer.data.categories`.
ARGUMENT_CHOICES: dict[str, dict[str, tuple[str | None, ...]]] = {
    "has_objects_in_relative_direction": {"direction": _DIRECTIONS},
    "get_objects_in_relative_direction": {"direction": _DIRECTIONS},
    "being_crossed_by": {
        "direction": _DIRECTIONS,
        "in_direction": ("clockwise", "counterclockwise", "either"),
    },
    "heading_in_relative_direction_to": {"direction": ("same", "opposite", "perpendicular")},
    "turning": {"direction": ("left", "right", None)},
    "changing_lanes": {"direction": ("left", "right", None)},
    "on_lane_type": {"lane_type": ("VEHICLE", "BIKE", "BUS")},
    "on_relative_side_of_road": {"side": ("same", "opposite")},
}

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


def _choice(value: Any, name: str, func: str) -> Any:
    """The value of ``ARGUMENT_CHOICES[func][name]`` equal to ``value`` (text compared case-insensitively)."""
    allowed = ARGUMENT_CHOICES[func][name]
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
