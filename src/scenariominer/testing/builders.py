"""Builders of hand-made logs with known answers (for tests of this package and of users' code).

A :class:`LogBuilder` places the ego and other road users on paths integrated exactly from a speed
and yaw-rate profile (sub-stepped trapezoids), then builds a canonical :class:`~scenariominer.data.log.Log`
through the validated :func:`~scenariominer.data.log.build_log`, optionally preprocessed like real
data. Positions are box centres in metres, headings radians, time seconds from 0.

Example:
    >>> t = times(8.0)
    >>> log = (
    ...     LogBuilder(t)
    ...     .ego(speed_mps=braking_speed(t, 10.0, brake_at_s=4.0, decel_mps2=5.0))
    ...     .add("lead", "REGULAR_VEHICLE", speed_mps=braking_speed(t, 10.0, 3.0, 6.0), x0_m=20.0)
    ...     .build()
    ... )
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from scenariominer.data.categories import EGO_CATEGORY
from scenariominer.data.log import Log, build_log
from scenariominer.geometry import wrap_angle

__all__ = ["BuiltTrack", "LogBuilder", "braking_speed", "integrate", "times"]

FloatArray = NDArray[np.float64]


def times(duration_s: float, dt_s: float = 0.1) -> FloatArray:
    """``(T,)`` sample times ``0, dt, ..., duration`` in seconds."""
    return np.arange(int(round(duration_s / dt_s)) + 1, dtype=np.float64) * dt_s


def braking_speed(t_s: ArrayLike, v0_mps: float, brake_at_s: float, decel_mps2: float) -> FloatArray:
    """Constant speed, then constant deceleration from ``brake_at_s`` down to standstill (m/s)."""
    t = np.asarray(t_s, dtype=np.float64)
    return np.maximum(v0_mps - decel_mps2 * np.clip(t - brake_at_s, 0.0, None), 0.0)


def integrate(
    t_s: ArrayLike,
    speed_mps: ArrayLike,
    yaw_rate_radps: ArrayLike = 0.0,
    x0_m: float = 0.0,
    y0_m: float = 0.0,
    yaw0_rad: float = 0.0,
    substeps: int = 50,
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Position and heading ``(T,)`` of a point moving along its heading (negative speed: backwards).

    Speed and yaw rate are linear between samples; ``substeps`` trapezoids per sample interval.
    """
    t = np.asarray(t_s, dtype=np.float64)
    speed = np.broadcast_to(np.asarray(speed_mps, dtype=np.float64), t.shape)
    rate = np.broadcast_to(np.asarray(yaw_rate_radps, dtype=np.float64), t.shape)
    if t.size < 2:
        return np.full(t.shape, x0_m), np.full(t.shape, y0_m), np.full(t.shape, float(wrap_angle(yaw0_rad)))
    fine = np.linspace(t[0], t[-1], (t.size - 1) * substeps + 1)
    v = np.interp(fine, t, speed)
    w = np.interp(fine, t, rate)
    h = np.diff(fine)
    yaw = yaw0_rad + np.concatenate([[0.0], np.cumsum(0.5 * (w[1:] + w[:-1]) * h)])
    vx, vy = v * np.cos(yaw), v * np.sin(yaw)
    x = x0_m + np.concatenate([[0.0], np.cumsum(0.5 * (vx[1:] + vx[:-1]) * h)])
    y = y0_m + np.concatenate([[0.0], np.cumsum(0.5 * (vy[1:] + vy[:-1]) * h)])
    return x[::substeps], y[::substeps], wrap_angle(yaw[::substeps])


@dataclass(frozen=True)
class BuiltTrack:
    """A track sampled at the builder's times; ``present`` selects the observed samples."""

    track_id: str
    category: str
    x_m: FloatArray
    y_m: FloatArray
    yaw_rad: FloatArray
    length_m: float
    width_m: float
    present: NDArray[np.bool_]


