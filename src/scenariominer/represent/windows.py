"""Trajectory windows: one chosen agent and its K nearest road users over a fixed time span.

A window of length ``L`` seconds starting at ``t0`` holds, for the chosen agent (row 0) and its
``K`` nearest surrounding road users (rows ``1..K``, nearest first by mean distance over the
window), their box centres resampled at ``S`` evenly spaced times from ``t0`` to ``t0 + L``,
expressed in the chosen agent's frame at ``t0`` (x forward, y left, origin at its box centre;
:func:`scenariominer.geometry.to_local`). Missing neighbours and samples where a road user is not
observed are zero and masked. Windows of one agent follow each other with a configurable overlap;
several lengths give multi-scale windows (a 5 s cut-in, a 45 s stop-and-go wave).

Everything is vectorised over tracks x windows x steps: all tracks of a log share one clock, so one
``searchsorted`` gives the interpolation weights of every track at once.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, fields

import numpy as np
from numpy.typing import NDArray

from scenariominer.config.represent import WindowConfig
from scenariominer.data.categories import CATEGORY_GROUPS
from scenariominer.data.log import Log
from scenariominer.geometry import to_local
from scenariominer.represent.errors import WindowConfigMismatchError

__all__ = ["ROAD_USER_CATEGORIES", "WindowSet", "extract_agent_window", "extract_windows", "window_id"]

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]
BoolArray = NDArray[np.bool_]

#: Categories that count as surrounding agents (static objects such as cones do not).
ROAD_USER_CATEGORIES: frozenset[str] = CATEGORY_GROUPS["VEHICLE"] | CATEGORY_GROUPS["VULNERABLE_ROAD_USER"]
#: Bound on ``pairs x tracks x steps`` distances computed at once while choosing neighbours.
_MAX_DISTANCE_CELLS = 4_000_000


def window_id(log_id: str, track_id: str, start_s: float, length_s: float) -> str:
    """Stable id of a window: ``<log>|<track>|<start ms since log start>|<length ms>``."""
    return f"{log_id}|{track_id}|{round(start_s * 1000)}|{round(length_s * 1000)}"


@dataclass(frozen=True, eq=False)
class WindowSet:
    """``W`` windows of ``A = 1 + K`` agents resampled at ``S`` steps (row 0: the chosen agent).

    Attributes:
        window_ids: ``(W,)`` str, see :func:`window_id`.
        log_ids: ``(W,)`` str, the log each window comes from.
        agent_ids: ``(W,)`` str, track id of the chosen agent.
        start_ns: ``(W,)`` int64, absolute start time (the log's clock), nanoseconds.
        start_s: ``(W,)`` float64, start in seconds since the log's first timestamp.
        length_s: ``(W,)`` float64, window length, seconds.
        track_ids: ``(W, A)`` str, track ids of the agents, ``""`` for padding.
        categories: ``(W, A)`` str, their categories, ``""`` for padding.
        xy_m: ``(W, A, S, 2)`` float32, (forward, left) box centre in the chosen agent's frame at
            the window start, metres; 0 where not ``valid``.
        vxy_mps: ``(W, A, S, 2)`` float32, velocity in the same frame, metres per second.
        valid: ``(W, A, S)`` bool, True where the agent exists and is observed.
        lane_ids: ``(W, A, S)`` int64, lane id (highD ``laneId``, Argoverse 2 lane segment id) of
            the nearest log sample, -1 where unknown.
    """

    window_ids: NDArray[np.str_]
    log_ids: NDArray[np.str_]
    agent_ids: NDArray[np.str_]
    start_ns: IntArray
    start_s: FloatArray
    length_s: FloatArray
    track_ids: NDArray[np.str_]
    categories: NDArray[np.str_]
    xy_m: NDArray[np.float32]
    vxy_mps: NDArray[np.float32]
    valid: BoolArray
    lane_ids: IntArray

    def __len__(self) -> int:
        return int(self.window_ids.shape[0])

    @property
    def n_agents(self) -> int:
        """Agents per window ``A`` (the chosen one plus ``K`` neighbours)."""
        return int(self.valid.shape[1])

    @property
    def n_steps(self) -> int:
        """Steps per window ``S``."""
        return int(self.valid.shape[2])

    def select(self, index: NDArray[np.intp] | NDArray[np.bool_] | Sequence[int]) -> WindowSet:
        """The windows at ``index`` (integer positions or a boolean mask), in that order."""
        idx = np.asarray(index)
        return WindowSet(**{f.name: getattr(self, f.name)[idx] for f in fields(self)})

    @classmethod
    def empty(cls, n_agents: int, n_steps: int) -> WindowSet:
        """A set of no windows with ``n_agents`` agents and ``n_steps`` steps."""
        a, s = n_agents, n_steps
        return cls(
            window_ids=np.empty(0, dtype=str),
            log_ids=np.empty(0, dtype=str),
            agent_ids=np.empty(0, dtype=str),
            start_ns=np.empty(0, dtype=np.int64),
            start_s=np.empty(0),
            length_s=np.empty(0),
            track_ids=np.empty((0, a), dtype=str),
            categories=np.empty((0, a), dtype=str),
            xy_m=np.empty((0, a, s, 2), dtype=np.float32),
            vxy_mps=np.empty((0, a, s, 2), dtype=np.float32),
            valid=np.empty((0, a, s), dtype=bool),
            lane_ids=np.empty((0, a, s), dtype=np.int64),
        )

    @classmethod
    def concat(cls, sets: Sequence[WindowSet]) -> WindowSet:
        """All windows of ``sets`` in order.

        Raises:
            WindowConfigMismatchError: the sets differ in agents per window or steps.
            ValueError: ``sets`` is empty.
        """
        if not sets:
            raise ValueError("concat needs at least one WindowSet")
        shapes = {(s.n_agents, s.n_steps) for s in sets}
        if len(shapes) > 1:
            raise WindowConfigMismatchError(
                f"windows with different (agents, steps) cannot be mixed: {sorted(shapes)}; rebuild "
                "them with one [represent.windows] setting"
            )
        return cls(**{f.name: np.concatenate([getattr(s, f.name) for s in sets]) for f in fields(cls)})


# ------------------------------------------------------------------------------------ extraction


@dataclass(frozen=True)
class _Resampled:
    """Every track of a log at the query times of ``Wt`` windows: arrays ``(N, Wt, S)``."""

    x: FloatArray
    y: FloatArray
    vx: FloatArray
    vy: FloatArray
    yaw0: FloatArray  # (N, Wt): heading at the window start (nearest log sample)
    valid: BoolArray
    nearest: IntArray  # (Wt, S): index of the nearest log sample of each query time


def _window_starts(duration_s: float, length_s: float, overlap: float, tolerance_s: float) -> FloatArray:
    """``(Wt,)`` start times (seconds since the log start) of full windows of ``length_s``."""
    if duration_s + tolerance_s < length_s:
        return np.empty(0)
    stride = length_s * (1.0 - overlap)
    n = int(np.floor((duration_s + tolerance_s - length_s) / stride + 1e-9)) + 1
    return np.arange(n, dtype=np.float64) * stride


def _resample(log: Log, query_s: FloatArray) -> _Resampled:
    """Linear interpolation of every track at ``query_s`` ``(Wt, S)`` seconds since the log start."""
    t = log.t_s
    q = np.clip(query_s, t[0], t[-1])
    hi = np.clip(np.searchsorted(t, q, side="right"), 1, t.size - 1)
    lo = hi - 1
    w = np.clip((q - t[lo]) / (t[hi] - t[lo]), 0.0, 1.0)

    def lerp(a: FloatArray) -> FloatArray:
        out: FloatArray = a[:, lo] * (1.0 - w) + a[:, hi] * w
        return out

    v = log.valid
    valid = (v[:, lo] | (w >= 1.0)) & (v[:, hi] | (w <= 0.0))
    nearest = np.where(w < 0.5, lo, hi)
    return _Resampled(
        x=lerp(log.x_m),
        y=lerp(log.y_m),
        vx=lerp(log.vx_mps),
        vy=lerp(log.vy_mps),
        yaw0=log.yaw_rad[:, nearest[:, 0]],
        valid=valid,
        nearest=nearest,
    )


def _nearest_neighbours(
    r: _Resampled, agent: IntArray, win: IntArray, candidates: BoolArray, k: int, radius_m: float
) -> IntArray:
    """``(P, K)`` track indices of the ``k`` nearest candidates of each (agent, window) pair, -1 padding.

    Distance is the mean centre distance over the steps where both are observed; a candidate never
    observed together with the agent, or farther than ``radius_m`` on average, is not a neighbour.
    """
    n = r.x.shape[0]
    p = agent.size
    out = np.full((p, k), -1, dtype=np.int64)
    if k == 0 or p == 0:
        return out
    chunk = max(1, _MAX_DISTANCE_CELLS // max(1, n * r.x.shape[2]))
    for s in range(0, p, chunk):
        a, wi = agent[s : s + chunk], win[s : s + chunk]
        dx = r.x[:, wi, :].transpose(1, 0, 2) - r.x[a, wi][:, None, :]  # (P, N, S)
        dy = r.y[:, wi, :].transpose(1, 0, 2) - r.y[a, wi][:, None, :]
        both = r.valid[:, wi, :].transpose(1, 0, 2) & r.valid[a, wi][:, None, :]
        count = both.sum(axis=2)
        total = np.where(both, np.hypot(dx, dy), 0.0).sum(axis=2)
        with np.errstate(invalid="ignore", divide="ignore"):
            mean_d = np.where(count > 0, total / count, np.inf)
        mean_d[:, ~candidates] = np.inf
        mean_d[np.arange(a.size), a] = np.inf
        mean_d[mean_d > radius_m] = np.inf
        order = np.argsort(mean_d, axis=1, kind="stable")[:, : min(k, n)]
        picked = np.take_along_axis(mean_d, order, axis=1)
        out[s : s + a.size, : order.shape[1]] = np.where(np.isfinite(picked), order, -1)
    return out


def extract_windows(log: Log, config: WindowConfig, lane_ids: IntArray | None = None) -> WindowSet:
    """Cut ``log`` into windows of every configured length (see the module docstring).

    Args:
        log: the log (any dataset; positions are box centres in its world frame).
        config: lengths, overlap, steps, neighbours and which agents are chosen.
        lane_ids: ``(N, T)`` int64 lane id of each track and timestamp (-1 unknown), or ``None``.

    Returns:
        Windows ordered by length (as configured), chosen agent (log order), then start. A chosen
        agent must be observed at every step of its window; shorter logs give no windows.

    Raises:
        ValueError: ``lane_ids`` does not have the log's ``(N, T)`` shape.
    """
    a_count, s_count = 1 + config.k_neighbours, config.n_steps
    if lane_ids is not None and lane_ids.shape != log.valid.shape:
        raise ValueError(
            f"lane_ids must have shape {log.valid.shape} (tracks, timestamps), got {lane_ids.shape}"
        )
    if log.n_timestamps < 2:
        return WindowSet.empty(a_count, s_count)
    road_user = np.isin(log.categories, sorted(ROAD_USER_CATEGORIES))
    if config.agents == "ego":
        chosen = np.asarray([log.ego_index], dtype=np.int64)
    else:
        chosen = np.flatnonzero(np.isin(log.categories, sorted(CATEGORY_GROUPS["VEHICLE"])))
    parts = [_extract_length(log, config, length, chosen, road_user, lane_ids) for length in config.lengths_s]
    return WindowSet.concat([p for p in parts if len(p)] or [WindowSet.empty(a_count, s_count)])


def _extract_length(
    log: Log,
    config: WindowConfig,
    length_s: float,
    chosen: IntArray,
    road_user: BoolArray,
    lane_ids: IntArray | None,
    starts: FloatArray | None = None,
) -> WindowSet:
    """Windows of one length for the ``chosen`` track indices (at ``starts``, default: the planned ones)."""
    if starts is None:
        starts = _window_starts(log.duration_s, length_s, config.overlap, config.end_tolerance_s)
    if starts.size == 0 or chosen.size == 0:
        return WindowSet.empty(1 + config.k_neighbours, config.n_steps)
    query = starts[:, None] + np.linspace(0.0, length_s, config.n_steps)[None, :]
    r = _resample(log, query)
    full = r.valid[chosen].all(axis=2)  # (C, Wt)
    ci, wi = np.nonzero(full)
    agent, win = chosen[ci], wi.astype(np.int64)
    neigh = _nearest_neighbours(r, agent, win, road_user, config.k_neighbours, config.neighbour_radius_m)
    sel = np.concatenate([agent[:, None], neigh], axis=1)  # (P, A)
    pad = sel < 0
    si = np.where(pad, 0, sel)
    wcol = win[:, None]
    x, y = r.x[si, wcol], r.y[si, wcol]  # (P, A, S)
    valid = r.valid[si, wcol] & ~pad[:, :, None]
    x0, y0 = r.x[agent, win, 0], r.y[agent, win, 0]
    yaw0 = r.yaw0[agent, win][:, None, None]
    fwd, left = to_local(x - x0[:, None, None], y - y0[:, None, None], yaw0)
    vf, vl = to_local(r.vx[si, wcol], r.vy[si, wcol], yaw0)
    xy = np.where(valid[..., None], np.stack([fwd, left], axis=-1), 0.0)
    vxy = np.where(valid[..., None], np.nan_to_num(np.stack([vf, vl], axis=-1)), 0.0)
    if lane_ids is None:
        lanes = np.full(valid.shape, -1, dtype=np.int64)
    else:
        lanes = np.where(valid, lane_ids[si[:, :, None], r.nearest[win][:, None, :]], -1)
    tids = np.where(pad, "", log.track_ids[si].astype(str))
    cats = np.where(pad, "", log.categories[si].astype(str))
    agent_ids = log.track_ids[agent].astype(str)
    start_s = starts[win]
    t0_ns = log.timestamps_ns[0] + np.round(start_s * 1e9).astype(np.int64)
    ids = [window_id(log.log_id, str(t), float(s), length_s) for t, s in zip(agent_ids, start_s, strict=True)]
    return WindowSet(
        window_ids=np.asarray(ids, dtype=str),
        log_ids=np.full(agent.size, log.log_id, dtype=object).astype(str),
        agent_ids=agent_ids,
        start_ns=t0_ns,
        start_s=start_s,
        length_s=np.full(agent.size, float(length_s)),
        track_ids=tids,
        categories=cats,
        xy_m=xy.astype(np.float32),
        vxy_mps=vxy.astype(np.float32),
        valid=valid,
        lane_ids=lanes.astype(np.int64),
    )


def extract_agent_window(
    log: Log,
    config: WindowConfig,
    track_id: str,
    start_s: float,
    length_s: float,
    lane_ids: IntArray | None = None,
) -> WindowSet:
    """The one window of ``track_id`` starting ``start_s`` seconds after the log start (query by example).

    Returns:
        One window, or none when the track is not observed at every step of it.

    Raises:
        KeyError: the track is not in the log.
    """
    road_user = np.isin(log.categories, sorted(ROAD_USER_CATEGORIES))
    chosen = np.asarray([log.track_index(track_id)], dtype=np.int64)
    starts = np.asarray([float(start_s)])
    return _extract_length(log, config, length_s, chosen, road_user, lane_ids, starts)
