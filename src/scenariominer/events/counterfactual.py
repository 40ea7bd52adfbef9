"""Counterfactual key objects: which object would the ego have met had it not braked.

The tag-based KeyIdent (:mod:`scenariominer.events.keyident`) needs a collision or trajectory-overlap
tag while the ego brakes. An early, smooth yield never raises one: the ego stops metres short of the
pedestrian or of the oncoming lane, so the recorded paths never meet. This module asks the
counterfactual question instead:

1. **Braking segments**: runs of ego frames tagged DECELERATING or STANDING_STILL (runs closer
   than ``KeyIdentConfig.max_gap_s`` merged) whose speed just before the onset (the largest speed in
   the ``ref_before_s`` before it) is at least ``min_onset_speed_mps``.
2. **Counterfactual ego**: from its recorded position at a reference time, the ego moves at its
   pre-braking speed along two paths: keeping its heading and turn rate, and along the path it
   actually drove (an offline log knows where it went, e.g. the left turn it waited to make;
   continued straight past the log's end). A conflict found only on the driven path costs
   ``driven_path_weight`` in the ranking: it may come from a manoeuvre the key object caused.
   Reference times run from ``ref_before_s`` before the
   onset to ``ref_after_s`` after it (at most to the segment's end), every ``ref_step_s``.
3. **Objects**: every object observed at the reference time within ``max_range_m`` moves with
   constant velocity and turn rate (:func:`~scenariominer.geometry.ctrv_predict`).
4. **Conflict**: an ego box and an object box overlap, the object being there at most
   ``max_gap_s`` before the ego or about at the same time (a predicted post-encroachment time);
   an object reaching the region well after the ego (a follower) is not a conflict.
   :func:`~scenariominer.geometry.prediction.first_conflicts` tests all ``objects × steps × steps``
   box pairs of a reference time at once.
5. **Ranking**: each conflicting object scores its time to conflict, plus weighted costs for the
   conflict's time gap, for how late after the onset the reference time is, and for how late after
   the onset the object was first seen (a braking that starts before an object appears is not
   caused by it); the ``max_per_segment`` lowest scores per segment become :class:`KeyEvent` s
   with ``method="counterfactual"``.

:func:`identify_key_objects` dispatches on ``KeyIdentConfig.method``: the paper's tags, the
counterfactual search, or both combined (tag events, plus the counterfactual key object of every
braking segment that no tag event overlaps).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import NDArray

from scenariominer.config.tags import CounterfactualConfig, KeyIdentConfig
from scenariominer.data.log import Log
from scenariominer.events.keyident import KeyEvent, find_key_objects
from scenariominer.geometry import OrientedBoxes, ctrv_predict, yaw_rate_radps
from scenariominer.geometry.prediction import first_conflicts, poses_along_path
from scenariominer.tags.engine import LogTags
from scenariominer.tags.vocab import CollisionTag, LongitudeTag, TrajOverlapTag, code_of, member_of

__all__ = [
    "BrakingSegment",
    "ConflictCandidate",
    "braking_segments",
    "counterfactual_key_objects",
    "identify_key_objects",
    "segment_candidates",
]

#: An object may reach the conflict region at most this long after the ego (seconds) and still
#: count: the two arrive together. Later arrivals (a follower reaching where the ego was) do not.
OBJECT_AFTER_EGO_S = 0.3

_BRAKING = (code_of(LongitudeTag.DECELERATING), code_of(LongitudeTag.STANDING_STILL))


@dataclass(frozen=True)
class BrakingSegment:
    """A run of braking frames of the ego.

    Attributes:
        onset: index of the first braking timestamp.
        end: index of the last braking timestamp (inclusive).
        onset_speed_mps: the ego's largest speed in the ``ref_before_s`` before the onset (m/s).
    """

    onset: int
    end: int
    onset_speed_mps: float


@dataclass(frozen=True)
class ConflictCandidate:
    """An object whose predicted footprint conflicts with the counterfactual ego's.

    Attributes:
        track_index: the object's row in the log.
        ref_index: timestamp index of the prediction that found the conflict.
        conflict_s: seconds from the braking onset to the ego's arrival at the conflict.
        gap_s: ``|ego time - object time|`` at the conflict, seconds.
        score: ranking cost (lower ranks first; see the module docstring).
    """

    track_index: int
    ref_index: int
    conflict_s: float
    gap_s: float
    score: float


def braking_segments(
    log: Log, tags: LogTags, cfg: CounterfactualConfig, merge_gap_s: float
) -> list[BrakingSegment]:
    """Braking segments of the ego (see the module docstring, step 1), in time order.

    Args:
        log: the (preprocessed) log the tags come from.
        tags: its tags.
        cfg: onset speed and look-back.
        merge_gap_s: runs separated by at most this many seconds are one segment.
    """
    braking = np.isin(tags.longitude[tags.ego_index], _BRAKING)
    if not braking.any():
        return []
    padded = np.concatenate([[False], braking, [False]])
    edges = np.diff(padded.astype(np.int8))
    starts = np.flatnonzero(edges == 1)
    stops = np.flatnonzero(edges == -1) - 1  # inclusive
    t_s = log.t_s
    gap = t_s[starts[1:]] - t_s[stops[:-1]]
    new = np.concatenate([[True], gap > merge_gap_s + 1e-9])
    seg_start = starts[new]
    seg_stop = np.append(stops[np.flatnonzero(new)[1:] - 1], stops[-1])
    speed = np.nan_to_num(log.speed_mps[log.ego_index], nan=0.0)
    lo = np.searchsorted(t_s, t_s[seg_start] - cfg.ref_before_s - 1e-9)
    out: list[BrakingSegment] = []
    for a, b, first in zip(seg_start, seg_stop, lo, strict=True):  # one iteration per segment
        v0 = float(speed[first : a + 1].max())
        if v0 >= cfg.min_onset_speed_mps:
            out.append(BrakingSegment(int(a), int(b), v0))
    return out


def _reference_indices(
    t_s: NDArray[np.float64], seg: BrakingSegment, cfg: CounterfactualConfig
) -> NDArray[np.intp]:
    t0 = t_s[seg.onset]
    last = min(t0 + cfg.ref_after_s, t_s[seg.end])
    wanted = np.arange(t0 - cfg.ref_before_s, last + 1e-9, cfg.ref_step_s)
    idx = np.clip(np.searchsorted(t_s, wanted - 1e-9), 0, t_s.size - 1)
    return np.unique(idx)


def segment_candidates(
    log: Log,
    seg: BrakingSegment,
    cfg: CounterfactualConfig,
    *,
    yaw_rate: NDArray[np.float64] | None = None,
    first_seen_s: NDArray[np.float64] | None = None,
) -> list[ConflictCandidate]:
    """Objects conflicting with the counterfactual ego of one braking segment, best ranked first.

    Args:
        log: the preprocessed log.
        seg: the braking segment.
        cfg: prediction and ranking settings.
        yaw_rate: ``(N, T)`` yaw rates (rad/s), computed when not given.
        first_seen_s: ``(N,)`` first observed time of every track (seconds), computed when not given.

    Returns:
        One candidate per conflicting object (its best reference time), lowest score first.
    """
    t_s = log.t_s
    e = log.ego_index
    if yaw_rate is None:
        yaw_rate = yaw_rate_radps(log.yaw_rad, t_s)
    if first_seen_s is None:
        first_seen_s = _first_seen_s(log)
    tau = np.arange(0.0, cfg.horizon_s + 1e-9, cfg.step_s)
    t0 = float(t_s[seg.onset])
    best: dict[int, ConflictCandidate] = {}
    rate = np.clip(
        np.nan_to_num(yaw_rate, nan=0.0), -cfg.ctrv_max_yaw_rate_radps, cfg.ctrv_max_yaw_rate_radps
    )
    for r in _reference_indices(t_s, seg, cfg):  # a handful of reference times per segment
        if not log.valid[e, r]:
            continue
        near = log.valid[:, r] & (
            np.hypot(log.x_m[:, r] - log.x_m[e, r], log.y_m[:, r] - log.y_m[e, r]) <= cfg.max_range_m
        )
        near[e] = False
        near &= first_seen_s <= t0 + cfg.max_late_s
        rows = np.flatnonzero(near)
        if rows.size == 0:
            continue
        ox, oy, oyaw = ctrv_predict(
            log.x_m[rows, r, None],
            log.y_m[rows, r, None],
            log.yaw_rad[rows, r, None],
            np.nan_to_num(log.vx_mps[rows, r, None]),
            np.nan_to_num(log.vy_mps[rows, r, None]),
            rate[rows, r, None],
            tau[None, :],
        )
        objects = OrientedBoxes(
            ox,
            oy,
            oyaw,
            np.broadcast_to(log.length_m[rows, r, None], ox.shape),
            np.broadcast_to(log.width_m[rows, r, None], ox.shape),
        )
        t_ref = float(t_s[r])
        for ego, path_cost in _ego_paths(log, r, seg.onset_speed_mps, tau, float(rate[e, r]), cfg):
            found = first_conflicts(
                ego, objects, tau, cfg.max_gap_s, cfg.margin_m, object_after_s=OBJECT_AFTER_EGO_S
            )
            hits = np.flatnonzero(found.found)
            if hits.size == 0:
                continue
            late = np.maximum(first_seen_s[rows[hits]] - t0, 0.0)
            gap = found.gap_s[hits]
            score = (
                found.ego_time_s[hits]
                + cfg.gap_weight * gap
                + cfg.ref_weight * max(t_ref - t0, 0.0)
                + cfg.late_weight * late
                + path_cost
            )
            for k, row in enumerate(rows[hits]):  # one iteration per conflicting object
                cand = ConflictCandidate(
                    int(row),
                    int(r),
                    t_ref - t0 + float(found.ego_time_s[hits[k]]),
                    float(gap[k]),
                    float(score[k]),
                )
                old = best.get(int(row))
                if old is None or cand.score < old.score:
                    best[int(row)] = cand
    return sorted(best.values(), key=lambda c: (c.score, c.track_index))


def _ego_paths(
    log: Log,
    r: int,
    speed_mps: float,
    tau: NDArray[np.float64],
    yaw_rate_radps: float,
    cfg: CounterfactualConfig,
) -> list[tuple[OrientedBoxes, float]]:
    """The counterfactual ego boxes ``(H,)`` from timestamp ``r``, each with its ranking cost.

    The boxes are narrowed by ``ego_width_shrink_m`` on each side. Two paths at the pre-braking
    speed: keeping the ego's heading and turn rate at ``r`` (cost 0),
    and along the path it actually drove from ``r`` on (cost ``driven_path_weight``: a conflict
    found only there relies on a later manoeuvre, e.g. the turn it was waiting to make, or the
    evasive lane change the key object itself caused).
    """
    e = log.ego_index
    length = np.full(tau.size, log.length_m[e, r])
    width = np.full(tau.size, max(float(log.width_m[e, r]) - 2.0 * cfg.ego_width_shrink_m, 0.1))
    yaw = log.yaw_rad[e, r : r + 1]
    hx, hy, hyaw = ctrv_predict(
        log.x_m[e, r : r + 1],
        log.y_m[e, r : r + 1],
        yaw,
        speed_mps * np.cos(yaw),
        speed_mps * np.sin(yaw),
        np.full(1, yaw_rate_radps),
        tau,
    )
    dx, dy, dyaw = poses_along_path(
        log.x_m[e, r:], log.y_m[e, r:], _last_finite(log.yaw_rad[e, r:]), speed_mps * tau
    )
    return [
        (OrientedBoxes(hx, hy, hyaw, length, width), 0.0),
        (OrientedBoxes(dx, dy, dyaw, length, width), cfg.driven_path_weight),
    ]


def _last_finite(values: NDArray[np.float64]) -> float:
    ok = np.flatnonzero(np.isfinite(values))
    return float(values[ok[-1]]) if ok.size else 0.0


def _first_seen_s(log: Log) -> NDArray[np.float64]:
    """``(N,)`` time of each track's first observation, seconds (inf for a track never observed)."""
    any_valid = log.valid.any(axis=1)
    first = np.argmax(log.valid, axis=1)
    return np.where(any_valid, log.t_s[first], np.inf)


