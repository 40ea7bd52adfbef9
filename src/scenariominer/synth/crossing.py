"""Scenario families across the ego's path: crossing pedestrians and objects, turns against traffic."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import shapely
from numpy.typing import NDArray

from scenariominer.data.adapters.av2 import AV2_EGO_SIZE_M
from scenariominer.synth.actors import (
    _first_run_on,
    _Path,
    _pick,
    _Profile,
    _size,
    _Track,
)
from scenariominer.synth.longitudinal import (
    _T,
    _ego_track,
    _Scene,
)
from scenariominer.synth.plans import (
    _Retry,
    _stop_and_go,
    _with_turn_exit,
)
from scenariominer.synth.roads import (
    _arc_end_s,
    _route,
)
from scenariominer.synth.vocab import (
    CROSSWALK_FAR_M,
    CROSSWALK_NEAR_M,
    ROAD_HALF_WIDTH_M,
    MapLayout,
)

BoolArray = NDArray[np.bool_]


@dataclass(frozen=True)
class _Crossing:
    """Parameters of a scenario where the guest crosses the ego's path."""

    ego_path: _Path
    guest_path: _Path
    guest_category: str
    guest_speed_mps: float
    walks_from_curb: bool
    v0_mps: float
    margin_m: tuple[float, float]
    turn: str = "straight"
    v_turn_mps: float = 0.0
    v_exit_mps: float = 0.0


def _scene_crossing(rng: np.random.Generator, spec: _Crossing) -> tuple[_Track, _Track, float, float]:
    le, we, _ = AV2_EGO_SIZE_M
    size = _size(rng, spec.guest_category)
    ego_corridor = shapely.buffer(shapely.LineString(spec.ego_path.xy), we / 2 + 0.3)
    guest_corridor = shapely.buffer(shapely.LineString(spec.guest_path.xy), size[1] / 2 + 0.3)
    span_g = _first_run_on(spec.guest_path, size[0], size[1], ego_corridor)
    span_e = _first_run_on(spec.ego_path, le, we, guest_corridor)
    if span_g is None or span_e is None:
        raise _Retry
    s_in, s_out = span_g
    s_conf = span_e[0]
    t_in = rng.uniform(5.0, 8.5)
    v_g = spec.guest_speed_mps
    if spec.walks_from_curb:
        t_walk = t_in - s_in / v_g - 0.4
        guest_profile = _Profile.of([(t_walk, 0.0), (t_walk + 0.8, v_g)], 0.0)
    else:
        guest_profile = _Profile.of([(0.0, v_g)], s_in - v_g * t_in)
    t_out = guest_profile.time_at(s_out)

    v0 = spec.v0_mps
    a = max(rng.uniform(1.8, 3.5), v0 / 5.5)
    s_stop = s_conf - rng.uniform(*spec.margin_m)
    s_b = s_stop - v0**2 / (2 * a)
    t_b = t_in + rng.uniform(-0.5, 1.0) - (s_conf - s_b) / v0
    s_e0 = s_b - v0 * t_b
    t_go = t_out + rng.uniform(0.4, 1.2)
    if t_b < 1.0 or s_e0 < 0.0 or t_go > 13.5:
        raise _Retry
    a_acc = rng.uniform(1.2, 2.5)
    if spec.turn == "straight":
        profile = _Profile.of(_stop_and_go(v0, t_b, a, t_go, a_acc, v0 * rng.uniform(0.8, 1.0)), s_e0)
    else:
        knots = _stop_and_go(v0, t_b, a, t_go, a_acc, spec.v_turn_mps)
        profile = _with_turn_exit(knots, s_e0, _arc_end_s(spec.turn), spec.v_exit_mps, a_acc)
    # By construction the ego's centre stays behind s_stop until the guest has left the corridor.
    ego = _ego_track(spec.ego_path, profile)
    guest = _Track.along(spec.guest_path, guest_profile, _T, spec.guest_category, size)
    # The interaction lasts until the ego drives on (it has come to its lowest speed by then).
    return ego, guest, min(t_b, t_in), t_go


