"""Rollout check (beyond the paper): does a manoeuvre avoid the conflict on the recorded scene.

The ego is re-simulated from a moment before the conflict with a kinematic model executing each
manoeuvre: a longitudinal acceleration built up at a limited jerk (speed clipped to
``[0, max_speed]``) and a smooth lateral displacement (half-cosine) applied along the normal of the
recorded ego path, which is followed by arc length (extended straight past its end). Every other
road user keeps its recorded path. All manoeuvres x objects x time steps are tested at once with the
oriented-box geometry of :mod:`scenariominer.geometry`.

Reported per manoeuvre and for the recorded ego: the smallest box distance, the smallest
distance-based time to collision (gap / closing speed, where the gap is closing) and whether the
boxes overlap (a collision) within the horizon.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from scenariominer.cbr.vocab import CbrError, Manoeuvre
from scenariominer.geometry import OrientedBoxes, box_distance_m, boxes_overlap

__all__ = ["RECORDED", "RolloutOutcome", "RolloutScene", "rollout", "scene_from_log"]

FloatArray = NDArray[np.float64]

#: Name of the outcome of the recorded ego trajectory.
RECORDED = "recorded"
_EXTEND_M = 300.0
_PATH_STEP_M = 0.5


@dataclass(frozen=True)
class RolloutScene:
    """Recorded trajectories from the start of the manoeuvre on.

    Attributes:
        t_s: ``(T,)`` seconds from the manoeuvre start (``t_s[0] == 0``), increasing.
        ego_x_m, ego_y_m, ego_yaw_rad: ``(T,)`` the recorded ego (box centre), world frame.
        ego_speed_mps: ego speed at ``t_s[0]``.
        ego_length_m, ego_width_m: ego box size.
        others: boxes of the other road users, every field ``(N, T)``, NaN where absent.
        other_ids: ``N`` track ids.
        start_ns: log time of ``t_s[0]`` (0 for synthetic scenes).
    """

    t_s: FloatArray
    ego_x_m: FloatArray
    ego_y_m: FloatArray
    ego_yaw_rad: FloatArray
    ego_speed_mps: float
    ego_length_m: float
    ego_width_m: float
    others: OrientedBoxes
    other_ids: tuple[str, ...]
    start_ns: int = 0

    def __post_init__(self) -> None:
        t = np.asarray(self.t_s)
        if t.ndim != 1 or t.size < 2 or np.any(np.diff(t) <= 0):
            raise CbrError("rollout scene: t_s must be at least two increasing times")
        if np.asarray(self.others.x_m).shape != (len(self.other_ids), t.size):
            raise CbrError("rollout scene: other boxes must be shaped (N, T) with N ids")


@dataclass(frozen=True)
class RolloutOutcome:
    """What one manoeuvre (or the recorded ego) does on the scene.

    Attributes:
        manoeuvre: manoeuvre name, or :data:`RECORDED`.
        min_distance_m: smallest box distance to any other road user (0 when they overlap).
        min_ttc_s: smallest gap / closing speed over the horizon (``inf`` if never closing).
        collision: the ego box overlaps (within the margin) another road user's box.
        first_collision_s: seconds from the start to the first overlap (NaN without one).
        closest_id: track id of the road user closest to the ego.
        x_m, y_m: ``(T,)`` the ego path of this outcome (for the picture).
    """

    manoeuvre: str
    min_distance_m: float
    min_ttc_s: float
    collision: bool
    first_collision_s: float
    closest_id: str
    x_m: FloatArray
    y_m: FloatArray

    @property
    def avoided(self) -> bool:
        """No collision within the horizon."""
        return not self.collision

    def to_json_dict(self) -> dict[str, Any]:
        """The numbers (not the path) as JSON-ready values (``inf``/NaN as ``None``)."""

        def num(x: float) -> float | None:
            return float(x) if np.isfinite(x) else None

        return {
            "manoeuvre": self.manoeuvre,
            "min_distance_m": num(self.min_distance_m),
            "min_ttc_s": num(self.min_ttc_s),
            "collision": self.collision,
            "first_collision_s": num(self.first_collision_s),
            "closest_id": self.closest_id,
        }


def _cumtrapz(values: FloatArray, t_s: FloatArray) -> FloatArray:
    """Cumulative trapezoid integral along the last axis, starting at 0; shape of ``values``."""
    dt = np.diff(t_s)
    steps = 0.5 * (values[..., 1:] + values[..., :-1]) * dt
    return np.concatenate([np.zeros(values.shape[:-1] + (1,)), np.cumsum(steps, axis=-1)], axis=-1)


def _reference_path(scene: RolloutScene) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """The recorded ego path as ``(s, x, y, heading)`` polyline, extended straight past its end."""
    x, y = np.asarray(scene.ego_x_m, float), np.asarray(scene.ego_y_m, float)
    ok = np.isfinite(x) & np.isfinite(y)
    x, y = x[ok], y[ok]
    if x.size == 0:
        raise CbrError("rollout scene: the recorded ego has no position")
    # Thin the path to points _PATH_STEP_M apart so annotation jitter does not turn its heading.
    s_all = np.concatenate([[0.0], np.cumsum(np.hypot(np.diff(x), np.diff(y)))])
    _, first = np.unique(np.floor(s_all / _PATH_STEP_M), return_index=True)
    x, y = x[first], y[first]
    yaw0 = float(np.asarray(scene.ego_yaw_rad)[0])
    heading_end = yaw0 if x.size == 1 else float(np.arctan2(y[-1] - y[-2], x[-1] - x[-2]))
    x = np.append(x, x[-1] + _EXTEND_M * np.cos(heading_end))
    y = np.append(y, y[-1] + _EXTEND_M * np.sin(heading_end))
    s = np.concatenate([[0.0], np.cumsum(np.hypot(np.diff(x), np.diff(y)))])
    heading = np.unwrap(np.arctan2(np.diff(y), np.diff(x)))
    return s, x, y, np.append(heading, heading[-1])


def simulate(
    scene: RolloutScene, manoeuvres: Sequence[Manoeuvre], max_speed_mps: float
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Ego poses under each manoeuvre: ``(x_m, y_m, yaw_rad)``, each ``(M, T)``."""
    t = np.asarray(scene.t_s, float)
    accel = np.array([m.accel_mps2 for m in manoeuvres], float)[:, None]
    jerk = np.array([m.jerk_mps3 for m in manoeuvres], float)[:, None]
    lat = np.array([m.lateral_m for m in manoeuvres], float)[:, None]
    lat_s = np.array([m.lateral_s for m in manoeuvres], float)[:, None]
    a = np.sign(accel) * np.minimum(np.abs(accel), jerk * t[None, :])  # (M, T)
    v = np.clip(scene.ego_speed_mps + _cumtrapz(a, t), 0.0, max(max_speed_mps, scene.ego_speed_mps))
    s_along = _cumtrapz(v, t)
    phase = np.clip(t[None, :] / lat_s, 0.0, 1.0)
    d = lat * 0.5 * (1.0 - np.cos(np.pi * phase))
    dd_dt = np.where(phase < 1.0, lat * 0.5 * np.pi / lat_s * np.sin(np.pi * phase), 0.0)
    s_ref, x_ref, y_ref, h_ref = _reference_path(scene)
    cx, cy, psi = (np.interp(s_along, s_ref, arr) for arr in (x_ref, y_ref, h_ref))
    x = cx - d * np.sin(psi)
    y = cy + d * np.cos(psi)
    yaw = psi + np.arctan2(dd_dt, np.maximum(v, 0.5))
    return x, y, yaw


