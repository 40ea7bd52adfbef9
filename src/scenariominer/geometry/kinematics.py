"""Kinematics from sampled tracks: yaw (or any angle's) rate, path curvature, CTRV prediction."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from scenariominer.geometry.angles import FloatArray, wrap_angle

__all__ = ["ctrv_predict", "path_curvature_1pm", "yaw_rate_radps"]


def ctrv_predict(
    x_m: FloatArray,
    y_m: FloatArray,
    yaw_rad: FloatArray,
    vx_mps: FloatArray,
    vy_mps: FloatArray,
    yaw_rate_radps: FloatArray,
    tau_s: FloatArray,
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Constant Turn Rate and Velocity prediction of box centre and heading.

    The velocity vector keeps its magnitude and rotates at the yaw rate, so the path is a circular
    arc (a straight line for zero yaw rate); the box heading rotates at the same rate. Using the
    world velocity vector rather than ``speed × heading`` keeps reversing vehicles and objects whose
    heading is not their direction of travel (pedestrians) on their observed course. With
    ``θ = ω τ``::

        p(τ) = p + (sin θ / ω) v + ((1 - cos θ) / ω) J v,   J = rotation by +90°

    with the series expansions ``sin θ / ω ≈ τ (1 - θ²/6)`` and ``(1 - cos θ) / ω ≈ τ θ / 2`` for
    ``|θ| < 1e-4``, so that ``ω → 0`` is exact to machine precision.

    Args:
        x_m: current centre x, metres (all state arrays broadcast together).
        y_m: current centre y, metres.
        yaw_rad: current box heading, radians.
        vx_mps: world-frame velocity x, m/s.
        vy_mps: world-frame velocity y, m/s.
        yaw_rate_radps: yaw rate, rad/s (counter-clockwise positive).
        tau_s: prediction times (seconds), broadcastable against the state (typically a trailing axis).

    Returns:
        Predicted ``(x_m, y_m, yaw_rad)``, each of the broadcast shape.
    """
    theta = yaw_rate_radps * tau_s
    small = np.abs(theta) < 1e-4
    safe_rate = np.where(small, 1.0, yaw_rate_radps)
    sin_term = np.where(small, tau_s * (1.0 - theta * theta / 6.0), np.sin(theta) / safe_rate)  # sin(ωτ)/ω
    cos_term = np.where(small, 0.5 * tau_s * theta, (1.0 - np.cos(theta)) / safe_rate)  # (1 - cos ωτ)/ω
    x = x_m + sin_term * vx_mps - cos_term * vy_mps
    y = y_m + sin_term * vy_mps + cos_term * vx_mps
    return (
        np.asarray(x, dtype=np.float64),
        np.asarray(y, dtype=np.float64),
        np.asarray(yaw_rad + theta, dtype=np.float64),
    )


def yaw_rate_radps(yaw_rad: FloatArray, t_s: FloatArray) -> FloatArray:
    """Yaw rate along axis 1 of ``yaw_rad`` ``(N, T)`` from wrapped finite differences, rad/s.

    Central differences between valid neighbours, one-sided at the ends of an observed span,
    0 for an isolated observation, NaN where ``yaw_rad`` is NaN. Differences are wrapped, so a
    heading crossing ±pi gives the true small rate.
    """
    n, t = yaw_rad.shape
    out = np.full((n, t), np.nan)
    finite = np.isfinite(yaw_rad)
    if t < 2:
        out[finite] = 0.0
        return out
    with np.errstate(invalid="ignore"):
        fwd = np.full((n, t), np.nan)
        fwd[:, :-1] = wrap_angle(np.diff(yaw_rad, axis=1)) / np.diff(t_s)
        bwd = np.full((n, t), np.nan)
        bwd[:, 1:] = fwd[:, :-1]
        central = np.full((n, t), np.nan)
        if t >= 3:
            central[:, 1:-1] = wrap_angle(yaw_rad[:, 2:] - yaw_rad[:, :-2]) / (t_s[2:] - t_s[:-2])
    out = np.where(np.isfinite(central), central, np.where(np.isfinite(fwd), fwd, bwd))
    out[~finite] = np.nan
    out[finite & ~np.isfinite(out)] = 0.0
    return out


def path_curvature_1pm(x_m: ArrayLike, y_m: ArrayLike) -> FloatArray:
    """Signed curvature (1/m, positive to the left) of paths sampled along the last axis.

    ``κ = (x' y'' - y' x'') / (x'² + y'²)^1.5`` with derivatives taken with respect to the sample
    index (``np.gradient``: central inside, one-sided at the ends), so the sampling rate does not
    matter. NaN where the path does not move (no direction) or an input is NaN; fewer than three
    samples give NaN.
    """
    x = np.asarray(x_m, dtype=np.float64)
    y = np.asarray(y_m, dtype=np.float64)
    if x.shape[-1] < 3:
        return np.full(np.broadcast_shapes(x.shape, y.shape), np.nan)
    dx, dy = np.gradient(x, axis=-1), np.gradient(y, axis=-1)
    ddx, ddy = np.gradient(dx, axis=-1), np.gradient(dy, axis=-1)
    speed2 = dx * dx + dy * dy
    with np.errstate(invalid="ignore", divide="ignore"):
        k = (dx * ddy - dy * ddx) / speed2**1.5
    return np.asarray(np.where(speed2 > 1e-12, k, np.nan), dtype=np.float64)