def _event(log: Log, tags: LogTags, cand: ConflictCandidate, seg: BrakingSegment) -> KeyEvent:
    """The KeyEvent of a counterfactual candidate: the braking segment, with the guest's tag peaks."""
    g = cand.track_index
    win = slice(seg.onset, seg.end + 1)
    coll = tags.collision[g, win]
    over = tags.traj_overlap[g, win]
    ttc = np.nan_to_num(tags.ttc_s[g, win], nan=np.inf)
    dist = np.nan_to_num(tags.distance_m[g, win], nan=np.inf)
    return KeyEvent(
        log_id=log.log_id,
        track_id=str(log.track_ids[g]),
        category=str(log.categories[g]),
        start_ns=int(log.timestamps_ns[seg.onset]),
        end_ns=int(log.timestamps_ns[seg.end]),
        n_frames=int(log.valid[g, win].sum()),
        peak_collision=member_of(CollisionTag, int(coll.max(initial=0))) or CollisionTag.NO,
        peak_traj_overlap=member_of(TrajOverlapTag, int(over.max(initial=0))) or TrajOverlapTag.NO,
        min_ttc_s=float(ttc.min(initial=np.inf)),
        min_distance_m=float(dist.min(initial=np.inf)),
        method="counterfactual",
        conflict_s=cand.conflict_s,
    )


