"""An urban run as an Argoverse 2 log: a 15 s window, tracker-like noise, the vector map.

The window holds :data:`WINDOW_S` seconds at 10 Hz around the ego's braking onset (the onset
4-7 s in, clipped to the run). Road users are kept while within :data:`VISIBLE_M` of the ego
(and with at least 5 frames). The scene is placed in a city frame by a random rotation and
translation (the map goes through the same transform). Noise by :class:`NoiseLevel`:

=========  ===========  =========  ==============  ==================  ======
level      position σ   yaw σ      dropped frames  id switches         ghosts
=========  ===========  =========  ==============  ==================  ======
none       0            0          0               0                   0
low        0.05 m       0.01 rad   1 %             0                   0
medium     0.15 m       0.03 rad   4 %             1 (guest: 40 %)     1
high       0.30 m       0.06 rad   10 %            2 (guest: 50 %)     3
=========  ===========  =========  ==============  ==================  ======

Vehicles parked beside the roads (:attr:`UrbanScenario.n_parked`, off the carriageway) are
added as still boxes; they take no part in the simulation. An id switch gives a track a new id
from a drawn frame on; the label names the guest's id at the braking onset. A ghost is a short
(3-8 frames), nearly still box 10-50 m from the ego. The ego's poses get 1 cm of jitter at every
level.
"""

from __future__ import annotations

import uuid
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from scenariominer.data.adapters.av2 import write_av2_log
from scenariominer.data.adapters.av2.map import write_av2_map
from scenariominer.data.log import FloatArray, build_log
from scenariominer.geometry import rotate_xy, wrap_angle
from scenariominer.sim.urban_label import UrbanLabel
from scenariominer.sim.urban_net import UrbanSimError, network_map, parked_spots
from scenariominer.sim.urban_run import EGO_ID, GUEST_ID, STEP_S, RunRecord
from scenariominer.sim.urban_scenario import NoiseLevel, UrbanScenario

__all__ = ["NOISE", "VISIBLE_M", "WINDOW_S", "ExportedLog", "NoiseSpec", "export_log"]

#: Length of an exported log, seconds.
WINDOW_S = 15.0
#: Road users farther than this from the ego (m) are not annotated.
VISIBLE_M = 120.0


#: Parked vehicles: (category, length, width, height), metres.
_PARKED_SIZE_M: tuple[tuple[str, float, float, float], ...] = (
    ("REGULAR_VEHICLE", 4.5, 1.8, 1.5),
    ("REGULAR_VEHICLE", 4.2, 1.75, 1.45),
    ("LARGE_VEHICLE", 5.6, 2.0, 2.2),
    ("BOX_TRUCK", 7.0, 2.4, 3.2),
)


@dataclass(frozen=True)
class NoiseSpec:
    """Tracker-like noise of one level (see the module docstring's table)."""

    pos_sigma_m: float
    yaw_sigma_rad: float
    drop_rate: float
    id_switches: int
    guest_switch_p: float
    ghosts: int


#: The noise of each level.
NOISE: dict[NoiseLevel, NoiseSpec] = {
    NoiseLevel.NONE: NoiseSpec(0.0, 0.0, 0.0, 0, 0.0, 0),
    NoiseLevel.LOW: NoiseSpec(0.05, 0.01, 0.01, 0, 0.0, 0),
    NoiseLevel.MEDIUM: NoiseSpec(0.15, 0.03, 0.04, 1, 0.4, 1),
    NoiseLevel.HIGH: NoiseSpec(0.30, 0.06, 0.10, 2, 0.5, 3),
}


@dataclass(frozen=True)
class ExportedLog:
    """What :func:`export_log` wrote.

    Attributes:
        log_id: the log's id (folder name).
        log_dir: the log folder.
        guest_id: the guest's track id at the braking onset.
        start_ns, end_ns: the interaction window (timestamps of the log).
        onset_ns: the ego's braking onset.
        n_tracks: tracks written, the ego included.
        id_switches: id switches added (on any track).
    """

    log_id: str
    log_dir: Path
    guest_id: str
    start_ns: int
    end_ns: int
    onset_ns: int
    n_tracks: int
    id_switches: int


def _uuid(rng: np.random.Generator) -> str:
    return str(uuid.UUID(bytes=rng.bytes(16), version=4))


