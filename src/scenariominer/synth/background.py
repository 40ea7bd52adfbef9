"""Not-relevant scenarios and the background traffic every scenario gets."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from scenariominer.synth.actors import (
    _VEHICLE_MIX,
    _conflicts,
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
)
from scenariominer.synth.roads import (
    _route,
)
from scenariominer.synth.vocab import (
    ARM_M,
    BOX_HALF_M,
    CROSSWALK_FAR_M,
    NOT_RELEVANT_RANGE_M,
    ROAD_HALF_WIDTH_M,
    MapLayout,
)

BoolArray = NDArray[np.bool_]


def _scene_not_relevant(rng: np.random.Generator) -> _Scene:
    variant = str(rng.choice(["oncoming", "overtaking", "far_lead", "cross_before", "sidewalk"]))
    layout = MapLayout.INTERSECTION if variant == "cross_before" else MapLayout.STRAIGHT
    lane = int(rng.integers(1, 3))
    v0 = rng.uniform(8.0, 14.0)
    x_e0 = rng.uniform(-270.0, -200.0)
    knots = [(0.0, v0)]
    if rng.random() < 0.5:  # a gentle acceleration, never a deceleration
        t_a = rng.uniform(2.0, 8.0)
        knots += [(t_a, v0), (t_a + rng.uniform(2.0, 4.0), v0 + rng.uniform(0.5, 1.5))]
    ego_path = _route(0, "straight", lane)
    ego_profile = _Profile.of(knots, x_e0 + ARM_M)
    ego = _ego_track(ego_path, ego_profile)
    t_pass = rng.uniform(4.0, 10.0)
    x_pass = float(ego_profile.distance(np.array([t_pass]))[0]) - ARM_M  # the ego's x when the guest passes
    if variant == "oncoming":
        category = _pick(rng, _VEHICLE_MIX)
        v_g = rng.uniform(6.0, 14.0)
        path = _route(2, "straight", int(rng.integers(1, 3)))  # runs from x = +ARM towards -ARM
        profile = _Profile.of([(0.0, v_g)], (ARM_M - x_pass) - v_g * t_pass)
    elif variant == "overtaking":
        category = _pick(rng, _VEHICLE_MIX)
        v_g = v0 + rng.uniform(2.0, 5.0)
        path = _route(0, "straight", 3 - lane)
        profile = _Profile.of([(0.0, v_g)], x_pass + ARM_M - v_g * t_pass)
    elif variant == "far_lead":
        category = _pick(rng, _VEHICLE_MIX)
        v_g = v0 + rng.uniform(1.0, 3.0)
        path = ego_path
        profile = _Profile.of([(0.0, v_g)], x_e0 + ARM_M + rng.uniform(45.0, 60.0))
    elif variant == "cross_before":
        category = _pick(rng, (("REGULAR_VEHICLE", 0.8), ("BICYCLIST", 0.2)))
        v_g = rng.uniform(6.0, 12.0) if category == "REGULAR_VEHICLE" else rng.uniform(3.0, 6.0)
        path = _route(int(rng.choice([1, 3])), "straight", int(rng.integers(1, 3)))
        t_ego_at_box = ego_profile.time_at(ARM_M - BOX_HALF_M)
        t_cross = t_ego_at_box - rng.uniform(4.5, 7.0)
        profile = _Profile.of([(0.0, v_g)], ARM_M - v_g * t_cross)
    else:  # sidewalk
        category = "PEDESTRIAN"
        v_g = rng.uniform(0.8, 1.6)
        side = rng.choice([-1.0, 1.0])
        y_walk = side * rng.uniform(8.5, 11.0)
        heading_sign = rng.choice([-1.0, 1.0])
        path = _Path.through(np.array([[-heading_sign * ARM_M, y_walk], [heading_sign * ARM_M, y_walk]]))
        s_pass = heading_sign * x_pass + ARM_M
        profile = _Profile.of([(0.0, v_g)], s_pass - v_g * t_pass)
    guest = _Track.along(path, profile, _T, category, _size(rng, category))
    if _conflicts(ego, guest, horizon_frames=30, margin_m=0.5):
        raise _Retry
    near = np.hypot(guest.x - ego.x, guest.y - ego.y) <= NOT_RELEVANT_RANGE_M
    if near.sum() < 10:
        raise _Retry
    frames = np.flatnonzero(near)
    return _Scene(layout, ego, guest, float(_T[frames[0]]), float(_T[frames[-1]]))


# ---------------------------------------------------------------------- background traffic


def _background_candidate(rng: np.random.Generator, layout: MapLayout, ego: _Track) -> _Track:
    x_e0 = float(ego.x[0])  # every ego route enters from the west arm heading +x
    kind = str(rng.choice(["same_dir", "oncoming", "cross", "parked", "pedestrian", "pedestrian"]))
    if kind == "cross" and layout is MapLayout.STRAIGHT:
        kind = "oncoming"
    if kind in ("same_dir", "oncoming", "cross"):
        category = _pick(rng, _VEHICLE_MIX)
        v = rng.uniform(5.0, 15.0)
        if kind == "same_dir":
            path = _route(0, "straight", int(rng.integers(1, 3)))
            s0 = x_e0 + ARM_M + rng.uniform(-60.0, 120.0)
        elif kind == "oncoming":
            path = _route(2, "straight", int(rng.integers(1, 3)))
            s0 = ARM_M - x_e0 - rng.uniform(0.0, 250.0)
        else:
            movement = str(rng.choice(["straight", "straight", "left", "right"]))
            path = _route(
                int(rng.integers(1, 4)),
                movement,
                1 if movement == "left" else 2 if movement == "right" else int(rng.integers(1, 3)),
            )
            s0 = ARM_M - BOX_HALF_M - v * rng.uniform(-3.0, 14.0)
        return _Track.along(path, _Profile.of([(0.0, v)], s0), _T, category, _size(rng, category))
    if kind == "parked":
        category = _pick(rng, (("REGULAR_VEHICLE", 0.85), ("LARGE_VEHICLE", 0.1), ("BOX_TRUCK", 0.05)))
        side = rng.choice([-1.0, 1.0])
        x = x_e0 + rng.uniform(-20.0, 220.0)
        if layout is MapLayout.INTERSECTION and abs(x) < CROSSWALK_FAR_M + 8.0:
            x += np.sign(x or 1.0) * 30.0
        size = _size(rng, category)
        y = side * (ROAD_HALF_WIDTH_M + 0.3 + size[1] / 2 + rng.uniform(0.0, 0.4))
        yaw = (0.0 if side < 0 else np.pi) + rng.normal(0.0, 0.03)
        n = _T.size
        return _Track(
            category,
            *size,
            x=np.full(n, x),
            y=np.full(n, y),
            yaw=np.full(n, yaw),
            valid=np.ones(n, dtype=bool),
        )
    side = rng.choice([-1.0, 1.0])
    y = side * rng.uniform(8.5, 11.0)
    direction = rng.choice([-1.0, 1.0])
    v = 0.0 if rng.random() < 0.3 else rng.uniform(0.8, 1.6)
    path = _Path.through(np.array([[-direction * ARM_M, y], [direction * ARM_M, y]]))
    x0 = x_e0 + rng.uniform(0.0, 200.0)
    return _Track.along(
        path, _Profile.of([(0.0, v)], direction * x0 + ARM_M), _T, "PEDESTRIAN", _size(rng, "PEDESTRIAN")
    )


def _background(rng: np.random.Generator, scene: _Scene, n_wanted: int, visible_m: float) -> list[_Track]:
    kept: list[_Track] = []
    for _ in range(8 * n_wanted):
        if len(kept) == n_wanted:
            break
        cand = _background_candidate(rng, scene.layout, scene.ego)
        seen = np.hypot(cand.x - scene.ego.x, cand.y - scene.ego.y) <= visible_m
        if seen.sum() < 10:
            continue
        if _conflicts(scene.ego, cand, horizon_frames=30, margin_m=0.5):
            continue
        if _conflicts(scene.guest, cand, horizon_frames=0, margin_m=0.5):
            continue
        if any(_conflicts(other, cand, horizon_frames=0, margin_m=0.3) for other in kept):
            continue
        kept.append(cand)
    return kept
