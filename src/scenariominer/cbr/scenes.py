"""Synthetic risk scenes for a labelled case set, with the ground truth from the rollout check.

Each scene is drawn directly as parameters (no per-frame simulation): the ego drives straight at a
constant speed along +x in the lane centred on ``y = 0`` (lanes are 3.5 m wide; ``y = +3.5`` is the
lane to its left, same direction or oncoming depending on the risk type, ``y = -3.5`` the lane or
kerb side to its right). One *main* road user creates the conflict of the scene's risk type, timed
so that the unreacting ego (the "recorded" trajectory) collides with it ``tc_s`` seconds after the
manoeuvre start. Optional *blockers* make some escapes impossible: a car in the left lane, parked
vehicles on the right, a car following closely behind the ego.

Every configured manoeuvre is rolled out (:mod:`.rollout`); the ground truth is the avoiding
manoeuvre of least effort. Scenes where the unreacting ego does not collide, or no manoeuvre avoids
the collision, are discarded and redrawn.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from scenariominer.cbr.rollout import RECORDED, RolloutOutcome, RolloutScene, rollout
from scenariominer.cbr.vocab import CbrError, ManoeuvreSet
from scenariominer.geometry import OrientedBoxes

__all__ = ["Actor", "LabelledScene", "SyntheticScene", "draw_scene", "label_scene"]

FloatArray = NDArray[np.float64]
LANE_M = 3.5
EGO_LENGTH_M = 4.6
EGO_WIDTH_M = 1.9
HORIZON_S = 5.0
DT_S = 0.1

_SIZES: dict[str, tuple[tuple[float, float], tuple[float, float]]] = {
    "car": ((4.2, 4.9), (1.75, 1.95)),
    "van": ((5.0, 5.6), (1.95, 2.1)),
    "truck": ((8.0, 10.0), (2.4, 2.55)),
    "pedestrian": ((0.5, 0.7), (0.5, 0.7)),
    "cyclist": ((1.7, 1.9), (0.6, 0.8)),
}


@dataclass(frozen=True)
class Actor:
    """A road user of a synthetic scene: its role, kind and ``(T,)`` pose arrays."""

    role: str
    kind: str
    x_m: FloatArray
    y_m: FloatArray
    yaw_rad: FloatArray
    length_m: float
    width_m: float


@dataclass(frozen=True)
class SyntheticScene:
    """One drawn scene before labelling.

    Attributes:
        scene_id: unique id within a build.
        risk_type: the risk type its main road user creates.
        t_s: ``(T,)`` times from the manoeuvre start.
        ego_speed_mps: the ego's constant speed.
        actors: main road user first, then blockers.
        facts: values the caption templates use (kinds, gaps, speeds, sides, road).
    """

    scene_id: str
    risk_type: str
    t_s: FloatArray
    ego_speed_mps: float
    actors: tuple[Actor, ...]
    facts: dict[str, Any] = field(default_factory=dict)

    def rollout_scene(self) -> RolloutScene:
        """The scene as the rollout check sees it (the unreacting ego as the recorded one)."""
        t = self.t_s
        stack = {k: np.vstack([getattr(a, k) for a in self.actors]) for k in ("x_m", "y_m", "yaw_rad")}
        lengths = np.array([[a.length_m] for a in self.actors]) * np.ones((1, t.size))
        widths = np.array([[a.width_m] for a in self.actors]) * np.ones((1, t.size))
        boxes = OrientedBoxes(stack["x_m"], stack["y_m"], stack["yaw_rad"], lengths, widths)
        return RolloutScene(
            t_s=t,
            ego_x_m=self.ego_speed_mps * t,
            ego_y_m=np.zeros_like(t),
            ego_yaw_rad=np.zeros_like(t),
            ego_speed_mps=self.ego_speed_mps,
            ego_length_m=EGO_LENGTH_M,
            ego_width_m=EGO_WIDTH_M,
            others=boxes,
            other_ids=tuple(a.role for a in self.actors),
        )


@dataclass(frozen=True)
class LabelledScene:
    """A scene with its rollout outcomes and ground-truth manoeuvre (least effort that avoids)."""

    scene: SyntheticScene
    outcomes: dict[str, RolloutOutcome]
    manoeuvre: str


# ---------------------------------------------------------------------------------- helpers
def _size(rng: np.random.Generator, kind: str) -> tuple[float, float]:
    (l0, l1), (w0, w1) = _SIZES[kind]
    return float(rng.uniform(l0, l1)), float(rng.uniform(w0, w1))


def _smooth(t: FloatArray, start_s: float, dur_s: float) -> FloatArray:
    """0 before ``start_s``, 1 after ``start_s + dur_s``, half-cosine in between."""
    phase = np.clip((t - start_s) / dur_s, 0.0, 1.0)
    return np.asarray(0.5 * (1.0 - np.cos(np.pi * phase)), dtype=np.float64)


def _yaw(x: FloatArray, y: FloatArray, default: float) -> FloatArray:
    dx, dy = np.gradient(x), np.gradient(y)
    moving = np.hypot(dx, dy) > 1e-4
    return np.asarray(np.where(moving, np.arctan2(dy, dx), default), dtype=np.float64)


def _actor(
    role: str, kind: str, x: FloatArray, y: FloatArray, size: tuple[float, float], default_yaw: float
) -> Actor:
    return Actor(role, kind, x, y, _yaw(x, y, default_yaw), size[0], size[1])


def _speed_profile_distance(t: FloatArray, v0: float, decel: float, start_s: float) -> FloatArray:
    """Distance travelled at ``v0`` braking at ``decel`` from ``start_s`` to a stop, ``(T,)``."""
    tb = np.clip(t - start_s, 0.0, v0 / decel if decel > 0 else np.inf)
    return np.asarray(v0 * np.minimum(t, start_s) + v0 * tb - 0.5 * decel * tb**2, dtype=np.float64)


def _vehicle_kind(rng: np.random.Generator) -> str:
    return str(rng.choice(["car", "car", "car", "van", "truck"]))


# ---------------------------------------------------------------------------------- main road users
def _vehicle_ahead(
    rng: np.random.Generator, t: FloatArray, v_e: float, tc: float
) -> tuple[Actor, dict[str, Any]]:
    kind = _vehicle_kind(rng)
    size = _size(rng, kind)
    action = str(rng.choice(["stopped", "slow", "braking"]))
    if action == "stopped":
        s = np.zeros_like(t)
        v_o = 0.0
    elif action == "slow":
        v_o = float(rng.uniform(0.15, 0.5) * v_e)
        s = v_o * t
    else:
        v_o = float(rng.uniform(0.7, 1.0) * v_e)
        s = _speed_profile_distance(t, v_o, float(rng.uniform(5.0, 9.0)), float(rng.uniform(0.0, 0.5)))
    x0 = v_e * tc - float(np.interp(tc, t, s)) + 0.5 * (EGO_LENGTH_M + size[0])
    facts = {
        "kind": kind,
        "action": action,
        "gap_m": x0 - 0.5 * (EGO_LENGTH_M + size[0]),
        "other_speed_mps": v_o,
    }
    return _actor("main", kind, x0 + s, np.zeros_like(t), size, 0.0), facts


def _pedestrian(
    rng: np.random.Generator, t: FloatArray, v_e: float, tc: float
) -> tuple[Actor, dict[str, Any]]:
    kind = str(rng.choice(["pedestrian", "pedestrian", "cyclist"]))
    size = _size(rng, kind)
    side = str(rng.choice(["right", "left"]))
    v_p = float(rng.uniform(1.2, 2.5) if kind == "pedestrian" else rng.uniform(3.0, 5.0))
    sign = 1.0 if side == "right" else -1.0  # crossing from the right moves towards +y
    x_cross = v_e * tc + 0.5 * EGO_LENGTH_M + float(rng.uniform(-0.5, 1.0))
    y = sign * v_p * (t - tc) - sign * float(rng.uniform(-0.6, 0.6))
    x = np.full_like(t, x_cross)
    facts = {"kind": kind, "side": side, "other_speed_mps": v_p, "gap_m": x_cross - 0.5 * EGO_LENGTH_M}
    return _actor("main", kind, x, y, size, sign * np.pi / 2), facts


def _adjacent(rng: np.random.Generator, t: FloatArray, v_e: float, tc: float) -> tuple[Actor, dict[str, Any]]:
    kind = _vehicle_kind(rng)
    size = _size(rng, kind)
    side = str(rng.choice(["left", "right"]))
    sign = 1.0 if side == "left" else -1.0
    v_o = float(v_e + rng.uniform(-2.0, 2.0))
    dx0 = float(rng.uniform(-1.0, 1.0) * 0.5 * (EGO_LENGTH_M + size[0]))
    vy = float(rng.uniform(0.8, 1.8))
    gap = LANE_M - 0.5 * (EGO_WIDTH_M + size[1])
    dur = LANE_M / vy
    start = max(0.0, tc - gap / vy * 0.9)
    x = dx0 + (v_o - v_e) * 0.0 + v_o * t
    y = sign * LANE_M * (1.0 - _smooth(t, start, dur))
    facts = {"kind": kind, "side": side, "other_speed_mps": v_o, "offset_m": dx0, "lateral_mps": vy}
    return _actor("main", kind, x, y, size, 0.0), facts


def _merging(rng: np.random.Generator, t: FloatArray, v_e: float, tc: float) -> tuple[Actor, dict[str, Any]]:
    kind = _vehicle_kind(rng)
    size = _size(rng, kind)
    side = str(rng.choice(["right", "right", "left"]))
    sign = 1.0 if side == "left" else -1.0
    v_m = float(max(2.0, v_e - rng.uniform(3.0, 9.0)))
    x0 = (v_e - v_m) * tc + 0.5 * (EGO_LENGTH_M + size[0]) + float(rng.uniform(-1.0, 0.5))
    dur = float(rng.uniform(2.0, 3.5))
    start = max(0.0, tc - 0.6 * dur - float(rng.uniform(0.2, 0.8)))
    y = sign * LANE_M * (1.0 - _smooth(t, start, dur))
    facts = {"kind": kind, "side": side, "other_speed_mps": v_m, "gap_m": x0 - 0.5 * (EGO_LENGTH_M + size[0])}
    return _actor("main", kind, x0 + v_m * t, y, size, 0.0), facts


def _oncoming(rng: np.random.Generator, t: FloatArray, v_e: float, tc: float) -> tuple[Actor, dict[str, Any]]:
    kind = _vehicle_kind(rng)
    size = _size(rng, kind)
    v_o = float(rng.uniform(8.0, 20.0))
    intrusion = float(rng.uniform(1.2, 2.4))
    returns = bool(rng.random() < 0.5)
    x0 = (v_e + v_o) * tc + 0.5 * (EGO_LENGTH_M + size[0])
    start = max(0.0, tc - float(rng.uniform(1.2, 2.0)))
    drift = _smooth(t, start, 1.2)
    if returns:
        drift = drift - _smooth(t, tc + float(rng.uniform(0.2, 0.8)), 1.2)
    y = LANE_M - intrusion * drift
    facts = {"kind": kind, "other_speed_mps": v_o, "intrusion_m": intrusion, "returns": returns, "gap_m": x0}
    return _actor("main", kind, x0 - v_o * t, y, size, np.pi), facts


def _head_on(rng: np.random.Generator, t: FloatArray, v_e: float, tc: float) -> tuple[Actor, dict[str, Any]]:
    kind = _vehicle_kind(rng)
    size = _size(rng, kind)
    v_o = float(rng.uniform(6.0, 20.0))
    x0 = (v_e + v_o) * tc + 0.5 * (EGO_LENGTH_M + size[0])
    offset = float(rng.uniform(-0.4, 0.4))
    facts = {"kind": kind, "other_speed_mps": v_o, "gap_m": x0 - 0.5 * (EGO_LENGTH_M + size[0])}
    return _actor("main", kind, x0 - v_o * t, np.full_like(t, offset), size, np.pi), facts


def _opposite_turning(
    rng: np.random.Generator, t: FloatArray, v_e: float, tc: float
) -> tuple[Actor, dict[str, Any]]:
    kind = str(rng.choice(["car", "car", "van"]))
    size = _size(rng, kind)
    v_t = float(rng.uniform(4.0, 9.0))
    radius = float(rng.uniform(7.0, 11.0))
    # Path: along y = +3.5 heading -x, a left turn (quarter circle, centre below), then heading -y.
    straight = np.linspace(60.0, 0.0, 121)
    ang = np.linspace(np.pi / 2, np.pi, 60)[1:]
    arc_x, arc_y = radius * np.cos(ang), (LANE_M - radius) + radius * np.sin(ang)
    tail = np.linspace(0.0, 40.0, 81)[1:]
    px = np.concatenate([straight, arc_x, np.full(tail.size, -radius)])
    py = np.concatenate([np.full(straight.size, LANE_M), arc_y, LANE_M - radius - tail])
    s = np.concatenate([[0.0], np.cumsum(np.hypot(np.diff(px), np.diff(py)))])
    i_cross = int(np.argmax(py <= 0.0))
    s_cross, x_cross0 = float(s[i_cross]), float(px[i_cross])
    target_x = v_e * tc + 0.5 * EGO_LENGTH_M + float(rng.uniform(0.0, 1.5))
    s_t = np.clip(s_cross + v_t * (t - tc), 0.0, s[-1])
    x = np.interp(s_t, s, px) + (target_x - x_cross0)
    y = np.interp(s_t, s, py)
    facts = {"kind": kind, "other_speed_mps": v_t, "gap_m": target_x - 0.5 * EGO_LENGTH_M}
    return _actor("main", kind, x, y, size, np.pi), facts


_MAIN: dict[str, Callable[[np.random.Generator, FloatArray, float, float], tuple[Actor, dict[str, Any]]]] = {
    "vehicle_ahead": _vehicle_ahead,
    "pedestrian": _pedestrian,
    "adjacent_vehicle": _adjacent,
    "merging_vehicle": _merging,
    "oncoming_vehicle": _oncoming,
    "head_on": _head_on,
    "opposite_turning_vehicle": _opposite_turning,
}
#: Risk types whose lane to the left of the ego carries oncoming traffic.
_ONCOMING_LEFT = frozenset({"oncoming_vehicle", "head_on", "opposite_turning_vehicle"})


# ---------------------------------------------------------------------------------- blockers
def _blockers(
    rng: np.random.Generator, t: FloatArray, v_e: float, tc: float, risk_type: str, main: dict[str, Any]
) -> tuple[list[Actor], dict[str, Any]]:
    out: list[Actor] = []
    facts: dict[str, Any] = {"left_lane": "oncoming" if risk_type in _ONCOMING_LEFT else "same"}
    main_side = main.get("side")
    if rng.random() < 0.4 and main_side != "left":
        size = _size(rng, "car")
        if risk_type in _ONCOMING_LEFT:
            v_o = float(rng.uniform(8.0, 16.0))
            x0 = v_e * tc + v_o * tc + float(rng.uniform(-8.0, 8.0))
            out.append(_actor("left", "car", x0 - v_o * t, np.full_like(t, LANE_M), size, np.pi))
        else:
            v_o = float(v_e + rng.uniform(-1.5, 1.5))
            x0 = float(rng.uniform(-3.0, 10.0))
            out.append(_actor("left", "car", x0 + v_o * t, np.full_like(t, LANE_M), size, 0.0))
        facts["left_blocked"] = True
    if rng.random() < 0.4 and main_side != "right":
        kind = str(rng.choice(["car", "van", "truck"]))
        size = _size(rng, kind)
        x0 = v_e * tc + float(rng.uniform(-12.0, 4.0))
        y0 = -LANE_M + float(rng.uniform(-0.2, 0.5))
        out.append(_actor("right", kind, np.full_like(t, x0), np.full_like(t, y0), size, 0.0))
        facts["right_blocked"] = kind
    if rng.random() < 0.3:
        size = _size(rng, "car")
        gap = float(rng.uniform(3.0, 8.0))
        x0 = -(gap + 0.5 * (EGO_LENGTH_M + size[0]))
        v_f = v_e * float(rng.uniform(0.97, 1.03))
        out.append(_actor("behind", "car", x0 + v_f * t, np.zeros_like(t), size, 0.0))
        facts["follower_gap_m"] = gap
    return out, facts


def draw_scene(rng: np.random.Generator, risk_type: str, scene_id: str) -> SyntheticScene:
    """Draw one scene of ``risk_type`` (not yet checked or labelled).

    Raises:
        CbrError: the risk type has no scene generator (only the paper's seven have one).
    """
    make = _MAIN.get(risk_type)
    if make is None:
        raise CbrError(f"no synthetic scene generator for risk type {risk_type!r}; known: {sorted(_MAIN)}")
    t = np.round(np.arange(0.0, HORIZON_S + 1e-9, DT_S), 6)
    v_e = float(rng.uniform(8.0, 22.0))
    tc = float(rng.uniform(1.3, 3.0))
    main, main_facts = make(rng, t, v_e, tc)
    blockers, extra = _blockers(rng, t, v_e, tc, risk_type, main_facts)
    road = str(rng.choice(["urban street", "arterial road", "suburban road", "two-lane road", "city avenue"]))
    facts = {**main_facts, **extra, "ego_speed_mps": v_e, "tc_s": tc, "road": road}
    return SyntheticScene(scene_id, risk_type, t, v_e, (main, *blockers), facts)


def label_scene(
    scene: SyntheticScene, manoeuvres: ManoeuvreSet, *, max_speed_mps: float = 36.0
) -> LabelledScene | None:
    """Roll out every manoeuvre; ``None`` unless the unreacting ego collides and one manoeuvre avoids."""
    outcomes = rollout(scene.rollout_scene(), manoeuvres.manoeuvres, max_speed_mps=max_speed_mps)
    if not outcomes[RECORDED].collision:
        return None
    for m in manoeuvres.by_effort():
        if outcomes[m.name].avoided:
            return LabelledScene(scene, outcomes, m.name)
    return None