def _outcomes(
    scene: RolloutScene, names: Sequence[str], x: FloatArray, y: FloatArray, yaw: FloatArray, margin_m: float
) -> list[RolloutOutcome]:
    """Distances, TTC and overlap of ``M`` ego paths ``(M, T)`` against the other road users."""
    t = np.asarray(scene.t_s, float)
    n_paths = x.shape[0]
    if not scene.other_ids:
        return [RolloutOutcome(n, np.inf, np.inf, False, np.nan, "", x[i], y[i]) for i, n in enumerate(names)]
    ego = OrientedBoxes(
        x[:, None, :],
        y[:, None, :],
        yaw[:, None, :],
        np.full((1, 1, 1), scene.ego_length_m),
        np.full((1, 1, 1), scene.ego_width_m),
    )
    o = scene.others
    others = OrientedBoxes(
        np.asarray(o.x_m)[None],
        np.asarray(o.y_m)[None],
        np.asarray(o.yaw_rad)[None],
        np.asarray(o.length_m)[None],
        np.asarray(o.width_m)[None],
    )
    valid = np.isfinite(np.asarray(o.x_m))[None] & np.ones((n_paths, 1, 1), bool)  # (M, N, T)
    dist = np.where(valid, box_distance_m(ego, others), np.inf)
    hit = valid & boxes_overlap(ego, others, margin_m=margin_m)
    finite = np.where(np.isfinite(dist), dist, np.nan)
    with np.errstate(invalid="ignore", divide="ignore"):
        closing = -np.gradient(np.nan_to_num(finite, nan=1e9), t, axis=-1)
        closing_ok = valid & (closing > 1e-6) & (np.abs(closing) < 1e6)
        ttc = np.where(closing_ok, np.maximum(dist, 0.0) / np.where(closing_ok, closing, 1.0), np.inf)
    ttc = np.where(hit, 0.0, ttc)
    out = []
    for i, name in enumerate(names):
        per_obj = dist[i].min(axis=-1)  # (N,)
        j = int(np.argmin(per_obj))
        hits = hit[i].any(axis=0)
        first = float(t[np.argmax(hits)]) if hits.any() else float("nan")
        min_d = 0.0 if hits.any() else float(per_obj[j])
        out.append(
            RolloutOutcome(
                name, min_d, float(ttc[i].min()), bool(hits.any()), first, scene.other_ids[j], x[i], y[i]
            )
        )
    return out


