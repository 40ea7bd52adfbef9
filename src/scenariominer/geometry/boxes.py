"""Oriented boxes: corners, overlap (separating axes), point-to-box and box-to-box distance.

Every function broadcasts over arbitrary leading shapes, so one call tests, e.g., all
``objects × timestamps × horizon steps`` box pairs at once. Boxes are 2-D rectangles in the world
frame: centre ``(x_m, y_m)``, heading ``yaw_rad`` (counter-clockwise from +x, along the length),
``length_m`` along the heading and ``width_m`` across it.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from scenariominer.geometry.angles import FloatArray

BoolArray = NDArray[np.bool_]

__all__ = ["OrientedBoxes", "box_distance_m", "boxes_overlap", "point_box_distance_m"]


@dataclass(frozen=True)
class OrientedBoxes:
    """A batch of oriented rectangles; the five arrays broadcast against each other.

    Attributes:
        x_m, y_m: box centre, metres.
        yaw_rad: heading of the length axis, radians counter-clockwise from world +x.
        length_m: extent along the heading, metres.
        width_m: extent across the heading, metres.
    """

    x_m: FloatArray
    y_m: FloatArray
    yaw_rad: FloatArray
    length_m: FloatArray
    width_m: FloatArray

    @property
    def radius_m(self) -> FloatArray:
        """Half diagonal: radius of the smallest circle around the box centre containing the box."""
        return np.asarray(0.5 * np.hypot(self.length_m, self.width_m), dtype=np.float64)

    def expanded(self, margin_m: float) -> OrientedBoxes:
        """Return the boxes enlarged by ``margin_m`` on every side (length and width grow by twice that)."""
        return OrientedBoxes(
            self.x_m, self.y_m, self.yaw_rad, self.length_m + 2.0 * margin_m, self.width_m + 2.0 * margin_m
        )

    def take(self, index: Any) -> OrientedBoxes:
        """Return the boxes at ``index`` (basic or fancy numpy indexing applied to every field)."""
        return OrientedBoxes(
            self.x_m[index], self.y_m[index], self.yaw_rad[index], self.length_m[index], self.width_m[index]
        )

    def corners(self) -> FloatArray:
        """Corners, counter-clockwise from front-left: shape ``(*batch, 4, 2)`` in metres."""
        c, s = np.cos(self.yaw_rad), np.sin(self.yaw_rad)
        hl, hw = 0.5 * self.length_m, 0.5 * self.width_m
        signs_l = np.array([1.0, -1.0, -1.0, 1.0])
        signs_w = np.array([1.0, 1.0, -1.0, -1.0])
        lx = hl[..., None] * signs_l
        wy = hw[..., None] * signs_w
        cx, cy, cc, ss = (np.asarray(a)[..., None] for a in (self.x_m, self.y_m, c, s))
        return np.stack([cx + cc * lx - ss * wy, cy + ss * lx + cc * wy], axis=-1)


def boxes_overlap(a: OrientedBoxes, b: OrientedBoxes, margin_m: float = 0.0) -> BoolArray:
    """Whether oriented rectangles intersect (touching counts), by the separating-axis theorem.

    For two rectangles the candidate separating axes are the two edge normals of each; along an
    axis ``n`` the projected half-extent of a box is ``l/2 |u·n| + w/2 |v·n|``. The test therefore
    reduces to four comparisons involving only ``|cos(yaw_b - yaw_a)|`` and ``|sin(...)|``.

    Args:
        a: first boxes; their fields broadcast with ``b``'s to a common batch shape ``S``.
        b: second boxes.
        margin_m: boxes also count as overlapping when no separating axis separates them by more
            than this (metres; 0: touching counts).

    Returns:
        ``S`` bool; NaN inputs give False.
    """
    dx, dy = b.x_m - a.x_m, b.y_m - a.y_m
    ca, sa = np.cos(a.yaw_rad), np.sin(a.yaw_rad)
    cb, sb = np.cos(b.yaw_rad), np.sin(b.yaw_rad)
    c = np.abs(ca * cb + sa * sb)  # |cos(yaw_b - yaw_a)|
    s = np.abs(sa * cb - ca * sb)  # |sin(yaw_b - yaw_a)|
    hla, hwa, hlb, hwb = 0.5 * a.length_m, 0.5 * a.width_m, 0.5 * b.length_m, 0.5 * b.width_m
    with np.errstate(invalid="ignore"):
        ok = np.abs(dx * ca + dy * sa) <= hla + hlb * c + hwb * s + margin_m
        ok &= np.abs(-dx * sa + dy * ca) <= hwa + hlb * s + hwb * c + margin_m
        ok &= np.abs(dx * cb + dy * sb) <= hlb + hla * c + hwa * s + margin_m
        ok &= np.abs(-dx * sb + dy * cb) <= hwb + hla * s + hwa * c + margin_m
    return np.asarray(ok, dtype=bool)


def point_box_distance_m(px_m: FloatArray, py_m: FloatArray, box: OrientedBoxes) -> FloatArray:
    """Euclidean distance from points to filled rectangles (0 inside). Broadcasts; metres."""
    dx, dy = px_m - box.x_m, py_m - box.y_m
    c, s = np.cos(box.yaw_rad), np.sin(box.yaw_rad)
    along = np.abs(dx * c + dy * s) - 0.5 * box.length_m
    across = np.abs(-dx * s + dy * c) - 0.5 * box.width_m
    return np.asarray(np.hypot(np.maximum(along, 0.0), np.maximum(across, 0.0)), dtype=np.float64)


def box_distance_m(a: OrientedBoxes, b: OrientedBoxes) -> FloatArray:
    """Minimum distance between two filled rectangles (0 when they overlap), metres.

    For disjoint convex polygons the closest pair of points always includes a vertex of one of
    them, so the distance is the smallest of the eight vertex-to-rectangle distances; overlap is
    decided by :func:`boxes_overlap`.

    Args:
        a: first boxes; their fields broadcast with ``b``'s to a common batch shape ``S``.
        b: second boxes.

    Returns:
        ``S`` float; NaN where an input is NaN.
    """
    shape = np.broadcast_shapes(*(np.shape(f) for f in (*_fields(a), *_fields(b))))
    a_b = OrientedBoxes(*(np.broadcast_to(f, shape) for f in _fields(a)))
    b_b = OrientedBoxes(*(np.broadcast_to(f, shape) for f in _fields(b)))
    ca, cb = a_b.corners(), b_b.corners()  # (*S, 4, 2)
    d_ab = point_box_distance_m(ca[..., 0], ca[..., 1], _expand_last(b_b)).min(axis=-1)
    d_ba = point_box_distance_m(cb[..., 0], cb[..., 1], _expand_last(a_b)).min(axis=-1)
    dist = np.minimum(d_ab, d_ba)
    return np.asarray(np.where(boxes_overlap(a_b, b_b), 0.0, dist), dtype=np.float64)


def _fields(box: OrientedBoxes) -> tuple[FloatArray, ...]:
    return (box.x_m, box.y_m, box.yaw_rad, box.length_m, box.width_m)


def _expand_last(box: OrientedBoxes) -> OrientedBoxes:
    return OrientedBoxes(*(np.asarray(f)[..., None] for f in _fields(box)))
