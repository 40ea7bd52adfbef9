"""Frames: world offsets in the frame of a heading (forward, left) and back; quaternion rotations."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from scenariominer.geometry.angles import FloatArray

__all__ = ["from_local", "quaternion_matrix", "quaternion_x_axis", "rotate_xy", "to_local"]


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


def _unit_quaternion(quat_wxyz: ArrayLike) -> FloatArray:
    """Quaternions ``(..., 4)`` scaled to unit norm (a zero quaternion gives NaN)."""
    q = np.asarray(quat_wxyz, dtype=np.float64)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.asarray(q / np.linalg.norm(q, axis=-1, keepdims=True), dtype=np.float64)


def _x_axis(w: FloatArray, x: FloatArray, y: FloatArray, z: FloatArray) -> tuple[FloatArray, ...]:
    """The first column of the rotation matrix of unit quaternions given by their components."""
    return 1.0 - 2.0 * (y * y + z * z), 2.0 * (x * y + w * z), 2.0 * (x * z - w * y)


def quaternion_matrix(quat_wxyz: ArrayLike) -> FloatArray:
    """``(..., 3, 3)`` rotation matrices of quaternions ``(..., 4)`` (w, x, y, z; normalised here).

    The Hamilton convention of Argoverse 2 and scipy (``Rotation.from_quat(q, scalar_first=True)``);
    a zero quaternion gives NaN.
    """
    q = _unit_quaternion(quat_wxyz)
    w, x, y, z = q[..., 0], q[..., 1], q[..., 2], q[..., 3]
    columns = (
        _x_axis(w, x, y, z),
        (2.0 * (x * y - w * z), 1.0 - 2.0 * (x * x + z * z), 2.0 * (y * z + w * x)),
        (2.0 * (x * z + w * y), 2.0 * (y * z - w * x), 1.0 - 2.0 * (x * x + y * y)),
    )
    return np.stack([np.stack(column, axis=-1) for column in columns], axis=-1)


def quaternion_x_axis(quat_wxyz: ArrayLike) -> FloatArray:
    """``(..., 3)`` the rotated x axis of quaternions ``(..., 4)``: ``quaternion_matrix(q)[..., :, 0]``.

    A box's heading is the image of its own x axis; this computes that column alone (about six
    times faster than the whole matrix for 14,000 boxes).
    """
    q = _unit_quaternion(quat_wxyz)
    return np.stack(_x_axis(q[..., 0], q[..., 1], q[..., 2], q[..., 3]), axis=-1)
