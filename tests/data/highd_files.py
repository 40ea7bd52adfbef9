"""Small highD-format recordings for tests, written with the real three-file layout.

The road is a 2 + 2 lane highway: the upper carriageway (lanes 2 and 3, driving towards -x) and
the lower one (lanes 5 and 6, driving towards +x), lane markings at image-y 8.0/11.8/15.6 and
21.0/24.8/28.6 m, so lane centres lie at image-y 9.9, 13.7, 22.9 and 26.7 m (canonical y is the
negative). At 25 Hz, vehicle ``i`` starting at frame ``f0`` is at ``x0 + v * (f - f0) / 25``:

====  =====  ======================  =====  =========  ==========  ==================
id    class  lane                    x0 m   v m/s      frames      size (L x W) m
====  =====  ======================  =====  =========  ==========  ==================
1     Car    5                       10     +30        1..300      4.5 x 1.9
2     Truck  6                       50     +22        1..500      12.0 x 2.5
3     Car    6 -> 5 (frames 101-201)  0     +28        51..350     4.5 x 1.9
4     Car    2                       480    -25        1..400      4.2 x 1.8
5     Car    5                       5      +30        450..470    4.5 x 1.9
====  =====  ======================  =====  =========  ==========  ==================

Car 3 changes lane with a half-cosine lateral profile over 4 s starting 2 s after it appears.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import numpy as np

from scenariominer.config import Config, IngestConfig
from scenariominer.data.adapters.highd import HighDFiles, HighDVehicle, write_highd_recording

FRAME_RATE_HZ = 25.0
UPPER_MARKINGS_M = (8.0, 11.8, 15.6)
LOWER_MARKINGS_M = (21.0, 24.8, 28.6)
LANE_CENTRE_IMAGE_Y_M = {2: 9.9, 3: 13.7, 5: 22.9, 6: 26.7}

#: (id, class, x0, v, first frame, n frames, length, width, lane)
VEHICLES: tuple[tuple[int, str, float, float, int, int, float, float, int], ...] = (
    (1, "Car", 10.0, 30.0, 1, 300, 4.5, 1.9, 5),
    (2, "Truck", 50.0, 22.0, 1, 500, 12.0, 2.5, 6),
    (3, "Car", 0.0, 28.0, 51, 300, 4.5, 1.9, 6),
    (4, "Car", 480.0, -25.0, 1, 400, 4.2, 1.8, 2),
    (5, "Car", 5.0, 30.0, 450, 21, 4.5, 1.9, 5),
)
LANE_CHANGE_START_S = 2.0
LANE_CHANGE_DURATION_S = 4.0


def lane_change_y(t_local_s: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Canonical y and vy of car 3 at ``t_local_s`` seconds after its first frame."""
    y0, y1 = -LANE_CENTRE_IMAGE_Y_M[6], -LANE_CENTRE_IMAGE_Y_M[5]
    u = np.clip((t_local_s - LANE_CHANGE_START_S) / LANE_CHANGE_DURATION_S, 0.0, 1.0)
    y = y0 + (y1 - y0) * 0.5 * (1.0 - np.cos(np.pi * u))
    inside = (u > 0.0) & (u < 1.0)
    vy = np.where(inside, (y1 - y0) * 0.5 * np.pi / LANE_CHANGE_DURATION_S * np.sin(np.pi * u), 0.0)
    return y, vy


def position(vehicle_id: int, frame: np.ndarray | int) -> tuple[np.ndarray, np.ndarray]:
    """Analytic canonical box centre (x, y) of a vehicle at highD ``frame``."""
    vid, _cls, x0, v, f0, _k, _l, _w, lane = VEHICLES[vehicle_id - 1]
    t = (np.asarray(frame, dtype=float) - f0) / FRAME_RATE_HZ
    x = x0 + v * t
    y = lane_change_y(t)[0] if vid == 3 else np.full_like(t, -LANE_CENTRE_IMAGE_Y_M[lane])
    return x, y


def small_highway_vehicles() -> list[HighDVehicle]:
    """The five vehicles of the table above."""
    out = []
    for vid, cls, x0, v, f0, k, length, width, lane in VEHICLES:
        t = np.arange(k) / FRAME_RATE_HZ
        if vid == 3:
            y, vy = lane_change_y(t)
        else:
            y, vy = np.full(k, -LANE_CENTRE_IMAGE_Y_M[lane]), np.zeros(k)
        out.append(
            HighDVehicle(
                vehicle_id=vid,
                vehicle_class=cls,
                first_frame=f0,
                x_m=x0 + v * t,
                y_m=y,
                length_m=length,
                width_m=width,
                vx_mps=np.full(k, v),
                vy_mps=vy,
            )
        )
    return out


def write_small_highway(out_dir: Path, recording_id: int = 1) -> HighDFiles:
    """Write the small 2 + 2 lane recording as ``NN_tracks.csv`` and its meta files."""
    return write_highd_recording(
        out_dir,
        recording_id,
        small_highway_vehicles(),
        upper_lane_markings_m=UPPER_MARKINGS_M,
        lower_lane_markings_m=LOWER_MARKINGS_M,
        frame_rate_hz=FRAME_RATE_HZ,
        speed_limit_mps=33.33,
    )


def highd_config(window_s: float = 4.0, **ingest: object) -> Config:
    """A config with short highD windows (the small recording lasts 20 s)."""
    return Config(ingest=IngestConfig(highd_window_s=window_s, **ingest))  # type: ignore[arg-type]


def edit_csv(path: Path, edit: Callable[[list[list[str]]], list[list[str]]]) -> None:
    """Rewrite a CSV file through ``edit`` over its rows (the header is row 0)."""
    rows = [line.split(",") for line in path.read_text(encoding="utf-8").splitlines()]
    path.write_text("\n".join(",".join(r) for r in edit(rows)) + "\n", encoding="utf-8")