def counterfactual_key_objects(
    log: Log, tags: LogTags, cfg: KeyIdentConfig | None = None
) -> list[tuple[BrakingSegment, list[KeyEvent]]]:
    """Counterfactual key objects of every braking segment (see the module docstring).

    Args:
        log: the preprocessed log the tags come from.
        tags: its tags (the ego's longitudinal tags define the braking segments).
        cfg: KeyIdent settings; ``cfg.counterfactual`` drives the search.

    Returns:
        ``(segment, events)`` for every braking segment; ``events`` holds at most
        ``max_per_segment`` events, best ranked first (empty when no object conflicts).
    """
    cfg = cfg or KeyIdentConfig()
    cf = cfg.counterfactual
    segments = braking_segments(log, tags, cf, cfg.max_gap_s)
    if not segments:
        return []
    yaw_rate = yaw_rate_radps(log.yaw_rad, log.t_s)
    first_seen = _first_seen_s(log)
    out = []
    for seg in segments:  # one iteration per braking segment
        cands = segment_candidates(log, seg, cf, yaw_rate=yaw_rate, first_seen_s=first_seen)
        out.append((seg, [_event(log, tags, c, seg) for c in cands[: cf.max_per_segment]]))
    return out


def identify_key_objects(
    log: Log,
    tags: LogTags,
    cfg: KeyIdentConfig | None = None,
    *,
    aliases: Mapping[str, tuple[str, ...]] | None = None,
) -> list[KeyEvent]:
    """Key objects of a log by the configured method (``cfg.method``).

    Args:
        log: the preprocessed log the tags come from.
        tags: its tags.
        cfg: KeyIdent settings (default: :class:`KeyIdentConfig`, method ``combined``).
        aliases: ``track id → other ids of the same object`` (from stitching); copied onto events.

    Returns:
        Events ordered by start time, then track id.
    """
    cfg = cfg or KeyIdentConfig()
    events: list[KeyEvent] = []
    if cfg.method in ("tags", "combined"):
        events = find_key_objects(tags, cfg)
    if cfg.method in ("counterfactual", "combined"):
        for seg, found in counterfactual_key_objects(log, tags, cfg):
            lo, hi = int(log.timestamps_ns[seg.onset]), int(log.timestamps_ns[seg.end])
            explained = cfg.method == "combined" and any(
                ev.method == "tags" and ev.start_ns <= hi and ev.end_ns >= lo for ev in events
            )
            if not explained:
                events.extend(found)
    if aliases:
        events = [replace(ev, aliases=tuple(aliases.get(ev.track_id, ()))) for ev in events]
    return sorted(events, key=lambda ev: (ev.start_ns, ev.track_id))
