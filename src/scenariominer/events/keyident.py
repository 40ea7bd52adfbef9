"""Key-object identification, KeyIdent (braking paper, section III-C).

An object is a *key candidate* at a timestamp when, at that same timestamp, the ego is
DECELERATING or STANDING_STILL and the object's CollisionTag or TrajOverlapTag is LOW or HIGH:
it is a likely reason for the ego's braking. Consecutive candidate timestamps of one object
(allowing gaps up to ``KeyIdentConfig.max_gap_s``) form one :class:`KeyEvent`.

Everything is a pure function of :class:`~scenariominer.tags.engine.LogTags`; the candidate mask
is vectorised over ``tracks × timestamps`` and events are found with one pass over the candidate
cells, not per frame.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from scenariominer.config.tags import KeyIdentConfig
from scenariominer.tags.engine import LogTags
from scenariominer.tags.vocab import (
    CollisionTag,
    LongitudeTag,
    TrajOverlapTag,
    code_of,
    member_of,
)

__all__ = ["KeyEvent", "find_key_objects", "key_candidates"]

_BRAKING = (code_of(LongitudeTag.DECELERATING), code_of(LongitudeTag.STANDING_STILL))
_RISKY_COLLISION = (code_of(CollisionTag.LOW), code_of(CollisionTag.HIGH))
_RISKY_OVERLAP = (code_of(TrajOverlapTag.LOW), code_of(TrajOverlapTag.HIGH))


@dataclass(frozen=True)
class KeyEvent:
    """A time window in which one object is a likely reason for the ego's braking.

    Attributes:
        log_id: the log.
        track_id: the guest object's track id.
        category: the guest's Argoverse 2 category.
        start_ns: first candidate timestamp, nanoseconds.
        end_ns: last candidate timestamp, nanoseconds (inclusive).
        n_frames: number of candidate timestamps in the window.
        peak_collision: highest CollisionTag over the candidate timestamps.
        peak_traj_overlap: highest TrajOverlapTag over the candidate timestamps.
        min_ttc_s: smallest CTRV time-to-collision in the window, seconds (``inf`` if none).
        min_distance_m: smallest box-to-box distance to the ego in the window, metres.
        method: what found the event: ``"tags"`` (collision / overlap tags) or ``"counterfactual"``
            (a predicted conflict had the ego not braked; see :mod:`scenariominer.events.counterfactual`).
        conflict_s: for a counterfactual event, seconds from the braking onset to the predicted
            conflict; NaN otherwise.
        aliases: other track ids of the same object (tracks stitched into this one after id switches).
    """

    log_id: str
    track_id: str
    category: str
    start_ns: int
    end_ns: int
    n_frames: int
    peak_collision: CollisionTag
    peak_traj_overlap: TrajOverlapTag
    min_ttc_s: float
    min_distance_m: float
    method: str = "tags"
    conflict_s: float = math.nan
    aliases: tuple[str, ...] = ()

    @property
    def duration_s(self) -> float:
        """Seconds from the first to the last candidate timestamp."""
        return (self.end_ns - self.start_ns) * 1e-9

    @property
    def event_id(self) -> str:
        """Stable identifier ``<log_id>:<track_id>:<start_ns>``."""
        return f"{self.log_id}:{self.track_id}:{self.start_ns}"


def key_candidates(tags: LogTags) -> NDArray[np.bool_]:
    """``(N, T)`` True where the object is a key candidate (the ego's row is always False)."""
    ego_braking = np.isin(tags.longitude[tags.ego_index], _BRAKING)
    risky = np.isin(tags.collision, _RISKY_COLLISION) | np.isin(tags.traj_overlap, _RISKY_OVERLAP)
    mask = risky & ego_braking[None, :]
    mask[tags.ego_index] = False
    return np.asarray(mask, dtype=bool)


def find_key_objects(tags: LogTags, cfg: KeyIdentConfig | None = None) -> list[KeyEvent]:
    """Find the objects that likely made the ego brake, as events (KeyIdent, section III-C).

    Args:
        tags: the log's tag matrices from :func:`scenariominer.tags.tag_log`.
        cfg: event merging; defaults to :class:`KeyIdentConfig` (no minimum duration, as the paper).

    Returns:
        Events ordered by track row, then start time.
    """
    cfg = cfg or KeyIdentConfig()
    rows, cols = np.nonzero(key_candidates(tags))  # row-major: grouped by track, time ascending
    if rows.size == 0:
        return []
    ts = tags.timestamps_ns[cols]
    gap_ns = np.diff(ts)
    new = np.concatenate([[True], (rows[1:] != rows[:-1]) | (gap_ns > cfg.max_gap_s * 1e9 + 1)])
    starts = np.flatnonzero(new)
    ends = np.append(starts[1:], rows.size) - 1
    coll = tags.collision[rows, cols]
    over = tags.traj_overlap[rows, cols]
    ttc = np.nan_to_num(tags.ttc_s[rows, cols], nan=np.inf)
    dist = np.nan_to_num(tags.distance_m[rows, cols], nan=np.inf)
    peak_coll = np.maximum.reduceat(coll, starts)
    peak_over = np.maximum.reduceat(over, starts)
    min_ttc = np.minimum.reduceat(ttc, starts)
    min_dist = np.minimum.reduceat(dist, starts)
    events: list[KeyEvent] = []
    for k, (a, b) in enumerate(zip(starts, ends, strict=True)):  # one iteration per event
        start_ns, end_ns = int(ts[a]), int(ts[b])
        if (end_ns - start_ns) * 1e-9 < cfg.min_duration_s - 1e-9:
            continue
        row = int(rows[a])
        # Both families share the pair mask, so candidate cells never hold ABSENT.
        collision = member_of(CollisionTag, int(peak_coll[k]))
        overlap = member_of(TrajOverlapTag, int(peak_over[k]))
        events.append(
            KeyEvent(
                log_id=tags.log_id,
                track_id=str(tags.track_ids[row]),
                category=str(tags.categories[row]),
                start_ns=start_ns,
                end_ns=end_ns,
                n_frames=int(b - a + 1),
                peak_collision=collision or CollisionTag.NO,
                peak_traj_overlap=overlap or TrajOverlapTag.NO,
                min_ttc_s=float(min_ttc[k]),
                min_distance_m=float(min_dist[k]),
            )
        )
    return events
