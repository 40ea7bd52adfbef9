"""Duration segments of an ego–guest pair's tags (braking paper, section III-D.1, Fig. 4a-b).

The per-timestamp tag matrices of a log (:class:`~scenariominer.tags.engine.LogTags`) are cut to
one ego–guest pair and one time window (:func:`pair_tags`), giving a ``(F, W)`` code matrix with
one row per :data:`PAIR_FEATURES` entry. :func:`segment_pair` turns it into a duration-based
representation: consecutive timestamps where *every* tag is unchanged form one segment, and each
segment knows which tags changed at its start and how long each new value lasts. Run-length
encoding is vectorised over the whole matrix (change masks, cumulative sums, ``bincount``),
never a per-frame loop.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Collection
from dataclasses import dataclass
from enum import StrEnum

import numpy as np
from numpy.typing import NDArray

from scenariominer.data.log import Log
from scenariominer.geometry.angles import wrap_angle
from scenariominer.geometry.frames import to_local
from scenariominer.tags.actor import frames_for, suppress_short_runs
from scenariominer.tags.engine import LogTags
from scenariominer.tags.vocab import ABSENT, TAG_FAMILIES, member_of

__all__ = [
    "FLICKER_FAMILIES",
    "PAIR_FEATURES",
    "Actor",
    "PairFeature",
    "PairSegments",
    "PairTags",
    "RunLengths",
    "pair_tags",
    "run_lengths",
    "segment_pair",
]

CodeArray = NDArray[np.int8]
FloatArray = NDArray[np.float64]
IntArray = NDArray[np.intp]


class Actor(StrEnum):
    """Whose tag a feature row is.

    Attributes:
        EGO: an activity tag of the ego vehicle.
        GUEST: an activity tag of the guest object.
        PAIR: an interaction tag of the guest relative to the ego.
    """

    EGO = "ego"
    GUEST = "guest"
    PAIR = "pair"


@dataclass(frozen=True)
class PairFeature:
    """One row of a pair's tag matrix.

    Attributes:
        actor: whose tag it is.
        family: tag family, a key of :data:`~scenariominer.tags.vocab.TAG_FAMILIES`.
    """

    actor: Actor
    family: str

    @property
    def key(self) -> str:
        """``<actor>.<family>``, e.g. ``ego.longitude``."""
        return f"{self.actor.value}.{self.family}"


#: Interaction families whose brief values are sector-boundary flicker rather than information
#: (a guest near the 22.5° line between FRONT and FRONT_LEFT). Actor tags are already debounced by
#: the tagger; collision and trajectory-overlap risk are never merged, a short HIGH matters.
FLICKER_FAMILIES: tuple[str, ...] = ("heading", "position", "distance")

#: Rows of a pair's tag matrix, in the order of a description (Fig. 4c).
PAIR_FEATURES: tuple[PairFeature, ...] = (
    PairFeature(Actor.EGO, "longitude"),
    PairFeature(Actor.EGO, "latitude"),
    PairFeature(Actor.GUEST, "longitude"),
    PairFeature(Actor.GUEST, "latitude"),
    PairFeature(Actor.PAIR, "collision"),
    PairFeature(Actor.PAIR, "heading"),
    PairFeature(Actor.PAIR, "position"),
    PairFeature(Actor.PAIR, "distance"),
    PairFeature(Actor.PAIR, "traj_overlap"),
)


@dataclass(frozen=True, eq=False)
class PairTags:
    """The tags of one ego–guest pair over a time window.

    Attributes:
        log_id: the log.
        guest_id: the guest's track id.
        guest_category: the guest's Argoverse 2 category.
        timestamps_ns: ``(W,)`` int64 timestamps of the window.
        codes: ``(F, W)`` int8 tag codes, one row per :data:`PAIR_FEATURES` entry
            (:data:`~scenariominer.tags.vocab.ABSENT` where undefined, e.g. the guest unobserved).
        frame_period_s: the log's median frame period, seconds (the duration of the last frame).
        event_start_ns: first timestamp of the event inside the window (KeyIdent's window start).
        event_end_ns: last timestamp of the event (inclusive).
        guest_left_m: ``(W,)`` lateral offset of the guest's box centre in the ego's frame,
            metres, positive to the ego's left, NaN where either is unobserved; ``None`` when
            the pair was cut without the log's positions (rules then use the tags alone).
        ego_turn_after_rad: the ego's accumulated heading change from the window's last timestamp
            to ``turn_lookahead_s`` later, radians, positive counter-clockwise (left); ``None``
            without the log's positions.
    """

    log_id: str
    guest_id: str
    guest_category: str
    timestamps_ns: NDArray[np.int64]
    codes: CodeArray
    frame_period_s: float
    event_start_ns: int
    event_end_ns: int
    guest_left_m: FloatArray | None = None
    ego_turn_after_rad: float | None = None

    def __post_init__(self) -> None:
        w = self.timestamps_ns.shape[0]
        if self.codes.shape != (len(PAIR_FEATURES), w):
            raise ValueError(f"codes must have shape ({len(PAIR_FEATURES)}, {w}), got {self.codes.shape}")
        if self.guest_left_m is not None and self.guest_left_m.shape != (w,):
            raise ValueError(f"guest_left_m must have shape ({w},), got {self.guest_left_m.shape}")
        if w == 0:
            raise ValueError(f"log {self.log_id}, guest {self.guest_id}: the window holds no timestamp")

    @property
    def n_timestamps(self) -> int:
        """Number of timestamps ``W`` in the window."""
        return int(self.timestamps_ns.shape[0])

    @property
    def edges_s(self) -> FloatArray:
        """``(W + 1,)`` frame boundaries in seconds from the window start.

        Frame ``i`` spans ``[edges_s[i], edges_s[i + 1])``; the last one lasts one frame period.
        """
        t = (self.timestamps_ns - self.timestamps_ns[0]).astype(np.float64) * 1e-9
        return np.append(t, t[-1] + self.frame_period_s)

    @property
    def duration_s(self) -> float:
        """Length of the window, seconds (last frame included)."""
        return float(self.edges_s[-1])

    @property
    def guest_frames(self) -> int:
        """Number of window timestamps at which the guest is observed."""
        guest_row = PAIR_FEATURES.index(PairFeature(Actor.GUEST, "longitude"))
        return int(np.count_nonzero(self.codes[guest_row] != ABSENT))


def pair_tags(
    tags: LogTags,
    guest_id: str,
    start_ns: int,
    end_ns: int,
    *,
    context_before_s: float = 0.0,
    context_after_s: float = 0.0,
    log: Log | None = None,
    turn_lookahead_s: float = 0.0,
) -> PairTags:
    """Cut the tags of one ego–guest pair to an event's window plus context.

    Args:
        tags: the log's tags.
        guest_id: the guest's track id.
        start_ns: first timestamp of the event.
        end_ns: last timestamp of the event (inclusive).
        context_before_s: seconds of context before ``start_ns``.
        context_after_s: seconds of context after ``end_ns``.
        log: the tagged log (same tracks and timestamps as ``tags``); when given, the pair also
            carries the guest's lateral offset in the ego's frame (``guest_left_m``) and the ego's
            heading change after the window (``ego_turn_after_rad``).
        turn_lookahead_s: seconds after the window over which ``ego_turn_after_rad`` is measured.

    Raises:
        KeyError: the guest is not in the log.
        ValueError: ``end_ns < start_ns`` or no log timestamp falls in the window.
    """
    if end_ns < start_ns:
        raise ValueError(f"log {tags.log_id}: event end {end_ns} is before its start {start_ns}")
    row = tags.track_index(guest_id)
    ts = tags.timestamps_ns
    lo = int(np.searchsorted(ts, start_ns - round(context_before_s * 1e9), side="left"))
    hi = int(np.searchsorted(ts, end_ns + round(context_after_s * 1e9), side="right"))
    if hi <= lo:
        raise ValueError(f"log {tags.log_id}: no timestamp between {start_ns} and {end_ns}")
    e = tags.ego_index
    rows = []
    for feature in PAIR_FEATURES:
        matrix = tags.codes(feature.family)
        rows.append(matrix[e if feature.actor is Actor.EGO else row, lo:hi])
    period = float(np.median(np.diff(ts))) * 1e-9 if ts.size >= 2 else 0.1
    return PairTags(
        log_id=tags.log_id,
        guest_id=guest_id,
        guest_category=str(tags.categories[row]),
        timestamps_ns=ts[lo:hi].copy(),
        codes=np.stack(rows).astype(np.int8),
        frame_period_s=period,
        event_start_ns=int(start_ns),
        event_end_ns=int(end_ns),
        guest_left_m=None if log is None else _guest_left_m(log, row, lo, hi),
        ego_turn_after_rad=None if log is None else _ego_turn_after_rad(log, hi - 1, turn_lookahead_s),
    )


def _ego_turn_after_rad(log: Log, last: int, lookahead_s: float) -> float:
    """Accumulated ego heading change from column ``last`` to ``lookahead_s`` later (radians)."""
    e = log.ego_index
    ts = log.timestamps_ns
    stop = int(np.searchsorted(ts, ts[last] + round(lookahead_s * 1e9), side="right"))
    yaw = log.yaw_rad[e, last:stop][log.valid[e, last:stop]]
    if yaw.size < 2:
        return 0.0
    return float(np.sum(wrap_angle(np.diff(yaw))))


def _guest_left_m(log: Log, row: int, lo: int, hi: int) -> FloatArray:
    """``(hi - lo,)`` lateral offset of track ``row`` in the ego's frame (NaN where unobserved)."""
    e = log.ego_index
    _, left = to_local(
        log.x_m[row, lo:hi] - log.x_m[e, lo:hi],
        log.y_m[row, lo:hi] - log.y_m[e, lo:hi],
        log.yaw_rad[e, lo:hi],
    )
    seen = log.valid[row, lo:hi] & log.valid[e, lo:hi]
    return np.where(seen, left, np.nan)


@dataclass(frozen=True, eq=False)
class RunLengths:
    """Run-length encoding of every row of a code matrix (runs ordered by row, then time).

    Attributes:
        row: ``(R,)`` row of each run.
        start: ``(R,)`` first column of each run.
        stop: ``(R,)`` one past the last column of each run.
        code: ``(R,)`` the run's code.
        run_of_cell: ``(F, W)`` index of the run each cell belongs to.
    """

    row: IntArray
    start: IntArray
    stop: IntArray
    code: CodeArray
    run_of_cell: IntArray


def run_lengths(codes: CodeArray) -> RunLengths:
    """Run-length encode each row of ``codes`` ``(F, W)`` (vectorised over all rows at once)."""
    f, w = codes.shape
    first = np.ones((f, w), dtype=bool)
    first[:, 1:] = codes[:, 1:] != codes[:, :-1]
    flat_first = first.ravel()
    starts_flat = np.flatnonzero(flat_first)
    stops_flat = np.append(starts_flat[1:], f * w)
    row = starts_flat // w
    # A run never crosses a row boundary because every row's first cell starts a run.
    return RunLengths(
        row=row,
        start=starts_flat - row * w,
        stop=stops_flat - row * w,
        code=codes.ravel()[starts_flat].astype(np.int8),
        run_of_cell=(np.cumsum(flat_first) - 1).reshape(f, w),
    )


@dataclass(frozen=True, eq=False)
class PairSegments:
    """Duration-based representation of a pair's tags (Fig. 4b).

    A *segment* is a maximal stretch of timestamps over which no tag changes.

    Attributes:
        pair: the (possibly flicker-merged) tags the segments were built from.
        start_s: ``(S,)`` segment start, seconds from the window start.
        duration_s: ``(S,)`` segment length, seconds.
        codes: ``(F, S)`` tag codes in each segment.
        changed: ``(F, S)`` True where a tag differs from the previous segment (all True in the first).
        value_duration_s: ``(F, S)`` how long the value a tag holds in that segment lasts from
            the segment's start (seconds) — across later segments where only other tags change.
    """

    pair: PairTags
    start_s: FloatArray
    duration_s: FloatArray
    codes: CodeArray
    changed: NDArray[np.bool_]
    value_duration_s: FloatArray

    @property
    def n_segments(self) -> int:
        """Number of segments ``S``."""
        return int(self.start_s.shape[0])

    def value(self, feature: int, segment: int) -> str | None:
        """Tag name of feature row ``feature`` in ``segment``; ``None`` where undefined."""
        enum_cls = TAG_FAMILIES[PAIR_FEATURES[feature].family]
        member = member_of(enum_cls, int(self.codes[feature, segment]))
        return None if member is None else member.value


def segment_pair(
    pair: PairTags, min_segment_s: float = 0.0, merged_families: Collection[str] = FLICKER_FAMILIES
) -> PairSegments:
    """Merge consecutive equal tags of a pair into duration segments.

    Args:
        pair: the pair's tags over the window.
        min_segment_s: values of the ``merged_families`` rows lasting less than this (seconds) are
            first absorbed by the preceding value of the same tag (the following one at the window
            start); undefined (absent) stretches are never changed. 0 keeps every change.
        merged_families: the interaction families whose short values are merged (default
            :data:`FLICKER_FAMILIES`); risk tags are left alone so a brief HIGH stays visible.

    Returns:
        The segments; their durations sum to :attr:`PairTags.duration_s`.
    """
    edges = pair.edges_s
    codes = pair.codes
    rows = [i for i, f in enumerate(PAIR_FEATURES) if f.actor is Actor.PAIR and f.family in merged_families]
    if min_segment_s > 0 and rows:
        codes = codes.copy()
        codes[rows] = suppress_short_runs(codes[rows], frames_for(min_segment_s, edges[:-1]))
        pair = dataclasses.replace(pair, codes=codes)
    w = codes.shape[1]
    seg_first = np.ones(w, dtype=bool)
    seg_first[1:] = np.any(codes[:, 1:] != codes[:, :-1], axis=0)
    seg_start = np.flatnonzero(seg_first)
    seg_stop = np.append(seg_start[1:], w)
    seg_codes = codes[:, seg_start]
    changed = np.ones(seg_codes.shape, dtype=bool)
    changed[:, 1:] = seg_codes[:, 1:] != seg_codes[:, :-1]
    runs = run_lengths(codes)
    run_at_seg = runs.run_of_cell[:, seg_start]  # (F, S): the run holding each segment's value
    value_left = edges[runs.stop[run_at_seg]] - edges[seg_start][None, :]
    return PairSegments(
        pair=pair,
        start_s=edges[seg_start],
        duration_s=edges[seg_stop] - edges[seg_start],
        codes=seg_codes,
        changed=changed,
        value_duration_s=value_left,
    )
