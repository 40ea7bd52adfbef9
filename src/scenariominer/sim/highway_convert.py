"""SUMO's floating-car data and lane-change log -> a highD recording plus its ground truth.

Coordinates. SUMO reports the centre of a vehicle's front bumper ``(x, y)``, its heading and its
lateral offset ``posLat`` from its lane's centre line. The recording's box centre is half a length
behind the bumper along the heading; its lateral place is SUMO's own lateral position (the
bumper's ``y``), clipped into the strip of the lane SUMO has the vehicle on (centre line
``y - posLat``; the clip moves ``y`` by at most the output rounding). So the lane the highD writer
derives from the box centre and the lane markings is SUMO's lane at every frame, and a lane change
shows in the recording's ``laneId`` at the frame SUMO made it.

The highD image frame: ``x`` along the section from its start (:attr:`HighwayNetwork.section_start_m`),
image ``y = IMAGE_Y_OFFSET_M - y_sumo`` (the carriageway's left border at image y
:data:`IMAGE_Y_OFFSET_M`, lanes below it), one lower carriageway (driving direction 2, towards
+x), no upper one. Lane markings sit every lane width; with an on-ramp the acceleration lane is the
rightmost lane of the recording.

Kept rows: box centre inside the section, vehicle on the main road (not yet on the ramp). A
vehicle's track is its first unbroken run of frames (SUMO may teleport a stuck vehicle; what
follows a jump is dropped); tracks shorter than :data:`MIN_TRACK_FRAMES` are dropped.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from scenariominer.data.adapters.highd import HighDFiles, HighDVehicle, write_highd_recording
from scenariominer.sim.highway_net import HighwayNetwork
from scenariominer.sim.highway_run import VEHICLE_TYPES
from scenariominer.sim.highway_scenario import HighwayScenario, HighwaySimError
from scenariominer.sim.highway_truth import (
    MANOEUVRE_GAP_S,
    LaneChange,
    TruthFrames,
    lane_changes_path,
    truth_frames_path,
    write_lane_changes,
    write_truth_frames,
)

__all__ = ["IMAGE_Y_OFFSET_M", "MIN_TRACK_FRAMES", "ConvertedRecording", "convert_run"]

#: Image y of the carriageway's left border, metres.
IMAGE_Y_OFFSET_M = 10.0
#: Tracks with fewer frames are not written.
MIN_TRACK_FRAMES = 10
#: Lateral margin kept from a lane's boundary when clipping, metres.
_LANE_MARGIN_M = 0.005

IntArray = NDArray[np.int64]
FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class ConvertedRecording:
    """What one conversion wrote.

    Attributes:
        files: the highD files.
        lane_changes_file: ``NN_laneChanges.csv``.
        truth_frames_file: ``NN_truthFrames.csv``.
        n_vehicles: vehicles written.
        n_trucks: of which trucks.
        n_rows: (vehicle, frame) rows.
        lane_changes: the lane changes written.
        lanes: lanes of the recording (markings minus one).
    """

    files: HighDFiles
    lane_changes_file: Path
    truth_frames_file: Path
    n_vehicles: int
    n_trucks: int
    n_rows: int
    lane_changes: tuple[LaneChange, ...]
    lanes: int


@dataclass(frozen=True, eq=False)
class _Rows:
    """Kept floating-car rows sorted by (vehicle, frame); ``M`` rows, ``V`` vehicles."""

    vid: IntArray  # (M,) highD id
    frame: IntArray  # (M,)
    x_m: FloatArray  # (M,) canonical box centre
    y_m: FloatArray  # (M,)
    vx_mps: FloatArray  # (M,)
    vy_mps: FloatArray  # (M,)
    speed_mps: FloatArray
    accel_mps2: FloatArray
    pos_lat_m: FloatArray
    lane: NDArray[np.str_]
    left_index: IntArray  # (M,) SUMO's lane counted from the median, 0 = leftmost
    leader: NDArray[np.str_]  # SUMO id
    leader_gap_m: FloatArray
    vtype: NDArray[np.str_]
    sumo_ids: list[str]  # (V,) SUMO id of highD id v + 1


def _read_csv(path: Path, columns: dict[str, str]) -> dict[str, NDArray[np.generic]]:
    """Read the named columns of a SUMO ``;``-separated CSV output (``str``/``float`` types)."""
    import pyarrow as pa
    import pyarrow.csv as pacsv

    if not path.is_file():
        raise HighwaySimError(f"SUMO wrote no {path.name} in {path.parent}")
    types = {c: pa.string() if t == "str" else pa.float64() for c, t in columns.items()}
    try:
        table = pacsv.read_csv(
            path,
            parse_options=pacsv.ParseOptions(delimiter=";"),
            convert_options=pacsv.ConvertOptions(
                include_columns=list(columns), column_types=types, strings_can_be_null=False
            ),
        )
    except (pa.ArrowInvalid, OSError) as exc:
        if "Empty CSV file" in str(exc):
            return {c: np.zeros(0, dtype=object if t == "str" else np.float64) for c, t in columns.items()}
        raise HighwaySimError(f"cannot read SUMO output {path}: {exc}") from None
    out: dict[str, NDArray[np.generic]] = {}
    for c, t in columns.items():
        values = table.column(c).to_numpy(zero_copy_only=False)
        out[c] = values.astype(str) if t == "str" else np.nan_to_num(values.astype(np.float64), nan=-1.0)
    return out


def _kept_rows(scenario: HighwayScenario, net: HighwayNetwork, fcd: Path) -> _Rows:
    cols = _read_csv(
        fcd,
        {
            "time": "f",
            "id": "str",
            "x": "f",
            "y": "f",
            "angle": "f",
            "type": "str",
            "speed": "f",
            "lane": "str",
            "posLat": "f",
            "acceleration": "f",
            "leaderID": "str",
            "leaderGap": "f",
        },
    )
    rate = scenario.frame_rate_hz
    frame = np.rint((cols["time"].astype(np.float64) - scenario.warmup_s) * rate).astype(np.int64) + 1
    vtype = cols["type"].astype(str)
    known = np.isin(vtype, list(VEHICLE_TYPES))
    if not known.all():
        raise HighwaySimError(f"{fcd}: unknown vehicle type(s) {sorted(set(vtype[~known]))[:3]}")
    length = np.select([vtype == k for k in VEHICLE_TYPES], [t.length_m for t in VEHICLE_TYPES.values()])
    heading = np.deg2rad(90.0 - cols["angle"].astype(np.float64))  # SUMO: degrees clockwise from north
    x_centre = cols["x"].astype(np.float64) - np.cos(heading) * length / 2
    y = cols["y"].astype(np.float64)
    lane = cols["lane"].astype(str)
    w = net.lane_width_m
    # SUMO's lane, as a left index: its centre line is at y - posLat (straight, parallel lanes).
    left_index = np.floor(-(y - cols["posLat"].astype(np.float64)) / w).astype(np.int64)
    y = np.clip(y, -(left_index + 1) * w + _LANE_MARGIN_M, -left_index * w - _LANE_MARGIN_M)
    inside = (
        (frame >= 1)
        & (x_centre >= net.section_start_m)
        & (x_centre <= net.section_end_m)
        & (left_index >= 0)
        & (left_index < net.max_lanes)
        & (np.char.startswith(lane, "hw") | np.char.startswith(lane, ":"))
    )
    if not inside.any():
        raise HighwaySimError(
            f"recording {scenario.recording_id:02d}: no vehicle drove through the recorded section "
            f"(demand {max(scenario.demand_vph):.0f} veh/h, {scenario.record_s:.0f} s recorded)"
        )
    ids = cols["id"].astype(str)[inside]
    frame = frame[inside]
    # highD ids in order of entry (first frame, then SUMO id); first unbroken run of frames only.
    uniq, code = np.unique(ids, return_inverse=True)
    order = np.lexsort((frame, code))
    code, frame = code[order], frame[order]
    new_vehicle = np.concatenate([[True], code[1:] != code[:-1]])
    broken = np.concatenate([[False], (frame[1:] - frame[:-1] != 1) & ~new_vehicle[1:]])
    run = np.cumsum(broken) - np.maximum.accumulate(np.where(new_vehicle, np.cumsum(broken), 0))
    keep = run == 0
    counts = np.bincount(code[keep], minlength=uniq.size)
    keep &= counts[code] >= MIN_TRACK_FRAMES
    first = np.full(uniq.size, np.iinfo(np.int64).max)
    np.minimum.at(first, code[keep], frame[keep])
    kept_vehicles = np.flatnonzero(counts >= MIN_TRACK_FRAMES)
    entry = kept_vehicles[np.lexsort((uniq[kept_vehicles], first[kept_vehicles]))]
    highd_id = np.zeros(uniq.size, dtype=np.int64)
    highd_id[entry] = np.arange(1, entry.size + 1)
    rows = np.flatnonzero(inside)[order][keep]
    vid = highd_id[code[keep]]
    final = np.lexsort((frame[keep], vid))
    rows, vid = rows[final], vid[final]
    speed = cols["speed"].astype(np.float64)[rows]
    return _Rows(
        vid=vid,
        frame=frame[keep][final],
        x_m=x_centre[rows] - net.section_start_m,
        y_m=y[rows] - IMAGE_Y_OFFSET_M,
        vx_mps=speed * np.cos(heading[rows]),
        vy_mps=speed * np.sin(heading[rows]),
        speed_mps=speed,
        accel_mps2=cols["acceleration"].astype(np.float64)[rows],
        pos_lat_m=cols["posLat"].astype(np.float64)[rows],
        lane=lane[rows],
        left_index=left_index[rows],
        leader=cols["leaderID"].astype(str)[rows],
        leader_gap_m=cols["leaderGap"].astype(np.float64)[rows],
        vtype=vtype[rows],
        sumo_ids=[str(s) for s in uniq[entry]],
    )


def _vehicles(r: _Rows) -> list[HighDVehicle]:
    starts = np.flatnonzero(np.concatenate([[True], r.vid[1:] != r.vid[:-1]]))
    ends = np.append(starts[1:], r.vid.size)
    out: list[HighDVehicle] = []
    for a, b in zip(starts.tolist(), ends.tolist(), strict=True):
        kind = VEHICLE_TYPES[str(r.vtype[a])]
        out.append(
            HighDVehicle(
                vehicle_id=int(r.vid[a]),
                vehicle_class=kind.highd_class,
                first_frame=int(r.frame[a]),
                x_m=r.x_m[a:b],
                y_m=r.y_m[a:b],
                length_m=kind.length_m,
                width_m=kind.width_m,
                vx_mps=r.vx_mps[a:b],
                vy_mps=r.vy_mps[a:b],
            )
        )
    return out


def _truth_frames(r: _Rows) -> TruthFrames:
    """Per-row truth: SUMO's leader mapped to highD ids, and the inverse relation (follower)."""
    n_ids = len(r.sumo_ids) + 1
    sumo_to_highd = {s: i + 1 for i, s in enumerate(r.sumo_ids)}
    leader = np.asarray([sumo_to_highd.get(str(s), 0) for s in r.leader], dtype=np.int64)
    key = r.frame * n_ids + r.vid
    key_order = np.argsort(key)
    lead_key = r.frame * n_ids + leader
    pos = np.clip(np.searchsorted(key[key_order], lead_key), 0, key.size - 1)
    present = (leader > 0) & (key[key_order][pos] == lead_key)
    leader = np.where(present, leader, 0)
    gap = np.where(r.leader_gap_m >= 0, r.leader_gap_m, -1.0)
    follower = np.zeros(key.size, dtype=np.int64)
    follower_gap = np.full(key.size, -1.0)
    has = np.flatnonzero(present)
    if has.size:
        # nearest follower per (frame, leader): sort by (leader key, gap), take the first of each
        by = has[np.lexsort((gap[has], lead_key[has]))]
        first = np.concatenate([[True], lead_key[by][1:] != lead_key[by][:-1]])
        chosen = by[first]
        target = key_order[pos[chosen]]
        follower[target] = r.vid[chosen]
        follower_gap[target] = gap[chosen]
    return TruthFrames(
        frame=r.frame,
        vehicle_id=r.vid,
        lane_id=r.left_index + 2,
        sumo_lane=r.lane,
        pos_lat_m=r.pos_lat_m,
        speed_mps=r.speed_mps,
        accel_mps2=r.accel_mps2,
        leader_id=leader,
        leader_gap_m=gap,
        follower_id=follower,
        follower_gap_m=follower_gap,
    )