def _window(label: UrbanLabel, n: int, rng: np.random.Generator) -> slice:
    frames = int(round(WINDOW_S / STEP_S))
    lead = int(round(rng.uniform(4.0, 7.0) / STEP_S))
    i0 = int(np.clip(label.onset_index - lead, 0, max(n - frames, 0)))
    return slice(i0, min(i0 + frames, n))


def export_log(
    scenario: UrbanScenario, run: RunRecord, label: UrbanLabel, net_file: Path, out_dir: Path, map_index: int
) -> ExportedLog:
    """Write ``run`` (labelled ``label``) as the Argoverse 2 log ``out_dir/<log_id>/`` with its map.

    Everything random (ids, placement, noise) is drawn from the scenario's seed, so the same
    scenario gives the same files.
    """
    rng = np.random.default_rng([scenario.sumo_seed, 23])
    noise = NOISE[scenario.noise]
    log_id = _uuid(rng)
    win = _window(label, run.t_s.size, rng)
    n_t = win.stop - win.start
    theta = float(rng.uniform(-np.pi, np.pi))
    offset = rng.uniform(500.0, 5000.0, size=2)
    z0 = float(rng.uniform(-20.0, 40.0))

    def tf(xy: FloatArray) -> FloatArray:
        return np.asarray(rotate_xy(np.asarray(xy, dtype=np.float64), theta) + offset, dtype=np.float64)

    t0_ns = 315_966_000_000_000_000 + int(rng.integers(0, 10**9)) * 1_000_000
    jitter = rng.integers(-300_000, 300_001, size=n_t)
    jitter[0] = 0
    timestamps = t0_ns + np.arange(n_t, dtype=np.int64) * 100_000_000 + jitter
    ego = run.objects[EGO_ID]
    ex, ey = ego.x_m[win], ego.y_m[win]

    ids: list[np.ndarray] = []
    cats: list[np.ndarray] = []
    ts: list[np.ndarray] = []
    cols: dict[str, list[FloatArray]] = {
        k: [] for k in ("x_m", "y_m", "z_m", "yaw_rad", "length_m", "width_m", "height_m")
    }
    onset_k = label.onset_index - win.start
    guest_id = ""
    n_switches = 0
    names = sorted(run.objects, key=lambda o: (o != EGO_ID, o != GUEST_ID, o))
    switch_left = noise.id_switches
    for name in names:
        obj = run.objects[name]
        x, y, yaw = obj.x_m[win], obj.y_m[win], obj.yaw_rad[win]
        valid = np.isfinite(x)
        is_ego = name == EGO_ID
        if not is_ego:
            valid &= np.hypot(x - ex, y - ey) <= VISIBLE_M
            dropped = rng.random(n_t) < noise.drop_rate
            if name == GUEST_ID and 0 <= onset_k < n_t:
                if not valid[onset_k]:
                    raise UrbanSimError(
                        f"scenario {scenario.index}: the guest is out of view at the braking onset"
                    )
                dropped[onset_k] = False  # the label names the guest as observed at the onset
            valid &= ~dropped
            if valid.sum() < 5:
                continue
        k = np.flatnonzero(valid)
        sigma, ysig = (0.01, 0.002) if is_ego else (noise.pos_sigma_m, noise.yaw_sigma_rad)
        xy = tf(np.column_stack([x[k], y[k]])) + rng.normal(0.0, sigma, size=(k.size, 2))
        track_ids = np.full(k.size, _uuid(rng), dtype=object)
        is_guest = name == GUEST_ID
        if not is_ego and switch_left > 0 and k.size >= 30:
            p = noise.guest_switch_p if is_guest else 0.15
            if rng.random() < p:
                cut = int(rng.integers(10, k.size - 10))
                track_ids[cut:] = _uuid(rng)
                switch_left -= 1
                n_switches += 1
        if is_guest:
            seen = np.flatnonzero(k <= onset_k)
            guest_id = str(track_ids[seen[-1]] if seen.size else track_ids[0])
        length, width, height = obj.size_m
        ids.append(track_ids.astype(str))
        cats.append(np.full(k.size, obj.category))
        ts.append(timestamps[k])
        cols["x_m"].append(xy[:, 0])
        cols["y_m"].append(xy[:, 1])
        cols["z_m"].append(z0 + height / 2 + rng.normal(0.0, sigma / 4, size=k.size))
        cols["yaw_rad"].append(wrap_angle(yaw[k] + theta + rng.normal(0.0, ysig, size=k.size)))
        cols["length_m"].append(np.full(k.size, length))
        cols["width_m"].append(np.full(k.size, width))
        cols["height_m"].append(np.full(k.size, height))
        if is_ego:
            ego_track_id = str(track_ids[0])
    for px, py, pyaw in parked_spots(net_file, scenario.n_parked, rng):
        keep = np.hypot(px - ex, py - ey) <= VISIBLE_M
        keep &= rng.random(n_t) >= noise.drop_rate
        k = np.flatnonzero(keep)
        if k.size < 5:
            continue
        pcat, plen, pwid, phei = _PARKED_SIZE_M[int(rng.integers(0, len(_PARKED_SIZE_M)))]
        xy = tf(np.tile([px, py], (k.size, 1))) + rng.normal(0.0, noise.pos_sigma_m, size=(k.size, 2))
        ids.append(np.full(k.size, _uuid(rng)))
        cats.append(np.full(k.size, pcat))
        ts.append(timestamps[k])
        cols["x_m"].append(xy[:, 0])
        cols["y_m"].append(xy[:, 1])
        cols["z_m"].append(np.full(k.size, z0 + phei / 2))
        cols["yaw_rad"].append(wrap_angle(pyaw + theta + rng.normal(0.0, noise.yaw_sigma_rad, size=k.size)))
        cols["length_m"].append(np.full(k.size, plen))
        cols["width_m"].append(np.full(k.size, pwid))
        cols["height_m"].append(np.full(k.size, phei))
    for _ in range(noise.ghosts):
        m = int(rng.integers(3, 9))
        k0 = int(rng.integers(0, max(n_t - m, 1)))
        k = np.arange(k0, min(k0 + m, n_t))
        ang, dist = rng.uniform(-np.pi, np.pi), rng.uniform(10.0, 50.0)
        gx = ex[k0] + dist * np.cos(ang) + np.cumsum(rng.normal(0.0, 0.1, size=k.size))
        gy = ey[k0] + dist * np.sin(ang) + np.cumsum(rng.normal(0.0, 0.1, size=k.size))
        cat, size = (
            ("PEDESTRIAN", (0.6, 0.6, 1.7)) if rng.random() < 0.5 else ("REGULAR_VEHICLE", (4.5, 1.9, 1.5))
        )
        ids.append(np.full(k.size, _uuid(rng)))
        cats.append(np.full(k.size, cat))
        ts.append(timestamps[k])
        cols["x_m"].append(tf(np.column_stack([gx, gy]))[:, 0])
        cols["y_m"].append(tf(np.column_stack([gx, gy]))[:, 1])
        cols["z_m"].append(np.full(k.size, z0 + size[2] / 2))
        cols["yaw_rad"].append(np.full(k.size, float(rng.uniform(-np.pi, np.pi))))
        cols["length_m"].append(np.full(k.size, size[0]))
        cols["width_m"].append(np.full(k.size, size[1]))
        cols["height_m"].append(np.full(k.size, size[2]))
    if not guest_id:
        raise UrbanSimError(f"scenario {scenario.index}: the guest is not observed in the exported window")
    log = build_log(
        log_id=log_id,
        track_id=np.concatenate(ids),
        category=np.concatenate(cats),
        timestamp_ns=np.concatenate(ts),
        fields={key: np.concatenate(v) for key, v in cols.items()},
        ego_track_id=ego_track_id,
        source="<sumo>",
        dataset="synthetic",
    )
    log_dir = write_av2_log(log, out_dir)
    av2_map = network_map(net_file, tf, z0)
    write_av2_map(av2_map, log_dir / "map" / f"log_map_archive_{log_id}____SUMO_city_{map_index:05d}.json")

    def at(i: int) -> int:
        return int(timestamps[int(np.clip(i - win.start, 0, n_t - 1))])

    return ExportedLog(
        log_id=log_id,
        log_dir=log_dir,
        guest_id=guest_id,
        start_ns=at(label.start_index),
        end_ns=at(label.end_index),
        onset_ns=at(label.onset_index),
        n_tracks=log.n_tracks,
        id_switches=n_switches,
    )
