"""LongitudeTag and LatitudeTag on hand-built tracks with known motion."""

from __future__ import annotations

import numpy as np
import pytest
from tag_scenarios import DT_S, Track, braking_lead_scene, integrate, left_turn_scene, make_log, times

from scenariominer.config.tags import TagConfig
from scenariominer.tags.actor import (
    classify_latitude,
    hysteresis,
    latitude_tags,
    longitude_tags,
    suppress_short_runs,
)
from scenariominer.tags.vocab import ABSENT, LatitudeTag, LongitudeTag, code_of, codes_to_names

CFG = TagConfig()


def _names(enum_cls: type, codes: np.ndarray) -> list[str | None]:
    return list(codes_to_names(enum_cls, codes))


def _run_lengths(row: np.ndarray) -> list[int]:
    edges = np.flatnonzero(np.diff(row) != 0)
    return np.diff(np.concatenate([[-1], edges, [row.size - 1]])).tolist()


# ---------------------------------------------------------------------- building blocks


def test_hysteresis_holds_the_state_between_on_and_off_events() -> None:
    on = np.array([[0, 1, 0, 0, 0, 1, 0]], dtype=bool)
    off = np.array([[1, 0, 0, 1, 0, 0, 0]], dtype=bool)
    assert hysteresis(on, off).tolist() == [[False, True, True, False, False, True, True]]


def test_short_runs_take_the_code_of_the_preceding_run() -> None:
    codes = np.array([[0, 0, 0, 2, 0, 0, 0, 3, 3, 3]], dtype=np.int8)
    assert suppress_short_runs(codes, 3).tolist() == [[0] * 7 + [3] * 3]


def test_a_short_run_at_the_start_of_a_span_takes_the_following_code() -> None:
    codes = np.array([[-1, -1, 2, 0, 0, 0, -1, 1, 4, 4, 4]], dtype=np.int8)
    out = suppress_short_runs(codes, 3)
    assert out.tolist() == [[-1, -1, 0, 0, 0, 0, -1, 4, 4, 4, 4]]


def test_absent_cells_and_all_short_spans_are_left_alone() -> None:
    codes = np.array([[1, 2, -1, 3, 3, 3], [0, 1, 0, 1, 0, 1]], dtype=np.int8)
    out = suppress_short_runs(codes, 3)
    assert out[0].tolist() == [1, 2, -1, 3, 3, 3]
    assert out[1].tolist() == [0, 1, 0, 1, 0, 1]


# ---------------------------------------------------------------------- longitude


def test_braking_lead_is_cruising_then_decelerating_then_standing_still() -> None:
    log = braking_lead_scene()
    tags = longitude_tags(log, CFG)
    lead = _names(LongitudeTag, tags[log.track_index("lead")])
    t = log.t_s
    # The lead brakes at -6 m/s^2 from 3.0 s and stops at 4.67 s.
    assert {lead[k] for k in np.flatnonzero(t < 2.4)} == {"CRUISING"}
    assert {lead[k] for k in np.flatnonzero((t > 3.2) & (t < 4.4))} == {"DECELERATING"}
    assert {lead[k] for k in np.flatnonzero(t > 5.2)} == {"STANDING_STILL"}
    ego = _names(LongitudeTag, tags[log.track_index("ego")])
    assert {ego[k] for k in np.flatnonzero((t > 4.2) & (t < 5.6))} == {"DECELERATING"}
    parked = _names(LongitudeTag, tags[log.track_index("parked")])
    assert set(parked) == {"STANDING_STILL"}


def test_a_parked_car_with_annotation_jitter_stands_still() -> None:
    t = times(10.0)
    rng = np.random.default_rng(3)
    ego = integrate(t, 5.0)
    jitter = rng.normal(0.0, 0.03, (3, t.size))
    parked = (20.0 + jitter[0], 4.0 + jitter[1], 0.4 + 0.5 * jitter[2])
    log = make_log([Track("ego", "EGO_VEHICLE", *ego), Track("car", "REGULAR_VEHICLE", *parked)], t)
    tags = longitude_tags(log, CFG)
    assert set(_names(LongitudeTag, tags[1])) == {"STANDING_STILL"}
    assert set(_names(LongitudeTag, tags[0])) == {"CRUISING"}


def test_a_car_backing_out_is_reversing() -> None:
    t = times(6.0)
    # Faces +x (yaw 0) but moves towards -x at 2 m/s.
    backing = integrate(t, -2.0, x0_m=10.0)
    log = make_log(
        [Track("ego", "EGO_VEHICLE", *integrate(t, 0.0)), Track("car", "REGULAR_VEHICLE", *backing)], t
    )
    assert set(_names(LongitudeTag, longitude_tags(log, CFG)[1])) == {"REVERSING"}


def test_accelerating_from_rest() -> None:
    t = times(8.0)
    speed = np.clip(2.0 * (t - 2.0), 0.0, 10.0)  # 0 until 2 s, +2 m/s^2 until 7 s, then 10 m/s
    log = make_log([Track("ego", "EGO_VEHICLE", *integrate(t, speed))], t)
    ego = _names(LongitudeTag, longitude_tags(log, CFG)[0])
    assert {ego[k] for k in np.flatnonzero(t < 1.5)} == {"STANDING_STILL"}
    assert {ego[k] for k in np.flatnonzero((t > 2.6) & (t < 6.5))} == {"ACCELERATING"}
    assert {ego[k] for k in np.flatnonzero(t > 7.6)} == {"CRUISING"}