def _lane_changes(scenario: HighwayScenario, r: _Rows, log: Path) -> list[LaneChange]:
    """Every frame a recorded vehicle's SUMO lane differs from the frame before.

    SUMO's lane-change log gives the motive (matched by vehicle and frame); a change SUMO does not
    log (it happens on a junction's internal lanes) gets the motive ``junction``.
    """
    cols = _read_csv(log, {"id": "str", "time": "f", "reason": "str"})
    rate = scenario.frame_rate_hz
    sumo_to_highd = {s: i + 1 for i, s in enumerate(r.sumo_ids)}
    logged: dict[tuple[int, int], str] = {}
    for sid, t, reason in zip(cols["id"], cols["time"], cols["reason"], strict=True):
        v = sumo_to_highd.get(str(sid), 0)
        if v:
            logged[(v, int(round((float(t) - scenario.warmup_s) * rate)) + 1)] = str(reason)
    at = np.flatnonzero((r.vid[1:] == r.vid[:-1]) & (r.left_index[1:] != r.left_index[:-1])) + 1
    raw = [
        (
            int(r.vid[i]),
            int(r.frame[i]),
            int(r.left_index[i - 1]) + 2,
            int(r.left_index[i]) + 2,
            logged.get((int(r.vid[i]), int(r.frame[i])), "junction"),
            float(r.speed_mps[i]),
            float(r.x_m[i]),
            r.sumo_ids[int(r.vid[i]) - 1],
            scenario.warmup_s + (int(r.frame[i]) - 1) / rate,
        )
        for i in at.tolist()
    ]
    raw.sort(key=lambda c: (c[0], c[1]))
    # Manoeuvres: same vehicle, same direction, crossings at most MANOEUVRE_GAP_S apart.
    group: list[int] = []
    for i, c in enumerate(raw):
        prev = raw[i - 1] if i else None
        same = (
            prev is not None
            and prev[0] == c[0]
            and (prev[3] < prev[2]) == (c[3] < c[2])
            and (c[1] - prev[1]) / rate <= MANOEUVRE_GAP_S
        )
        group.append(group[-1] if same else (group[-1] + 1 if group else 1))
    sizes = np.bincount(np.asarray(group, dtype=np.int64), minlength=1)
    return [
        LaneChange(
            recording_id=scenario.recording_id,
            vehicle_id=v,
            frame=f,
            t_s=f / rate,
            from_lane=a,
            to_lane=b,
            direction="left" if b < a else "right",
            manoeuvre=g,
            lanes_crossed=int(sizes[g]),
            reason=reason,
            speed_mps=speed,
            x_m=x,
            sumo_id=sid,
            sumo_time_s=t,
        )
        for (v, f, a, b, reason, speed, x, sid, t), g in zip(raw, group, strict=True)
    ]


