"""Criticality measures of a braking event, used to rank and filter events.

Validation engineers rank scenarios by surrogate safety measures; four are computed per event:

* **minimum time-to-collision** (s): the smallest CTRV time-to-collision of the guest with the
  ego in the window (:attr:`~scenariominer.tags.engine.LogTags.ttc_s`), ``inf`` when no
  collision is predicted within the horizon;
* **post-encroachment time** (s): the shortest time between one actor leaving and the other
  entering a region both occupy at some time, i.e. the smallest ``|t_ego - t_guest|`` over all
  pairs of recorded ego and guest boxes that overlap (0 for an actual contact), NaN when their
  paths never share a region. All ``W × W`` box pairs are tested at once (bounding circles, then
  separating axes);
* **time headway** (s): while the guest is ahead of the ego (PositionTag FRONT) and travels the
  same way (HeadingTag SAME), the bumper-to-bumper gap along the ego's heading divided by the
  ego's speed; the minimum over the window, NaN when the guest never leads a moving ego;
* **peak deceleration** (m/s²): the largest deceleration of the ego along its heading in the
  window (the smoothed acceleration of preprocessing), 0 when it never decelerates.

The window is the event's *analysis window* (the KeyIdent window plus the configured context);
post-encroachment time looks ``pet_horizon_s`` further, for the second actor to arrive.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from scenariominer.config.explain import ExplainConfig
from scenariominer.data.log import Log
from scenariominer.geometry import OrientedBoxes, boxes_overlap
from scenariominer.tags.engine import LogTags
from scenariominer.tags.vocab import HeadingTag, PositionTag, code_of

__all__ = [
    "Criticality",
    "event_criticality",
    "peak_deceleration_mps2",
    "post_encroachment_time_s",
    "time_headway_s",
]

FloatArray = NDArray[np.float64]
BoolArray = NDArray[np.bool_]


@dataclass(frozen=True)
class Criticality:
    """Surrogate safety measures of one braking event.

    Attributes:
        min_ttc_s: minimum CTRV time-to-collision in the window, seconds (``inf`` if none).
        pet_s: post-encroachment time, seconds (NaN when the paths never share a region).
        headway_s: minimum time headway while the guest leads the ego, seconds (NaN if never).
        peak_decel_mps2: the ego's largest deceleration along its heading, m/s² (>= 0).
        closest_ns: timestamp of the smallest ego–guest box distance inside the KeyIdent window
            (the event's start when the distance is unknown); the key time of a picture.
    """

    min_ttc_s: float
    pet_s: float
    headway_s: float
    peak_decel_mps2: float
    closest_ns: int


def peak_deceleration_mps2(
    ax_mps2: FloatArray, ay_mps2: FloatArray, yaw_rad: FloatArray, valid: BoolArray
) -> float:
    """Largest deceleration along the heading, m/s² (0 if the actor never decelerates).

    Args:
        ax_mps2: ``(W,)`` world-frame acceleration x.
        ay_mps2: ``(W,)`` world-frame acceleration y.
        yaw_rad: ``(W,)`` heading.
        valid: ``(W,)`` observed frames.
    """
    a_lon = ax_mps2 * np.cos(yaw_rad) + ay_mps2 * np.sin(yaw_rad)
    a_lon = a_lon[valid & np.isfinite(a_lon)]
    if a_lon.size == 0:
        return 0.0
    return float(max(0.0, -float(a_lon.min())))


def time_headway_s(
    ego: OrientedBoxes,
    guest: OrientedBoxes,
    ego_speed_mps: FloatArray,
    following: BoolArray,
    min_speed_mps: float,
) -> float:
    """Minimum time headway of the ego behind a leading guest, seconds.

    The gap is the guest's centre offset along the ego's heading minus half of both lengths
    (clipped at 0), divided by the ego's speed.

    Args:
        ego: ``(W,)`` ego boxes.
        guest: ``(W,)`` guest boxes.
        ego_speed_mps: ``(W,)`` ego ground speed.
        following: ``(W,)`` frames where the guest leads the ego (ahead, same direction).
        min_speed_mps: frames where the ego is slower are ignored.

    Returns:
        The minimum over the qualifying frames, NaN when there is none.
    """
    dx = guest.x_m - ego.x_m
    dy = guest.y_m - ego.y_m
    ahead = dx * np.cos(ego.yaw_rad) + dy * np.sin(ego.yaw_rad)
    gap = np.maximum(ahead - 0.5 * ego.length_m - 0.5 * guest.length_m, 0.0)
    with np.errstate(invalid="ignore"):
        use = following & (ego_speed_mps >= min_speed_mps) & np.isfinite(gap)
    if not use.any():
        return math.nan
    return float(np.min(gap[use] / ego_speed_mps[use]))


def post_encroachment_time_s(ego: OrientedBoxes, guest: OrientedBoxes, t_s: FloatArray) -> float:
    """Post-encroachment time from recorded boxes: the smallest ``|t_i - t_j|`` over overlapping pairs.

    Args:
        ego: ``(W,)`` ego boxes (NaN where unobserved).
        guest: ``(W,)`` guest boxes (NaN where unobserved).
        t_s: ``(W,)`` seconds.

    Returns:
        Seconds (0 when the boxes overlap at the same time), NaN when no ego box ever overlaps a
        guest box.
    """
    ok_e = np.isfinite(ego.x_m) & np.isfinite(ego.y_m)
    ok_g = np.isfinite(guest.x_m) & np.isfinite(guest.y_m)
    ie, ig = np.flatnonzero(ok_e), np.flatnonzero(ok_g)
    if ie.size == 0 or ig.size == 0:
        return math.nan
    e, g = ego.take(ie), guest.take(ig)
    # Bounding circles prune the W x W pairs before the separating-axis test.
    reach = e.radius_m[:, None] + g.radius_m[None, :]
    near = (e.x_m[:, None] - g.x_m[None, :]) ** 2 + (e.y_m[:, None] - g.y_m[None, :]) ** 2 <= reach * reach
    a, b = np.nonzero(near)
    if a.size == 0:
        return math.nan
    hit = boxes_overlap(e.take(a), g.take(b))
    if not hit.any():
        return math.nan
    return float(np.min(np.abs(t_s[ie[a[hit]]] - t_s[ig[b[hit]]])))


def _boxes(log: Log, row: int, sl: slice) -> OrientedBoxes:
    return OrientedBoxes(
        log.x_m[row, sl], log.y_m[row, sl], log.yaw_rad[row, sl], log.length_m[row, sl], log.width_m[row, sl]
    )


def event_criticality(
    log: Log,
    tags: LogTags,
    guest_id: str,
    start_ns: int,
    end_ns: int,
    cfg: ExplainConfig | None = None,
) -> Criticality:
    """Compute the criticality measures of one event (see the module docstring).

    Args:
        log: the preprocessed log the tags were computed from.
        tags: its tags.
        guest_id: the guest's track id.
        start_ns: first KeyIdent timestamp of the event.
        end_ns: last KeyIdent timestamp (inclusive).
        cfg: window context, PET horizon and headway speed floor; defaults to :class:`ExplainConfig`.

    Raises:
        KeyError: the guest is not in the log.
    """
    cfg = cfg or ExplainConfig()
    g = log.track_index(guest_id)
    e = log.ego_index
    ts = log.timestamps_ns
    lo = int(np.searchsorted(ts, start_ns - round(cfg.context_before_s * 1e9), side="left"))
    hi = int(np.searchsorted(ts, end_ns + round(cfg.context_after_s * 1e9), side="right"))
    hi_pet = int(
        np.searchsorted(ts, end_ns + round((cfg.context_after_s + cfg.pet_horizon_s) * 1e9), "right")
    )
    win = slice(lo, max(hi, lo + 1))

    ttc = tags.ttc_s[g, win]
    ttc = ttc[np.isfinite(ttc) | np.isinf(ttc)]
    min_ttc = float(ttc.min()) if ttc.size else math.inf

    ego_valid = log.valid[e, win]
    decel = peak_deceleration_mps2(log.ax_mps2[e, win], log.ay_mps2[e, win], log.yaw_rad[e, win], ego_valid)

    following = (tags.position[g, win] == code_of(PositionTag.FRONT)) & (
        tags.heading[g, win] == code_of(HeadingTag.SAME)
    )
    headway = time_headway_s(
        _boxes(log, e, win), _boxes(log, g, win), log.speed_mps[e, win], following, cfg.headway_min_speed_mps
    )

    pet_win = slice(lo, max(hi_pet, lo + 1))
    t_s = (ts[pet_win] - ts[lo]).astype(np.float64) * 1e-9
    pet = post_encroachment_time_s(_boxes(log, e, pet_win), _boxes(log, g, pet_win), t_s)

    ev_lo = int(np.searchsorted(ts, start_ns, side="left"))
    ev_hi = max(int(np.searchsorted(ts, end_ns, side="right")), ev_lo + 1)
    dist = np.nan_to_num(tags.distance_m[g, ev_lo:ev_hi], nan=np.inf)
    closest = int(ts[min(ev_lo + int(np.argmin(dist)), ts.size - 1)]) if np.isfinite(dist).any() else start_ns
    return Criticality(
        min_ttc_s=min_ttc, pet_s=pet, headway_s=headway, peak_decel_mps2=decel, closest_ns=int(closest)
    )
