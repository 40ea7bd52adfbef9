"""Assembly: a scenario in the canonical frame, placed, observed with noise and written."""

from __future__ import annotations

import uuid
from collections.abc import Callable, Sequence
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from scenariominer.data.adapters.av2 import write_av2_log
from scenariominer.data.adapters.av2.map import (
    write_av2_map,
)
from scenariominer.data.log import FloatArray, build_log
from scenariominer.geometry import rotate_xy, wrap_angle
from scenariominer.synth.actors import (
    _conflicts,
    _Track,
)
from scenariominer.synth.background import (
    _background,
    _scene_not_relevant,
)
from scenariominer.synth.crossing import (
    _scene_left_oppo,
    _scene_obj_crossing,
    _scene_ped_crossing,
    _scene_right_ped,
)
from scenariominer.synth.longitudinal import (
    _T,
    _Scene,
    _scene_approach_stop,
    _scene_cut_in,
    _scene_lead_brake,
)
from scenariominer.synth.plans import (
    _Retry,
)
from scenariominer.synth.roads import (
    _build_map,
)
from scenariominer.synth.vocab import (
    FRAME_PERIOD_S,
    N_FRAMES,
    ScenarioCategory,
    ScenarioLabel,
    SynthLog,
    SynthResult,
    write_labels,
)

BoolArray = NDArray[np.bool_]


_SCENES: dict[ScenarioCategory, Callable[[np.random.Generator], _Scene]] = {
    ScenarioCategory.CUT_IN: _scene_cut_in,
    ScenarioCategory.LEAD_BRAKE: _scene_lead_brake,
    ScenarioCategory.APPROACH_STOP: _scene_approach_stop,
    ScenarioCategory.PED_CROSSING: _scene_ped_crossing,
    ScenarioCategory.OBJ_CROSSING: _scene_obj_crossing,
    ScenarioCategory.LEFT_OPPO: _scene_left_oppo,
    ScenarioCategory.RIGHT_PED: _scene_right_ped,
    ScenarioCategory.NOT_RELEVANT: _scene_not_relevant,
}


# ---------------------------------------------------------------------- assembly


def _uuid(rng: np.random.Generator) -> str:
    return str(uuid.UUID(bytes=rng.bytes(16), version=4))


def _observe(
    rng: np.random.Generator, track: _Track, ego: _Track, visible_m: float, *, is_guest: bool
) -> BoolArray:
    """Visibility mask: within range, minus random dropped frames and (background only) an occlusion gap."""
    valid = np.hypot(track.x - ego.x, track.y - ego.y) <= visible_m
    p_drop = rng.uniform(0.0, 0.02 if is_guest else 0.05)
    valid &= rng.random(valid.size) >= p_drop
    if not is_guest and rng.random() < 0.3:
        start = int(rng.integers(0, valid.size))
        valid[start : start + int(rng.integers(3, 11))] = False
    return valid


def _scene_for(category: ScenarioCategory, rng: np.random.Generator) -> _Scene:
    for _ in range(200):
        try:
            scene = _SCENES[category](rng)
        except _Retry:
            continue
        if _conflicts(scene.ego, scene.guest, horizon_frames=0, margin_m=0.2):
            continue
        if category is not ScenarioCategory.NOT_RELEVANT:
            i0, i1 = np.searchsorted(_T, [scene.start_s, scene.end_s])
            speed = np.hypot(np.gradient(scene.ego.x, _T), np.gradient(scene.ego.y, _T))
            if speed[min(i1, N_FRAMES - 1)] > speed[min(i0, N_FRAMES - 1)] - 1.0:
                continue
        return scene
    raise RuntimeError(
        f"could not draw a valid {category.value} scenario in 200 attempts"
    )  # pragma: no cover


