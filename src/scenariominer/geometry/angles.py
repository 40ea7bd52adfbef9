"""Angle wrapping: one convention for the whole project."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

FloatArray = NDArray[np.float64]

__all__ = ["FloatArray", "wrap_angle"]


def wrap_angle(angle_rad: ArrayLike) -> FloatArray:
    """Wrap angles to ``[-pi, pi)``, element-wise, any shape; NaN stays NaN.

    Values already in range are returned bit for bit (no round-off from the modulo), so wrapping
    is idempotent and a stored heading does not drift when it is wrapped again.
    """
    a = np.asarray(angle_rad, dtype=np.float64)
    with np.errstate(invalid="ignore"):
        inside = (a >= -np.pi) & (a < np.pi)
        wrapped = (a + np.pi) % (2.0 * np.pi) - np.pi
        out = np.where(inside, a, wrapped)
        # (a + pi) % 2pi can round up to exactly 2pi for a just below an odd multiple of pi.
        out = np.where(out >= np.pi, out - 2.0 * np.pi, out)
    return np.asarray(out, dtype=np.float64)
