"""Ground truth of highway windows from the recording itself, for judging retrieval relevance.

The truth of a window (chosen vehicle ``v``, highD frames ``f0..f1``) is read from the recording's
own per-frame columns at full frame rate, never from our descriptions or window arrays: ``laneId``
(the simulator's lane index where the recording comes from ``scenariominer simulate highway``),
``precedingId``/``dhw`` (leader and gap), the left/right preceding and following ids, velocities,
``drivingDirection`` and the lane markings. Lane-change direction follows highD's numbering: on
the lower carriageway (driving direction 2, towards +x) a higher lane id is further right, on the
upper one (direction 1) further left.

Each window's truth is a flat dict of numbers and booleans (see :data:`TRUTH_FIELDS`) that the
query rules of ``highway_queries.toml`` are written against.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from scenariominer.data.adapters.highd import HighDFiles
from scenariominer.data.adapters.highd.format import read_recording_meta

__all__ = ["TRUTH_FIELDS", "RecordingTruth", "load_recording_truth", "window_truth"]

IntArray = NDArray[np.int64]
FloatArray = NDArray[np.float64]

#: Every field of a window's truth, with its meaning (units in the name).
TRUTH_FIELDS: dict[str, str] = {
    "road_lanes": "lanes of the chosen vehicle's carriageway",
    "lane_position": "0 right, 1 middle, 2 left lane of the carriageway (at the window's middle)",
    "lane_changes": "lane changes of the chosen vehicle",
    "lane_changes_left": "lane changes to the left",
    "lane_changes_right": "lane changes to the right",
    "max_shift_left": "largest number of lanes moved to the left of the start lane",
    "max_shift_right": "largest number of lanes moved to the right of the start lane",
    "lane_change_speed_mps": "speed at the first lane change (0 without)",
    "peak_lateral_mps": "largest lateral speed",
    "mean_speed_mps": "mean speed",
    "start_speed_mps": "speed at the first frame",
    "end_speed_mps": "speed at the last frame",
    "speed_range_mps": "largest minus smallest speed",
    "accel_mps2": "(end - start speed) / duration",
    "stop_and_go": "speed falls below 3 m/s after being above 8 m/s and rises above 8 m/s again",
    "density": "mean number of vehicles on the carriageway within 50 m of the chosen vehicle",
    "density_right": "mean vehicles per frame in the right lane within 100 m",
    "density_middle": "mean vehicles per frame in the middle lane(s) within 100 m",
    "density_left": "mean vehicles per frame in the left lane within 100 m",
    "follows": "a leader in the same lane within 60 m for >= 60 % of the frames",
    "gap_change_m": "change of the gap to the same leader from the first to the last frame (0 without)",
    "cut_ins": "vehicles that changed lane and became the chosen vehicle's leader within 40 m",
    "overtakes": "vehicles that went from a side lane's preceding to its following vehicle",
    "passed_left": "vehicles that went from the left lane's following to its preceding vehicle",
    "passed_right": "vehicles that went from the right lane's following to its preceding vehicle",
    "evasive": "a lane change while the leader was within 20 m, or with >= 1.5 m/s lateral speed",
    "evasive_right": "such an evasive lane change to the right",
    "merge": "the first lane change goes left out of the rightmost lane",
    "vehicles_changing_lane": "vehicles within 100 m (the chosen one included) changing lane in the window",
    "lane_change_after_pass_by": "a lane change after a vehicle passed the chosen vehicle",
    "end_lane_position": "lane position (0 right, 1 middle, 2 left) at the last frame",
}

_COLUMNS = (
    "frame",
    "id",
    "x",
    "xVelocity",
    "yVelocity",
    "laneId",
    "dhw",
    "precedingId",
    "leftPrecedingId",
    "leftFollowingId",
    "rightPrecedingId",
    "rightFollowingId",
)


@dataclass(frozen=True, eq=False)
class RecordingTruth:
    """A recording's per-frame columns, sorted by (vehicle, frame), plus frame-sorted order.

    Attributes:
        frame_rate_hz: frames per second.
        lanes_by_direction: driving direction -> lane ids of that carriageway, rightmost first.
        columns: column name -> ``(M,)`` array (see the module docstring).
        direction: vehicle id -> driving direction (1 or 2).
        vehicle_ids: ``(V,)`` ascending ids; ``starts``/``ends`` ``(V,)`` their row ranges.
        frame_order: ``(M,)`` rows sorted by frame; ``frame_sorted`` their frames.
    """

    frame_rate_hz: float
    lanes_by_direction: dict[int, tuple[int, ...]]
    columns: dict[str, NDArray[np.float64]]
    direction: dict[int, int]
    vehicle_ids: IntArray
    starts: IntArray
    ends: IntArray
    frame_order: IntArray
    frame_sorted: IntArray

    def rows(self, vehicle_id: int, f0: int, f1: int) -> IntArray:
        """Rows of ``vehicle_id`` at frames ``f0..f1`` (inclusive)."""
        v = int(np.searchsorted(self.vehicle_ids, vehicle_id))
        if v >= self.vehicle_ids.size or self.vehicle_ids[v] != vehicle_id:
            return np.zeros(0, np.int64)
        a, b = int(self.starts[v]), int(self.ends[v])
        fr = self.columns["frame"][a:b]
        lo, hi = np.searchsorted(fr, f0), np.searchsorted(fr, f1, side="right")
        return np.arange(a + lo, a + hi, dtype=np.int64)

    def frame_rows(self, frame: int) -> IntArray:
        """Rows of every vehicle at ``frame``."""
        lo, hi = np.searchsorted(self.frame_sorted, [frame, frame + 1])
        return self.frame_order[lo:hi]


@functools.lru_cache(maxsize=8)
def load_recording_truth(tracks_path: str) -> RecordingTruth:
    """Read a highD-format recording's truth columns (cached per path).

    Raises:
        LogFormatError: the files are missing or malformed (missing optional columns read as 0).
    """
    import pyarrow.csv as pacsv

    from scenariominer.data.log import LogFormatError

    files = HighDFiles.from_path(Path(tracks_path))
    if files is None:
        raise LogFormatError(tracks_path, "not a highD tracks file with its meta files")
    meta = read_recording_meta(files.recording_meta)
    header = files.tracks.open(encoding="utf-8").readline().strip().split(",")
    table = pacsv.read_csv(
        files.tracks,
        convert_options=pacsv.ConvertOptions(include_columns=[c for c in _COLUMNS if c in header]),
    )
    n = table.num_rows
    cols = {
        c: (table.column(c).to_numpy().astype(np.float64) if c in header else np.zeros(n)) for c in _COLUMNS
    }
    order = np.lexsort((cols["frame"], cols["id"]))
    cols = {k: v[order] for k, v in cols.items()}
    vid = cols["id"].astype(np.int64)
    vids, starts = np.unique(vid, return_index=True)
    ends = np.append(starts[1:], vid.size)
    tmeta = pacsv.read_csv(
        files.tracks_meta, convert_options=pacsv.ConvertOptions(include_columns=["id", "drivingDirection"])
    )
    direction = dict(
        zip(tmeta.column("id").to_pylist(), tmeta.column("drivingDirection").to_pylist(), strict=True)
    )
    upper = len(meta.upper_lane_markings_m)
    lower = len(meta.lower_lane_markings_m)
    upper_ids = tuple(range(2, upper + 1))  # between markings i and i+1 -> id i + 2
    lower_ids = tuple(range(upper + 2, upper + lower + 1))
    frames = cols["frame"].astype(np.int64)
    forder = np.argsort(frames, kind="stable")
    return RecordingTruth(
        frame_rate_hz=meta.frame_rate_hz,
        # rightmost first: direction 1 (upper, towards -x) has its right side at low ids
        lanes_by_direction={1: upper_ids, 2: tuple(reversed(lower_ids))},
        columns=cols,
        direction={int(k): int(v) for k, v in direction.items()},
        vehicle_ids=vids.astype(np.int64),
        starts=starts.astype(np.int64),
        ends=ends.astype(np.int64),
        frame_order=forder.astype(np.int64),
        frame_sorted=frames[forder],
    )


def _position(lane: int, lanes: tuple[int, ...]) -> int:
    """0 right, 1 middle, 2 left; -1 when the lane is not on the carriageway."""
    if lane not in lanes:
        return -1
    i = lanes.index(lane)
    return 0 if i == 0 else 2 if i == len(lanes) - 1 else 1


def window_truth(rec: RecordingTruth, vehicle_id: int, f0: int, f1: int) -> dict[str, float] | None:
    """Truth of vehicle ``vehicle_id`` over frames ``f0..f1`` (``None`` when it is not there)."""
    rows = rec.rows(vehicle_id, f0, f1)
    if rows.size < 2:
        return None
    c = rec.columns
    direction = rec.direction.get(vehicle_id, 2)
    lanes = rec.lanes_by_direction.get(direction, ())
    rank = {lane: i for i, lane in enumerate(lanes)}  # 0 = rightmost
    lane = c["laneId"][rows].astype(np.int64)
    lane_rank = np.asarray([rank.get(int(x), -1) for x in lane])
    steps = np.diff(lane_rank)
    change_at = np.flatnonzero(steps != 0)
    left = int((steps > 0).sum())
    right = int((steps < 0).sum())
    speed = np.hypot(c["xVelocity"][rows], c["yVelocity"][rows])
    duration_s = (rows.size - 1) / rec.frame_rate_hz
    above = speed > 8.0
    low = np.flatnonzero(speed < 3.0)
    stop_go = bool(low.size and above[: low[0]].any() and above[low[0] :].any())
    dhw = c["dhw"][rows]
    lead = c["precedingId"][rows].astype(np.int64)
    follows = bool(((lead > 0) & (dhw > 0) & (dhw <= 60)).mean() >= 0.6)
    gap_change = float(dhw[-1] - dhw[0]) if lead[0] > 0 and lead[0] == lead[-1] else 0.0
    half_s = int(rec.frame_rate_hz)
    cut_ins = 0
    new_lead = np.flatnonzero((np.diff(lead) != 0) & (lead[1:] > 0)) + 1
    for i in new_lead.tolist():
        other = int(lead[i])
        fr = int(c["frame"][rows[i]])
        theirs = rec.rows(other, fr - 2 * half_s, fr)
        if (
            theirs.size >= 2
            and len(set(c["laneId"][theirs].astype(np.int64).tolist())) > 1
            and 0 < dhw[i] <= 40
        ):
            cut_ins += 1
    first_seen: dict[tuple[str, int], int] = {}
    for name in ("leftPrecedingId", "leftFollowingId", "rightPrecedingId", "rightFollowingId"):
        ids = c[name][rows].astype(np.int64)
        for k in np.unique(ids[ids > 0]).tolist():
            first_seen[(name, k)] = int(np.flatnonzero(ids == k)[0])
            first_seen[(name + "_last", k)] = int(np.flatnonzero(ids == k)[-1])
    overtakes = 0
    passed: dict[str, list[int]] = {"left": [], "right": []}
    for side in ("left", "right"):
        pre, fol = f"{side}PrecedingId", f"{side}FollowingId"
        for name, k in first_seen:
            if (
                name == pre
                and (fol, k) in first_seen
                and first_seen[(fol, k)] > first_seen[(pre + "_last", k)]
            ):
                overtakes += 1
            if (
                name == fol
                and (pre, k) in first_seen
                and first_seen[(pre, k)] > first_seen[(fol + "_last", k)]
            ):
                passed[side].append(first_seen[(pre, k)])
    peak_lat = float(np.abs(c["yVelocity"][rows]).max())
    evasive = evasive_right = False
    for i in change_at.tolist():
        window = slice(max(i - 3 * half_s, 0), i + 1)
        close = bool(((lead[window] > 0) & (dhw[window] > 0) & (dhw[window] < 20)).any())
        lateral = float(np.abs(c["yVelocity"][rows][max(i - half_s, 0) : i + half_s]).max())
        if close or lateral >= 1.5:
            evasive = True
            evasive_right = evasive_right or steps[i] < 0
    start_rank = lane_rank[0]
    mid = rows[rows.size // 2]
    frames = range(f0, f1 + 1, max(half_s, 1))
    x0 = {int(c["frame"][r]): float(c["x"][r]) for r in rows[:: max(half_s, 1)]}
    near_counts: list[int] = []
    per_lane: dict[int, list[int]] = {0: [], 1: [], 2: []}
    changing: set[int] = set()
    for fr in frames:
        if fr not in x0:
            continue
        fr_rows = rec.frame_rows(fr)
        ids = c["id"][fr_rows].astype(np.int64)
        same = np.asarray([rec.direction.get(int(v), 0) == direction for v in ids], dtype=bool)
        dx = np.abs(c["x"][fr_rows] - x0[fr])
        near_counts.append(int((same & (dx <= 50) & (ids != vehicle_id)).sum()))
        pos = np.asarray([_position(int(x), lanes) for x in c["laneId"][fr_rows]])
        within = same & (dx <= 100)
        for p in (0, 1, 2):
            per_lane[p].append(int((within & (pos == p)).sum()))
        changing.update(int(v) for v in ids[within])
    n_changing = 0
    for v in changing:
        vr = rec.rows(v, f0, f1)
        if vr.size and np.unique(c["laneId"][vr]).size > 1:
            n_changing += 1
    first_pass = min(passed["left"] + passed["right"], default=None)
    middle_lanes = max(len(lanes) - 2, 1)
    return {
        "road_lanes": float(len(lanes)),
        "lane_position": float(_position(int(c["laneId"][mid]), lanes)),
        "end_lane_position": float(_position(int(lane[-1]), lanes)),
        "lane_changes": float(left + right),
        "lane_changes_left": float(left),
        "lane_changes_right": float(right),
        "max_shift_left": float(max(int(lane_rank.max() - start_rank), 0)) if start_rank >= 0 else 0.0,
        "max_shift_right": float(max(int(start_rank - lane_rank[lane_rank >= 0].min()), 0))
        if start_rank >= 0
        else 0.0,
        "lane_change_speed_mps": float(speed[change_at[0]]) if change_at.size else 0.0,
        "peak_lateral_mps": peak_lat,
        "mean_speed_mps": float(speed.mean()),
        "start_speed_mps": float(speed[0]),
        "end_speed_mps": float(speed[-1]),
        "speed_range_mps": float(speed.max() - speed.min()),
        "accel_mps2": float(speed[-1] - speed[0]) / max(duration_s, 1e-6),
        "stop_and_go": float(stop_go),
        "density": float(np.mean(near_counts)) if near_counts else 0.0,
        "density_right": float(np.mean(per_lane[0])) if per_lane[0] else 0.0,
        "density_middle": float(np.mean(per_lane[1])) / middle_lanes if per_lane[1] else 0.0,
        "density_left": float(np.mean(per_lane[2])) if per_lane[2] else 0.0,
        "follows": float(follows),
        "gap_change_m": gap_change,
        "cut_ins": float(cut_ins),
        "overtakes": float(overtakes),
        "passed_left": float(len(passed["left"])),
        "passed_right": float(len(passed["right"])),
        "evasive": float(evasive),
        "evasive_right": float(evasive_right),
        "merge": float(bool(change_at.size) and lane_rank[change_at[0]] == 0 and steps[change_at[0]] > 0),
        "vehicles_changing_lane": float(n_changing),
        "lane_change_after_pass_by": float(
            first_pass is not None and bool(change_at.size) and bool((change_at > first_pass).any())
        ),
    }
