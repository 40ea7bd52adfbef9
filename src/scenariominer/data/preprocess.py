"""Preprocessing (braking paper, section III-A): gap interpolation, then Savitzky-Golay smoothing.

1. Inside each track's lifespan, missing timestamps are filled by linear interpolation
   (heading along the shorter arc) when the gap is at most ``max_gap_s``.
2. Positions (and, optionally, the unwrapped heading) are smoothed with a Savitzky-Golay
   filter; velocity and acceleration are the filter's first and second derivatives, so they
   are consistent with the smoothed path. Savitzky-Golay is chosen over splines because it
   keeps short, sharp events (a sudden brake) that spline fitting flattens.

Everything is vectorised over tracks: interpolation is a single pass over the ``(N, T)``
arrays, and smoothing is one matrix product per distinct span length (the filter, edge fit
included, is a cached linear operator), never a loop over frames.
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np
from numpy.typing import NDArray

from scenariominer.config import PreprocessConfig
from scenariominer.data.log import FloatArray, Log, time_derivative
from scenariominer.geometry import wrap_angle

_INTERPOLATED = ("x_m", "y_m", "z_m", "length_m", "width_m", "height_m")


def interpolate_gaps(log: Log, max_gap_s: float) -> tuple[Log, int]:
    """Fill gaps of at most ``max_gap_s`` inside each track's lifespan by linear interpolation.

    Returns:
        The filled log and the number of cells filled.
    """
    n, t = log.valid.shape
    if t < 3:
        return log, 0
    valid = log.valid
    cols = np.arange(t)
    prev_idx = np.maximum.accumulate(np.where(valid, cols, -1), axis=1)
    next_idx = np.minimum.accumulate(np.where(valid, cols, t)[:, ::-1], axis=1)[:, ::-1]
    inside = (~valid) & (prev_idx >= 0) & (next_idx < t)
    if not inside.any():
        return log, 0
    t_s = log.t_s
    pi = np.clip(prev_idx, 0, t - 1)
    ni = np.clip(next_idx, 0, t - 1)
    gap_s = t_s[ni] - t_s[pi]
    fill = inside & (gap_s <= max_gap_s + 1e-9)
    if not fill.any():
        return log, 0
    rows = np.nonzero(fill)[0]
    p, q = pi[fill], ni[fill]
    w = (t_s[np.nonzero(fill)[1]] - t_s[p]) / (t_s[q] - t_s[p])
    changes: dict[str, FloatArray | NDArray[np.bool_]] = {}
    for name in _INTERPOLATED:
        arr = getattr(log, name).copy()
        arr[fill] = arr[rows, p] * (1.0 - w) + arr[rows, q] * w
        changes[name] = arr
    yaw = log.yaw_rad.copy()
    dyaw = wrap_angle(yaw[rows, q] - yaw[rows, p])
    yaw[fill] = wrap_angle(yaw[rows, p] + dyaw * w)
    changes["yaw_rad"] = yaw
    new_valid = valid | fill
    changes["valid"] = new_valid
    # Kinematics of filled cells are recomputed by smoothing; mark them NaN meanwhile.
    for name in ("vx_mps", "vy_mps", "ax_mps2", "ay_mps2"):
        arr = getattr(log, name).copy()
        arr[fill] = np.nan
        changes[name] = arr
    return log.replace(**changes), int(fill.sum())


def window_samples(window_s: float, dt_s: float, length: int, polyorder: int) -> int:
    """Odd Savitzky-Golay window in samples for a span of ``length`` samples; 0 means no smoothing."""
    w = int(round(window_s / dt_s)) if dt_s > 0 else 0
    w = max(w, polyorder + 2)
    if w % 2 == 0:
        w += 1
    if w > length:
        w = length if length % 2 == 1 else length - 1
    return w if w > polyorder else 0


@lru_cache(maxsize=256)
def _sg_weights(
    window: int, order: int, deriv: int, delta_s: float
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Savitzky-Golay weights: interior ``(W,)``, left edge ``(W//2, W)``, right edge ``(W//2, W)``.

    A Savitzky-Golay value is the ``deriv``-th derivative, at one sample, of the least-squares
    polynomial of degree ``order`` through ``window`` samples, so every output is a fixed linear
    combination of the window's samples. Interior samples use the centred window; the first and
    last ``window // 2`` samples use the first and last full window evaluated off-centre (the
    polynomial edge fit of ``scipy.signal.savgol_filter(mode="interp")``, which tests compare
    against). Derivatives are per second for samples ``delta_s`` apart.
    """
    t = np.arange(window, dtype=np.float64)
    fit = np.linalg.pinv(np.vander(t, order + 1, increasing=True))  # (order+1, W): samples -> coefficients
    powers = np.arange(order + 1)
    # d^deriv/dt^deriv of t^k is k!/(k-deriv)! t^(k-deriv) for k >= deriv.
    falling = np.array([math.perm(int(k), deriv) if k >= deriv else 0 for k in powers], dtype=np.float64)
    exponents = np.clip(powers - deriv, 0, None)

    def at(points: FloatArray) -> FloatArray:
        basis = falling[None, :] * points[:, None] ** exponents[None, :]
        weights: FloatArray = basis @ fit / delta_s**deriv
        return weights

    half = window // 2
    centre = at(np.array([float(half)]))[0]
    return centre, at(t[:half]), at(t[window - half :])


