"""Writing highD-format recordings (tracks, tracksMeta, recordingMeta CSV files)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import pyarrow as pa
import pyarrow.csv as pacsv
from numpy.typing import NDArray

from scenariominer.data.adapters.highd.format import (
    RECORDING_META_COLUMNS,
    TRACKS_COLUMNS,
    TRACKS_META_COLUMNS,
    HighDDirection,
    HighDFiles,
)
from scenariominer.data.log import FloatArray

IntArray = NDArray[np.int64]


# ---------------------------------------------------------------------------------------- writer


@dataclass(frozen=True, eq=False)
class HighDVehicle:
    """One vehicle to write, in the canonical frame (box centre, y = -image y), ``K`` frames.

    Attributes:
        vehicle_id: positive highD id, unique in the recording.
        vehicle_class: ``"Car"`` or ``"Truck"``.
        first_frame: highD frame of the first sample; the track covers ``K`` consecutive frames.
        x_m, y_m: ``(K,)`` box centre, metres (y is negative on a highD road).
        length_m, width_m: box size, metres.
        vx_mps, vy_mps: ``(K,)`` velocity; ``None`` derives it from the positions.
        ax_mps2, ay_mps2: ``(K,)`` acceleration; ``None`` derives it from the velocity.
    """

    vehicle_id: int
    vehicle_class: str
    first_frame: int
    x_m: FloatArray
    y_m: FloatArray
    length_m: float
    width_m: float
    vx_mps: FloatArray | None = None
    vy_mps: FloatArray | None = None
    ax_mps2: FloatArray | None = None
    ay_mps2: FloatArray | None = None

    @property
    def n_frames(self) -> int:
        """Number of frames ``K``."""
        return int(np.asarray(self.x_m).shape[0])


def _derivative(values: FloatArray, dt_s: float) -> FloatArray:
    if values.size < 2:
        return np.zeros_like(values)
    return np.gradient(values, dt_s)


def _neighbours(
    code: IntArray,
    query_code: IntArray,
    x: FloatArray,
    length: FloatArray,
    sign: FloatArray,
    *,
    same_lane: bool,
    reach: int = 6,
) -> tuple[IntArray, IntArray, IntArray]:
    """Row index of the preceding, alongside and following vehicle in lane group ``query_code``.

    Rows are grouped by ``code`` (frame and lane); for each row the candidates are the ``2 * reach``
    rows of group ``query_code`` nearest in x. "Alongside" means the boxes overlap along x (never
    for the own lane); "preceding" is the nearest non-overlapping one ahead in the driving direction
    ``sign``, "following" the nearest behind. -1 where there is none.
    """
    m = x.size
    x0 = float(x.min())
    scale = float(x.max() - x0) + 10.0
    key = code.astype(np.float64) * scale + (x - x0)
    order = np.argsort(key, kind="stable")
    skey, scode = key[order], code[order]
    qkey = query_code.astype(np.float64) * scale + (x - x0)
    pos = np.searchsorted(skey, qkey)
    self_rows = np.arange(m)
    out = {name: np.full(m, -1, dtype=np.int64) for name in ("prec", "along", "fol")}
    best = {name: np.full(m, np.inf) for name in ("prec", "along", "fol")}
    for offset in range(-reach, reach):
        p = pos + offset
        ok = (p >= 0) & (p < m)
        pc = np.clip(p, 0, m - 1)
        cand = order[pc]
        ok &= (scode[pc] == query_code) & (cand != self_rows)
        ahead = (x[cand] - x) * sign
        overlap = np.zeros(m, dtype=bool) if same_lane else np.abs(ahead) < 0.5 * (length + length[cand])
        for name, hit, dist in (
            ("prec", ok & ~overlap & (ahead > 0), ahead),
            ("fol", ok & ~overlap & (ahead <= 0), -ahead),
            ("along", ok & overlap, np.abs(ahead)),
        ):
            better = hit & (dist < best[name])
            best[name][better] = dist[better]
            out[name][better] = cand[better]
    return out["prec"], out["along"], out["fol"]


def _decimal_column(values: FloatArray, decimals: int) -> pa.Array:
    return pa.array(np.round(values, decimals)).cast(pa.decimal128(18, decimals), safe=False)


def _write_csv(path: Path, columns: Sequence[str], data: Mapping[str, pa.Array | NDArray[Any]]) -> None:
    table = pa.table({c: data[c] for c in columns})
    with path.open("wb") as fh:
        fh.write((",".join(columns) + "\n").encode())
        pacsv.write_csv(
            table, fh, write_options=pacsv.WriteOptions(include_header=False, quoting_style="none")
        )


def write_highd_recording(
    out_dir: str | Path,
    recording_id: int,
    vehicles: Sequence[HighDVehicle],
    *,
    upper_lane_markings_m: Sequence[float],
    lower_lane_markings_m: Sequence[float],
    frame_rate_hz: float = 25.0,
    location_id: int = 1,
    speed_limit_mps: float | None = None,
    month: str = "09.2017",
    week_day: str = "Tue",
    start_time: str = "08:00",
    road_length_m: float | None = None,
    decimals: int = 2,
) -> HighDFiles:
    """Write vehicles as the three CSV files of a highD recording, in the published format.

    Positions are converted back to highD's image frame (upper-left box corner, y down). The
    derived columns follow the format's meaning, computed from the data:

    * ``laneId`` from the box centre's image-y and the lane markings (the lane between markings
      ``i`` and ``i + 1`` of all markings top to bottom is ``i + 2``, so a 2 + 2 lane road has lanes
      2, 3 and 5, 6 as in highD);
    * ``drivingDirection`` 2 when the mean x velocity is >= 0, else 1;
    * same-lane ``precedingId``/``followingId`` and the left/right lane's preceding, alongside
      (boxes overlap along x) and following vehicle, 0 when none ("left" is relative to the driving
      direction); ``dhw`` is the bumper-to-bumper gap to the preceding vehicle, ``thw`` = dhw /
      speed, ``ttc`` = dhw / closing speed when closing, and all three (and ``precedingXVelocity``)
      are 0 without a preceding vehicle; the meta file's ``minDHW``/``minTHW``/``minTTC`` are -1
      when never defined;
    * ``frontSightDistance``/``backSightDistance`` to the ends of the road section
      ``[min(0, rear-most x), road_length_m or front-most x]``.

    Floats are written with ``decimals`` decimals (highD uses 2).

    Args:
        out_dir: folder to write ``NN_tracks.csv``, ``NN_tracksMeta.csv``, ``NN_recordingMeta.csv``.
        recording_id: ``NN``.
        vehicles: the vehicles (any order; written by ascending id).
        upper_lane_markings_m: image-y of the upper carriageway's markings (metres, ascending).
        lower_lane_markings_m: image-y of the lower carriageway's markings (metres, ascending).
        frame_rate_hz: frames per second.
        location_id: highD location id.
        speed_limit_mps: posted limit, m/s; ``None`` writes highD's ``-1`` (no limit).
        month: ``MM.YYYY`` as in highD.
        week_day: three-letter week day.
        start_time: ``HH:MM``.
        road_length_m: image length of the road section; default: the front-most box edge.
        decimals: decimals of float columns.

    Returns:
        The paths written.

    Raises:
        ValueError: no vehicles, duplicate or non-positive ids, an unknown class, mismatched
            array lengths or non-finite positions.
    """
    if not vehicles:
        raise ValueError("write_highd_recording needs at least one vehicle")
    vehicles = sorted(vehicles, key=lambda v: v.vehicle_id)
    ids = np.array([v.vehicle_id for v in vehicles], dtype=np.int64)
    if np.any(ids <= 0) or np.unique(ids).size != ids.size:
        raise ValueError(f"vehicle ids must be positive and unique, got {ids.tolist()}")
    dt_s = 1.0 / frame_rate_hz
    cols: dict[str, list[NDArray[Any]]] = {k: [] for k in ("vid", "frame", "x", "y", "vx", "vy", "ax", "ay")}
    lengths, widths, classes = [], [], []
    for v in vehicles:
        if v.vehicle_class not in ("Car", "Truck"):
            raise ValueError(
                f"vehicle {v.vehicle_id}: class must be 'Car' or 'Truck', got {v.vehicle_class!r}"
            )
        x = np.asarray(v.x_m, dtype=np.float64)
        y = np.asarray(v.y_m, dtype=np.float64)
        k = x.size
        if k == 0 or y.shape != (k,) or not (np.all(np.isfinite(x)) and np.all(np.isfinite(y))):
            raise ValueError(
                f"vehicle {v.vehicle_id}: x_m and y_m must be equal-length, non-empty and finite"
            )
        vx = _derivative(x, dt_s) if v.vx_mps is None else np.asarray(v.vx_mps, dtype=np.float64)
        vy = _derivative(y, dt_s) if v.vy_mps is None else np.asarray(v.vy_mps, dtype=np.float64)
        ax = _derivative(vx, dt_s) if v.ax_mps2 is None else np.asarray(v.ax_mps2, dtype=np.float64)
        ay = _derivative(vy, dt_s) if v.ay_mps2 is None else np.asarray(v.ay_mps2, dtype=np.float64)
        for name, arr in (("vx_mps", vx), ("vy_mps", vy), ("ax_mps2", ax), ("ay_mps2", ay)):
            if arr.shape != (k,):
                raise ValueError(f"vehicle {v.vehicle_id}: {name} has shape {arr.shape}, expected ({k},)")
        cols["vid"].append(np.full(k, v.vehicle_id, dtype=np.int64))
        cols["frame"].append(v.first_frame + np.arange(k, dtype=np.int64))
        for name, arr in (("x", x), ("y", y), ("vx", vx), ("vy", vy), ("ax", ax), ("ay", ay)):
            cols[name].append(arr)
        lengths.append(float(v.length_m))
        widths.append(float(v.width_m))
        classes.append(v.vehicle_class)
    c = {name: np.concatenate(parts) for name, parts in cols.items()}
    counts = np.array([v.n_frames for v in vehicles], dtype=np.int64)
    starts = np.concatenate([[0], np.cumsum(counts)[:-1]]).astype(np.int64)
    row_v = np.repeat(np.arange(len(vehicles)), counts)
    length = np.asarray(lengths)[row_v]
    width = np.asarray(widths)[row_v]
    mean_vx = np.add.reduceat(c["vx"], starts) / counts
    direction = np.where(mean_vx >= 0, int(HighDDirection.RIGHT), int(HighDDirection.LEFT)).astype(np.int64)
    sign = np.where(direction[row_v] == HighDDirection.RIGHT, 1.0, -1.0)

    # Image frame.
    img_y_centre = -c["y"]
    markings = np.sort(np.concatenate([np.asarray(upper_lane_markings_m), np.asarray(lower_lane_markings_m)]))
    lane = (np.searchsorted(markings, img_y_centre, side="right") + 1).astype(np.int64)

    # Surrounding vehicles.
    lane_span = int(markings.size) + 4
    code = c["frame"] * lane_span + lane
    step = np.where(sign > 0, -1, 1).astype(np.int64)  # lane id of the left neighbour is lane + step
    prec, _, fol = _neighbours(code, code, c["x"], length, sign, same_lane=True)
    lp, la, lf = _neighbours(code, code + step, c["x"], length, sign, same_lane=False)
    rp, ra, rf = _neighbours(code, code - step, c["x"], length, sign, same_lane=False)

    def ids_of(rows: IntArray) -> IntArray:
        return np.where(rows >= 0, c["vid"][np.clip(rows, 0, None)], 0).astype(np.int64)

    has_prec = prec >= 0
    pc = np.clip(prec, 0, None)
    speed = np.abs(c["vx"])
    dhw = np.where(has_prec, (c["x"][pc] - c["x"]) * sign - 0.5 * (length + length[pc]), 0.0)
    thw = np.where(has_prec & (speed > 0), dhw / np.where(speed > 0, speed, 1.0), 0.0)
    closing = speed - np.abs(c["vx"][pc])
    ttc_ok = has_prec & (closing > 0)
    ttc = np.where(ttc_ok, dhw / np.where(closing > 0, closing, 1.0), 0.0)
    prec_vx = np.where(has_prec, c["vx"][pc], 0.0)
    rear = c["x"] - 0.5 * length
    front = c["x"] + 0.5 * length
    road_start = min(0.0, float(rear.min()))
    road_end = float(front.max()) if road_length_m is None else float(road_length_m)
    front_sight = np.where(sign > 0, road_end - front, rear - road_start)
    back_sight = np.where(sign > 0, rear - road_start, road_end - front)

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    files = HighDFiles.for_recording(out, recording_id)

    def dec(a: FloatArray) -> pa.Array:
        return _decimal_column(a, decimals)

    tracks: dict[str, pa.Array | NDArray[Any]] = {
        "frame": c["frame"],
        "id": c["vid"],
        "x": dec(rear),
        "y": dec(img_y_centre - 0.5 * width),
        "width": dec(length),
        "height": dec(width),
        "xVelocity": dec(c["vx"]),
        "yVelocity": dec(-c["vy"]),
        "xAcceleration": dec(c["ax"]),
        "yAcceleration": dec(-c["ay"]),
        "frontSightDistance": dec(front_sight),
        "backSightDistance": dec(back_sight),
        "dhw": dec(dhw),
        "thw": dec(thw),
        "ttc": dec(ttc),
        "precedingXVelocity": dec(prec_vx),
        "precedingId": ids_of(prec),
        "followingId": ids_of(fol),
        "leftPrecedingId": ids_of(lp),
        "leftAlongsideId": ids_of(la),
        "leftFollowingId": ids_of(lf),
        "rightPrecedingId": ids_of(rp),
        "rightAlongsideId": ids_of(ra),
        "rightFollowingId": ids_of(rf),
        "laneId": lane,
    }
    _write_csv(files.tracks, TRACKS_COLUMNS, tracks)

    # Per-vehicle statistics (reduceat over each vehicle's contiguous rows).
    def seg_min(values: FloatArray, valid: NDArray[np.bool_]) -> FloatArray:
        mins = np.minimum.reduceat(np.where(valid, values, np.inf), starts)
        return np.where(np.isfinite(mins), mins, -1.0)

    step_len = np.hypot(np.diff(c["x"], prepend=c["x"][0]), np.diff(c["y"], prepend=c["y"][0]))
    step_len[starts] = 0.0
    lane_change = np.concatenate([[0], (lane[1:] != lane[:-1]).astype(np.int64)])
    lane_change[starts] = 0
    traveled = np.add.reduceat(step_len, starts)
    tracks_meta: dict[str, pa.Array | NDArray[Any]] = {
        "id": ids,
        "width": dec(np.asarray(lengths)),
        "height": dec(np.asarray(widths)),
        "initialFrame": c["frame"][starts],
        "finalFrame": c["frame"][starts + counts - 1],
        "numFrames": counts,
        "class": pa.array(classes, type=pa.string()),
        "drivingDirection": direction,
        "traveledDistance": dec(traveled),
        "minXVelocity": dec(np.minimum.reduceat(speed, starts)),
        "maxXVelocity": dec(np.maximum.reduceat(speed, starts)),
        "meanXVelocity": dec(np.add.reduceat(speed, starts) / counts),
        "minDHW": dec(seg_min(dhw, has_prec)),
        "minTHW": dec(seg_min(thw, has_prec & (thw > 0))),
        "minTTC": dec(seg_min(ttc, ttc_ok)),
        "numLaneChanges": np.add.reduceat(lane_change, starts).astype(np.int64),
    }
    _write_csv(files.tracks_meta, TRACKS_META_COLUMNS, tracks_meta)

    def num(value: float) -> str:
        return str(int(value)) if float(value).is_integer() else f"{value:.{decimals}f}"

    n_trucks = sum(1 for cls in classes if cls == "Truck")
    frames_all = c["frame"]
    recording_meta = {
        "id": str(recording_id),
        "frameRate": num(frame_rate_hz),
        "locationId": str(location_id),
        "speedLimit": f"{-1.0 if speed_limit_mps is None else speed_limit_mps:.2f}",
        "month": month,
        "weekDay": week_day,
        "startTime": start_time,
        "duration": f"{(int(frames_all.max()) - int(frames_all.min()) + 1) * dt_s:.2f}",
        "totalDrivenDistance": f"{float(traveled.sum()):.2f}",
        "totalDrivenTime": f"{float(counts.sum()) * dt_s:.2f}",
        "numVehicles": str(len(vehicles)),
        "numCars": str(len(vehicles) - n_trucks),
        "numTrucks": str(n_trucks),
        "upperLaneMarkings": ";".join(f"{m:.2f}" for m in upper_lane_markings_m),
        "lowerLaneMarkings": ";".join(f"{m:.2f}" for m in lower_lane_markings_m),
    }
    files.recording_meta.write_text(
        ",".join(RECORDING_META_COLUMNS)
        + "\n"
        + ",".join(recording_meta[k] for k in RECORDING_META_COLUMNS)
        + "\n",
        encoding="utf-8",
    )
    return files