def generate_log(category: ScenarioCategory | str, rng: np.random.Generator) -> SynthLog:
    """Generate one labelled scenario in memory.

    Args:
        category: the scenario category to generate.
        rng: source of every random draw (the result is a pure function of its state).

    Returns:
        The log (ego at its box centre, ``dataset="synthetic"``), its map, label and layout.
    """
    category = ScenarioCategory(category)
    log_id = _uuid(rng)
    scene = _scene_for(category, rng)
    visible_m = rng.uniform(60.0, 90.0)
    background = _background(rng, scene, int(rng.integers(4, 11)), visible_m)

    # Noise-free canonical tracks → observed, noisy, city-frame rows.
    theta = rng.uniform(-np.pi, np.pi)
    offset = rng.uniform(-2000.0, 2000.0, size=2) + np.array([3000.0, 3000.0])
    z0 = rng.uniform(-30.0, 30.0)

    def tf(xy: FloatArray) -> FloatArray:
        return np.asarray(rotate_xy(np.asarray(xy, dtype=np.float64), theta) + offset, dtype=np.float64)

    sigma_pos = rng.uniform(0.05, 0.1)
    sigma_yaw = rng.uniform(0.01, 0.03)
    tracks = [scene.ego, scene.guest, *background]
    for i, track in enumerate(tracks):
        track.track_id = _uuid(rng)
        if i == 0:
            continue
        track.valid = _observe(rng, track, scene.ego, visible_m, is_guest=i == 1)
    tracks = [tr for i, tr in enumerate(tracks) if i < 2 or tr.valid.sum() >= 5]

    n_t = _T.size
    t0_ns = 315_966_000_000_000_000 + int(rng.integers(0, 10**9)) * 1_000_000
    jitter = rng.integers(-300_000, 300_001, size=n_t)
    jitter[0] = 0
    timestamps = t0_ns + np.arange(n_t, dtype=np.int64) * 100_000_000 + jitter

    ids: list[NDArray[np.str_]] = []
    cats: list[NDArray[np.str_]] = []
    ts: list[NDArray[np.int64]] = []
    cols: dict[str, list[FloatArray]] = {
        k: [] for k in ("x_m", "y_m", "z_m", "yaw_rad", "length_m", "width_m", "height_m")
    }
    for i, tr in enumerate(tracks):
        k = np.flatnonzero(tr.valid)
        pos_sigma, yaw_sigma = (
            (0.01, 0.002)
            if i == 0
            else (sigma_pos, sigma_yaw * (3.0 if tr.category == "PEDESTRIAN" else 1.0))
        )
        xy = tf(np.column_stack([tr.x[k], tr.y[k]])) + rng.normal(0.0, pos_sigma, size=(k.size, 2))
        ids.append(np.full(k.size, tr.track_id))
        cats.append(np.full(k.size, tr.category))
        ts.append(timestamps[k])
        cols["x_m"].append(xy[:, 0])
        cols["y_m"].append(xy[:, 1])
        cols["z_m"].append(z0 + tr.height / 2 + rng.normal(0.0, pos_sigma / 4, size=k.size))
        cols["yaw_rad"].append(wrap_angle(tr.yaw[k] + theta + rng.normal(0.0, yaw_sigma, size=k.size)))
        cols["length_m"].append(np.full(k.size, tr.length))
        cols["width_m"].append(np.full(k.size, tr.width))
        cols["height_m"].append(np.full(k.size, tr.height))
    log = build_log(
        log_id=log_id,
        track_id=np.concatenate(ids),
        category=np.concatenate(cats),
        timestamp_ns=np.concatenate(ts),
        fields={k: np.concatenate(v) for k, v in cols.items()},
        ego_track_id=scene.ego.track_id,
        source="<synthetic>",
        dataset="synthetic",
    )
    i0 = int(np.clip(np.round(scene.start_s / FRAME_PERIOD_S), 0, n_t - 1))
    i1 = int(np.clip(np.round(scene.end_s / FRAME_PERIOD_S), i0, n_t - 1))
    label = ScenarioLabel(log_id, scene.guest.track_id, category, int(timestamps[i0]), int(timestamps[i1]))
    return SynthLog(log=log, av2_map=_build_map(scene.layout, tf, z0), label=label, layout=scene.layout)


def generate(
    out_dir: Path,
    n: int,
    seed: int = 0,
    categories: Sequence[str] | None = None,
    progress: Callable[[int], None] | None = None,
) -> SynthResult:
    """Generate ``n`` labelled scenarios as Argoverse 2 logs with vector maps, plus ``labels.csv``.

    Log ``i`` has category ``categories[i % len(categories)]`` and depends only on ``(seed, i)``,
    so a larger ``n`` extends a smaller run with the same seed.

    Args:
        out_dir: output folder; receives ``<log_id>/`` folders (annotations, poses, ``map/``) and
            ``labels.csv``.
        n: number of logs.
        seed: random seed.
        categories: scenario category names to cycle through; all of :class:`ScenarioCategory`
            by default.
        progress: called with the number of logs written so far after each log.

    Returns:
        Paths, labels and per-log track counts.

    Raises:
        ValueError: ``n`` is negative or a category name is unknown.
    """
    if n < 0:
        raise ValueError(f"n must be >= 0, got {n}")
    try:
        cycle = (
            [ScenarioCategory(c) for c in categories] if categories is not None else list(ScenarioCategory)
        )
    except ValueError:
        known = [c.value for c in ScenarioCategory]
        raise ValueError(f"unknown scenario category in {list(categories or [])}; known: {known}") from None
    if not cycle:
        raise ValueError("categories must not be empty")
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    log_dirs, labels, n_tracks = [], [], []
    for i in range(n):
        synth = generate_log(cycle[i % len(cycle)], np.random.default_rng([seed, i]))
        log_dir = write_av2_log(synth.log, out_dir)
        write_av2_map(
            synth.av2_map, log_dir / "map" / f"log_map_archive_{synth.log.log_id}____SYN_city_{i:05d}.json"
        )
        log_dirs.append(log_dir)
        labels.append(synth.label)
        n_tracks.append(synth.log.n_tracks)
        if progress is not None:
            progress(i + 1)
    labels_csv = write_labels(labels, out_dir / "labels.csv")
    return SynthResult(out_dir, labels_csv, tuple(log_dirs), tuple(labels), tuple(n_tracks))
