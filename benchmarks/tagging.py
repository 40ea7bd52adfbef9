"""Throughput of rule-based tagging (braking paper, III-B) on synthetic urban logs.

Builds logs of N tracks (ego + N-1 objects: traffic in both directions, parked cars, pedestrians,
each with a random lifespan and 5 cm annotation jitter) through ``build_log``, preprocesses them,
then times every tag family and the whole ``tag_log`` and prints tracks × timestamps per second.
A naive per-frame baseline (box distance with shapely, one object and one frame at a time) is
timed in the same run for comparison.

    .venv/bin/python benchmarks/tagging.py --tracks 100 --seconds 15 --hz 10 --repeats 5
"""

from __future__ import annotations

import os

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import argparse  # noqa: E402
import time  # noqa: E402
from collections.abc import Callable  # noqa: E402

import numpy as np  # noqa: E402
import shapely  # noqa: E402

from scenariominer.config.tags import TagConfig  # noqa: E402
from scenariominer.data.log import Log, build_log  # noqa: E402
from scenariominer.data.preprocess import preprocess  # noqa: E402
from scenariominer.tags import tag_log  # noqa: E402
from scenariominer.tags.actor import latitude_tags, longitude_tags  # noqa: E402
from scenariominer.tags.interaction import (  # noqa: E402
    collision_tags,
    distance_tags,
    heading_tags,
    log_boxes,
    position_tags,
    traj_overlap_tags,
)


