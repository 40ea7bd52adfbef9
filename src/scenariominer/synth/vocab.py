"""The generator's public vocabulary: scenario categories, map layouts, labels and their CSV files."""

from __future__ import annotations

import csv
from collections.abc import Sequence
from dataclasses import dataclass
from enum import StrEnum
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from scenariominer.data.adapters.av2.map import (
    Av2Map,
)
from scenariominer.data.log import Log

BoolArray = NDArray[np.bool_]


# ---------------------------------------------------------------------- public vocabulary


class ScenarioCategory(StrEnum):
    """Scenario categories of the braking paper (Table III) that the generator produces."""

    CUT_IN = "cut_in"
    LEAD_BRAKE = "lead_brake"
    APPROACH_STOP = "approach_stop"
    PED_CROSSING = "ped_crossing"
    OBJ_CROSSING = "obj_crossing"
    LEFT_OPPO = "left_oppo"
    RIGHT_PED = "right_ped"
    NOT_RELEVANT = "not_relevant"


class MapLayout(StrEnum):
    """Road layouts of the synthetic vector maps."""

    STRAIGHT = "straight"
    INTERSECTION = "intersection"


#: Columns of ``labels.csv``.
LABEL_COLUMNS: tuple[str, ...] = ("log_id", "guest_id", "scenario_category", "start_ns", "end_ns")

#: Frame period (s) and number of frames of a generated log (15 s at 10 Hz).
FRAME_PERIOD_S = 0.1
N_FRAMES = 150

#: Road geometry (metres): lane width, half-width of a road (two lanes each way), half-size of the
#: intersection box, length of each arm from the centre, crosswalk near/far distance from the centre.
LANE_WIDTH_M = 3.5
ROAD_HALF_WIDTH_M = 7.0
BOX_HALF_M = 12.0
ARM_M = 300.0
CROSSWALK_NEAR_M = 13.0
CROSSWALK_FAR_M = 16.0

#: Guests within this distance (m) of the ego define a ``not_relevant`` label's window.
NOT_RELEVANT_RANGE_M = 40.0


@dataclass(frozen=True)
class ScenarioLabel:
    """One row of ``labels.csv``.

    Attributes:
        log_id: the log's id (its folder name).
        guest_id: track id of the labelled guest object.
        scenario_category: what the guest does to the ego.
        start_ns: first timestamp of the interaction window (a timestamp of the log).
        end_ns: last timestamp of the interaction window.
    """

    log_id: str
    guest_id: str
    scenario_category: ScenarioCategory
    start_ns: int
    end_ns: int


@dataclass(frozen=True, eq=False)
class SynthLog:
    """One generated scenario in memory.

    Attributes:
        log: the log, ego at its box centre, ``dataset="synthetic"``.
        av2_map: its vector map (city frame).
        label: the labelled guest and window.
        layout: the road layout of the map.
    """

    log: Log
    av2_map: Av2Map
    label: ScenarioLabel
    layout: MapLayout


@dataclass(frozen=True)
class SynthResult:
    """What :func:`generate` wrote.

    Attributes:
        out_dir: the output folder (holds one folder per log and ``labels.csv``).
        labels_csv: path of ``labels.csv``.
        log_dirs: ``(n,)`` Argoverse 2 log folders, in generation order.
        labels: ``(n,)`` label rows, in the same order.
        n_tracks: ``(n,)`` tracks per log, the ego included (what a reader returns).
    """

    out_dir: Path
    labels_csv: Path
    log_dirs: tuple[Path, ...]
    labels: tuple[ScenarioLabel, ...]
    n_tracks: tuple[int, ...]


def write_labels(labels: Sequence[ScenarioLabel], path: Path) -> Path:
    """Write label rows as CSV with the columns :data:`LABEL_COLUMNS`."""
    path.parent.mkdir(parents=True, exist_ok=True)
    with path.open("w", newline="", encoding="utf-8") as fh:
        writer = csv.writer(fh)
        writer.writerow(LABEL_COLUMNS)
        for lab in labels:
            writer.writerow([lab.log_id, lab.guest_id, lab.scenario_category.value, lab.start_ns, lab.end_ns])
    return path


def read_labels(path: Path) -> tuple[ScenarioLabel, ...]:
    """Read a labels CSV written by :func:`write_labels` (or annotated by hand in the same layout).

    Raises:
        ValueError: a column is missing, or a row has an unknown category or non-integer times.
    """
    with Path(path).open(newline="", encoding="utf-8") as fh:
        reader = csv.DictReader(fh)
        missing = [c for c in LABEL_COLUMNS if c not in (reader.fieldnames or [])]
        if missing:
            raise ValueError(f"{path}: missing label column(s) {missing}; expected {list(LABEL_COLUMNS)}")
        out = []
        for line, row in enumerate(reader, start=2):
            try:
                out.append(
                    ScenarioLabel(
                        row["log_id"],
                        row["guest_id"],
                        ScenarioCategory(row["scenario_category"]),
                        int(row["start_ns"]),
                        int(row["end_ns"]),
                    )
                )
            except ValueError as exc:
                raise ValueError(f"{path}:{line}: {exc}") from None
    return tuple(out)
