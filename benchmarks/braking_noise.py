"""Make a tracker-noise copy of a labelled Argoverse 2 braking set (for the why-braking hold-out).

Usage::

    python benchmarks/braking_noise.py SRC_DIR OUT_DIR [--seed 7]

``SRC_DIR`` holds AV2 log folders and a ``labels.csv`` (as written by ``scenariominer synth``).
Each log is copied with the noise of one level, cycling ``clean``, ``low``, ``high`` over the logs
in ``labels.csv`` order, and ``OUT_DIR/labels.csv`` gets a ``noise_level`` column (read by
``eval braking``'s per-method table). What a tracker does wrong, per level (low / high):

* **id switches**: the labelled guest's id changes once (probability 0.5 / 1.0) at a random time
  from 2 s before to 1 s after its labelled start, with one or two frames dropped at the switch;
  every other object switches with probability 0 / 0.3 at a random time of its life. The label
  keeps the guest's original id (the object's true identity);
* **dropped frames**: every non-ego observation is dropped with probability 0.05 / 0.15;
* **position jitter**: Gaussian, sigma 0.05 / 0.15 m added to non-ego x and y;
* **ghosts**: 2 / 6 detections of 2-3 frames at random places within 30 m of the ego.

The noise parameters were fixed before any measurement and no threshold is tuned on the output.
"""

from __future__ import annotations

import argparse
import csv
import shutil
import uuid
from pathlib import Path

import numpy as np

from scenariominer.data.adapters.av2 import read_av2_log, write_av2_log
from scenariominer.data.log import STATE_FIELDS, Log, build_log

LEVELS: dict[str, dict[str, float]] = {
    "clean": {"p_guest_switch": 0.0, "p_other_switch": 0.0, "p_drop": 0.0, "sigma_m": 0.0, "n_ghosts": 0},
    "low": {"p_guest_switch": 0.5, "p_other_switch": 0.0, "p_drop": 0.05, "sigma_m": 0.05, "n_ghosts": 2},
    "high": {"p_guest_switch": 1.0, "p_other_switch": 0.3, "p_drop": 0.15, "sigma_m": 0.15, "n_ghosts": 6},
}