def convert_run(
    scenario: HighwayScenario, net: HighwayNetwork, fcd: Path, lane_change_log: Path, out_dir: Path
) -> ConvertedRecording:
    """Write recording ``NN`` (highD files) and its ground truth into ``out_dir``.

    Raises:
        HighwaySimError: SUMO's outputs are missing or unreadable, or no vehicle crossed the
            section (e.g. a recording far too short).
    """
    rows = _kept_rows(scenario, net, fcd)
    if rows.vid.size == 0:
        raise HighwaySimError(
            f"recording {scenario.recording_id:02d}: no vehicle stayed {MIN_TRACK_FRAMES} frames in the "
            f"recorded section ({scenario.record_s:.0f} s recorded)"
        )
    vehicles = _vehicles(rows)
    w = net.lane_width_m
    markings = [IMAGE_Y_OFFSET_M + k * w for k in range(net.max_lanes + 1)]
    files = write_highd_recording(
        out_dir,
        scenario.recording_id,
        vehicles,
        upper_lane_markings_m=[],
        lower_lane_markings_m=markings,
        frame_rate_hz=scenario.frame_rate_hz,
        speed_limit_mps=scenario.speed_limit_mps,
        road_length_m=scenario.section_m,
        location_id=0,
    )
    changes = _lane_changes(scenario, rows, lane_change_log)
    lc_path = lane_changes_path(out_dir, scenario.recording_id)
    write_lane_changes(lc_path, changes)
    tf_path = truth_frames_path(out_dir, scenario.recording_id)
    write_truth_frames(tf_path, _truth_frames(rows))
    return ConvertedRecording(
        files=files,
        lane_changes_file=lc_path,
        truth_frames_file=tf_path,
        n_vehicles=len(vehicles),
        n_trucks=sum(v.vehicle_class == "Truck" for v in vehicles),
        n_rows=int(rows.vid.size),
        lane_changes=tuple(changes),
        lanes=net.max_lanes,
    )
