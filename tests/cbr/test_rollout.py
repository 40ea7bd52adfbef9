"""Rollout check with hand-built tracks whose answers are known from kinematics."""

from __future__ import annotations

import numpy as np
import pytest

from scenariominer.cbr.rollout import RECORDED, RolloutScene, rollout
from scenariominer.cbr.scenes import draw_scene, label_scene
from scenariominer.cbr.vocab import load_manoeuvres
from scenariominer.geometry import OrientedBoxes

MANOEUVRES = load_manoeuvres()
T = np.round(np.arange(0.0, 5.0 + 1e-9, 0.1), 6)


def _scene(
    speed_mps: float, others: list[tuple[np.ndarray, np.ndarray, float]], ids: list[str]
) -> RolloutScene:
    """Ego at the origin driving along +x at ``speed_mps`` without reacting; others (x, y, yaw) tracks."""
    n = len(others)
    boxes = OrientedBoxes(
        np.vstack([o[0] * np.ones_like(T) for o in others]),
        np.vstack([o[1] * np.ones_like(T) for o in others]),
        np.vstack([np.full_like(T, o[2]) for o in others]),
        np.full((n, T.size), 4.5),
        np.full((n, T.size), 1.8),
    )
    return RolloutScene(
        T, speed_mps * T, np.zeros_like(T), np.zeros_like(T), speed_mps, 4.5, 1.8, boxes, tuple(ids)
    )


def test_stopped_car_ahead_hard_braking_avoids_keep_going_collides() -> None:
    # 15 m/s, stopped car with its rear 25.5 m ahead of the ego's front (centres 30 m apart).
    # Braking at 8 m/s² with a 0.2 s build-up needs 15²/16 + ~1.5 = 15.6 m: it stops ~10 m short.
    out = rollout(_scene(15.0, [(np.asarray(30.0), np.asarray(0.0), 0.0)], ["car"]), MANOEUVRES.manoeuvres)
    rec, brake = out[RECORDED], out["emergency_braking"]
    assert rec.collision and rec.first_collision_s == pytest.approx(1.7, abs=0.11)  # 25.5 m / 15 m/s
    assert brake.avoided and 8.0 < brake.min_distance_m < 11.5
    assert out["sudden_acceleration"].collision
    assert np.isfinite(brake.min_ttc_s) and brake.min_ttc_s > rec.min_ttc_s


def test_too_close_to_brake_but_steering_into_a_free_lane_avoids() -> None:
    # Rear of the stopped car 30 m ahead at 25 m/s: braking needs 25²/16 + ~5 = 44 m; after 1.2 s
    # (when the ego reaches it) the half-cosine lane change has moved it 3.0 m aside (> 1.8 m width).
    out = rollout(_scene(25.0, [(np.asarray(34.5), np.asarray(0.0), 0.0)], ["car"]), MANOEUVRES.manoeuvres)
    assert out["emergency_braking"].collision
    assert out["evasive_steering_left"].avoided and out["evasive_steering_right"].avoided


def test_steering_into_an_occupied_lane_collides_with_that_road_user() -> None:
    left_car = (25.0 * T, np.full_like(T, 3.5), 0.0)  # keeps pace in the left lane
    out = rollout(
        _scene(25.0, [(np.asarray(34.5), np.asarray(0.0), 0.0), left_car], ["stopped", "left"]),
        MANOEUVRES.manoeuvres,
    )
    assert out["evasive_steering_left"].collision and out["evasive_steering_left"].closest_id == "left"
    assert out["evasive_steering_right"].avoided


def test_nothing_around_means_no_collision_and_infinite_ttc() -> None:
    far = (np.asarray(500.0), np.asarray(50.0), 0.0)
    out = rollout(_scene(10.0, [far], ["far"]), MANOEUVRES.manoeuvres)
    assert all(o.avoided for o in out.values())
    assert out[RECORDED].min_distance_m > 400


def test_braking_path_stops_where_kinematics_says() -> None:
    out = rollout(_scene(10.0, [(np.asarray(900.0), np.asarray(0.0), 0.0)], ["x"]), MANOEUVRES.manoeuvres)
    x = out["emergency_braking"].x_m
    # Build-up to 8 m/s² at 40 m/s³ takes 0.2 s: 10*0.2 - 20*0.2³/3 = 1.947 m, leaving 9.2 m/s;
    # then 9.2²/16 = 5.29 m: 7.237 m in all.
    assert x[-1] == pytest.approx(7.237, abs=0.02)
    assert np.all(np.diff(x) >= -1e-9)


def test_synthetic_label_is_the_least_effort_avoiding_manoeuvre() -> None:
    rng = np.random.default_rng(5)
    seen = 0
    for _ in range(40):
        labelled = label_scene(draw_scene(rng, "vehicle_ahead", "t"), MANOEUVRES)
        if labelled is None:
            continue
        seen += 1
        assert labelled.outcomes[RECORDED].collision
        order = [m.name for m in MANOEUVRES.by_effort()]
        first_ok = next(n for n in order if labelled.outcomes[n].avoided)
        assert labelled.manoeuvre == first_ok
    assert seen > 10
