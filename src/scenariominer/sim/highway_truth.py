"""The simulator's ground truth beside simulated highD recordings: writing and reading it.

Two CSV files per recording ``NN`` (comma separated, one header line), in the recording's id
space (the highD ``id`` and ``frame`` of ``NN_tracks.csv``) and lane numbering (highD ``laneId``
of the lower carriageway: 2 is the lane next to the median, higher ids further right):

``NN_laneChanges.csv`` — one row per lane boundary crossed: every frame at which SUMO has a
recorded vehicle on another lane than at the frame before, sorted by (vehicle, frame); the motive
comes from SUMO's lane-change log (``--lanechange-output``):

====================  ========================================================================
column                meaning
====================  ========================================================================
``recording_id``      ``NN``
``vehicle_id``        highD id of the vehicle
``frame``             first highD frame on the new lane (``laneId`` of ``NN_tracks.csv`` is
                      ``to_lane`` at this frame and ``from_lane`` at the frame before)
``t_s``               ``frame / frameRate``, seconds (the highD adapter's clock)
``from_lane``         highD ``laneId`` before the change
``to_lane``           highD ``laneId`` after the change
``direction``         ``left`` or ``right`` (relative to the driving direction)
``manoeuvre``         id of the manoeuvre within the recording: consecutive crossings of one
                      vehicle in one direction at most :data:`MANOEUVRE_GAP_S` apart
``lanes_crossed``     lane boundaries crossed by that manoeuvre (2+ = a multi-lane change)
``reason``            SUMO's motive: ``strategic`` (route, lane ends, merge), ``speedGain``,
                      ``keepRight``, ``cooperative``, ``sublane``; ``|urgent`` etc. appended;
                      ``junction`` for a change inside a junction, which SUMO does not log
``speed_mps``         speed at the change, m/s
``x_m``               box centre along the recorded section, metres (highD ``x + width / 2``)
``sumo_id``           SUMO's vehicle id
``sumo_time_s``       SUMO's simulation time of ``frame``, seconds
====================  ========================================================================

``NN_truthFrames.csv`` — one row per row of ``NN_tracks.csv`` (same vehicles and frames):

====================  ========================================================================
column                meaning
====================  ========================================================================
``frame``, ``id``     highD frame and vehicle id
``lane_id``           highD ``laneId`` from SUMO's own lane (equal to the recording's; on
                      junction-internal lanes from the lateral position)
``sumo_lane``         SUMO lane id (``hw<k>_<i>``, ``i`` counted from the right; ``:...`` inside
                      a junction)
``pos_lat_m``         SUMO lateral offset from the lane centre, metres (left positive)
``speed_mps``         SUMO speed, m/s
``accel_mps2``        SUMO longitudinal acceleration, m/s²
``leader_id``         SUMO's leader (highD id; 0: none within 150 m or not in the recording)
``leader_gap_m``      gap to SUMO's leader, metres (bumper to bumper, minGap excluded; -1 none)
``follower_id``       the vehicle whose SUMO leader this one is (nearest such; 0 none)
``follower_gap_m``    that vehicle's gap, metres (-1 none)
====================  ========================================================================
"""

from __future__ import annotations

import csv
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from scenariominer.sim.highway_scenario import HighwaySimError

__all__ = [
    "LANE_CHANGE_COLUMNS",
    "MANOEUVRE_GAP_S",
    "TRUTH_FRAME_COLUMNS",
    "HighwayTruth",
    "LaneChange",
    "TruthFrames",
    "lane_changes_path",
    "read_highway_truth",
    "read_truth_frames",
    "truth_frames_path",
    "write_lane_changes",
    "write_truth_frames",
]

#: Crossings of one vehicle in one direction at most this far apart form one manoeuvre, seconds.
MANOEUVRE_GAP_S = 4.0

#: Columns of ``NN_laneChanges.csv``.
LANE_CHANGE_COLUMNS: tuple[str, ...] = (
    "recording_id",
    "vehicle_id",
    "frame",
    "t_s",
    "from_lane",
    "to_lane",
    "direction",
    "manoeuvre",
    "lanes_crossed",
    "reason",
    "speed_mps",
    "x_m",
    "sumo_id",
    "sumo_time_s",
)

#: Columns of ``NN_truthFrames.csv``.
TRUTH_FRAME_COLUMNS: tuple[str, ...] = (
    "frame",
    "id",
    "lane_id",
    "sumo_lane",
    "pos_lat_m",
    "speed_mps",
    "accel_mps2",
    "leader_id",
    "leader_gap_m",
    "follower_id",
    "follower_gap_m",
)


