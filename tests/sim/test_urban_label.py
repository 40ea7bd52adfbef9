"""Labelling of urban runs on hand-built records (no simulator): who forced the ego to brake."""

from __future__ import annotations

import numpy as np
import pytest

from scenariominer.sim.urban_label import label_run
from scenariominer.sim.urban_net import UrbanSimError
from scenariominer.sim.urban_run import GUEST_ID, STEP_S, RunRecord
from scenariominer.sim.urban_scenario import NoiseLevel, noise_for
from scenariominer.synth.vocab import ScenarioCategory

N = 200  # 20 s


def _speed(brake_at_s: float | None, to_mps: float = 2.0, decel: float = 3.0, v0: float = 12.0) -> np.ndarray:
    """Cruise at ``v0``, from ``brake_at_s`` brake at ``decel`` down to ``to_mps`` and stay there."""
    t = np.arange(N) * STEP_S
    if brake_at_s is None:
        return np.full(N, v0)
    return np.maximum(v0 - decel * np.clip(t - brake_at_s, 0.0, None), to_mps)


def _record(
    speed: np.ndarray,
    *,
    leader: list[str] | None = None,
    foes: list[tuple[str, ...]] | None = None,
    guest_edge: list[str] | None = None,
    guest_lane: list[int] | None = None,
    guest_accel: np.ndarray | None = None,
    guest_speed: np.ndarray | None = None,
    action_s: float = 5.0,
    collisions: tuple[str, ...] = (),
) -> RunRecord:
    t = (np.arange(N) + 1) * STEP_S
    accel = np.gradient(speed, STEP_S)
    return RunRecord(
        t_s=t,
        objects={},
        ego_speed_mps=speed,
        ego_accel_mps2=accel,
        ego_to_junction_m=np.full(N, np.nan),
        ego_leader=leader or [""] * N,
        ego_leader_gap_m=np.full(N, 20.0),
        ego_lane=[1] * N,
        ego_foes=foes or [()] * N,
        guest_speed_mps=guest_speed if guest_speed is not None else np.full(N, 10.0),
        guest_accel_mps2=guest_accel if guest_accel is not None else np.zeros(N),
        guest_lane=guest_lane or [1] * N,
        guest_edge=guest_edge or ["in2"] * N,
        guest_action_s=action_s,
        collisions=collisions,
    )


def test_a_pedestrian_on_the_crossing_is_the_cause_from_the_onset_of_the_extra_braking() -> None:
    edge = ["in2"] * 60 + [":C_c1"] * 80 + ["out2"] * 60
    full = _record(_speed(7.0), guest_edge=edge, action_s=5.0)
    label = label_run(ScenarioCategory.PED_CROSSING, full, _record(_speed(None)))
    assert label.ok and label.category is ScenarioCategory.PED_CROSSING
    assert abs(label.onset_index - 69) <= 2  # braking starts at 7.0 s (t_s starts at 0.1 s)
    assert label.start_index == int(np.searchsorted(full.t_s, 5.0))  # from the guest's action
    assert label.end_index > label.onset_index


def test_a_pedestrian_still_on_the_sidewalk_is_not_taken_as_the_cause() -> None:
    full = _record(_speed(7.0), guest_edge=["in2"] * N)
    label = label_run(ScenarioCategory.PED_CROSSING, full, _record(_speed(None)))
    assert not label.ok and "not on a crossing" in label.reason


def test_no_label_when_the_ego_brakes_as_much_without_the_guest() -> None:
    edge = [":C_c1"] * N
    label = label_run(
        ScenarioCategory.PED_CROSSING, _record(_speed(7.0), guest_edge=edge), _record(_speed(7.5))
    )
    assert not label.ok
    assert "did not slow the ego down" in label.reason or "ambiguous" in label.reason


def test_a_turn_slow_down_without_the_guest_does_not_make_a_left_turn_yield_ambiguous() -> None:
    foes = [()] * 50 + [(GUEST_ID,)] * 150
    full = _record(_speed(7.0, to_mps=0.0), foes=foes)
    without = _record(_speed(7.0, to_mps=8.0))  # slows for the turn only: 4 of the 12 m/s
    label = label_run(ScenarioCategory.LEFT_OPPO, full, without)
    assert label.ok and label.category is ScenarioCategory.LEFT_OPPO


def test_a_vehicle_that_is_not_a_junction_foe_is_not_the_cause_of_a_yield() -> None:
    label = label_run(ScenarioCategory.LEFT_OPPO, _record(_speed(7.0, to_mps=0.0)), _record(_speed(None)))
    assert not label.ok and "junction foes" in label.reason


def test_a_gentle_slow_down_is_not_a_braking() -> None:
    full = _record(_speed(7.0, to_mps=10.5, decel=0.5), guest_edge=[":C_c1"] * N)
    label = label_run(ScenarioCategory.PED_CROSSING, full, _record(_speed(None)))
    assert not label.ok and "barely braked" in label.reason


def test_a_collision_with_the_ego_drops_the_run() -> None:
    full = _record(_speed(7.0), guest_edge=[":C_c1"] * N, collisions=(GUEST_ID,))
    label = label_run(ScenarioCategory.PED_CROSSING, full, _record(_speed(None)))
    assert not label.ok and "collided" in label.reason


def test_a_cut_in_needs_a_new_leader_that_changed_lanes() -> None:
    leader = [""] * 60 + [GUEST_ID] * 140
    lanes = [2] * 60 + [1] * 140
    full = _record(_speed(7.0), leader=leader, guest_lane=lanes)
    assert label_run(ScenarioCategory.CUT_IN, full, _record(_speed(None))).category is ScenarioCategory.CUT_IN
    # the same vehicle ahead all along is a braking leader's situation, not a cut-in
    always = _record(_speed(7.0), leader=[GUEST_ID] * N, guest_lane=[1] * N)
    label = label_run(ScenarioCategory.CUT_IN, always, _record(_speed(None)))
    assert not label.ok and "already the ego's leader" in label.reason


def test_a_braking_lead_must_brake_and_have_been_the_leader() -> None:
    guest_accel = np.where((np.arange(N) >= 50) & (np.arange(N) < 80), -4.0, 0.0)
    full = _record(_speed(5.5), leader=[GUEST_ID] * N, guest_accel=guest_accel)
    assert label_run(ScenarioCategory.LEAD_BRAKE, full, _record(_speed(None))).ok
    steady = _record(_speed(5.5), leader=[GUEST_ID] * N)
    assert "did not brake" in label_run(ScenarioCategory.LEAD_BRAKE, steady, _record(_speed(None))).reason


def test_a_stopped_vehicle_ahead_labels_approach_stop() -> None:
    full = _record(_speed(6.0, to_mps=0.0), leader=[GUEST_ID] * N, guest_speed=np.zeros(N), action_s=0.1)
    label = label_run(ScenarioCategory.APPROACH_STOP, full, _record(_speed(None)))
    assert label.category is ScenarioCategory.APPROACH_STOP
    assert label.end_index >= label.onset_index


def test_noise_levels_cycle_under_mixed_and_a_bad_level_is_named() -> None:
    assert [noise_for("mixed", i) for i in range(4)] == [
        NoiseLevel.LOW,
        NoiseLevel.MEDIUM,
        NoiseLevel.HIGH,
        NoiseLevel.LOW,
    ]
    assert noise_for("none", 5) is NoiseLevel.NONE
    with pytest.raises(UrbanSimError, match="unknown noise level 'loud'"):
        noise_for("loud", 0)
