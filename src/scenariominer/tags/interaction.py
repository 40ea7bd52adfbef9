"""Interaction tags of every object with respect to the ego (Table I, section III-B).

All functions return ``(N, T)`` arrays aligned with the log's rows; row ``log.ego_index`` and cells
where the object or the ego is unobserved hold :data:`~scenariominer.tags.vocab.ABSENT` (codes) or
NaN (floats).

* **Heading** — relative heading ``yaw_obj - yaw_ego`` in four 90° sectors centred on 0 (SAME),
  +90° (LEFT), 180° (OPPOSITE), -90° (RIGHT).
* **Position** — bearing of the object's centre in the ego frame (x forward, y left) in eight 45°
  sectors centred on 0° (FRONT), +45° (FRONT_LEFT), ... -45° (FRONT_RIGHT).
* **Distance** — box-to-box distance; VERY_CLOSE when the boxes enlarged by a margin overlap.
* **Collision** — time-to-collision: both boxes are predicted with Constant Turn Rate and Velocity
  over a horizon and the first step at which they overlap is the TTC. Tested as one batch of
  ``candidates × horizon steps`` box pairs, after a reachability prefilter (pairs whose bounding
  circles cannot meet within the horizon at the current speeds are skipped).
* **TrajOverlap** — do the regions swept by the *recorded* future boxes of ego and object within
  ``[now, now + Δt]`` intersect? That holds when some ego box at ``t1`` overlaps some object box at
  ``t2`` with both times in the window. Each overlapping pair ``(t1, t2)`` answers "yes" for every
  ``now`` in ``[max(t1, t2) - Δt, min(t1, t2)]``, so the tag is computed from the overlapping pairs
  of a ``|t1 - t2| <= Δt`` band (bounding-circle prefilter, then separating axes) by marking
  those intervals with a difference array — never a per-``now`` loop.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from scenariominer.config.tags import TagConfig
from scenariominer.data.log import BoolArray, FloatArray, Log
from scenariominer.geometry import (
    OrientedBoxes,
    box_distance_m,
    boxes_overlap,
    ctrv_predict,
    yaw_rate_radps,
)
from scenariominer.tags.vocab import (
    ABSENT,
    CollisionTag,
    DistanceTag,
    TrajOverlapTag,
    code_of,
)

__all__ = [
    "classify_distance",
    "classify_ttc",
    "collision_tags",
    "distance_tags",
    "heading_codes",
    "heading_tags",
    "log_boxes",
    "position_codes",
    "position_tags",
    "swept_overlap",
    "traj_overlap_tags",
    "ttc_s",
]

CodeArray = NDArray[np.int8]


def log_boxes(log: Log) -> OrientedBoxes:
    """Return the ``(N, T)`` boxes of every track of ``log`` (NaN where absent)."""
    return OrientedBoxes(log.x_m, log.y_m, log.yaw_rad, log.length_m, log.width_m)


def _pair_mask(log: Log) -> BoolArray:
    """``(N, T)`` cells where both the object and the ego are observed; False on the ego's row."""
    mask = log.valid & log.valid[log.ego_index][None, :]
    mask[log.ego_index] = False
    return np.asarray(mask, dtype=bool)


def _finish(codes: CodeArray, mask: BoolArray) -> CodeArray:
    codes = codes.astype(np.int8, copy=False)
    codes[~mask] = ABSENT
    return codes


# ---------------------------------------------------------------------- heading and position


def heading_codes(rel_heading_rad: FloatArray) -> CodeArray:
    """:class:`HeadingTag` codes for relative headings (object minus ego), any shape.

    Sector boundaries at ±45° and ±135° belong to the counter-clockwise sector (45° is LEFT).
    """
    return np.asarray(
        np.floor(np.mod(rel_heading_rad + np.pi / 4, 2 * np.pi) / (np.pi / 2)) % 4, dtype=np.int8
    )


def position_codes(bearing_rad: FloatArray) -> CodeArray:
    """:class:`PositionTag` codes for bearings in the ego frame (0 = ahead, +90° = left), any shape.

    Sector boundaries at ±22.5°, ±67.5°, ... belong to the counter-clockwise sector.
    """
    return np.asarray(np.floor(np.mod(bearing_rad + np.pi / 8, 2 * np.pi) / (np.pi / 4)) % 8, dtype=np.int8)


def heading_tags(log: Log) -> CodeArray:
    """``(N, T)`` int8 :class:`HeadingTag` codes of every object relative to the ego."""
    mask = _pair_mask(log)
    rel = np.where(mask, log.yaw_rad - log.yaw_rad[log.ego_index][None, :], 0.0)
    return _finish(heading_codes(rel), mask)


