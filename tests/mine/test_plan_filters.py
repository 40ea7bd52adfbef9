"""Filter expressions (mine/plan_filters.py) and other wordings met before a hold-out, read by the rules.

Written in session 22 from wordings of my own, before the fresh41-fresh44 runs were scored (those
were scored with the code of the commit before these rules): a filter's syntax must build the
program of its plain English, and text without filter syntax must come through unchanged.
"""

from __future__ import annotations

import pytest
from mining_scenes import rules_program, rules_referred, street_scene

from scenariominer.mine.plan_filters import filter_wording

SCENE = street_scene()


@pytest.mark.parametrize(
    ("written", "plain"),
    [
        ("speed_mps > 10 AND category == REGULAR_VEHICLE", "regular vehicles faster than 10 m/s"),
        ("category IN (BUS, BOX_TRUCK) AND on_intersection", "buses or box trucks on an intersection"),
        (
            "SELECT * FROM tracks WHERE class = 'PEDESTRIAN' AND dist_to_ego < 15 m",
            "pedestrians within 15 m of the ego vehicle",
        ),
        ("category == VEHICLE && is_parked == false", "vehicles that are not parked"),
        (
            "cat=PEDESTRIAN, v > 1.5 m/s, !in_drivable_area",
            "pedestrians faster than 1.5 m/s outside the drivable area",
        ),
        ("where speed < 2 and class = bus", "buses slower than 2 m/s"),
        ("filter: category == VEHICLE && lane_change_left", "vehicles changing lanes to the left"),
        ("distance to ego >= 30 && type == REGULAR_VEHICLE", "cars not within 30 m of the ego vehicle"),
    ],
)
def test_a_filter_builds_the_program_of_its_plain_english(written: str, plain: str) -> None:
    assert rules_program(written) == rules_program(plain)


@pytest.mark.parametrize(
    "text",
    [
        "where are vehicles parked on the road lanes",
        "vehicles stopped at a crosswalk while a pedestrian is crossing",
        "the ego vehicle turning left, with a bus behind it",
    ],
)
def test_text_without_filter_syntax_is_unchanged(text: str) -> None:
    assert filter_wording(text) == text


@pytest.mark.parametrize(
    ("written", "plain"),
    [
        # annotators' instructions: the verb asks for the result
        (
            "Tag every pedestrian who crosses in front of the ego vehicle",
            "pedestrians crossing in front of the ego vehicle",
        ),
        ("Annotate each frame in which a truck is turning left", "trucks turning left"),
        ("Label all parked cars within 10 m of the ego", "parked cars within 10 m of the ego vehicle"),
        # a news story's names for the ego vehicle and for people on foot
        ("a jogger crossing in front of the robotaxi", "a pedestrian crossing in front of the ego vehicle"),
        ("the driverless car turning left", "the ego vehicle turning left"),
        # bounds in words
        ("vehicles moving at most 2 m/s", "vehicles slower than 2 m/s"),
        ("vehicles at least 20 m away from the ego vehicle", "vehicles not within 20 m of the ego vehicle"),
        ("vehicles with acceleration less than -3 m/s^2", "vehicles braking harder than 3 m/s^2"),
        # another road user's own condition in a bare "with" clause stays its own
        (
            "the ego vehicle turning left with oncoming vehicles",
            "the ego vehicle turning left with oncoming vehicles nearby",
        ),
        ("vehicles with a parked car", "vehicles with a parked car nearby"),
        # an annotator's exclusions
        (
            "Tag moving vehicles on the intersection; do not tag parked ones",
            "moving vehicles on the intersection that are not parked",
        ),
        (
            "Tag pedestrians on the crosswalk, excluding those standing still",
            "pedestrians on the crosswalk that are not stationary",
        ),
        (
            "Label vehicles turning left (exclude the ego vehicle)",
            "vehicles turning left other than the ego vehicle",
        ),
        ("Mark cars but skip the parked ones", "cars that are not parked"),
        ("Tag buses only while they are stopped", "buses that are stopped"),
        # a scenario catalogue's titles
        (
            "Cut-in from the left",
            "vehicles changing lanes to the right and cutting in ahead of the ego vehicle",
        ),
        (
            "Truck cut-in from right lane",
            "trucks changing lanes to the left and cutting in ahead of the ego vehicle",
        ),
        ("Vehicle cut-in", "vehicles cutting in ahead of the ego vehicle"),
        ("Lead vehicle braking", "vehicles braking while being followed by the ego vehicle"),
    ],
)
def test_wordings_met_before_the_hold_out(written: str, plain: str) -> None:
    assert rules_program(written) == rules_program(plain)


def test_a_modified_road_user_after_with_is_conditioned_itself_not_the_subject() -> None:
    program = rules_program("vehicles with a parked car")
    assert "stationary(related_1" in program
    assert "stationary(subject" not in program


def test_a_filter_finds_what_its_plain_english_finds() -> None:
    assert rules_referred(SCENE, "category == PEDESTRIAN AND dist_to_ego < 20 m") == rules_referred(
        SCENE, "pedestrians within 20 m of the ego vehicle"
    )
    assert rules_referred(SCENE, "category == PEDESTRIAN AND dist_to_ego < 20 m")


def test_a_lead_vehicle_related_to_the_ego_in_words_is_read_as_written() -> None:
    assert rules_program("lead vehicle in the ego's lane less than 20 m ahead") == rules_program(
        "vehicle in the same lane as the ego vehicle within 20 m ahead"
    )
