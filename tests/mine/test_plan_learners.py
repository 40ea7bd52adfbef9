"""Wording of writers whose first language is not English (mine/plan_learners.py), read by the rules.

Written from our own descriptions (no evaluation split): each learner's wording must build the
same program as its plain English.
"""

from __future__ import annotations

import pytest
from mining_scenes import rules_program, rules_referred, street_scene

from scenariominer.mine.plan_learners import learner_wording


@pytest.mark.parametrize(
    ("learner", "plain"),
    [
        ("vehicles which are turning to left", "vehicles turning left"),
        ("vehicles in the intersection area that turn to right", "vehicles on an intersection turning right"),
        ("pedestrian goes over the street", "pedestrian crossing the street"),
        ("cars which are parking on the road", "cars parked on the road"),
        ("bicycle drives on the bicycle way", "bicycles in a bike lane"),
        ("a truck makes a lane change to the left side", "trucks changing lanes to the left"),
        ("car is standing at the crossing", "cars stopped at the crosswalk"),
        ("ego car drives with more than 10 m/s", "the ego vehicle moving faster than 10 m/s"),
        ("cars driving at a speed of more than 10 m/s", "cars driving faster than 10 m/s"),
        ("the ego is overtaken from a bus", "the ego vehicle being overtaken by a bus"),
        ("vehicles in the distance of less than 5 m to a pedestrian", "vehicles within 5 m of a pedestrian"),
    ],
)
def test_a_learners_wording_builds_the_program_of_its_plain_english(learner: str, plain: str) -> None:
    assert rules_program(learner) == rules_program(plain)


def test_the_rewrites_keep_plain_english_and_nouns_as_they_are() -> None:
    for text in (
        "pedestrians standing at the crosswalk",  # people standing are not stopped vehicles
        "vehicles in the parking lot",
        "cars turning to the left of the ego vehicle",
        "a pedestrian crossing the road",
        "cars that cut across our direction of travel at right angles",
        "vehicle getting passed from the right",
    ):
        assert learner_wording(text) == text
    assert rules_referred(street_scene(), "pedestrian goes over the street") == {"ped"}


@pytest.mark.parametrize(
    ("asked", "plain"),
    [
        # a planner's questions and a student's shorthand (our own descriptions)
        (
            "how do cyclists behave when they ride through an intersection?",
            "cyclists riding on an intersection",
        ),
        ("where do buses stop close to a crosswalk?", "buses stopping within 5 m of a crosswalk"),
        (
            "do vehicles slow down as they approach pedestrians?",
            "vehicles slowing down approaching pedestrians",
        ),
        ("I'd like to see every pedestrian who crosses the road", "pedestrians crossing the road"),
        ("# of peds near ego > 3", "the ego vehicle with at least 4 pedestrians nearby"),
        ("number of vehicles around the ego >= 2", "the ego vehicle with at least 2 vehicles nearby"),
        ("peds w/in 5m of ego", "pedestrians within 5 m of the ego vehicle"),
    ],
)
def test_questions_and_shorthand_build_the_program_of_their_plain_english(asked: str, plain: str) -> None:
    assert rules_program(asked) == rules_program(plain)