def position_tags(log: Log) -> CodeArray:
    """``(N, T)`` int8 :class:`PositionTag` codes: bearing of each object's centre in the ego frame."""
    mask = _pair_mask(log)
    e = log.ego_index
    dx = np.where(mask, log.x_m - log.x_m[e][None, :], 0.0)
    dy = np.where(mask, log.y_m - log.y_m[e][None, :], 0.0)
    yaw_e = np.nan_to_num(log.yaw_rad[e])[None, :]
    forward = dx * np.cos(yaw_e) + dy * np.sin(yaw_e)
    left = -dx * np.sin(yaw_e) + dy * np.cos(yaw_e)
    return _finish(position_codes(np.arctan2(left, forward)), mask)


# ---------------------------------------------------------------------- distance


def classify_distance(distance_m: FloatArray, very_close: BoolArray, cfg: TagConfig) -> CodeArray:
    """:class:`DistanceTag` codes from box distance and the expanded-box overlap flag, any shape."""
    codes = np.full(np.shape(distance_m), code_of(DistanceTag.FAR), dtype=np.int8)
    with np.errstate(invalid="ignore"):
        codes[distance_m <= cfg.distance_far_m] = code_of(DistanceTag.MEDIUM)
        codes[distance_m < cfg.distance_close_m] = code_of(DistanceTag.CLOSE)
    codes[very_close] = code_of(DistanceTag.VERY_CLOSE)
    return codes


def distance_tags(log: Log, cfg: TagConfig) -> tuple[CodeArray, FloatArray]:
    """Box-to-box distance of each object to the ego and its :class:`DistanceTag`.

    Returns:
        ``(N, T)`` int8 codes and ``(N, T)`` distance in metres (0 when the boxes overlap, NaN
        where absent).
    """
    mask = _pair_mask(log)
    rows, cols = np.nonzero(mask)
    boxes = log_boxes(log)
    obj = boxes.take((rows, cols))
    ego = boxes.take((np.full_like(cols, log.ego_index), cols))
    dist = np.full(mask.shape, np.nan)
    dist[rows, cols] = box_distance_m(ego, obj)
    very_close = np.zeros(mask.shape, dtype=bool)
    margin = cfg.distance_margin_m
    # Rectangles enlarged by m lie within m·sqrt(2) of the originals: farther pairs cannot touch.
    near = dist[rows, cols] <= 2.0 * margin * np.sqrt(2.0) + 1e-9
    very_close[rows[near], cols[near]] = boxes_overlap(
        ego.take(near).expanded(margin), obj.take(near).expanded(margin)
    )
    return _finish(classify_distance(dist, very_close, cfg), mask), dist


# ---------------------------------------------------------------------- collision (CTRV TTC)


def classify_ttc(ttc: FloatArray, cfg: TagConfig) -> CodeArray:
    """:class:`CollisionTag` codes from time-to-collision in seconds (inf = none), any shape."""
    codes = np.full(np.shape(ttc), code_of(CollisionTag.NO), dtype=np.int8)
    with np.errstate(invalid="ignore"):
        codes[ttc <= cfg.ttc_horizon_s + 1e-9] = code_of(CollisionTag.LOW)
        codes[ttc < cfg.ttc_high_s - 1e-9] = code_of(CollisionTag.HIGH)
    return codes


def _prediction_state(log: Log, cfg: TagConfig) -> FloatArray:
    """``(N, T)`` yaw rate used for CTRV: clipped, and zero for actors below standstill speed."""
    rate = np.clip(
        yaw_rate_radps(log.yaw_rad, log.t_s), -cfg.ctrv_max_yaw_rate_radps, cfg.ctrv_max_yaw_rate_radps
    )
    with np.errstate(invalid="ignore"):
        rate[log.speed_mps < cfg.standing_speed_mps] = 0.0
    return np.asarray(np.nan_to_num(rate), dtype=np.float64)


