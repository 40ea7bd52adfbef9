"""SE(2) frames: world offsets expressed in the frame of a heading (forward, left) and back."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from scenariominer.geometry.angles import FloatArray

__all__ = ["from_local", "rotate_xy", "to_local"]


def to_local(dx_m: ArrayLike, dy_m: ArrayLike, yaw_rad: ArrayLike) -> tuple[FloatArray, FloatArray]:
    """World-frame offsets (or velocities) in the frame of heading ``yaw_rad``: ``(forward, left)``.

    All arguments broadcast; the result has the broadcast shape.
    """
    c, s = np.cos(yaw_rad), np.sin(yaw_rad)
    dx, dy = np.asarray(dx_m, dtype=np.float64), np.asarray(dy_m, dtype=np.float64)
    return np.asarray(c * dx + s * dy, dtype=np.float64), np.asarray(-s * dx + c * dy, dtype=np.float64)


def from_local(fwd_m: ArrayLike, left_m: ArrayLike, yaw_rad: ArrayLike) -> tuple[FloatArray, FloatArray]:
    """Inverse of :func:`to_local`: ``(forward, left)`` offsets in the frame of ``yaw_rad`` → world."""
    c, s = np.cos(yaw_rad), np.sin(yaw_rad)
    f, left = np.asarray(fwd_m, dtype=np.float64), np.asarray(left_m, dtype=np.float64)
    return np.asarray(c * f - s * left, dtype=np.float64), np.asarray(s * f + c * left, dtype=np.float64)


def rotate_xy(xy: ArrayLike, theta_rad: float) -> FloatArray:
    """Points ``(..., 2)`` rotated counter-clockwise by ``theta_rad`` about the origin."""
    p = np.asarray(xy, dtype=np.float64)
    x, y = from_local(p[..., 0], p[..., 1], theta_rad)
    return np.stack([x, y], axis=-1)