def lane_changes_path(folder: Path, recording_id: int) -> Path:
    """``folder / NN_laneChanges.csv``."""
    return folder / f"{recording_id:02d}_laneChanges.csv"


def truth_frames_path(folder: Path, recording_id: int) -> Path:
    """``folder / NN_truthFrames.csv``."""
    return folder / f"{recording_id:02d}_truthFrames.csv"


@dataclass(frozen=True)
class LaneChange:
    """One lane boundary crossed (a row of ``NN_laneChanges.csv``; see the module docstring)."""

    recording_id: int
    vehicle_id: int
    frame: int
    t_s: float
    from_lane: int
    to_lane: int
    direction: str
    manoeuvre: int
    lanes_crossed: int
    reason: str
    speed_mps: float
    x_m: float
    sumo_id: str
    sumo_time_s: float


@dataclass(frozen=True, eq=False)
class TruthFrames:
    """``NN_truthFrames.csv`` as columns over ``M`` rows (see the module docstring).

    Attributes:
        frame, vehicle_id, lane_id, leader_id, follower_id: ``(M,)`` int64.
        sumo_lane: ``(M,)`` str.
        pos_lat_m, speed_mps, accel_mps2, leader_gap_m, follower_gap_m: ``(M,)`` float64.
    """

    frame: NDArray[np.int64]
    vehicle_id: NDArray[np.int64]
    lane_id: NDArray[np.int64]
    sumo_lane: NDArray[np.str_]
    pos_lat_m: NDArray[np.float64]
    speed_mps: NDArray[np.float64]
    accel_mps2: NDArray[np.float64]
    leader_id: NDArray[np.int64]
    leader_gap_m: NDArray[np.float64]
    follower_id: NDArray[np.int64]
    follower_gap_m: NDArray[np.float64]


@dataclass(frozen=True)
class HighwayTruth:
    """The ground truth of a folder of simulated recordings.

    Attributes:
        folder: the folder.
        recording_ids: recordings that have a lane-change file, ascending.
        lane_changes: every lane change, sorted by (recording, vehicle, frame).
    """

    folder: Path
    recording_ids: tuple[int, ...]
    lane_changes: tuple[LaneChange, ...]

    def of_recording(self, recording_id: int) -> tuple[LaneChange, ...]:
        """Lane changes of one recording."""
        return tuple(c for c in self.lane_changes if c.recording_id == recording_id)

    def frames(self, recording_id: int) -> TruthFrames:
        """The per-frame truth of one recording (read on each call)."""
        return read_truth_frames(truth_frames_path(self.folder, recording_id))


def write_lane_changes(path: Path, changes: Sequence[LaneChange]) -> None:
    """Write ``NN_laneChanges.csv`` (rows in the given order)."""
    with path.open("w", newline="", encoding="utf-8") as fh:
        writer = csv.writer(fh, lineterminator="\n")
        writer.writerow(LANE_CHANGE_COLUMNS)
        for c in changes:
            writer.writerow(
                [
                    c.recording_id,
                    c.vehicle_id,
                    c.frame,
                    f"{c.t_s:.3f}",
                    c.from_lane,
                    c.to_lane,
                    c.direction,
                    c.manoeuvre,
                    c.lanes_crossed,
                    c.reason,
                    f"{c.speed_mps:.2f}",
                    f"{c.x_m:.2f}",
                    c.sumo_id,
                    f"{c.sumo_time_s:.2f}",
                ]
            )


def write_truth_frames(path: Path, frames: TruthFrames) -> None:
    """Write ``NN_truthFrames.csv`` with pyarrow (floats with 3 decimals)."""
    import pyarrow as pa
    import pyarrow.csv as pacsv

    def dec(values: NDArray[np.float64]) -> pa.Array:
        return pa.array(np.round(values, 3)).cast(pa.decimal128(18, 3), safe=False)

    table = pa.table(
        {
            "frame": frames.frame,
            "id": frames.vehicle_id,
            "lane_id": frames.lane_id,
            "sumo_lane": pa.array(frames.sumo_lane.tolist(), type=pa.string()),
            "pos_lat_m": dec(frames.pos_lat_m),
            "speed_mps": dec(frames.speed_mps),
            "accel_mps2": dec(frames.accel_mps2),
            "leader_id": frames.leader_id,
            "leader_gap_m": dec(frames.leader_gap_m),
            "follower_id": frames.follower_id,
            "follower_gap_m": dec(frames.follower_gap_m),
        }
    )
    pacsv.write_csv(table, path, write_options=pacsv.WriteOptions(quoting_style="none"))


