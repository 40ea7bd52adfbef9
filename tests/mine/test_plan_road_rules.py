"""The register of road rules read by the phrase rules: what an offence looks like in the logs.

Written from our own descriptions (no evaluation split): a vehicle that fails to yield is moving
while the other road user crosses in front of it; blocking a place is being stopped on it.
"""

from __future__ import annotations

from mining_scenes import rules_program, rules_referred, street_scene

SCENE = street_scene()


def test_failing_to_yield_is_moving_while_the_other_crosses_in_front() -> None:
    for description in (
        "vehicles failing to yield to a pedestrian",
        "is there any vehicle that does not give way to a pedestrian?",
        "vehicles not yielding to pedestrians",
    ):
        program = rules_program(description)
        assert "has_velocity(subject, log_dir, min_velocity=0.5)" in program, description
        assert "being_crossed_by(step_1, related_1, log_dir, direction='forward')" in program, description
    # the lead drives on while the pedestrian crosses in front of it
    assert rules_referred(SCENE, "vehicles failing to yield to a pedestrian") == {"lead"}


def test_blocking_a_place_is_stopped_on_it_and_encroaching_is_being_in_it() -> None:
    program = rules_program("cars blocking the intersection")
    assert "on_intersection(subject, log_dir)" in program and "stationary(step_1, log_dir)" in program
    assert "at_pedestrian_crossing(subject, log_dir, within_distance=0)" in rules_program(
        "a vehicle obstructing the crosswalk"
    )
    assert "on_lane_type(subject, log_dir, lane_type='BIKE')" in rules_program(
        "vehicles encroaching into the bike lane"
    )
    assert rules_referred(SCENE, "cars blocking the intersection") == set()  # the turner keeps moving


def test_following_too_closely_and_a_cut_in_closer_than_a_gap() -> None:
    assert "following(subject, related_1, log_dir)" in rules_program(
        "vehicles following too closely behind another vehicle"
    )
    assert "direction='forward', forward_thresh=10)" in rules_program(
        "vehicles cutting in front of the ego with less than 10 m gap"
    )
