"""Per-sample descriptions from the data (stage 1 of the paper's three-stage description, section 3.3).

Every window gets facts computed from its arrays (no language model): the traffic state around the
chosen agent, each road user's path relative to the lanes (lane kept, lane changes with direction
and time, speed trend) and its interactions with the chosen agent (follows, overtakes, passes,
cuts in front of). A template turns the facts into a short text that keeps the references: window
id, log, track ids, times (seconds since the log's first timestamp, and highD frames where the log
is a highD recording) and the cluster.

Definitions (all in the chosen agent's frame at the window start: x forward, y left):

* **lane change**: the lane id changes between consecutive valid steps (where the data has lane
  ids); without lane ids, a net lateral shift of at least ``lane_width_m * 0.8``. Its direction is
  the sign of the lateral shift over the change, flipped for road users driving the other way
  (left is relative to each road user's own travel direction).
* **direction**: a road user drives the other way when its mean forward velocity is negative;
  such road users are described but take part in no interaction.
* **same lane**: equal lane ids, or (without ids) a lateral offset below half a lane width.
* **follows**: the other road user is ahead in the same lane, 0 to ``follow_gap_m`` metres, for at
  least 60 % of the steps both are observed.
* **overtakes / passes**: the longitudinal offset changes sign (beyond 2 m) while the two are in
  different lanes: the chosen agent overtakes a road user that ends behind it, and a road user
  that ends ahead passes the chosen agent (from the side it is on).
* **cuts in front of**: a road user changes lane into the other's lane and ends 0 to
  ``cut_in_gap_m`` metres ahead of it right after the change.
* **traffic density**: mean number of same-direction road users within 50 m of the chosen agent
  per step: ``free`` (< 2), ``moderate`` (2 to < 4), ``dense`` (>= 4); ``congested`` when dense and
  the chosen agent's mean speed is below 12 m/s.
* **speed trend**: ``stop-and-go`` (speed falls below 3 m/s and rises above 8 m/s after a phase
  above 8 m/s), ``accelerating`` / ``decelerating`` (end minus start speed beyond 2 m/s and
  0.25 m/s² on average), else ``constant speed``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from scenariominer.represent.windows import WindowSet

__all__ = [
    "DescribeSettings",
    "Interaction",
    "LaneChange",
    "VehicleFacts",
    "WindowDescription",
    "describe_windows",
    "highd_frame",
]

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class DescribeSettings:
    """Thresholds of the template descriptions (see the module docstring).

    Attributes:
        lane_width_m: nominal lane width, metres (lateral tests without lane ids).
        follow_gap_m: largest gap for "follows", metres.
        cut_in_gap_m: largest gap ahead right after a cut-in, metres.
        density_radius_m: radius around the chosen agent counted for the density, metres.
        highd_frame_rate_hz: frame rate used to name frames of highD logs (ids ``highd-...``).
    """

    lane_width_m: float = 3.5
    follow_gap_m: float = 60.0
    cut_in_gap_m: float = 40.0
    density_radius_m: float = 50.0
    highd_frame_rate_hz: float = 25.0


@dataclass(frozen=True)
class LaneChange:
    """One lane change of one road user.

    Attributes:
        track_id: the road user.
        t_s: time of the change, seconds since the log's first timestamp.
        frame: highD frame of the change, ``None`` for other logs.
        from_lane: lane id before (-1 without lane ids).
        to_lane: lane id after (-1 without lane ids).
        direction: ``left`` or ``right`` relative to the road user's travel direction.
    """

    track_id: str
    t_s: float
    frame: int | None
    from_lane: int
    to_lane: int
    direction: str


@dataclass(frozen=True)
class VehicleFacts:
    """What one road user of a window does.

    Attributes:
        track_id: its track id.
        category: its category.
        chosen: True for the window's chosen agent.
        oncoming: True when it drives the other way.
        lane_start: lane id at its first observed step (-1 unknown).
        lane_end: lane id at its last observed step (-1 unknown).
        lane_changes: its lane changes, in time order.
        speed_start_mps: speed at its first observed step, m/s.
        speed_end_mps: speed at its last observed step, m/s.
        speed_mean_mps: mean speed, m/s.
        speed_min_mps: lowest speed, m/s.
        speed_max_mps: highest speed, m/s.
        speed_trend: ``constant speed``, ``accelerating``, ``decelerating`` or ``stop-and-go``.
        peak_lateral_mps: largest lateral speed, m/s.
    """

    track_id: str
    category: str
    chosen: bool
    oncoming: bool
    lane_start: int
    lane_end: int
    lane_changes: tuple[LaneChange, ...]
    speed_start_mps: float
    speed_end_mps: float
    speed_mean_mps: float
    speed_min_mps: float
    speed_max_mps: float
    speed_trend: str
    peak_lateral_mps: float


@dataclass(frozen=True)
class Interaction:
    """A relation between two road users of a window.

    Attributes:
        kind: ``follows``, ``overtakes``, ``passes`` or ``cuts_in_front_of``.
        subject: track id of the road user doing it.
        obj: track id of the other one.
        t_s: when (seconds since the log's first timestamp): the first step for ``follows``, the
            crossing for ``overtakes``/``passes``, the lane change for ``cuts_in_front_of``.
        frame: highD frame of ``t_s``, ``None`` for other logs.
        side: ``left``/``right`` (side the subject is on, seen from the object) or ``""``.
        gap_m: mean gap for ``follows``, gap right after a cut-in, else 0.
    """

    kind: str
    subject: str
    obj: str
    t_s: float
    frame: int | None
    side: str
    gap_m: float


@dataclass(frozen=True)
class WindowDescription:
    """Facts and template text of one window (sample).

    Attributes:
        window_id: the window.
        log_id: its log.
        agent_id: its chosen agent's track id.
        start_s: start, seconds since the log's first timestamp.
        end_s: end, seconds since the log's first timestamp.
        start_frame: highD frame of the start, ``None`` for other logs.
        end_frame: highD frame of the end, ``None`` for other logs.
        cluster: cluster label (-1 outlier, ``None`` when not clustered).
        density: ``free``, ``moderate``, ``dense`` or ``congested``.
        neighbours_per_step: mean same-direction road users within the density radius.
        n_lanes: distinct lanes observed (0 without lane ids).
        mean_speed_mps: the chosen agent's mean speed.
        vehicles: facts of each road user (chosen agent first).
        interactions: relations involving the chosen agent.
        text: the template description.
    """

    window_id: str
    log_id: str
    agent_id: str
    start_s: float
    end_s: float
    start_frame: int | None
    end_frame: int | None
    cluster: int | None
    density: str
    neighbours_per_step: float
    n_lanes: int
    mean_speed_mps: float
    vehicles: tuple[VehicleFacts, ...]
    interactions: tuple[Interaction, ...]
    text: str


def highd_frame(log_id: str, t_ns: int, frame_rate_hz: float = 25.0) -> int | None:
    """HighD frame at absolute log time ``t_ns`` for highD logs (ids ``highd-...``), else ``None``."""
    if not log_id.startswith("highd-"):
        return None
    return round(t_ns * 1e-9 * frame_rate_hz)


def _speed_trend(speed: FloatArray, length_s: float) -> str:
    """Trend of one speed profile ``(n,)`` (valid steps only) over ``length_s`` seconds."""
    if speed.size < 2:
        return "constant speed"
    above = speed > 8.0
    low = np.flatnonzero(speed < 3.0)
    if low.size and above[: low[0]].any() and above[low[0] :].any():
        return "stop-and-go"
    dv = float(speed[-1] - speed[0])
    if abs(dv) > 2.0 and abs(dv) / max(length_s, 1e-6) > 0.25:
        return "accelerating" if dv > 0 else "decelerating"
    return "constant speed"


def _lane_changes(
    lanes: NDArray[np.int64],
    y_m: FloatArray,
    ok: NDArray[np.bool_],
    sign: float,
    times_s: FloatArray,
    settings: DescribeSettings,
) -> list[tuple[int, int, int, str]]:
    """Lane changes of one track: ``(step, from lane, to lane, direction)``; arrays are ``(S,)``."""
    idx = np.flatnonzero(ok)
    if idx.size < 2:
        return []
    out: list[tuple[int, int, int, str]] = []
    ln, yy = lanes[idx], y_m[idx]
    if (ln >= 0).all():
        change = np.flatnonzero(np.diff(ln) != 0)
        for c in change.tolist():
            lo, hi = max(c - 1, 0), min(c + 2, idx.size - 1)
            dy = float(yy[hi] - yy[lo]) * sign
            out.append((int(idx[c + 1]), int(ln[c]), int(ln[c + 1]), "left" if dy > 0 else "right"))
        return out
    shift = float(yy[-1] - yy[0]) * sign
    if abs(shift) >= 0.8 * settings.lane_width_m:
        mid = int(idx[np.argmin(np.abs(yy - (yy[0] + yy[-1]) / 2))])
        out.append((mid, -1, -1, "left" if shift > 0 else "right"))
    return out


def _frame(log_id: str, start_ns: int, start_s: float, t_s: float, s: DescribeSettings) -> int | None:
    return highd_frame(log_id, start_ns + round((t_s - start_s) * 1e9), s.highd_frame_rate_hz)


def describe_windows(
    windows: WindowSet,
    clusters: NDArray[np.int64] | None = None,
    settings: DescribeSettings | None = None,
) -> list[WindowDescription]:
    """Facts and template text of every window (``clusters``: ``(W,)`` labels, optional)."""
    s = settings or DescribeSettings()
    n_w, _a, n_s = windows.valid.shape
    t_rel = np.linspace(0.0, 1.0, n_s)
    xy = windows.xy_m.astype(np.float64)
    v = windows.vxy_mps.astype(np.float64)
    speed = np.hypot(v[..., 0], v[..., 1])  # (W, A, S)
    counts = np.maximum(windows.valid.sum(axis=2), 1)
    mean_vx = np.where(windows.valid, v[..., 0], 0.0).sum(axis=2) / counts  # (W, A)
    oncoming = mean_vx < 0
    rel = xy - xy[:, :1]  # (W, A, S, 2) offset from the chosen agent
    near = (
        windows.valid
        & windows.valid[:, :1]
        & (np.hypot(rel[..., 0], rel[..., 1]) <= s.density_radius_m)
        & ~oncoming[..., None]
    )
    near[:, 0] = False
    per_step = near.sum(axis=1).mean(axis=1)  # (W,)
    out: list[WindowDescription] = []
    for w in range(n_w):
        out.append(_describe_one(windows, w, t_rel, xy, v, speed, oncoming[w], per_step[w], clusters, s))
    return out


def _describe_one(
    ws: WindowSet,
    w: int,
    t_rel: FloatArray,
    xy: FloatArray,
    v: FloatArray,
    speed: FloatArray,
    oncoming: NDArray[np.bool_],
    per_step: float,
    clusters: NDArray[np.int64] | None,
    s: DescribeSettings,
) -> WindowDescription:
    """Facts and text of window ``w`` (arrays as in :func:`describe_windows`)."""
    log_id, start_s, length_s = str(ws.log_ids[w]), float(ws.start_s[w]), float(ws.length_s[w])
    start_ns = int(ws.start_ns[w])
    times_s = start_s + t_rel * length_s
    valid, lanes = ws.valid[w], ws.lane_ids[w]
    vehicles: list[VehicleFacts] = []
    changes_at: dict[int, list[tuple[int, int, int, str]]] = {}
    for a in np.flatnonzero(valid.any(axis=1)):
        ok = valid[a]
        sign = -1.0 if oncoming[a] else 1.0
        ch = _lane_changes(lanes[a], xy[w, a, :, 1], ok, sign, times_s, s)
        changes_at[int(a)] = ch
        sp = speed[w, a][ok]
        lane_known = lanes[a][ok]
        tid = str(ws.track_ids[w, a])
        vehicles.append(
            VehicleFacts(
                track_id=tid,
                category=str(ws.categories[w, a]),
                chosen=bool(a == 0),
                oncoming=bool(oncoming[a]),
                lane_start=int(lane_known[0]),
                lane_end=int(lane_known[-1]),
                lane_changes=tuple(
                    LaneChange(
                        tid,
                        float(times_s[st]),
                        _frame(log_id, start_ns, start_s, float(times_s[st]), s),
                        fr,
                        to,
                        d,
                    )
                    for st, fr, to, d in ch
                ),
                speed_start_mps=float(sp[0]),
                speed_end_mps=float(sp[-1]),
                speed_mean_mps=float(sp.mean()),
                speed_min_mps=float(sp.min()),
                speed_max_mps=float(sp.max()),
                speed_trend=_speed_trend(sp, length_s),
                peak_lateral_mps=float(np.abs(v[w, a, :, 1][ok]).max()),
            )
        )
    interactions = _interactions(ws, w, xy[w], times_s, oncoming, changes_at, s)
    known = lanes[valid & (lanes >= 0)]
    n_lanes = int(np.unique(known).size)
    mean_speed = vehicles[0].speed_mean_mps if vehicles else 0.0
    density = "free" if per_step < 2 else "moderate" if per_step < 4 else "dense"
    if density == "dense" and mean_speed < 12.0:
        density = "congested"
    cluster = None if clusters is None else int(clusters[w])
    end_s = start_s + length_s
    desc = WindowDescription(
        window_id=str(ws.window_ids[w]),
        log_id=log_id,
        agent_id=str(ws.agent_ids[w]),
        start_s=start_s,
        end_s=end_s,
        start_frame=highd_frame(log_id, start_ns, s.highd_frame_rate_hz),
        end_frame=_frame(log_id, start_ns, start_s, end_s, s),
        cluster=cluster,
        density=density,
        neighbours_per_step=float(per_step),
        n_lanes=n_lanes,
        mean_speed_mps=mean_speed,
        vehicles=tuple(vehicles),
        interactions=tuple(interactions),
        text="",
    )
    return _with_text(desc, _lane_positions(ws, w, xy[w], oncoming))


def _interactions(
    ws: WindowSet,
    w: int,
    xy: FloatArray,
    times_s: FloatArray,
    oncoming: NDArray[np.bool_],
    changes_at: dict[int, list[tuple[int, int, int, str]]],
    s: DescribeSettings,
) -> list[Interaction]:
    """Relations between the chosen agent (row 0) and each same-direction road user; ``xy`` ``(A, S, 2)``."""
    log_id, start_ns, start_s = str(ws.log_ids[w]), int(ws.start_ns[w]), float(ws.start_s[w])
    valid, lanes = ws.valid[w], ws.lane_ids[w]
    me = str(ws.track_ids[w, 0])
    out: list[Interaction] = []
    half = s.lane_width_m / 2
    for j in np.flatnonzero(valid.any(axis=1)):
        if j == 0 or oncoming[j]:
            continue
        both = valid[0] & valid[j]
        if both.sum() < 3:
            continue
        other = str(ws.track_ids[w, j])
        dx = xy[j, :, 0] - xy[0, :, 0]
        dy = xy[j, :, 1] - xy[0, :, 1]
        with_ids = (lanes[0] >= 0) & (lanes[j] >= 0)
        same = np.where(with_ids, lanes[0] == lanes[j], np.abs(dy) < half) & both
        idx = np.flatnonzero(both)

        def frame(t: float) -> int | None:
            return _frame(log_id, start_ns, start_s, t, s)

        for ahead, subj, obj in ((dx, me, other), (-dx, other, me)):
            hold = same & (ahead > 0) & (ahead <= s.follow_gap_m)
            if hold.sum() >= 0.6 * both.sum():
                t0 = float(times_s[np.flatnonzero(hold)[0]])
                gap = float(ahead[hold].mean())
                out.append(Interaction("follows", subj, obj, t0, frame(t0), "", round(gap, 1)))
        d = dx[idx]
        if d[0] > 2.0 and d[-1] < -2.0 or d[0] < -2.0 and d[-1] > 2.0:
            cross = int(idx[np.flatnonzero(np.sign(d[:-1]) != np.sign(d[1:]))[0] + 1])
            if not same[cross]:
                t = float(times_s[cross])
                if d[0] > 0:  # the chosen agent overtakes the other, which is on side dy
                    side = "right" if dy[cross] > 0 else "left"
                    out.append(Interaction("overtakes", me, other, t, frame(t), side, 0.0))
                else:
                    side = "left" if dy[cross] > 0 else "right"
                    out.append(Interaction("passes", other, me, t, frame(t), side, 0.0))
        for mover, target, sgn in ((int(j), 0, 1.0), (0, int(j), -1.0)):
            for st, _fr, to, _d in changes_at.get(mover, []):
                after = min(st + 1, xy.shape[1] - 1)
                gap = sgn * float(dx[after])
                into = lanes[target][st] == to if to >= 0 else abs(float(dy[after])) < half
                if into and both[after] and 0 < gap <= s.cut_in_gap_m:
                    t = float(times_s[st])
                    names = (other, me) if mover else (me, other)
                    out.append(Interaction("cuts_in_front_of", *names, t, frame(t), "", round(gap, 1)))
    return out


def _lane_positions(ws: WindowSet, w: int, xy: FloatArray, oncoming: NDArray[np.bool_]) -> dict[int, str]:
    """Lane id -> ``right``/``middle``/``left`` among the same-direction lanes seen in window ``w``."""
    valid, lanes = ws.valid[w], ws.lane_ids[w]
    mask = valid & (lanes >= 0) & ~oncoming[:, None]
    if not mask.any():
        return {}
    ids = lanes[mask]
    lat = xy[..., 1][mask]
    uniq = np.unique(ids)
    if uniq.size < 2:
        return {}
    mean_y = np.array([lat[ids == u].mean() for u in uniq])
    order = uniq[np.argsort(mean_y)]  # rightmost (lowest y, y is left) first
    names = {int(order[0]): "right", int(order[-1]): "left"}
    for u in order[1:-1]:
        names[int(u)] = "middle"
    return names


def _lane(lane: int, positions: dict[int, str]) -> str:
    if lane < 0:
        return "its lane"
    pos = positions.get(lane)
    return f"lane {lane} ({pos} lane)" if pos else f"lane {lane}"


def _at(t_s: float, frame: int | None) -> str:
    return f"{t_s:.1f} s" + (f" (frame {frame})" if frame is not None else "")


def _vehicle_text(f: VehicleFacts, positions: dict[int, str]) -> str:
    kind = "truck" if f.category in ("TRUCK", "BOX_TRUCK", "BUS") else "car"
    role = ", chosen agent" if f.chosen else ", oncoming" if f.oncoming else ""
    head = f"Vehicle {f.track_id} ({kind}{role})"
    if f.lane_changes:
        moves = []
        for c in f.lane_changes:
            where = f"from lane {c.from_lane} to lane {c.to_lane} " if c.from_lane >= 0 else ""
            moves.append(f"changes lane {where}to the {c.direction} at {_at(c.t_s, c.frame)}")
        path = "; ".join(moves)
        dirs = {c.direction for c in f.lane_changes}
        if len(f.lane_changes) >= 2 and len(dirs) == 1:
            path += f" (a multi-lane change to the {dirs.pop()} over {len(f.lane_changes)} lanes)"
    else:
        path = f"keeps {_lane(f.lane_start, positions)}"
    lateral = ""
    if not f.lane_changes and f.peak_lateral_mps > 0.6:
        lateral = f", lateral movement without lane change (up to {f.peak_lateral_mps:.1f} m/s)"
    return (
        f"{head} {path}{lateral}; speed {f.speed_start_mps:.1f} to {f.speed_end_mps:.1f} m/s "
        f"(mean {f.speed_mean_mps:.1f}, {f.speed_trend})."
    )


_VERB = {
    "follows": "follows",
    "overtakes": "overtakes",
    "passes": "passes",
    "cuts_in_front_of": "cuts in front of",
}


def _interaction_text(i: Interaction) -> str:
    text = f"vehicle {i.subject} {_VERB[i.kind]} vehicle {i.obj}"
    if i.kind == "follows":
        return f"{text} at a mean gap of {i.gap_m:.0f} m from {_at(i.t_s, i.frame)}"
    if i.kind == "cuts_in_front_of":
        return f"{text} at {_at(i.t_s, i.frame)}, {i.gap_m:.0f} m ahead of it"
    if i.kind == "passes":
        return f"{text} from the {i.side} (a pass-by) at {_at(i.t_s, i.frame)}"
    return f"{text} on its {i.side} at {_at(i.t_s, i.frame)}"


def _with_text(d: WindowDescription, positions: dict[int, str]) -> WindowDescription:
    frames = f", frames {d.start_frame}-{d.end_frame}" if d.start_frame is not None else ""
    cluster = "" if d.cluster is None else (" outlier" if d.cluster < 0 else f" cluster {d.cluster}")
    lanes = f" on {d.n_lanes} lanes" if d.n_lanes else ""
    parts = [
        f"Sample {d.window_id} (log {d.log_id}, {d.start_s:.1f}-{d.end_s:.1f} s{frames},"
        f"{cluster or ' unclustered'}).",
        f"Traffic: {d.density} traffic{lanes}, {d.neighbours_per_step:.1f} road users within 50 m on "
        f"average, chosen vehicle {d.agent_id} at a mean speed of {d.mean_speed_mps:.1f} m/s "
        f"({d.mean_speed_mps * 3.6:.0f} km/h).",
    ]
    parts += [_vehicle_text(f, positions) for f in d.vehicles]
    if d.interactions:
        parts.append("Interactions: " + "; ".join(_interaction_text(i) for i in d.interactions) + ".")
    else:
        parts.append("Interactions: none with the chosen vehicle.")
    return WindowDescription(**{**d.__dict__, "text": " ".join(parts)})
