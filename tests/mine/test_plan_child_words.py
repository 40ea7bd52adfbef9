"""A request in a child's plain words (mine/plan_registers.py).

The first wordings are my own, written for plan-reader/53 before the fresh58 pass was read; the
later ones come from that spent run (plan-reader/54). Each must build the program of its plain
English.
"""

from __future__ import annotations

import pytest
from mining_scenes import rules_program


@pytest.mark.parametrize(
    ("written", "plain"),
    [
        ("Look for a car that turns left at a crossroads.", "cars turning left at an intersection"),
        ("Find a car that moves into another lane.", "cars changing lanes"),
        ("cars that stop for a long time", "stationary cars"),
        ("a car coming toward our car", "cars heading toward the ego vehicle"),
    ],
)
def test_a_childs_words_build_the_program_of_the_plain_english(written: str, plain: str) -> None:
    assert rules_program(written) == rules_program(plain)


@pytest.mark.parametrize(
    ("written", "plain"),
    [
        # from the spent fresh58 run
        ("cars moving over from their lane into the lane next to it", "cars changing lanes"),
        ("people walking out in the street where the cars go", "people walking on the road"),
        (
            "people on the painted stripes where you walk across the street",
            "pedestrians at a pedestrian crossing",
        ),
        ("cars right in the middle of the spot where two roads meet", "cars on an intersection"),
        (
            "cars close to where roads meet that are not turning",
            "cars near an intersection that are not turning",
        ),
        (
            "a car driving along behind another car in the same lane",
            "a car driving behind another car in the same lane",
        ),
        (
            "cars going the other way from our car",
            "cars travelling in the opposite direction to the ego vehicle",
        ),
        (
            "our car with a big box-shaped delivery truck somewhere in front of it",
            "the ego vehicle with a box truck in front of it",
        ),
        (
            "short posts in the ground with a person standing close by, 2 meters or less",
            "bollards within 2 m of a person",
        ),
        (
            "people, bikes and scooters, anyone not inside a car, close to where roads meet",
            "vulnerable road users near an intersection",
        ),
        ("trucks that are not moving, parked ones too", "trucks that are not moving"),
        (
            "cars on the other half of the road from our car, where cars drive the other way",
            "cars on the opposite side of the road from the ego vehicle",
        ),
        (
            "cars going sideways across the way our car is going",
            "cars travelling perpendicular to the ego vehicle",
        ),
        ("a bus driving in the special lane that is only for buses", "buses driving in a bus lane"),
        ("cars driving in the lane that is just for bikes", "cars driving in a bike lane"),
        ("bikes that are just left standing and nobody moves them", "stationary bicycles"),
        (
            "people walking the same way our car is going",
            "people walking in the same direction as the ego vehicle",
        ),
        ("people who are walking, not standing around", "people walking"),
    ],
)
def test_a_childs_words_from_the_spent_run_build_the_program_of_the_plain_english(
    written: str, plain: str
) -> None:
    assert rules_program(written) == rules_program(plain)


def test_an_appositive_that_is_no_list_keeps_the_subject() -> None:
    # "pedestrians, being vulnerable road users ...": the subject stays the pedestrians
    assert "PEDESTRIAN'" in rules_program("pedestrians, being vulnerable road users, on a crosswalk")
