"""Hand-built windows with known manoeuvres, and a small highD-format highway recording."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from scenariominer.data.adapters.highd import HighDFiles, HighDVehicle, write_highd_recording
from scenariominer.represent.windows import WindowSet

N_STEPS = 31
LENGTH_S = 15.0
LANE_WIDTH_M = 3.8


@dataclass(frozen=True)
class Agent:
    """One road user of a hand-built window: start offset, speed, lanes and lateral path."""

    track_id: str
    x0_m: float
    speed_mps: float
    lane: int
    y0_m: float = 0.0
    change_at_step: int | None = None
    change_lanes: int = 0  # +1: one lane to the left (new lane id lane - 1), -1: to the right
    category: str = "REGULAR_VEHICLE"


def window_of(agents: Sequence[Agent], log_id: str = "highd-01-ego7-w0", start_s: float = 0.0) -> WindowSet:
    """One window (row 0 = the first agent) in the chosen agent's start frame."""
    t = np.linspace(0.0, LENGTH_S, N_STEPS)
    a = len(agents)
    xy = np.zeros((1, a, N_STEPS, 2), np.float32)
    v = np.zeros((1, a, N_STEPS, 2), np.float32)
    lanes = np.zeros((1, a, N_STEPS), np.int64)
    for i, ag in enumerate(agents):
        y = np.full(N_STEPS, ag.y0_m)
        lane = np.full(N_STEPS, ag.lane)
        if ag.change_at_step is not None:
            u = np.clip((np.arange(N_STEPS) - ag.change_at_step + 2) / 4.0, 0.0, 1.0)
            y = ag.y0_m + ag.change_lanes * LANE_WIDTH_M * 0.5 * (1 - np.cos(np.pi * u))
            lane = np.where(np.arange(N_STEPS) >= ag.change_at_step, ag.lane - ag.change_lanes, ag.lane)
        xy[0, i, :, 0] = ag.x0_m + ag.speed_mps * t
        xy[0, i, :, 1] = y
        v[0, i, :, 0] = ag.speed_mps
        v[0, i, :, 1] = np.gradient(y, t)
        lanes[0, i] = lane
    return WindowSet(
        window_ids=np.asarray([f"{log_id}|{agents[0].track_id}|{round(start_s * 1000)}|15000"]),
        log_ids=np.asarray([log_id]),
        agent_ids=np.asarray([agents[0].track_id]),
        start_ns=np.asarray([round((start_s + 0.04) * 1e9)], np.int64),
        start_s=np.asarray([start_s]),
        length_s=np.asarray([LENGTH_S]),
        track_ids=np.asarray([[ag.track_id for ag in agents]]),
        categories=np.asarray([[ag.category for ag in agents]]),
        xy_m=xy,
        vxy_mps=v,
        valid=np.ones((1, a, N_STEPS), bool),
        lane_ids=lanes,
    )


#: lower carriageway of a 3 + 3 lane road: markings (image-y, m) and lane centres (canonical y)
UPPER_MARKINGS_M = (8.0, 11.8, 15.6, 19.4)
LOWER_MARKINGS_M = (22.0, 25.8, 29.6, 33.4)
LOWER_LANES = {6: -23.9, 7: -27.7, 8: -31.5}  # 8 is the rightmost lane driving towards +x


def write_highway(out_dir: Path, recording_id: int = 1, frame_rate_hz: float = 25.0) -> HighDFiles:
    """A 60 s recording: cruising cars on three lanes plus a known left lane change and an overtake.

    Vehicle 7 starts in lane 8 at 30 m/s and moves one lane to the left (lane 7) from 20 s to 24 s,
    passing the 22 m/s truck 3 that keeps lane 8. Others keep their lanes at fixed speeds.
    """
    fr = frame_rate_hz
    k = int(60 * fr)
    t = np.arange(k) / fr
    vehicles = []
    plan = [  # id, class, x0, v, lane
        (1, "Car", 40.0, 27.0, 7),
        (2, "Car", 90.0, 33.0, 6),
        (3, "Truck", 120.0, 22.0, 8),
        (4, "Car", 10.0, 33.0, 6),
        (5, "Car", 160.0, 27.0, 7),
    ]
    for vid, cls, x0, v, lane in plan:
        vehicles.append(
            HighDVehicle(
                vid,
                cls,
                1,
                x0 + v * t,
                np.full(k, LOWER_LANES[lane]),
                12.0 if cls == "Truck" else 4.5,
                2.5 if cls == "Truck" else 1.9,
                np.full(k, v),
                np.zeros(k),
            )  # fmt: skip
        )
    u = np.clip((t - 20.0) / 4.0, 0.0, 1.0)
    y = LOWER_LANES[8] + (LOWER_LANES[7] - LOWER_LANES[8]) * 0.5 * (1 - np.cos(np.pi * u))
    vy = np.gradient(y, t)
    vehicles.append(HighDVehicle(7, "Car", 1, 0.0 + 30.0 * t, y, 4.5, 1.9, np.full(k, 30.0), vy))
    return write_highd_recording(
        out_dir,
        recording_id,
        vehicles,
        upper_lane_markings_m=UPPER_MARKINGS_M,
        lower_lane_markings_m=LOWER_MARKINGS_M,
        frame_rate_hz=fr,
        speed_limit_mps=36.0,
    )