def ttc_s(log: Log, cfg: TagConfig) -> FloatArray:
    """Time-to-collision of each object with the ego under Constant Turn Rate and Velocity, seconds.

    Both boxes are predicted at ``0, step, 2·step, ... horizon``; the TTC is the first predicted
    time at which they overlap (0 when they overlap now).

    Returns:
        ``(N, T)`` float: TTC in seconds, ``inf`` where no overlap is predicted within the horizon,
        NaN where the object or the ego is absent (and on the ego's row).
    """
    mask = _pair_mask(log)
    out = np.full(mask.shape, np.nan)
    out[mask] = np.inf
    n_steps = int(round(cfg.ttc_horizon_s / cfg.ttc_step_s))
    tau: FloatArray = np.arange(n_steps + 1, dtype=np.float64) * cfg.ttc_step_s  # (H,)
    e = log.ego_index
    speed = np.nan_to_num(log.speed_mps)
    boxes = log_boxes(log)
    radius = np.nan_to_num(boxes.radius_m)
    rate = _prediction_state(log, cfg)
    # Reachability prefilter: the bounding circles can only meet if the gap closes within the horizon.
    # Under CTRV the relative displacement after τ is at most |v_rel| τ plus the bend of both arcs,
    # (|v_e ω_e| + |v_o ω_o|) τ² / 2 (|R(θ) - I| <= |θ|), and never more than (|v_e| + |v_o|) τ.
    horizon = float(tau[-1])
    with np.errstate(invalid="ignore"):
        gap = (
            np.hypot(log.x_m - log.x_m[e][None, :], log.y_m - log.y_m[e][None, :])
            - radius
            - radius[e][None, :]
        )
        vx, vy = np.nan_to_num(log.vx_mps), np.nan_to_num(log.vy_mps)
        v_rel = np.hypot(vx - vx[e][None, :], vy - vy[e][None, :])
        bend = np.abs(speed * rate)
        closing_m = np.minimum(
            v_rel * horizon + (bend + bend[e][None, :]) * horizon * horizon / 2.0,
            (speed + speed[e][None, :]) * horizon,
        )
        candidate = mask & (gap <= closing_m + 1e-9)
    rows, cols = np.nonzero(candidate)
    if rows.size == 0:
        return out

    def predict(r: NDArray[np.intp], c: NDArray[np.intp]) -> OrientedBoxes:
        x, y, yaw = ctrv_predict(
            log.x_m[r, c][:, None],
            log.y_m[r, c][:, None],
            log.yaw_rad[r, c][:, None],
            np.nan_to_num(log.vx_mps[r, c])[:, None],
            np.nan_to_num(log.vy_mps[r, c])[:, None],
            rate[r, c][:, None],
            tau[None, :],
        )
        return OrientedBoxes(x, y, yaw, log.length_m[r, c][:, None], log.width_m[r, c][:, None])

    # The ego's prediction depends on the timestamp only: once per timestamp, then gathered.
    ego_t = np.unique(cols)
    ego_pred = predict(np.full_like(ego_t, e), ego_t)
    ego = ego_pred.take(np.searchsorted(ego_t, cols))  # (K, H) centre/yaw, (K, 1) size
    obj = predict(rows, cols)  # (K, H)
    # Bounding circles first; the separating-axis test only where they meet.
    reach_m = (radius[e, cols] + radius[rows, cols])[:, None]
    close = (ego.x_m - obj.x_m) ** 2 + (ego.y_m - obj.y_m) ** 2 <= reach_m * reach_m
    k_idx, h_idx = np.nonzero(close)
    hit = np.zeros(close.shape, dtype=bool)
    hit[k_idx, h_idx] = boxes_overlap(
        OrientedBoxes(
            ego.x_m[k_idx, h_idx],
            ego.y_m[k_idx, h_idx],
            ego.yaw_rad[k_idx, h_idx],
            ego.length_m[k_idx, 0],
            ego.width_m[k_idx, 0],
        ),
        OrientedBoxes(
            obj.x_m[k_idx, h_idx],
            obj.y_m[k_idx, h_idx],
            obj.yaw_rad[k_idx, h_idx],
            obj.length_m[k_idx, 0],
            obj.width_m[k_idx, 0],
        ),
    )
    any_hit = hit.any(axis=1)
    first = np.argmax(hit, axis=1)
    out[rows[any_hit], cols[any_hit]] = tau[first[any_hit]]
    return out


def collision_tags(log: Log, cfg: TagConfig) -> tuple[CodeArray, FloatArray]:
    """``(N, T)`` int8 :class:`CollisionTag` codes and the ``(N, T)`` TTC in seconds (see :func:`ttc_s`)."""
    ttc = ttc_s(log, cfg)
    return _finish(classify_ttc(ttc, cfg), _pair_mask(log)), ttc


# ---------------------------------------------------------------------- trajectory overlap


