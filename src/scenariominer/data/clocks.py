"""Tracks on their own clocks: snap near-coincident timestamps onto one log clock, or refuse.

A :class:`~scenariominer.data.log.Log` is dense over the *union* of its tracks' timestamps. When
every track is stamped by its own clock (fleet data merged from several sensors, float seconds
rounded per row, a 1 µs offset per object), that union grows with the number of tracks: 200 tracks
of 100 frames offset by 1 µs from each other give 20,000 timestamps 1 µs apart instead of 100 frames
0.1 s apart, every track is then "missing" at 99.5 % of the timestamps, gap filling turns each into
20,000 cells, and smoothing works on a 1 µs frame period (minutes and gigabytes for a 2 MB file).

:func:`align_track_clocks` runs inside :func:`~scenariominer.data.log.build_log` on rows sorted by
(track, time) and does, all vectorised:

1. ``period``: the frame period of the fastest track (the smallest per-track median step);
2. *snap*: distinct timestamps closer than ``SNAP_FRACTION * period`` to their neighbour form a
   cluster; when every cluster is narrower than that and holds at most one row of each track, each
   row moves to its cluster's time (the ego's time where the ego has a row in it, else the earliest),
   with a note giving the largest shift;
3. *refuse*: when, after that, the log still has more than ``MAX_CLOCK_FACTOR`` times the timestamps
   the fastest track's period gives over the log's span, the clocks are too far apart to snap and
   the log is refused with the sizes and what to do.

Logs whose tracks share timestamps (Argoverse 2, highD, anything already on one clock) are unchanged.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

__all__ = ["MAX_CLOCK_FACTOR", "SNAP_FRACTION", "ClockAlignment", "align_track_clocks"]

#: Timestamps closer than this fraction of the frame period are taken as the same instant.
SNAP_FRACTION = 0.05
#: A log may have at most this many times the timestamps its fastest track's period needs.
MAX_CLOCK_FACTOR = 8.0


@dataclass(frozen=True)
class ClockAlignment:
    """Result of :func:`align_track_clocks`.

    Attributes:
        timestamps_ns: ``(M,)`` the rows' timestamps, snapped where a note says so.
        note: the stated repair, empty when nothing moved.
        problem: why the log must be refused, empty when it may be built.
    """

    timestamps_ns: NDArray[np.int64]
    note: str = ""
    problem: str = ""


def _per_track_median_step(steps: NDArray[np.int64], track_of_step: NDArray[np.int64]) -> NDArray[np.float64]:
    """Median of ``steps`` within each track (``track_of_step`` ascending), one value per track."""
    order = np.lexsort((steps, track_of_step))
    s, tr = steps[order], track_of_step[order]
    starts = np.flatnonzero(np.concatenate([[True], tr[1:] != tr[:-1]]))
    counts = np.diff(np.append(starts, s.size))
    lo = starts + (counts - 1) // 2
    hi = starts + counts // 2
    return np.asarray(0.5 * (s[lo].astype(np.float64) + s[hi].astype(np.float64)), dtype=np.float64)


def _nothing_to_do(uniq: NDArray[np.int64], period_bound: float) -> bool:
    """Whether the log can neither be snapped nor refused, from an upper bound on the frame period.

    The frame period (the smallest per-track median step) is at most any one track's median step,
    e.g. the ego's; so when no two distinct timestamps ``uniq`` ``(U,)`` are within the snapping
    tolerance of that bound, and their number fits the limit that the bound allows, the exact
    period cannot change the outcome and its per-track sort is skipped (the usual case: every
    track on one clock).
    """
    if period_bound <= 0 or uniq.size < 2:
        return False
    if float(np.diff(uniq).min()) <= SNAP_FRACTION * period_bound:
        return False
    span = float(uniq[-1] - uniq[0])
    return bool(uniq.size <= MAX_CLOCK_FACTOR * (span / period_bound + 1.0))


def align_track_clocks(
    timestamps_ns: NDArray[np.int64], track_start: NDArray[np.bool_], is_ego: NDArray[np.bool_]
) -> ClockAlignment:
    """Snap tracks on their own clocks onto one clock, or say why the log cannot be built.

    Args:
        timestamps_ns: ``(M,)`` row timestamps, rows sorted by (track, time), no (track, time) twice.
        track_start: ``(M,)`` True at the first row of each track.
        is_ego: ``(M,)`` True at the ego's rows.

    Returns:
        The (possibly snapped) timestamps with a note, or a problem to refuse the log with.
    """
    ts = np.asarray(timestamps_ns, dtype=np.int64)
    uniq = np.unique(ts)
    same_track = ~track_start[1:]
    if uniq.size < 2 or not same_track.any():
        return ClockAlignment(ts)
    steps = np.diff(ts)[same_track]
    track_of_step = (np.cumsum(track_start) - 1)[1:][same_track]
    period = float(_per_track_median_step(steps, track_of_step).min())
    if period <= 0:
        return ClockAlignment(ts)
    tol = SNAP_FRACTION * period
    note = ""
    gaps = np.diff(uniq)
    if np.any(gaps <= tol):
        new_cluster = np.concatenate([[True], gaps > tol])
        cluster_of_uniq = np.cumsum(new_cluster) - 1
        first = uniq[new_cluster]
        last = uniq[np.concatenate([new_cluster[1:], [True]])]
        row_cluster = cluster_of_uniq[np.searchsorted(uniq, ts)]
        twice = same_track & (row_cluster[1:] == row_cluster[:-1])
        if float((last - first).max()) <= tol and not twice.any():
            target = first.copy()
            target[row_cluster[is_ego]] = ts[is_ego]
            snapped = target[row_cluster]
            shift = np.abs(snapped - ts)
            moved = shift > 0
            n_tracks = int(np.unique(np.cumsum(track_start)[moved]).size)
            note = (
                f"snapped {int(moved.sum())} timestamp(s) of {n_tracks} track(s) on their own clocks "
                f"(shifts up to {float(shift.max()) / 1e3:g} µs) to one clock of {first.size} timestamps "
                f"(frame period {period / 1e6:g} ms)"
            )
            ts, uniq = snapped, first
    span = float(uniq[-1] - uniq[0])
    needed = span / period + 1.0
    if uniq.size > MAX_CLOCK_FACTOR * needed:
        return ClockAlignment(
            ts,
            problem=(
                f"the tracks are on different clocks: {uniq.size} distinct timestamps where the fastest "
                f"track's frame period ({period / 1e6:g} ms) needs {needed:.0f} over the log's "
                f"{span / 1e9:g} s, and they are too far apart (over {tol / 1e6:g} ms) to snap to one "
                "clock; resample the tracks onto a common clock before ingesting"
            ),
        )
    return ClockAlignment(ts, note=note)