class LogBuilder:
    """Collects tracks over common sample times ``t_s`` and builds a :class:`Log` (ego first).

    Args:
        t_s: ``(T,)`` sample times, seconds (see :func:`times`).
        log_id: the log's id.
        dataset: the log's dataset name.
    """

    def __init__(self, t_s: ArrayLike, *, log_id: str = "built", dataset: str = "synthetic") -> None:
        self.t_s = np.asarray(t_s, dtype=np.float64)
        self.log_id = log_id
        self.dataset = dataset
        self._tracks: list[BuiltTrack] = []

    def ego(
        self,
        *,
        speed_mps: ArrayLike = 0.0,
        yaw_rate_radps: ArrayLike = 0.0,
        x0_m: float = 0.0,
        y0_m: float = 0.0,
        yaw0_rad: float = 0.0,
        length_m: float = 4.877,
        width_m: float = 2.0,
    ) -> LogBuilder:
        """Add the ego, track id ``"ego"`` (must come first); arguments as for :meth:`add`."""
        if self._tracks:
            raise ValueError("the ego must be the first track added")
        return self.add(
            "ego",
            EGO_CATEGORY,
            speed_mps=speed_mps,
            yaw_rate_radps=yaw_rate_radps,
            x0_m=x0_m,
            y0_m=y0_m,
            yaw0_rad=yaw0_rad,
            length_m=length_m,
            width_m=width_m,
        )

    def add(
        self,
        track_id: str,
        category: str,
        *,
        speed_mps: ArrayLike = 0.0,
        yaw_rate_radps: ArrayLike = 0.0,
        x0_m: float = 0.0,
        y0_m: float = 0.0,
        yaw0_rad: float = 0.0,
        length_m: float = 4.5,
        width_m: float = 2.0,
        present: ArrayLike | None = None,
    ) -> LogBuilder:
        """Add a road user moving from ``(x0_m, y0_m)`` at heading ``yaw0_rad`` with these profiles.

        ``present`` (``(T,)`` bool) marks the observed samples (default: all).
        """
        x, y, yaw = integrate(self.t_s, speed_mps, yaw_rate_radps, x0_m, y0_m, yaw0_rad)
        return self.add_path(
            track_id, category, x, y, yaw, length_m=length_m, width_m=width_m, present=present
        )

    def add_path(
        self,
        track_id: str,
        category: str,
        x_m: ArrayLike,
        y_m: ArrayLike,
        yaw_rad: ArrayLike,
        *,
        length_m: float = 4.5,
        width_m: float = 2.0,
        present: ArrayLike | None = None,
    ) -> LogBuilder:
        """Add a road user from sampled ``(T,)`` positions and headings."""
        n = self.t_s.size
        keep = np.ones(n, dtype=bool) if present is None else np.asarray(present, dtype=bool)
        x, y, yaw = (np.broadcast_to(np.asarray(a, dtype=np.float64), (n,)) for a in (x_m, y_m, yaw_rad))
        self._tracks.append(BuiltTrack(track_id, category, x, y, yaw, length_m, width_m, keep))
        return self

    def build(self, *, smooth: bool = False) -> Log:
        """The log (ego first); ``smooth=True`` preprocesses it like ingested data."""
        if not self._tracks or self._tracks[0].category != EGO_CATEGORY:
            raise ValueError("add the ego first (LogBuilder.ego)")
        tid: list[str] = []
        cat: list[str] = []
        ts: list[NDArray[np.int64]] = []
        cols: dict[str, list[FloatArray]] = {k: [] for k in ("x_m", "y_m", "yaw_rad", "length_m", "width_m")}
        for tr in self._tracks:
            k = int(tr.present.sum())
            tid += [tr.track_id] * k
            cat += [tr.category] * k
            ts.append(np.round(self.t_s[tr.present] * 1e9).astype(np.int64))
            cols["x_m"].append(tr.x_m[tr.present])
            cols["y_m"].append(tr.y_m[tr.present])
            cols["yaw_rad"].append(tr.yaw_rad[tr.present])
            cols["length_m"].append(np.full(k, tr.length_m))
            cols["width_m"].append(np.full(k, tr.width_m))
        log = build_log(
            log_id=self.log_id,
            track_id=tid,
            category=cat,
            timestamp_ns=np.concatenate(ts),
            fields={k: np.concatenate(v) for k, v in cols.items()},
            ego_track_id=self._tracks[0].track_id,
            source="<LogBuilder>",
            dataset=self.dataset,
        )
        if smooth:
            from scenariominer.data.preprocess import preprocess

            return preprocess(log)
        return log
