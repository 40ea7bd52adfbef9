"""Path following and footprint conflicts for counterfactual predictions.

* :func:`poses_along_path`: poses at given arc lengths along a sampled polyline, continued
  straight past its end (a vehicle that had not braked keeps to the path it was on);
* :func:`first_conflicts`: for one predicted ego footprint sequence and many predicted object
  footprint sequences, the earliest ego time at which an ego box overlaps an object box occupied
  within a time tolerance of it (a predicted post-encroachment time below the tolerance), tested as
  one batch of ``objects × ego steps × object steps`` box pairs.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from scenariominer.geometry.angles import FloatArray
from scenariominer.geometry.boxes import OrientedBoxes, boxes_overlap

__all__ = ["Conflicts", "first_conflicts", "poses_along_path"]

#: Path samples closer than this (metres) to the previous kept sample are dropped (standing still).
_MIN_STEP_M = 1e-3


def poses_along_path(
    x_m: ArrayLike, y_m: ArrayLike, end_yaw_rad: float, s_m: ArrayLike
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Poses at arc lengths ``s_m`` along a polyline, continued straight at ``end_yaw_rad`` past its end.

    Samples that do not move (a standing vehicle) are skipped, so the arc length only grows; the
    heading of a pose is the direction of the polyline segment it lies on (``end_yaw_rad`` on the
    continuation and for a polyline of one distinct point).

    Args:
        x_m: ``(P,)`` polyline x, metres, in driving order (NaN samples are ignored).
        y_m: ``(P,)`` polyline y, metres.
        end_yaw_rad: heading of the straight continuation past the last sample.
        s_m: ``(H,)`` arc lengths from the first sample, metres (>= 0).

    Returns:
        ``(x_m, y_m, yaw_rad)``, each ``(H,)``.

    Raises:
        ValueError: the polyline has no finite sample.
    """
    x, y = np.asarray(x_m, dtype=np.float64), np.asarray(y_m, dtype=np.float64)
    s = np.asarray(s_m, dtype=np.float64)
    ok = np.isfinite(x) & np.isfinite(y)
    if not ok.any():
        raise ValueError("the path has no finite sample")
    x, y = x[ok], y[ok]
    step = np.hypot(np.diff(x), np.diff(y))
    keep = np.concatenate([[True], step > _MIN_STEP_M])
    x, y = x[keep], y[keep]
    # Continue straight past the end, far enough for every query.
    reach = float(np.max(s, initial=0.0)) + 1.0
    x = np.append(x, x[-1] + reach * np.cos(end_yaw_rad))
    y = np.append(y, y[-1] + reach * np.sin(end_yaw_rad))
    seg_len = np.hypot(np.diff(x), np.diff(y))
    arc = np.concatenate([[0.0], np.cumsum(seg_len)])
    seg_yaw = np.arctan2(np.diff(y), np.diff(x))
    seg_yaw[-1] = end_yaw_rad
    i = np.clip(np.searchsorted(arc, s, side="right") - 1, 0, seg_len.size - 1)
    frac = np.clip((s - arc[i]) / seg_len[i], 0.0, None)
    px = x[i] + frac * (x[i + 1] - x[i])
    py = y[i] + frac * (y[i + 1] - y[i])
    return px, py, seg_yaw[i]


@dataclass(frozen=True)
class Conflicts:
    """Earliest predicted footprint conflicts of an ego with each of ``K`` objects.

    Attributes:
        ego_time_s: ``(K,)`` earliest ego time (seconds from the prediction start) at which the
            ego's box overlaps a box the object occupies within the tolerance; ``inf`` when none.
        object_time_s: ``(K,)`` the object's time of that overlapping box (``inf`` when none).
    """

    ego_time_s: FloatArray
    object_time_s: FloatArray

    @property
    def found(self) -> NDArray[np.bool_]:
        """``(K,)`` True where a conflict exists."""
        return np.asarray(np.isfinite(self.ego_time_s), dtype=bool)

    @property
    def gap_s(self) -> FloatArray:
        """``(K,)`` ``|ego time - object time|`` of the conflict (a predicted PET); ``inf`` when none."""
        with np.errstate(invalid="ignore"):
            gap = np.abs(self.ego_time_s - self.object_time_s)
        return np.asarray(np.where(self.found, gap, np.inf), dtype=np.float64)


def first_conflicts(
    ego: OrientedBoxes,
    objects: OrientedBoxes,
    t_s: FloatArray,
    max_gap_s: float,
    margin_m: float = 0.0,
    *,
    object_after_s: float | None = None,
) -> Conflicts:
    """Earliest overlap of predicted ego boxes with predicted object boxes within a time tolerance.

    An ego box at ``t_i`` conflicts with an object box at ``t_j`` when the two overlap (boxes
    grown by ``margin_m``) and ``-max_gap_s <= t_j - t_i <= object_after_s``; 0 tolerance asks for
    a predicted collision. All ``K × H × H`` pairs are tested at once after a bounding-circle prefilter.

    Args:
        ego: ``(H,)`` predicted ego boxes.
        objects: ``(K, H)`` predicted object boxes (NaN where unknown).
        t_s: ``(H,)`` prediction times, seconds.
        max_gap_s: the object may occupy the region at most this long before the ego, seconds.
        margin_m: each box grows by this on every side, metres.
        object_after_s: the object may occupy the region at most this long after the ego
            (seconds); ``None``: ``max_gap_s`` (symmetric).

    Returns:
        The earliest conflict per object.
    """
    k, h = np.shape(objects.x_m)
    ego_t = np.full(k, np.inf)
    obj_t = np.full(k, np.inf)
    if k == 0 or h == 0:
        return Conflicts(ego_t, obj_t)
    after = max_gap_s if object_after_s is None else object_after_s
    lag = t_s[None, :] - t_s[:, None]  # (H ego, H object): object time - ego time
    band = (lag >= -max_gap_s - 1e-9) & (lag <= after + 1e-9)
    reach = ego.radius_m[None, :, None] + objects.radius_m[:, None, :] + 2.0 * margin_m
    with np.errstate(invalid="ignore"):
        d2 = (ego.x_m[None, :, None] - objects.x_m[:, None, :]) ** 2 + (
            ego.y_m[None, :, None] - objects.y_m[:, None, :]
        ) ** 2
        near = (d2 <= reach * reach) & band[None, :, :]
    obj, ie, jo = np.nonzero(near)
    if obj.size == 0:
        return Conflicts(ego_t, obj_t)
    hit = boxes_overlap(ego.take(ie).expanded(margin_m), objects.take((obj, jo)).expanded(margin_m))
    obj, ie, jo = obj[hit], ie[hit], jo[hit]
    if obj.size == 0:
        return Conflicts(ego_t, obj_t)
    # Earliest ego time per object; among equal ego times the closest object time.
    order = np.lexsort((np.abs(t_s[ie] - t_s[jo]), t_s[ie], obj))
    obj, ie, jo = obj[order], ie[order], jo[order]
    first = np.concatenate([[True], obj[1:] != obj[:-1]])
    ego_t[obj[first]] = t_s[ie[first]]
    obj_t[obj[first]] = t_s[jo[first]]
    return Conflicts(ego_t, obj_t)
