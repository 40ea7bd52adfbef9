"""A voice transcript, a Given/When/Then specification, exam questions and a traffic engineer's
jargon (mine/plan_registers.py), read by the phrase rules.

The wordings come from the spent fresh45-fresh48 runs (0.897, 0.692, 0.919, 0.818 clean with
plan-reader/47); each must build the program of its plain English.
"""

from __future__ import annotations

import pytest
from mining_scenes import rules_program

from scenariominer.mine.plan_registers import register_wording


@pytest.mark.parametrize(
    ("written", "plain"),
    [
        # a voice transcript (fresh45)
        ("um show me pedestrians walking on the road", "pedestrians walking on the road"),
        ("cars going faster than ten no sorry twelve meters per second", "cars faster than 12 m/s"),
        (
            "oncoming traffic um vehicles traveling the opposite direction to the ego",
            "vehicles travelling in the opposite direction to the ego vehicle",
        ),
        # a test specification (fresh47)
        (
            "Given a pedestrian, when at least 3 other pedestrians are within 5 m, then select it",
            "pedestrians with at least 3 other pedestrians within 5 m",
        ),
        (
            "Given a vehicle, when it shares a lane with a bus, then select the vehicle",
            "vehicles sharing a lane with a bus",
        ),
        (
            "Given a parked vehicle, when a pedestrian is within 3 m of it, then select the vehicle",
            "parked vehicles with a pedestrian within 3 m",
        ),
        (
            "Given a vehicle, when another vehicle is directly behind it within 10 m, then select it",
            "vehicles with another vehicle directly behind it within 10 m",
        ),
        (
            "Given a vehicle, when its lateral acceleration to the left exceeds 2 m/s², then select it",
            "vehicles with a leftward lateral acceleration of more than 2 m/s^2",
        ),
        (
            "Given a vehicle, when a bollard is on its right within 3 m, then select it",
            "vehicles with a bollard on its right within 3 m",
        ),
        # exam questions (fresh48)
        (
            "At which moments does the ego vehicle drive faster than 20 mph?",
            "the ego vehicle faster than 20 mph",
        ),
        ("Which vehicles perform a lane change to the left?", "vehicles changing lanes to the left"),
        (
            "Which vehicles have a pedestrian cross the path in front of them?",
            "vehicles being crossed by a pedestrian",
        ),
        ("Which vehicles share a lane with a bus?", "vehicles sharing a lane with a bus"),
        (
            "Excluding the ego, which vehicles are on an intersection?",
            "vehicles on an intersection other than the ego vehicle",
        ),
        (
            "Which left-turning vehicles point toward a pedestrian during the turn?",
            "vehicles turning left pointing toward a pedestrian",
        ),
        (
            "Which pedestrians are walking while their body overlaps a marked crosswalk?",
            "pedestrians walking on a crosswalk",
        ),
        # a traffic engineer (fresh46)
        ("the ego vehicle executing a right-turn movement", "the ego vehicle turning right"),
        (
            "vehicles executing a lane change into the lane to their left",
            "vehicles changing lanes to the left",
        ),
        (
            "queued vehicles on an intersection approach: stopped within 15 m of the intersection with"
            " another"
            " vehicle directly ahead within 10 m",
            "vehicles stopped within 15 m of the intersection with another vehicle directly ahead within"
            " 10 m",
        ),
        (
            "right-turning vehicles whose path is crossed by a pedestrian (permissive right turn"
            " conflicting with"
            " the ped phase)",
            "vehicles turning right being crossed by a pedestrian",
        ),
        ("non-motorised road users inside the intersection box", "vulnerable road users on an intersection"),
        (
            "pedestrians standing still within 2 m of a crosswalk, waiting for the walk phase",
            "pedestrians standing still within 2 m of a crosswalk",
        ),
    ],
)
def test_a_register_builds_the_program_of_its_plain_english(written: str, plain: str) -> None:
    assert rules_program(written) == rules_program(plain)


def test_a_heavy_vehicle_named_in_brackets_is_the_related_road_user_not_the_subject() -> None:
    program = rules_program("vehicles sharing a lane with a heavy vehicle (truck or box truck)")
    assert "category='VEHICLE')" in program.splitlines()[0]
    assert "in_same_lane" in program


def test_plain_text_is_unchanged() -> None:
    text = "vehicles turning right with a pedestrian within 5 m"
    assert register_wording(text) == text