def _ped_path(rng: np.random.Generator, k: int, across_x: float) -> _Path:
    """Walk across arm ``k``'s crosswalk, from a curb 3 m off the road, in a random direction."""
    x = across_x + rng.uniform(-0.8, 0.8)
    y0 = ROAD_HALF_WIDTH_M + 3.0
    ys = np.array([-y0, y0 + 40.0]) if rng.random() < 0.5 else np.array([y0, -y0 - 40.0])
    return _Path.through(np.column_stack([[x, x], ys])).rotated(k * np.pi / 2)


def _scene_ped_crossing(rng: np.random.Generator) -> _Scene:
    far_side = rng.random() < 0.5
    across_x = (1 if far_side else -1) * 0.5 * (CROSSWALK_NEAR_M + CROSSWALK_FAR_M)
    spec = _Crossing(
        ego_path=_route(0, "straight", int(rng.integers(1, 3))),
        guest_path=_ped_path(rng, 0, across_x),
        guest_category="PEDESTRIAN",
        guest_speed_mps=rng.uniform(1.0, 1.8),
        walks_from_curb=True,
        v0_mps=rng.uniform(7.0, 13.0),
        margin_m=(1.0, 3.5),
    )
    ego, guest, t0, t1 = _scene_crossing(rng, spec)
    return _Scene(MapLayout.INTERSECTION, ego, guest, t0, t1)


def _scene_obj_crossing(rng: np.random.Generator) -> _Scene:
    category = _pick(rng, (("REGULAR_VEHICLE", 0.6), ("BICYCLIST", 0.25), ("MOTORCYCLIST", 0.15)))
    speed = {"REGULAR_VEHICLE": (6.0, 12.0), "BICYCLIST": (3.0, 6.0), "MOTORCYCLIST": (7.0, 12.0)}[category]
    spec = _Crossing(
        ego_path=_route(0, "straight", int(rng.integers(1, 3))),
        guest_path=_route(int(rng.choice([1, 3])), "straight", int(rng.integers(1, 3))),
        guest_category=category,
        guest_speed_mps=rng.uniform(*speed),
        walks_from_curb=False,
        v0_mps=rng.uniform(8.0, 13.0),
        margin_m=(2.0, 8.0),
    )
    ego, guest, t0, t1 = _scene_crossing(rng, spec)
    return _Scene(MapLayout.INTERSECTION, ego, guest, t0, t1)


def _scene_left_oppo(rng: np.random.Generator) -> _Scene:
    category = _pick(
        rng, (("REGULAR_VEHICLE", 0.75), ("LARGE_VEHICLE", 0.1), ("BOX_TRUCK", 0.05), ("MOTORCYCLIST", 0.1))
    )
    spec = _Crossing(
        ego_path=_route(0, "left", 1),
        guest_path=_route(2, "straight", int(rng.integers(1, 3))),
        guest_category=category,
        guest_speed_mps=rng.uniform(7.0, 13.0),
        walks_from_curb=False,
        v0_mps=rng.uniform(6.0, 10.0),
        margin_m=(0.8, 2.5),
        turn="left",
        v_turn_mps=rng.uniform(4.0, 6.0),
        v_exit_mps=rng.uniform(8.0, 12.0),
    )
    ego, guest, t0, t1 = _scene_crossing(rng, spec)
    return _Scene(MapLayout.INTERSECTION, ego, guest, t0, t1)


def _scene_right_ped(rng: np.random.Generator) -> _Scene:
    # The south arm's crosswalk is the west arm's turned a quarter counter-clockwise.
    spec = _Crossing(
        ego_path=_route(0, "right", 2),
        guest_path=_ped_path(rng, 1, -0.5 * (CROSSWALK_NEAR_M + CROSSWALK_FAR_M)),
        guest_category="PEDESTRIAN",
        guest_speed_mps=rng.uniform(1.0, 1.8),
        walks_from_curb=True,
        v0_mps=rng.uniform(5.0, 8.0),
        margin_m=(1.0, 3.0),
        turn="right",
        v_turn_mps=rng.uniform(3.0, 4.5),
        v_exit_mps=rng.uniform(7.0, 11.0),
    )
    ego, guest, t0, t1 = _scene_crossing(rng, spec)
    return _Scene(MapLayout.INTERSECTION, ego, guest, t0, t1)
