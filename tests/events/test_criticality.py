"""Criticality measures on hand-built tracks with known TTC, PET, headway and deceleration."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from scenariominer.config.explain import ExplainConfig
from scenariominer.data.log import Log, build_log
from scenariominer.events.criticality import (
    event_criticality,
    peak_deceleration_mps2,
    post_encroachment_time_s,
    time_headway_s,
)
from scenariominer.geometry import OrientedBoxes
from scenariominer.tags import tag_log

DT_S = 0.1


def _log(tracks: dict[str, dict[str, np.ndarray | float]], t_s: np.ndarray) -> Log:
    """A log with exact kinematics (velocities and accelerations given, not derived)."""
    n = t_s.size
    cols: dict[str, list[np.ndarray]] = {}
    ids, cats = [], []
    for tid, tr in tracks.items():
        ids += [tid] * n
        cats += [str(tr["category"])] * n
        for name in (
            "x_m",
            "y_m",
            "yaw_rad",
            "length_m",
            "width_m",
            "vx_mps",
            "vy_mps",
            "ax_mps2",
            "ay_mps2",
        ):
            cols.setdefault(name, []).append(np.broadcast_to(np.asarray(tr.get(name, 0.0), float), (n,)))
    return build_log(
        log_id="crit",
        track_id=ids,
        category=cats,
        timestamp_ns=np.tile(np.round(t_s * 1e9).astype(np.int64), len(tracks)),
        fields={k: np.concatenate(v) for k, v in cols.items()},
        ego_track_id="ego",
        source="<test>",
    )


def _boxes(x: np.ndarray, y: np.ndarray, yaw: float, size: float) -> OrientedBoxes:
    return OrientedBoxes(x, y, np.full_like(x, yaw), np.full_like(x, size), np.full_like(x, size))


def test_pet_of_perpendicular_crossing() -> None:
    # Ego (1.5 m square) drives +x through the origin at t = 5 s, the guest drives +y through it
    # at t = 7 s: boxes overlap for ego samples 4.9-5.1 s and guest samples 6.9-7.1 s -> PET 1.8 s.
    t = np.arange(101) * DT_S
    ego = _boxes(-50.0 + 10.0 * t, np.zeros_like(t), 0.0, 1.5)
    guest = _boxes(np.zeros_like(t), -70.0 + 10.0 * t, np.pi / 2, 1.5)
    assert post_encroachment_time_s(ego, guest, t) == pytest.approx(1.8)
    # Swap the order: the guest passes first; PET is symmetric.
    assert post_encroachment_time_s(guest, ego, t) == pytest.approx(1.8)


def test_pet_is_zero_for_contact_and_nan_for_disjoint_paths() -> None:
    t = np.arange(21) * DT_S
    ego = _boxes(-10.0 + 10.0 * t, np.zeros_like(t), 0.0, 1.5)
    guest = _boxes(np.zeros_like(t), -10.0 + 10.0 * t, np.pi / 2, 1.5)  # both at the origin at 1.0 s
    assert post_encroachment_time_s(ego, guest, t) == 0.0
    parallel = _boxes(-10.0 + 10.0 * t, np.full_like(t, 5.0), 0.0, 1.5)
    assert math.isnan(post_encroachment_time_s(ego, parallel, t))
    absent = _boxes(np.full_like(t, np.nan), np.full_like(t, np.nan), 0.0, 1.5)
    assert math.isnan(post_encroachment_time_s(ego, absent, t))


def test_time_headway_is_bumper_gap_over_ego_speed() -> None:
    t = np.arange(11) * DT_S
    ego = OrientedBoxes(
        10.0 * t, np.zeros_like(t), np.zeros_like(t), np.full_like(t, 4.0), np.full_like(t, 2.0)
    )
    lead = OrientedBoxes(
        25.0 + 10.0 * t, np.zeros_like(t), np.zeros_like(t), np.full_like(t, 4.0), np.full_like(t, 2.0)
    )
    speed = np.full_like(t, 10.0)
    following = np.ones(t.size, dtype=bool)
    # Gap 25 m between centres minus 2 m + 2 m of half lengths = 21 m at 10 m/s.
    assert time_headway_s(ego, lead, speed, following, 1.0) == pytest.approx(2.1)
    assert math.isnan(time_headway_s(ego, lead, speed, np.zeros(t.size, dtype=bool), 1.0))
    assert math.isnan(time_headway_s(ego, lead, np.full_like(t, 0.5), following, 1.0))


def test_peak_deceleration_uses_acceleration_along_heading() -> None:
    yaw = np.full(4, np.pi / 2)  # heading +y
    ax = np.array([0.0, 0.0, 0.0, 5.0])  # sideways: not a deceleration
    ay = np.array([0.5, -2.0, -4.5, 0.0])
    valid = np.array([True, True, True, True])
    assert peak_deceleration_mps2(ax, ay, yaw, valid) == pytest.approx(4.5)
    assert peak_deceleration_mps2(ax, ay, yaw, np.array([True, True, False, True])) == pytest.approx(2.0)
    assert peak_deceleration_mps2(ax, np.abs(ay), yaw, valid) == 0.0


def test_event_criticality_of_a_braking_follower() -> None:
    # Ego follows a lead 25 m ahead (centres) at 10 m/s; the ego brakes at -3 m/s^2 from 2 s to 3 s.
    t = np.arange(61) * DT_S
    ego_ax = np.where((t >= 2.0) & (t <= 3.0), -3.0, 0.0)
    log = _log(
        {
            "ego": {
                "category": "EGO_VEHICLE",
                "x_m": 10.0 * t,
                "vx_mps": 10.0,
                "ax_mps2": ego_ax,
                "length_m": 4.0,
                "width_m": 2.0,
            },
            "lead": {
                "category": "REGULAR_VEHICLE",
                "x_m": 25.0 + 10.0 * t,
                "vx_mps": 10.0,
                "length_m": 4.0,
                "width_m": 2.0,
            },
        },
        t,
    )
    tags = tag_log(log)
    ttc = np.full(tags.ttc_s.shape, np.inf)
    ttc[1, 25] = 2.4
    ttc[1, 45] = 0.5  # outside the analysis window below
    ttc[0] = np.nan
    distance = np.full(tags.distance_m.shape, 21.0)
    distance[1, 27] = 20.5  # the closest approach inside the event
    distance[1, 40] = 3.0  # after the event: not its key time
    distance[0] = np.nan
    tags = dataclasses.replace(tags, ttc_s=ttc, distance_m=distance)
    cfg = ExplainConfig(context_before_s=0.5, context_after_s=0.5, pet_horizon_s=2.0)
    crit = event_criticality(log, tags, "lead", int(2.0e9), int(3.0e9), cfg)
    assert crit.min_ttc_s == pytest.approx(2.4)
    assert crit.peak_decel_mps2 == pytest.approx(3.0)
    assert crit.headway_s == pytest.approx(2.1)
    # The ego's front reaches the place of the lead's rear 21 m / 10 m/s = 2.1 s after the lead left it.
    assert crit.pet_s == pytest.approx(2.1)
    assert crit.closest_ns == int(2.7e9)


def test_event_without_risk_prediction_has_infinite_ttc() -> None:
    t = np.arange(31) * DT_S
    log = _log(
        {
            "ego": {"category": "EGO_VEHICLE", "x_m": 5.0 * t, "vx_mps": 5.0},
            "ped": {
                "category": "PEDESTRIAN",
                "x_m": 20.0,
                "y_m": 20.0,
                "yaw_rad": np.pi / 2,
                "length_m": 0.6,
                "width_m": 0.6,
            },
        },
        t,
    )
    crit = event_criticality(log, tag_log(log), "ped", int(1.0e9), int(2.0e9))
    assert math.isinf(crit.min_ttc_s)
    assert math.isnan(crit.pet_s)
    assert math.isnan(crit.headway_s)
    assert crit.peak_decel_mps2 == 0.0
    with pytest.raises(KeyError):
        event_criticality(log, tag_log(log), "nobody", 0, int(1e9))
