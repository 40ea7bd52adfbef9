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

    Spans (maximal runs of valid cells) at least one full window long, nearly all of them, are
    filtered together over the whole ``(N, T)`` array: one sliding-window product for every
    interior cell and one product per span edge for the edge fits. Shorter spans use the longest
    odd window that fits, one matrix product per distinct length; spans too short for any window
    (fewer than ``polyorder + 1`` samples) keep their raw values and get finite-difference
    kinematics.
    """
    n, t = log.valid.shape
    t_s = log.t_s
    dt_s = float(np.median(np.diff(t_s))) if t > 1 else 0.0
    out = _Smoothed(log)

    padded = np.zeros((n, t + 2), dtype=bool)
    padded[:, 1:-1] = log.valid
    edges = np.diff(padded.astype(np.int8), axis=1)
    span_rows, span_start = np.nonzero(edges == 1)
    _, span_stop = np.nonzero(edges == -1)
    lengths = span_stop - span_start

    full = window_samples(cfg.smooth_window_s, dt_s, t, cfg.smooth_polyorder)
    long_spans = lengths >= full if full else np.zeros(lengths.shape, dtype=bool)
    if long_spans.any():
        _smooth_full_window(log, out, cfg, dt_s, full, span_rows[long_spans], span_start[long_spans],
                            span_stop[long_spans])  # fmt: skip
    rough = np.zeros((n, t), dtype=bool)
    short = ~long_spans
    for length in np.unique(lengths[short]):
        sel = short & (lengths == length)
        rows, starts = span_rows[sel], span_start[sel]
        cols = starts[:, None] + np.arange(length)[None, :]
        rr = np.broadcast_to(rows[:, None], cols.shape)
        w = window_samples(cfg.smooth_window_s, dt_s, int(length), cfg.smooth_polyorder)
        if w == 0:
            rough[rr, cols] = True
            continue
        _smooth_block(log, out, cfg, dt_s, w, rr, cols)

    if rough.any():
        rows_all = np.flatnonzero(rough.any(axis=1))
        for src, vel, acc in ((log.x_m, out.vx, out.ax), (log.y_m, out.vy, out.ay)):
            masked = np.where(rough, src, np.nan)[rows_all]
            v = time_derivative(masked, t_s)
            a = time_derivative(v, t_s)
            vel[rows_all] = np.where(rough[rows_all], v, vel[rows_all])
            acc[rows_all] = np.where(rough[rows_all], a, acc[rows_all])
    return out.to_log(log)


class _Smoothed:
    """The output arrays of :func:`smooth`, ``(N, T)`` each, filled span by span."""

    def __init__(self, log: Log) -> None:
        n, t = log.valid.shape
        self.x, self.y, self.yaw = log.x_m.copy(), log.y_m.copy(), log.yaw_rad.copy()
        self.vx, self.vy = np.full((n, t), np.nan), np.full((n, t), np.nan)
        self.ax, self.ay = np.full((n, t), np.nan), np.full((n, t), np.nan)

    def to_log(self, log: Log) -> Log:
        arrays = (self.x, self.y, self.yaw, self.vx, self.vy, self.ax, self.ay)
        invalid = ~log.valid
        for arr in arrays:
            arr[invalid] = np.nan
        names = ("x_m", "y_m", "yaw_rad", "vx_mps", "vy_mps", "ax_mps2", "ay_mps2")
        return log.replace(**dict(zip(names, arrays, strict=True)))


def _smooth_block(
    log: Log, out: _Smoothed, cfg: PreprocessConfig, dt_s: float, w: int, rr: NDArray[np.intp],
    cols: NDArray[np.intp],
) -> None:  # fmt: skip
    """Filter spans of one length, gathered as ``(K, L)`` row/column indices, with window ``w``."""
    order = min(cfg.smooth_polyorder, w - 1)
    for src, pos, vel, acc in ((log.x_m, out.x, out.vx, out.ax), (log.y_m, out.y, out.vy, out.ay)):
        block = src[rr, cols]
        pos[rr, cols] = savgol_rows(block, w, order, 0, dt_s)
        v = savgol_rows(block, w, order, 1, dt_s)
        vel[rr, cols] = v
        acc[rr, cols] = savgol_rows(block, w, order, 2, dt_s) if order >= 2 else np.gradient(v, dt_s, axis=1)
    if cfg.smooth_yaw:
        unwrapped = np.unwrap(log.yaw_rad[rr, cols], axis=1)
        out.yaw[rr, cols] = wrap_angle(savgol_rows(unwrapped, w, order, 0, dt_s))


def _smooth_full_window(
    log: Log, out: _Smoothed, cfg: PreprocessConfig, dt_s: float, w: int, rows: NDArray[np.intp],
    starts: NDArray[np.intp], stops: NDArray[np.intp],
) -> None:  # fmt: skip
    """Filter every span of at least ``w`` samples (``rows``, ``starts``, ``stops``: ``(S,)``) at once.

    Interior cells come from one sliding-window product over the rows that hold such spans (a
    window centred on an interior cell lies inside its span, so the values outside spans never
    enter); the first and last ``w // 2`` cells of each span from the edge weights applied to
    the span's first and last ``w`` samples.
    """
    order = min(cfg.smooth_polyorder, w - 1)
    half = w // 2
    t = log.valid.shape[1]
    owners, local = np.unique(rows, return_inverse=True)  # the rows holding long spans
    interior = np.zeros((owners.size, t + 1), dtype=np.int8)
    np.add.at(interior, (local, starts + half), 1)
    np.add.at(interior, (local, stops - half), -1)
    inner = np.cumsum(interior[:, :t], axis=1) > 0
    head = starts[:, None] + np.arange(w)[None, :]  # (S, w) first window of each span
    tail = stops[:, None] - w + np.arange(w)[None, :]  # (S, w) last window
    head_cells = starts[:, None] + np.arange(half)[None, :]
    tail_cells = stops[:, None] - half + np.arange(half)[None, :]

    def apply(values: FloatArray, deriv: int) -> FloatArray:
        """The filtered ``(R, T)`` values of the owner rows (garbage outside the long spans)."""
        centre, left, right = _sg_weights(w, order, deriv, dt_s)
        result = np.zeros_like(values)
        result[:, half : t - half] = np.lib.stride_tricks.sliding_window_view(values, w, axis=1) @ centre
        full_rows = values[local]
        result[local[:, None], head_cells] = np.take_along_axis(full_rows, head, axis=1) @ left.T
        result[local[:, None], tail_cells] = np.take_along_axis(full_rows, tail, axis=1) @ right.T
        return result

    span_mask = inner.copy()
    span_mask[local[:, None], head_cells] = True
    span_mask[local[:, None], tail_cells] = True
    targets = [(log.x_m, out.x, out.vx, out.ax), (log.y_m, out.y, out.vy, out.ay)]
    for src, pos, vel, acc in targets:
        values = np.nan_to_num(src[owners], nan=0.0, posinf=0.0, neginf=0.0)
        _put(pos, owners, span_mask, apply(values, 0))
        _put(vel, owners, span_mask, apply(values, 1))
        if order >= 2:
            _put(acc, owners, span_mask, apply(values, 2))
        else:  # a first-order fit has no second derivative: difference the velocity within each span
            v = apply(values, 1)
            a = np.gradient(v, dt_s, axis=1)
            last = stops - 1
            a[local, starts] = (v[local, starts + 1] - v[local, starts]) / dt_s
            a[local, last] = (v[local, last] - v[local, last - 1]) / dt_s
            _put(acc, owners, span_mask, a)
    if cfg.smooth_yaw:
        _put(out.yaw, owners, span_mask, wrap_angle(apply(_unwrap_rows(log.yaw_rad[owners]), 0)))


def _unwrap_rows(yaw_rad: FloatArray) -> FloatArray:
    """Unwrap each row's heading across its valid cells (NaN cells repeat the last valid value).

    Within a run of valid cells the result differs from ``np.unwrap`` of that run alone by a
    whole number of turns, which the caller's final wrap removes.
    """
    valid = np.isfinite(yaw_rad)
    last = np.where(valid, np.arange(yaw_rad.shape[1])[None, :], 0)
    np.maximum.accumulate(last, axis=1, out=last)
    filled = np.take_along_axis(np.where(valid, yaw_rad, 0.0), last, axis=1)
    unwrapped: FloatArray = np.unwrap(filled, axis=1)
    return unwrapped


def _put(target: FloatArray, owners: NDArray[np.intp], mask: NDArray[np.bool_], values: FloatArray) -> None:
    """``target[owners][mask] = values[mask]`` written through to ``target``."""
    block = target[owners]
    block[mask] = values[mask]
    target[owners] = block


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