def test_jittery_cruising_does_not_flip_every_frame() -> None:
    t = times(15.0)
    rng = np.random.default_rng(11)
    x, y, yaw = integrate(t, 10.0 + 0.25 * np.sin(t))  # gentle speed oscillation, |a| <= 0.25 m/s^2
    log = make_log([Track("ego", "EGO_VEHICLE", x + rng.normal(0, 0.05, t.size), y, yaw)], t)
    row = longitude_tags(log, CFG)[0]
    assert min(_run_lengths(row)) >= round(CFG.min_segment_s / DT_S)
    assert np.mean(row == code_of(LongitudeTag.CRUISING)) > 0.8


def test_absent_frames_get_the_absent_code() -> None:
    t = times(6.0)
    present = (t >= 2.0) & (t <= 4.0)
    log = make_log(
        [
            Track("ego", "EGO_VEHICLE", *integrate(t, 5.0)),
            Track("car", "REGULAR_VEHICLE", *integrate(t, 5.0, y0_m=4.0), present=present),
        ],
        t,
    )
    for tags in (longitude_tags(log, CFG), latitude_tags(log, CFG)):
        assert np.all(tags[1, ~present] == ABSENT)
        assert np.all(tags[1, present] != ABSENT)
        assert np.all(tags[0] != ABSENT)


# ---------------------------------------------------------------------- latitude


@pytest.mark.parametrize(
    ("angle_rad", "expected"),
    [
        (0.03, LatitudeTag.FACING_FORWARD),
        (0.10, LatitudeTag.VEERING_LEFT),
        (-0.10, LatitudeTag.VEERING_RIGHT),
        (0.40, LatitudeTag.TURNING_LEFT),
        (-1.2, LatitudeTag.TURNING_RIGHT),
    ],
)
def test_accumulated_angle_of_a_constant_rate_arc_decides_veering_or_turning(
    angle_rad: float, expected: LatitudeTag
) -> None:
    # 2 s straight, a constant yaw-rate arc sweeping angle_rad in 2 s, 2 s straight.
    t = times(6.0)
    arc = (t >= 2.0 - 1e-9) & (t < 4.0 - 1e-9)
    rate = np.where(arc, angle_rad / 2.0, 0.0)[None, :]
    valid = np.ones_like(rate, dtype=bool)
    codes, accumulated = classify_latitude(rate, valid, valid, t, CFG)
    assert set(_names(LatitudeTag, codes[0, arc])) == {expected.value}
    assert set(_names(LatitudeTag, codes[0, ~arc])) == {"FACING_FORWARD"}
    if expected is not LatitudeTag.FACING_FORWARD:
        assert accumulated[0, arc] == pytest.approx(angle_rad, rel=1e-9)


def test_a_turning_but_stationary_object_faces_forward() -> None:
    t = times(3.0)
    rate = np.full((1, t.size), 0.5)
    valid = np.ones_like(rate, dtype=bool)
    codes, _ = classify_latitude(rate, ~valid, valid, t, CFG)
    assert set(_names(LatitudeTag, codes[0])) == {"FACING_FORWARD"}


@pytest.mark.parametrize(("angle_rad", "expected"), [(0.11, "VEERING_LEFT"), (-0.45, "TURNING_RIGHT")])
def test_constant_curvature_path_after_preprocessing(angle_rad: float, expected: str) -> None:
    t = times(9.0)
    arc = (t >= 3.0) & (t < 6.0)
    log = make_log([Track("ego", "EGO_VEHICLE", *integrate(t, 10.0, np.where(arc, angle_rad / 3.0, 0.0)))], t)
    names = _names(LatitudeTag, latitude_tags(log, CFG)[0])
    assert {names[k] for k in np.flatnonzero((t > 3.5) & (t < 5.5))} == {expected}
    assert {names[k] for k in np.flatnonzero((t < 2.0) | (t > 7.0))} == {"FACING_FORWARD"}


def test_lane_change_reads_veering_left_then_veering_right() -> None:
    t = times(10.0)
    # Heading swings to +0.08 rad and back: yaw rate is +, then - (a 3.5 m lane change at 15 m/s).
    rate = np.where((t >= 3.0) & (t < 5.0), 0.08 * np.sin(np.pi * (t - 3.0) / 1.0) * np.pi / 2, 0.0)
    log = make_log([Track("ego", "EGO_VEHICLE", *integrate(t, 15.0, rate))], t)
    names = _names(LatitudeTag, latitude_tags(log, CFG)[0])
    assert {names[k] for k in np.flatnonzero((t > 3.3) & (t < 3.7))} == {"VEERING_LEFT"}
    assert {names[k] for k in np.flatnonzero((t > 4.3) & (t < 4.7))} == {"VEERING_RIGHT"}


def test_ego_turning_left_at_an_intersection() -> None:
    log = left_turn_scene()
    names = _names(LatitudeTag, latitude_tags(log, CFG)[0])
    t = log.t_s
    # The 90° arc lasts from 3.75 s to 5.71 s.
    assert {names[k] for k in np.flatnonzero((t > 4.0) & (t < 5.5))} == {"TURNING_LEFT"}
    assert {names[k] for k in np.flatnonzero(t < 3.0)} == {"FACING_FORWARD"}