def synthetic_log(n_tracks: int, seconds: float, hz: float, seed: int) -> Log:
    """An urban scene around an ego that drives, slows down and turns left."""
    rng = np.random.default_rng(seed)
    t = np.arange(int(round(seconds * hz)) + 1) / hz
    dt = 1.0 / hz
    speed = np.clip(10.0 - 2.0 * np.clip(t - 0.4 * seconds, 0, None), 3.0, None)
    rate = np.where((t > 0.6 * seconds) & (t < 0.6 * seconds + 3.0), 0.45, 0.0)
    yaw = np.cumsum(rate) * dt
    ex = np.cumsum(speed * np.cos(yaw)) * dt
    ey = np.cumsum(speed * np.sin(yaw)) * dt
    rows: dict[str, list[np.ndarray]] = {k: [] for k in ("tid", "cat", "ts", "x", "y", "yaw", "l", "w")}

    def add(
        name: str,
        cat: str,
        x: np.ndarray,
        y: np.ndarray,
        h: np.ndarray,
        length: float,
        width: float,
        keep: np.ndarray,
    ) -> None:
        k = int(keep.sum())
        rows["tid"].append(np.full(k, name))
        rows["cat"].append(np.full(k, cat))
        rows["ts"].append(np.round(t[keep] * 1e9).astype(np.int64))
        rows["x"].append(x[keep] + rng.normal(0, 0.05, k))
        rows["y"].append(y[keep] + rng.normal(0, 0.05, k))
        rows["yaw"].append(h[keep] + rng.normal(0, 0.02, k))
        rows["l"].append(np.full(k, length))
        rows["w"].append(np.full(k, width))

    add("ego", "EGO_VEHICLE", ex, ey, yaw, 4.8, 2.0, np.ones(t.size, dtype=bool))
    for i in range(n_tracks - 1):
        kind = rng.choice(["same", "oncoming", "parked", "pedestrian"], p=[0.35, 0.25, 0.2, 0.2])
        x0, y0 = rng.uniform(-40, 120), rng.choice([-7.0, -3.5, 3.5, 7.0]) + rng.normal(0, 0.3)
        if kind == "same":
            v, h, cat, dims = rng.uniform(4, 14), 0.0, "REGULAR_VEHICLE", (4.6, 1.9)
        elif kind == "oncoming":
            v, h, cat, dims = rng.uniform(5, 14), np.pi, "REGULAR_VEHICLE", (4.6, 1.9)
        elif kind == "parked":
            v, h, cat, dims = 0.0, 0.0, "REGULAR_VEHICLE", (4.5, 1.9)
            y0 = rng.choice([-9.0, 9.0])
        else:
            v, h, cat, dims = (
                rng.uniform(0.8, 1.8),
                rng.choice([np.pi / 2, -np.pi / 2]),
                "PEDESTRIAN",
                (0.6, 0.6),
            )
            y0 = rng.uniform(-12, 12)
        accel = rng.choice([0.0, -1.5, 1.0]) if kind in ("same", "oncoming") else 0.0
        v_t = np.clip(v + accel * np.clip(t - rng.uniform(0, seconds), 0, None), 0, None)
        s = np.cumsum(v_t) * dt
        x = x0 + s * np.cos(h)
        y = y0 + s * np.sin(h)
        start = rng.integers(0, t.size // 2)
        stop = rng.integers(start + 5, t.size + 1)
        keep = np.zeros(t.size, dtype=bool)
        keep[start:stop] = True
        add(f"obj{i:04d}", cat, x, y, np.full(t.size, h), *dims, keep)

    cat = np.concatenate(rows["cat"])
    x = np.concatenate(rows["x"])
    return build_log(
        log_id=f"bench{seed}",
        track_id=np.concatenate(rows["tid"]),
        category=cat,
        timestamp_ns=np.concatenate(rows["ts"]),
        fields={
            "x_m": x,
            "y_m": np.concatenate(rows["y"]),
            "yaw_rad": np.concatenate(rows["yaw"]),
            "length_m": np.concatenate(rows["l"]),
            "width_m": np.concatenate(rows["w"]),
        },
        ego_track_id="ego",
        source="<benchmark>",
        dataset="synthetic",
    )


def naive_distance(log: Log) -> np.ndarray:
    """Per-frame, per-object shapely box distance (the loop the vectorised code replaces)."""
    corners = log_boxes(log).corners()
    out = np.full(log.valid.shape, np.nan)
    for k in range(log.n_timestamps):
        if not log.valid[0, k]:
            continue
        ego = shapely.Polygon(corners[0, k])
        for i in range(1, log.n_tracks):
            if log.valid[i, k]:
                out[i, k] = ego.distance(shapely.Polygon(corners[i, k]))
    return out


def best_time(fn: Callable[[], object], repeats: int) -> float:
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        fn()
        times.append(time.perf_counter() - start)
    return min(times)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--tracks", type=int, default=100, help="tracks per log, the ego included")
    parser.add_argument("--seconds", type=float, default=15.0, help="log duration in seconds")
    parser.add_argument("--hz", type=float, default=10.0, help="frame rate")
    parser.add_argument("--repeats", type=int, default=5, help="timed repetitions (best is reported)")
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()

    cfg = TagConfig()
    log = preprocess(synthetic_log(args.tracks, args.seconds, args.hz, args.seed))
    cells = log.n_tracks * log.n_timestamps
    print(
        f"log: {log.n_tracks} tracks x {log.n_timestamps} timestamps = {cells} cells "
        f"({log.n_frames} observed), {args.hz:g} Hz, {log.duration_s:.1f} s; best of {args.repeats}"
    )
    tag_log(log, cfg)  # warm-up
    families: dict[str, Callable[[], object]] = {
        "longitude": lambda: longitude_tags(log, cfg),
        "latitude": lambda: latitude_tags(log, cfg),
        "collision (CTRV TTC)": lambda: collision_tags(log, cfg),
        "heading": lambda: heading_tags(log),
        "position": lambda: position_tags(log),
        "distance": lambda: distance_tags(log, cfg),
        "traj_overlap": lambda: traj_overlap_tags(log, cfg),
        "tag_log (all)": lambda: tag_log(log, cfg),
    }
    print(f"{'family':<22}{'ms':>10}{'cells/s':>16}")
    results = {}
    for name, fn in families.items():
        sec = best_time(fn, args.repeats)
        results[name] = sec
        print(f"{name:<22}{sec * 1e3:>10.2f}{cells / sec:>16,.0f}")

    naive_s = best_time(lambda: naive_distance(log), max(1, min(args.repeats, 2)))
    np.testing.assert_allclose(naive_distance(log), distance_tags(log, cfg)[1], atol=1e-6)
    print(
        f"naive per-frame shapely distance: {naive_s * 1e3:.1f} ms ({cells / naive_s:,.0f} cells/s); "
        f"vectorised distance is {naive_s / results['distance']:.0f}x faster (same answers)"
    )


if __name__ == "__main__":
    main()