def read_truth_frames(path: Path) -> TruthFrames:
    """Read ``NN_truthFrames.csv``.

    Raises:
        HighwaySimError: the file is missing, lacks a column or cannot be parsed.
    """
    import pyarrow as pa
    import pyarrow.csv as pacsv

    if not path.is_file():
        raise HighwaySimError(f"{path}: ground-truth frame file is missing")
    ints = ("frame", "id", "lane_id", "leader_id", "follower_id")
    types = {
        c: (pa.int64() if c in ints else pa.string() if c == "sumo_lane" else pa.float64())
        for c in TRUTH_FRAME_COLUMNS
    }
    try:
        table = pacsv.read_csv(path, convert_options=pacsv.ConvertOptions(column_types=types))
    except (pa.ArrowInvalid, OSError) as exc:
        raise HighwaySimError(f"{path}: cannot parse the ground-truth frames ({exc})") from None
    missing = [c for c in TRUTH_FRAME_COLUMNS if c not in table.column_names]
    if missing:
        raise HighwaySimError(f"{path}: missing column(s) {missing}; expected {list(TRUTH_FRAME_COLUMNS)}")

    def col(name: str) -> NDArray[np.generic]:
        return np.asarray(table.column(name).to_numpy(zero_copy_only=False))

    return TruthFrames(
        frame=col("frame").astype(np.int64),
        vehicle_id=col("id").astype(np.int64),
        lane_id=col("lane_id").astype(np.int64),
        sumo_lane=col("sumo_lane").astype(str),
        pos_lat_m=col("pos_lat_m").astype(np.float64),
        speed_mps=col("speed_mps").astype(np.float64),
        accel_mps2=col("accel_mps2").astype(np.float64),
        leader_id=col("leader_id").astype(np.int64),
        leader_gap_m=col("leader_gap_m").astype(np.float64),
        follower_id=col("follower_id").astype(np.int64),
        follower_gap_m=col("follower_gap_m").astype(np.float64),
    )


def _lane_change(path: Path, line: int, row: dict[str, str]) -> LaneChange:
    try:
        return LaneChange(
            recording_id=int(row["recording_id"]),
            vehicle_id=int(row["vehicle_id"]),
            frame=int(row["frame"]),
            t_s=float(row["t_s"]),
            from_lane=int(row["from_lane"]),
            to_lane=int(row["to_lane"]),
            direction=row["direction"],
            manoeuvre=int(row["manoeuvre"]),
            lanes_crossed=int(row["lanes_crossed"]),
            reason=row["reason"],
            speed_mps=float(row["speed_mps"]),
            x_m=float(row["x_m"]),
            sumo_id=row["sumo_id"],
            sumo_time_s=float(row["sumo_time_s"]),
        )
    except (KeyError, ValueError, TypeError) as exc:
        raise HighwaySimError(f"{path}, line {line}: not a lane-change row ({exc!r})") from None


def read_highway_truth(folder: str | Path) -> HighwayTruth:
    """Read every ``NN_laneChanges.csv`` of a folder written by ``scenariominer simulate highway``.

    Raises:
        HighwaySimError: the folder holds no lane-change file, or a file lacks a column or has a
            malformed row (the message names file and line).
    """
    root = Path(folder)
    files = sorted(root.glob("[0-9][0-9]_laneChanges.csv"))
    if not files:
        raise HighwaySimError(
            f"{root}: no NN_laneChanges.csv file "
            "(expected the output folder of `scenariominer simulate highway`)"
        )
    changes: list[LaneChange] = []
    ids: list[int] = []
    for path in files:
        ids.append(int(path.name[:2]))
        with path.open(newline="", encoding="utf-8") as fh:
            reader = csv.DictReader(fh)
            missing = [c for c in LANE_CHANGE_COLUMNS if c not in (reader.fieldnames or [])]
            if missing:
                raise HighwaySimError(
                    f"{path}: missing column(s) {missing}; expected {list(LANE_CHANGE_COLUMNS)}"
                )
            changes.extend(_lane_change(path, i + 2, row) for i, row in enumerate(reader))
    changes.sort(key=lambda c: (c.recording_id, c.vehicle_id, c.frame))
    return HighwayTruth(folder=root, recording_ids=tuple(ids), lane_changes=tuple(changes))