def savgol_rows(block: FloatArray, window: int, order: int, deriv: int, delta_s: float) -> FloatArray:
    """Savitzky-Golay filter (or derivative) of each row of ``block`` ``(K, L)``, ``L >= window``.

    One vectorised pass: the interior through a sliding-window product, the edges through the
    fitted edge weights; no per-row or per-sample Python loop.
    """
    centre, left, right = _sg_weights(window, order, deriv, delta_s)
    half = window // 2
    out = np.empty_like(block, dtype=np.float64)
    out[:, half : block.shape[1] - half] = (
        np.lib.stride_tricks.sliding_window_view(block, window, axis=1) @ centre
    )
    out[:, :half] = block[:, :window] @ left.T
    out[:, block.shape[1] - half :] = block[:, -window:] @ right.T
    return out


def smooth(log: Log, cfg: PreprocessConfig) -> Log:
    """Savitzky-Golay smoothing of positions (and heading) with derived velocity/acceleration.

    Tracks too short for the configured window use the longest odd window that fits; spans too
    short for any window (fewer than ``polyorder + 1`` samples) keep their raw values and get
    finite-difference kinematics. All spans of equal length are filtered in one matrix product.
    """
    n, t = log.valid.shape
    t_s = log.t_s
    dt_s = float(np.median(np.diff(t_s))) if t > 1 else 0.0
    x, y = log.x_m.copy(), log.y_m.copy()
    yaw = log.yaw_rad.copy()
    vx, vy = np.full((n, t), np.nan), np.full((n, t), np.nan)
    ax, ay = np.full((n, t), np.nan), np.full((n, t), np.nan)

    # Observed spans (maximal runs of valid cells), vectorised over the whole (N, T) mask.
    padded = np.zeros((n, t + 2), dtype=bool)
    padded[:, 1:-1] = log.valid
    edges = np.diff(padded.astype(np.int8), axis=1)
    span_rows, span_start = np.nonzero(edges == 1)
    _, span_stop = np.nonzero(edges == -1)
    lengths = span_stop - span_start

    rough = np.zeros((n, t), dtype=bool)
    for length in np.unique(lengths):
        sel = lengths == length
        rows, starts = span_rows[sel], span_start[sel]
        w = window_samples(cfg.smooth_window_s, dt_s, int(length), cfg.smooth_polyorder)
        cols = starts[:, None] + np.arange(length)[None, :]
        rr = np.broadcast_to(rows[:, None], cols.shape)
        if w == 0:
            rough[rr, cols] = True
            continue
        order = min(cfg.smooth_polyorder, w - 1)
        for src, pos, vel, acc in ((log.x_m, x, vx, ax), (log.y_m, y, vy, ay)):
            block = src[rr, cols]
            pos[rr, cols] = savgol_rows(block, w, order, 0, dt_s)
            v = savgol_rows(block, w, order, 1, dt_s)
            vel[rr, cols] = v
            acc[rr, cols] = (
                savgol_rows(block, w, order, 2, dt_s) if order >= 2 else np.gradient(v, dt_s, axis=1)
            )
        if cfg.smooth_yaw:
            unwrapped = np.unwrap(log.yaw_rad[rr, cols], axis=1)
            yaw[rr, cols] = wrap_angle(savgol_rows(unwrapped, w, order, 0, dt_s))

    if rough.any():
        rows_all = np.flatnonzero(rough.any(axis=1))
        for src, vel, acc in ((log.x_m, vx, ax), (log.y_m, vy, ay)):
            masked = np.where(rough, src, np.nan)[rows_all]
            v = time_derivative(masked, t_s)
            a = time_derivative(v, t_s)
            vel[rows_all] = np.where(rough[rows_all], v, vel[rows_all])
            acc[rows_all] = np.where(rough[rows_all], a, acc[rows_all])

    invalid = ~log.valid
    for arr in (x, y, yaw, vx, vy, ax, ay):
        arr[invalid] = np.nan
    return log.replace(x_m=x, y_m=y, yaw_rad=yaw, vx_mps=vx, vy_mps=vy, ax_mps2=ax, ay_mps2=ay)


def preprocess(log: Log, cfg: PreprocessConfig | None = None) -> Log:
    """Interpolate gaps and smooth a log (section III-A of the braking paper).

    Args:
        log: a log as produced by an adapter.
        cfg: window, order and gap settings; defaults to :class:`PreprocessConfig`.

    Returns:
        A new log with filled gaps, smoothed ``x_m``, ``y_m`` (and ``yaw_rad``), and velocity
        and acceleration from the filter's derivatives. ``notes`` records what was filled.
    """
    cfg = cfg or PreprocessConfig()
    filled, n_filled = interpolate_gaps(log, cfg.max_gap_s)
    out = smooth(filled, cfg)
    notes = out.notes
    if n_filled:
        notes = (*notes, f"interpolated {n_filled} missing track-timestamp cell(s)")
    # A valid cell must have finite kinematics (a NaN could only come from a degenerate span).
    for name in ("vx_mps", "vy_mps", "ax_mps2", "ay_mps2"):
        arr = getattr(out, name)
        bad = out.valid & ~np.isfinite(arr)
        if bad.any():
            arr = arr.copy()
            arr[bad] = 0.0
            out = out.replace(**{name: arr})
    return out.replace(notes=notes)