def _noisy(log: Log, guest_id: str, start_ns: int, level: dict[str, float], rng: np.random.Generator) -> Log:
    """The log with this level's tracker noise (see the module docstring)."""
    table = log.to_arrow()
    tid = np.asarray(table.column("track_id").to_pylist(), dtype=object)
    cat = np.asarray(table.column("category").to_pylist(), dtype=object)
    ts = np.asarray(table.column("timestamp_ns").to_pylist(), dtype=np.int64)
    cols = {name: table.column(name).to_numpy().copy() for name in STATE_FIELDS if name in table.column_names}
    ego_id = str(log.track_ids[log.ego_index])
    other = tid != ego_id
    keep = np.ones(tid.size, dtype=bool)
    for track in np.unique(tid[other]):
        rows = np.flatnonzero(tid == track)
        is_guest = track == guest_id
        if (
            rng.random() >= (level["p_guest_switch"] if is_guest else level["p_other_switch"])
            or rows.size < 8
        ):
            continue
        if is_guest:
            at = start_ns + int(rng.uniform(-2.0, 1.0) * 1e9)
        else:
            at = int(ts[rows[int(rng.integers(3, rows.size - 3))]])
        after = rows[ts[rows] >= at]
        if after.size < 3 or after.size > rows.size - 3:
            continue
        keep[after[: int(rng.integers(1, 3))]] = False  # the frame(s) of the switch are lost
        tid[after] = str(uuid.UUID(bytes=rng.bytes(16), version=4))
    keep &= ~(other & (rng.random(tid.size) < level["p_drop"]))
    jitter = other * level["sigma_m"]
    cols["x_m"] = cols["x_m"] + rng.normal(0.0, 1.0, tid.size) * jitter
    cols["y_m"] = cols["y_m"] + rng.normal(0.0, 1.0, tid.size) * jitter
    ghost_rows: dict[str, list[object]] = {k: [] for k in ("track_id", "category", "timestamp_ns", *cols)}
    ego_rows = np.flatnonzero(tid == ego_id)
    for _ in range(int(level["n_ghosts"])):
        n = int(rng.integers(2, 4))
        i0 = int(rng.integers(0, ego_rows.size - n))
        base = ego_rows[i0]
        angle, dist = rng.uniform(-np.pi, np.pi), rng.uniform(5.0, 30.0)
        ghost_id = str(uuid.UUID(bytes=rng.bytes(16), version=4))
        category = "PEDESTRIAN" if rng.random() < 0.5 else "REGULAR_VEHICLE"
        size = (0.6, 0.6, 1.7) if category == "PEDESTRIAN" else (4.5, 1.9, 1.5)
        for k in range(n):
            r = ego_rows[i0 + k]
            ghost_rows["track_id"].append(ghost_id)
            ghost_rows["category"].append(category)
            ghost_rows["timestamp_ns"].append(int(ts[r]))
            for name in cols:
                value = {
                    "x_m": cols["x_m"][base] + dist * np.cos(angle),
                    "y_m": cols["y_m"][base] + dist * np.sin(angle),
                    "yaw_rad": rng.uniform(-np.pi, np.pi),
                    "length_m": size[0],
                    "width_m": size[1],
                    "height_m": size[2],
                }.get(name, 0.0 if name != "z_m" else cols["z_m"][base])
                ghost_rows[name].append(value)
    fields = {
        name: np.concatenate([cols[name][keep], np.asarray(ghost_rows[name], dtype=float)]) for name in cols
    }
    for name in ("vx_mps", "vy_mps", "ax_mps2", "ay_mps2"):
        fields.pop(name, None)  # re-derived from the noisy positions
    return build_log(
        log_id=log.log_id,
        track_id=np.concatenate([tid[keep], np.asarray(ghost_rows["track_id"], dtype=object)]).astype(str),
        category=np.concatenate([cat[keep], np.asarray(ghost_rows["category"], dtype=object)]).astype(str),
        timestamp_ns=np.concatenate([ts[keep], np.asarray(ghost_rows["timestamp_ns"], dtype=np.int64)]),
        fields=fields,
        ego_track_id=ego_id,
        source="<noisy copy>",
        dataset=log.dataset,
    )


def main() -> None:
    """Write the noisy copy (see the module docstring)."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("src", type=Path)
    parser.add_argument("out", type=Path)
    parser.add_argument("--seed", type=int, default=7)
    args = parser.parse_args()
    with (args.src / "labels.csv").open(newline="", encoding="utf-8") as fh:
        labels = list(csv.DictReader(fh))
    args.out.mkdir(parents=True, exist_ok=True)
    names = list(LEVELS)
    counts = dict.fromkeys(names, 0)
    for i, row in enumerate(labels):
        level = names[i % len(names)]
        rng = np.random.default_rng([args.seed, i])
        src_dir = args.src / row["log_id"]
        log = read_av2_log(src_dir)
        noisy = _noisy(log, row["guest_id"], int(row["start_ns"]), LEVELS[level], rng)
        out_dir = write_av2_log(noisy, args.out)
        if (src_dir / "map").is_dir():
            shutil.copytree(src_dir / "map", out_dir / "map", dirs_exist_ok=True)
        row["noise_level"] = level
        counts[level] += 1
    with (args.out / "labels.csv").open("w", newline="", encoding="utf-8") as fh:
        writer = csv.DictWriter(fh, fieldnames=[*labels[0].keys()])
        writer.writeheader()
        writer.writerows(labels)
    print(f"{len(labels)} logs written to {args.out} ({counts})")


if __name__ == "__main__":
    main()
