"""Ego speed plans: stopping, yielding and driving on after a turn."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from numpy.typing import NDArray

from scenariominer.data.log import FloatArray
from scenariominer.synth.actors import (
    _Profile,
)

BoolArray = NDArray[np.bool_]


# ---------------------------------------------------------------------- ego speed plans


class _Retry(Exception):
    """The drawn parameters do not give a valid scenario; draw again."""


def _stop_and_go(
    v0: float, t_b: float, a_brake: float, t_go: float, a_acc: float, v_resume: float, v_floor: float = 0.0
) -> list[tuple[float, float]]:
    """Knots: cruise at ``v0``, brake from ``t_b`` towards ``v_floor``, hold, accelerate from ``t_go``."""
    t_floor = t_b + (v0 - v_floor) / a_brake
    knots = [(0.0, v0), (t_b, v0)]
    if t_go < t_floor:
        v_go = v0 - a_brake * max(t_go - t_b, 0.0)
        knots.append((max(t_go, t_b), v_go))
    else:
        knots += [(t_floor, v_floor), (t_go, v_floor)]
        v_go = v_floor
    knots.append((max(t_go, t_b) + abs(v_resume - v_go) / a_acc, v_resume))
    return knots


def _gentlest_brake(
    build: Callable[[float], _Profile],
    t_fine: FloatArray,
    front_limit_m: FloatArray,
    a_pref: float,
    a_max: float = 8.0,
) -> tuple[float, _Profile]:
    """Smallest deceleration ``>= a_pref`` whose profile keeps ``distance <= front_limit_m`` throughout."""
    for a in a_pref * 1.06 ** np.arange(80):
        if a > a_max:
            break
        profile = build(float(a))
        if np.all(profile.distance(t_fine) <= front_limit_m):
            return float(a), profile
    raise _Retry


def _with_turn_exit(
    knots: list[tuple[float, float]], s0: float, arc_end_s: float, v_exit: float, a_acc: float
) -> _Profile:
    """Append an acceleration to ``v_exit`` once the ego has left the turn at ``arc_end_s``."""
    profile = _Profile.of(knots, s0)
    t_exit = max(profile.time_at(arc_end_s), knots[-1][0])
    if not np.isfinite(t_exit):
        return profile
    v_turn = knots[-1][1]
    return _Profile.of([*knots, (t_exit, v_turn), (t_exit + max(v_exit - v_turn, 0.0) / a_acc, v_exit)], s0)