def rollout(
    scene: RolloutScene,
    manoeuvres: Sequence[Manoeuvre],
    *,
    max_speed_mps: float = 36.0,
    margin_m: float = 0.0,
) -> dict[str, RolloutOutcome]:
    """Re-simulate the ego under each manoeuvre; outcomes by name, :data:`RECORDED` included.

    Args:
        scene: the recorded trajectories from the manoeuvre start on.
        manoeuvres: the manoeuvres to execute (may be empty: only the recorded ego is measured).
        max_speed_mps: the accelerating manoeuvres stop gaining speed here.
        margin_m: boxes closer than this count as a collision.
    """
    rec_x = np.asarray(scene.ego_x_m, float)[None]
    rec_y = np.asarray(scene.ego_y_m, float)[None]
    rec_yaw = np.asarray(scene.ego_yaw_rad, float)[None]
    names = [RECORDED]
    xs, ys, yaws = [rec_x], [rec_y], [rec_yaw]
    if manoeuvres:
        x, y, yaw = simulate(scene, manoeuvres, max_speed_mps)
        names += [m.name for m in manoeuvres]
        xs.append(x)
        ys.append(y)
        yaws.append(yaw)
    outcomes = _outcomes(scene, names, np.vstack(xs), np.vstack(ys), np.vstack(yaws), margin_m)
    return {o.manoeuvre: o for o in outcomes}


def scene_from_log(
    log: Any, conflict_ns: int, *, lead_s: float, horizon_s: float, exclude_categories: Sequence[str] = ()
) -> RolloutScene:
    """Cut a :class:`RolloutScene` from a :class:`~scenariominer.data.log.Log` around a conflict.

    The manoeuvre starts ``lead_s`` before ``conflict_ns`` (clamped to the log start) and runs for
    ``horizon_s`` (or to the log end) on the log's own clock. Road users absent at every step of
    that window, and categories in ``exclude_categories``, are left out.

    Raises:
        CbrError: the window holds fewer than two timestamps or the ego has no pose at its start.
    """
    ts = np.asarray(log.timestamps_ns, np.int64)
    i0 = int(np.searchsorted(ts, conflict_ns - int(lead_s * 1e9)))
    i0 = min(max(i0, 0), ts.size - 1)
    i1 = int(np.searchsorted(ts, ts[i0] + int(horizon_s * 1e9), side="right"))
    if i1 - i0 < 2:
        raise CbrError(f"log {log.log_id}: fewer than two timestamps after the manoeuvre start")
    e = int(log.ego_index)
    sl = slice(i0, i1)
    x, y, yaw = log.x_m[e, sl], log.y_m[e, sl], log.yaw_rad[e, sl]
    if not (np.isfinite(x[0]) and np.isfinite(y[0]) and np.isfinite(yaw[0])):
        raise CbrError(f"log {log.log_id}: the ego has no pose at the manoeuvre start")
    speed = float(np.hypot(log.vx_mps[e, i0], log.vy_mps[e, i0]))
    rows = np.arange(log.n_tracks) != e
    rows &= ~np.isin(np.asarray(log.categories), list(exclude_categories))
    rows &= np.asarray(log.valid)[:, sl].any(axis=1)
    idx = np.flatnonzero(rows)
    others = OrientedBoxes(
        log.x_m[idx, sl], log.y_m[idx, sl], log.yaw_rad[idx, sl], log.length_m[idx, sl], log.width_m[idx, sl]
    )
    return RolloutScene(
        t_s=(ts[sl] - ts[i0]).astype(np.float64) * 1e-9,
        ego_x_m=x,
        ego_y_m=y,
        ego_yaw_rad=yaw,
        ego_speed_mps=speed if np.isfinite(speed) else 0.0,
        ego_length_m=float(np.nanmax(log.length_m[e])),
        ego_width_m=float(np.nanmax(log.width_m[e])),
        others=others,
        other_ids=tuple(str(s) for s in np.asarray(log.track_ids)[idx]),
        start_ns=int(ts[i0]),
    )
