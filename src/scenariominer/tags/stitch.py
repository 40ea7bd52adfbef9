"""Repair of tracker noise before tagging: id switches, ghost detections, dropped frames.

Tags are computed per track, so a tracker that gives the key object a new id half-way through
its approach splits its history in two (neither half may hold enough frames for a turning or
overlap tag), and a ghost detection (a box that lives a few frames) can become a key object.
:func:`stitch_tracks` cleans a preprocessed :class:`~scenariominer.data.log.Log`:

1. **Id switches**: a track ``i`` that ends and a track ``j`` of the same category that starts
   after it, within ``max_gap_s``, are one object when ``j``'s first box lies within
   ``max_position_error_m + position_error_per_s_m × gap`` of ``i``'s last box extrapolated over the
   gap at ``i``'s velocity (its mean over ``i``'s last five frames), their speeds (``j``: over its
   first five) differ by at most ``max_speed_change_mps`` and their
   lengths and widths by at most ``max_size_change_m``. Every feasible ``(ending, starting)``
   pair is scored by its position error (plus the speed difference, m/s counted as metres) and
   the pairs are matched one to one by :func:`scipy.optimize.linear_sum_assignment`; chains
   (``i → j → k``) merge into the earliest track, whose id the object keeps (the others become its
   *aliases*).
2. **Dropped frames**: gaps of a merged track up to ``fill_gap_s`` are filled by linear
   interpolation of every state field (heading along the shorter arc); gaps inside a single track
   were already filled by preprocessing.
3. **Ghosts**: a track observed in at most ``ghost_max_frames`` frames that was not stitched, or
   whose median speed exceeds ``ghost_max_speed_mps``, is dropped.

The ego is never changed. Every repair is listed in :attr:`StitchResult.notes`.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from scenariominer.config.tags import StitchConfig
from scenariominer.data.log import STATE_FIELDS, FloatArray, Log
from scenariominer.geometry import wrap_angle

__all__ = ["ALIAS_NOTE_PREFIX", "StitchResult", "aliases_from_notes", "match_switches", "stitch_tracks"]

#: An event's note listing the other ids of its guest starts with this (then comma-separated ids).
ALIAS_NOTE_PREFIX = "same object as track(s) "

#: Cost of an infeasible pair in the assignment (larger than any feasible cost).
_INFEASIBLE = 1e9
#: A track's velocity at its end (start) is its mean velocity over its last (first) this many frames.
_END_FRAMES = 5


@dataclass(frozen=True, eq=False)
class StitchResult:
    """A cleaned log and what was done to it.

    Attributes:
        log: the cleaned log (merged tracks keep the earliest id; ghosts removed).
        aliases: ``kept track id → ids merged into it`` (in time order), for stitched objects only.
        ghosts: ids of the tracks dropped as ghost detections.
        n_filled: cells filled inside stitched tracks.
        notes: one line per kind of repair (empty when nothing was changed).
    """

    log: Log
    aliases: dict[str, tuple[str, ...]] = field(default_factory=dict)
    ghosts: tuple[str, ...] = ()
    n_filled: int = 0
    notes: tuple[str, ...] = ()


def _span(valid: NDArray[np.bool_]) -> tuple[NDArray[np.intp], NDArray[np.intp], NDArray[np.bool_]]:
    """First and last observed column of every row, and whether the row is observed at all."""
    any_valid = np.asarray(valid.any(axis=1), dtype=bool)
    first = np.asarray(np.argmax(valid, axis=1), dtype=np.intp)
    last = np.asarray(valid.shape[1] - 1 - np.argmax(valid[:, ::-1], axis=1), dtype=np.intp)
    return first, last, any_valid


def match_switches(log: Log, cfg: StitchConfig) -> list[tuple[int, int]]:
    """Pairs ``(ending row, starting row)`` that are one object whose id switched (step 1).

    Args:
        log: a preprocessed log.
        cfg: the gates.

    Returns:
        Matched row pairs, one to one, ordered by the ending row.
    """
    from scipy.optimize import linear_sum_assignment

    n = log.n_tracks
    if n < 3:
        return []
    first, last, seen = _span(log.valid)
    rows = np.arange(n)
    t_s = log.t_s
    e_x, e_y = log.x_m[rows, last], log.y_m[rows, last]
    s_x, s_y = log.x_m[rows, first], log.y_m[rows, first]
    # Velocities at a track's ends as mean velocities over its last / first frames: the smoothed
    # velocity of an end sample is an extrapolating edge fit, unreliable on noisy boxes.
    before = np.maximum(first, last - _END_FRAMES)
    after = np.minimum(last, first + _END_FRAMES)
    with np.errstate(invalid="ignore", divide="ignore"):
        dt_end = np.where(last > before, t_s[last] - t_s[before], np.inf)
        dt_start = np.where(after > first, t_s[after] - t_s[first], np.inf)
        e_vx = np.nan_to_num((e_x - log.x_m[rows, before]) / dt_end)
        e_vy = np.nan_to_num((e_y - log.y_m[rows, before]) / dt_end)
        s_vx = np.nan_to_num((log.x_m[rows, after] - s_x) / dt_start)
        s_vy = np.nan_to_num((log.y_m[rows, after] - s_y) / dt_start)
    gap = t_s[first][None, :] - t_s[last][:, None]  # (ending i, starting j)
    pred_x = e_x[:, None] + e_vx[:, None] * gap
    pred_y = e_y[:, None] + e_vy[:, None] * gap
    error = np.hypot(pred_x - s_x[None, :], pred_y - s_y[None, :])
    dv = np.abs(np.hypot(e_vx, e_vy)[:, None] - np.hypot(s_vx, s_vy)[None, :])
    d_len = np.abs(log.length_m[rows, last][:, None] - log.length_m[rows, first][None, :])
    d_wid = np.abs(log.width_m[rows, last][:, None] - log.width_m[rows, first][None, :])
    with np.errstate(invalid="ignore"):
        ok = (
            (gap > 0)
            & (gap <= cfg.max_gap_s + 1e-9)
            & (log.categories[:, None] == log.categories[None, :])
            & (error <= cfg.max_position_error_m + cfg.position_error_per_s_m * gap)
            & (dv <= cfg.max_speed_change_mps)
            & (d_len <= cfg.max_size_change_m)
            & (d_wid <= cfg.max_size_change_m)
        )
    ok &= seen[:, None] & seen[None, :]
    ok[log.ego_index, :] = False
    ok[:, log.ego_index] = False
    if not ok.any():
        return []
    cost = np.where(ok, error + dv, _INFEASIBLE)
    ends, starts = linear_sum_assignment(cost)
    keep = ok[ends, starts]
    return sorted(zip(ends[keep].tolist(), starts[keep].tolist(), strict=True))


def _chains(pairs: list[tuple[int, int]]) -> list[list[int]]:
    """Chains ``[i, j, k, ...]`` of rows linked by matched pairs (each row links at most once each way)."""
    nxt = dict(pairs)
    has_prev = {j for _, j in pairs}
    chains = []
    for i, _ in pairs:
        if i in has_prev:
            continue
        chain = [i]
        while chain[-1] in nxt:
            chain.append(nxt[chain[-1]])
        chains.append(chain)
    return chains


def _fill_rows(
    arrays: dict[str, FloatArray],
    valid: NDArray[np.bool_],
    t_s: FloatArray,
    rows: NDArray[np.intp],
    max_gap_s: float,
) -> int:
    """Linearly fill gaps up to ``max_gap_s`` inside the lifespan of ``rows``, in place; cells filled."""
    sub = valid[rows]
    t = sub.shape[1]
    cols = np.arange(t)
    prev_idx = np.maximum.accumulate(np.where(sub, cols, -1), axis=1)
    next_idx = np.minimum.accumulate(np.where(sub, cols, t)[:, ::-1], axis=1)[:, ::-1]
    inside = (~sub) & (prev_idx >= 0) & (next_idx < t)
    p, q = np.clip(prev_idx, 0, t - 1), np.clip(next_idx, 0, t - 1)
    fill = inside & (t_s[q] - t_s[p] <= max_gap_s + 1e-9)
    if not fill.any():
        return 0
    r_local, c = np.nonzero(fill)
    r = rows[r_local]
    p, q = p[fill], q[fill]
    w = (t_s[c] - t_s[p]) / (t_s[q] - t_s[p])
    for name, arr in arrays.items():
        if name == "yaw_rad":
            arr[r, c] = wrap_angle(arr[r, p] + wrap_angle(arr[r, q] - arr[r, p]) * w)
        else:
            arr[r, c] = arr[r, p] * (1.0 - w) + arr[r, q] * w
    valid[r, c] = True
    return int(fill.sum())


def stitch_tracks(log: Log, cfg: StitchConfig | None = None) -> StitchResult:
    """Merge id-switched tracks, fill their gaps and drop ghost detections (see the module docstring).

    Args:
        log: a preprocessed log.
        cfg: gates and thresholds (default :class:`StitchConfig`).

    Returns:
        The cleaned log (unchanged, same object, when ``cfg.enabled`` is False or nothing applies).
    """
    cfg = cfg or StitchConfig()
    if not cfg.enabled:
        return StitchResult(log)
    chains = _chains(match_switches(log, cfg))
    valid = log.valid.copy()
    arrays = {name: getattr(log, name).copy() for name in STATE_FIELDS}
    merged = np.zeros(log.n_tracks, dtype=bool)
    aliases: dict[str, tuple[str, ...]] = {}
    for chain in chains:  # one iteration per stitched object
        root, rest = chain[0], np.asarray(chain[1:])
        for arr in arrays.values():
            take = valid[rest]
            cells = np.nonzero(take)
            arr[root, cells[1]] = arr[rest[cells[0]], cells[1]]
        valid[root] |= valid[rest].any(axis=0)
        merged[rest] = True
        aliases[str(log.track_ids[root])] = tuple(str(log.track_ids[i]) for i in rest)
    roots = np.asarray([c[0] for c in chains], dtype=np.intp)
    n_filled = _fill_rows(arrays, valid, log.t_s, roots, cfg.fill_gap_s) if roots.size else 0

    n_frames = valid.sum(axis=1)
    speed = np.hypot(arrays["vx_mps"], arrays["vy_mps"])
    with np.errstate(all="ignore"):
        median_speed = np.nanmedian(np.where(valid, speed, np.nan), axis=1)
    stitched = np.zeros(log.n_tracks, dtype=bool)
    stitched[roots] = True
    ghost = ((n_frames <= cfg.ghost_max_frames) & ~stitched) | (
        np.nan_to_num(median_speed) > cfg.ghost_max_speed_mps
    )
    ghost[log.ego_index] = False
    ghost &= ~merged
    if not chains and not ghost.any():
        return StitchResult(log)
    for arr in arrays.values():
        arr[~valid] = np.nan
    keep = ~(merged | ghost)
    notes = []
    if chains:
        notes.append(
            f"stitched {len(chains)} object(s) whose track id switched "
            f"(e.g. {'; '.join(f'{k} <- {chr(44).join(v)}' for k, v in list(aliases.items())[:2])})"
        )
    if n_filled:
        notes.append(f"interpolated {n_filled} dropped frame(s) of stitched tracks")
    ghost_ids = tuple(str(i) for i in log.track_ids[ghost])
    if ghost_ids:
        notes.append(f"dropped {len(ghost_ids)} ghost detection(s) (e.g. {list(ghost_ids[:3])})")
    cleaned = log.replace(valid=valid, notes=(*log.notes, *notes), **arrays).select_tracks(keep)
    return StitchResult(cleaned, aliases, ghost_ids, n_filled, tuple(notes))


def aliases_from_notes(notes: str) -> tuple[str, ...]:
    """The alias ids an event's ``; ``-joined notes list after :data:`ALIAS_NOTE_PREFIX` (none: ``()``)."""
    for note in notes.split("; "):
        if note.startswith(ALIAS_NOTE_PREFIX):
            return tuple(i for i in note[len(ALIAS_NOTE_PREFIX) :].split(",") if i)
    return ()