def swept_overlap(log: Log, windows_s: tuple[float, ...]) -> list[BoolArray]:
    """Tell, per window ``Δt``, whether recorded ego and object boxes within ``[now, now + Δt]`` meet.

    Args:
        log: preprocessed log.
        windows_s: window lengths in seconds.

    Returns:
        One ``(N, T)`` bool array per window; False on the ego's row and where the pair is absent.
    """
    mask = _pair_mask(log)
    n, t = mask.shape
    out = [np.zeros((n, t), dtype=bool) for _ in windows_s]
    if t == 0 or not mask.any():
        return out
    e = log.ego_index
    ts = log.timestamps_ns.astype(np.float64) * 1e-9
    ts = ts - ts[0]
    widest = max(windows_s)
    reach = np.searchsorted(ts, ts + widest + 1e-9, side="right") - 1 - np.arange(t)  # frames per window
    band = int(reach.max())
    offsets = np.arange(-band, band + 1)  # t1 - t2
    boxes = log_boxes(log)
    radius = np.nan_to_num(boxes.radius_m)
    ex, ey, ego_ok = log.x_m[e], log.y_m[e], log.valid[e]

    # Ego box pairs (t2, t1) inside the band: (T, D).
    t1_band = np.arange(t)[:, None] + offsets[None, :]
    t1_clip = np.clip(t1_band, 0, t - 1)
    band_ok = (t1_band >= 0) & (t1_band < t) & ego_ok[t1_clip]
    band_ok &= np.abs(ts[t1_clip] - ts[:, None]) <= widest + 1e-9
    # Stage 1: object cells (i, t2) near enough to the ego at t2 that some ego box of the band could
    # reach them: within the band of t2 the ego's centre stays within `ego_travel[t2]` metres of
    # where it is at t2.
    with np.errstate(invalid="ignore"):
        travel = np.hypot(ex[t1_clip] - ex[:, None], ey[t1_clip] - ey[:, None])
    ego_travel = np.max(np.where(band_ok, np.nan_to_num(travel), 0.0), axis=1)  # (T,)
    obj_ok = log.valid.copy()
    obj_ok[e] = False
    with np.errstate(invalid="ignore"):
        centre_gap = np.hypot(log.x_m - ex[None, :], log.y_m - ey[None, :])
        near = centre_gap <= ego_travel[None, :] + radius + float(radius[e].max()) + 1e-9
    cell_i, cell_t2 = np.nonzero(obj_ok & (near | ~ego_ok[None, :]))
    if cell_i.size == 0:
        return out
    # Stage 2: bounding circles of the object box at t2 and each ego box of its band: (M, D).
    t1 = t1_clip[cell_t2]
    with np.errstate(invalid="ignore"):
        dx = log.x_m[cell_i, cell_t2][:, None] - ex[t1]
        dy = log.y_m[cell_i, cell_t2][:, None] - ey[t1]
        reach_m = radius[cell_i, cell_t2][:, None] + radius[e][t1]
        candidate = band_ok[cell_t2] & (dx * dx + dy * dy <= reach_m * reach_m)
    m, d = np.nonzero(candidate)
    if m.size == 0:
        return out
    obj_i, time2, time1 = cell_i[m], cell_t2[m], t1[m, d]
    hit = boxes_overlap(boxes.take((np.full_like(obj_i, e), time1)), boxes.take((obj_i, time2)))
    obj_i, time1, time2 = obj_i[hit], time1[hit], time2[hit]
    late = np.maximum(time1, time2)
    early = np.minimum(time1, time2)
    for k, window_s in enumerate(windows_s):
        lo = np.searchsorted(ts, ts[late] - window_s - 1e-9, side="left")
        keep = lo <= early
        diff = np.zeros((n, t + 1), dtype=np.int64)
        np.add.at(diff, (obj_i[keep], lo[keep]), 1)
        np.add.at(diff, (obj_i[keep], early[keep] + 1), -1)
        out[k] = (np.cumsum(diff[:, :t], axis=1) > 0) & mask
    return out


def traj_overlap_tags(log: Log, cfg: TagConfig) -> CodeArray:
    """``(N, T)`` int8 :class:`TrajOverlapTag` codes from the recorded future boxes (see module doc)."""
    high, low = swept_overlap(log, (cfg.overlap_high_s, cfg.overlap_low_s))
    codes = np.full(high.shape, code_of(TrajOverlapTag.NO), dtype=np.int8)
    codes[low] = code_of(TrajOverlapTag.LOW)
    codes[high] = code_of(TrajOverlapTag.HIGH)
    return _finish(codes, _pair_mask(log))
