"""Scenario families ahead of the ego in its lane: cut-in, lead vehicle braking, approach to a stop."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from scenariominer.data.adapters.av2 import AV2_EGO_SIZE_M
from scenariominer.data.log import FloatArray
from scenariominer.synth.actors import (
    _VEHICLE_MIX,
    _Path,
    _pick,
    _Profile,
    _size,
    _Track,
)
from scenariominer.synth.plans import (
    _gentlest_brake,
    _stop_and_go,
)
from scenariominer.synth.roads import (
    _LANE_Y,
    _route,
)
from scenariominer.synth.vocab import (
    ARM_M,
    FRAME_PERIOD_S,
    N_FRAMES,
    MapLayout,
)

BoolArray = NDArray[np.bool_]


# ---------------------------------------------------------------------- scenarios (canonical frame)


@dataclass(eq=False)
class _Scene:
    layout: MapLayout
    ego: _Track
    guest: _Track
    start_s: float
    end_s: float


_T: FloatArray = np.arange(N_FRAMES, dtype=np.float64) * FRAME_PERIOD_S
_T_FINE: FloatArray = np.arange(0.0, N_FRAMES * FRAME_PERIOD_S, 0.02, dtype=np.float64)


def _ego_track(path: _Path, profile: _Profile) -> _Track:
    return _Track.along(path, profile, _T, "EGO_VEHICLE", AV2_EGO_SIZE_M)


def _scene_cut_in(rng: np.random.Generator) -> _Scene:
    lane_e = int(rng.integers(1, 3))
    y_e, y_g = _LANE_Y[lane_e], _LANE_Y[3 - lane_e]
    le, we, _ = AV2_EGO_SIZE_M
    v0 = rng.uniform(9.0, 15.0)
    v_g = max(v0 - rng.uniform(2.0, 5.5), 3.0)
    t_c, dur, gap, tau = (
        rng.uniform(3.0, 7.0),
        rng.uniform(2.0, 3.5),
        rng.uniform(4.0, 12.0),
        rng.uniform(0.3, 1.0),
    )
    category = _pick(rng, (("REGULAR_VEHICLE", 0.8), ("LARGE_VEHICLE", 0.1), ("MOTORCYCLIST", 0.1)))
    size = _size(rng, category)
    x_e0 = rng.uniform(-270.0, -230.0)
    x_gc = x_e0 + v0 * t_c + le / 2 + gap + size[0] / 2
    xs = np.arange(-ARM_M, ARM_M, 0.5)
    u = np.clip((xs - x_gc) / (v_g * dur), 0.0, 1.0)
    guest_path = _Path.through(np.column_stack([xs, y_g + (y_e - y_g) * u * u * (3 - 2 * u)]))
    guest_profile = _Profile.of([(0.0, v_g)], s0_m=(x_gc + ARM_M) - v_g * t_c)
    gx, gy, gyaw = guest_path.pose(guest_profile.distance(_T_FINE))
    in_lane = np.abs(gy - y_e) < (we + size[1]) / 2 + 0.2
    rear = gx - 0.5 * size[0] * np.abs(np.cos(gyaw)) - 0.5 * size[1] * np.abs(np.sin(gyaw))
    limit = np.where(in_lane, rear - 1.0 - le / 2 + ARM_M, np.inf)
    t_b = t_c + tau
    v_t = v_g * rng.uniform(0.85, 1.0)
    a, profile = _gentlest_brake(
        lambda a: _Profile.of([(0.0, v0), (t_b, v0), (t_b + (v0 - v_t) / a, v_t)], x_e0 + ARM_M),
        _T_FINE,
        limit,
        rng.uniform(1.5, 3.5),
    )
    ego_path = _route(0, "straight", lane_e)
    guest = _Track.along(guest_path, guest_profile, _T, category, size)
    return _Scene(
        MapLayout.STRAIGHT, _ego_track(ego_path, profile), guest, t_c, max(t_c + dur, t_b + (v0 - v_t) / a)
    )


def _scene_lead_brake(rng: np.random.Generator) -> _Scene:
    lane = int(rng.integers(1, 3))
    le = AV2_EGO_SIZE_M[0]
    v0 = rng.uniform(8.0, 16.0)
    category = _pick(rng, _VEHICLE_MIX)
    size = _size(rng, category)
    gap0 = v0 * rng.uniform(0.9, 2.0) + 2.0
    t_lb, a_l = rng.uniform(3.5, 7.0), rng.uniform(3.0, 7.0)
    v_end = 0.0 if rng.random() < 0.4 else v0 * rng.uniform(0.1, 0.5)
    hold, a_acc_l, v_res = rng.uniform(1.5, 4.0), rng.uniform(1.0, 2.5), v0 * rng.uniform(0.6, 1.0)
    t_lstop = t_lb + (v0 - v_end) / a_l
    t_lgo = t_lstop + hold
    x_e0 = rng.uniform(-270.0, -230.0)
    lead_profile = _Profile.of(
        [(0.0, v0), (t_lb, v0), (t_lstop, v_end), (t_lgo, v_end), (t_lgo + (v_res - v_end) / a_acc_l, v_res)],
        s0_m=x_e0 + ARM_M + le / 2 + gap0 + size[0] / 2,
    )
    # The ego keeps at least this gap (m) to the lead's rear; its braking is the gentlest that does.
    limit = lead_profile.distance(_T_FINE) - size[0] / 2 - rng.uniform(2.0, 4.0) - le / 2
    t_b = t_lb + rng.uniform(0.5, 1.2)
    t_go = t_lgo + rng.uniform(0.8, 1.5)
    a_acc = a_acc_l * rng.uniform(0.7, 1.0)
    _, profile = _gentlest_brake(
        lambda a: _Profile.of(_stop_and_go(v0, t_b, a, t_go, a_acc, v_res, v_end), x_e0 + ARM_M),
        _T_FINE,
        limit,
        rng.uniform(1.0, 2.0),
    )
    path = _route(0, "straight", lane)
    guest = _Track.along(path, lead_profile, _T, category, size)
    # The interaction lasts until the ego drives on again behind the lead.
    return _Scene(MapLayout.STRAIGHT, _ego_track(path, profile), guest, t_lb, t_go)


def _scene_approach_stop(rng: np.random.Generator) -> _Scene:
    lane = int(rng.integers(1, 3))
    le = AV2_EGO_SIZE_M[0]
    v0 = rng.uniform(7.0, 14.0)
    category = _pick(
        rng, (("REGULAR_VEHICLE", 0.6), ("BOX_TRUCK", 0.15), ("BUS", 0.1), ("LARGE_VEHICLE", 0.15))
    )
    size = _size(rng, category)
    v_g = 0.0 if rng.random() < 0.6 else rng.uniform(1.0, 3.5)
    t_b = rng.uniform(3.0, 7.0)
    a = max(rng.uniform(1.5, 3.0), v0 / 5.0)
    gap_final = rng.uniform(2.5, 6.0)
    x_e0 = rng.uniform(-270.0, -230.0)
    s_front_b = x_e0 + ARM_M + v0 * t_b + le / 2
    rear_at_b = s_front_b + gap_final + (v0 - v_g) ** 2 / (2 * a)
    guest_profile = _Profile.of([(0.0, v_g)], s0_m=rear_at_b + size[0] / 2 - v_g * t_b)
    t_end = t_b + (v0 - v_g) / a
    profile = _Profile.of([(0.0, v0), (t_b, v0), (t_end, v_g)], x_e0 + ARM_M)
    path = _route(0, "straight", lane)
    guest = _Track.along(path, guest_profile, _T, category, size)
    return _Scene(MapLayout.STRAIGHT, _ego_track(path, profile), guest, t_b, t_end)
