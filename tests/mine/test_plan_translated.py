"""Machine-translated requests in the words the phrase tables read (mine/plan_translated.py)."""

from __future__ import annotations

import pytest
from plan_checks import assert_program_has

from scenariominer.mine.plan_translated import translated_wording


@pytest.mark.parametrize(
    ("translated", "calls"),
    [
        (
            "Foot-goers who are standing directly upon the zebra crossing.",
            ["category='PEDESTRIAN'", "at_pedestrian_crossing("],
        ),
        (
            "Load cars which are making the turning into the right direction.",
            ["category='TRUCK'", "direction='right'"],
        ),
        ("Box-type load cars in vicinity of intersection, within distance of 15 meter.", ["threshold=15"]),
        ("Omnibus which is moving with the speed of more than 3 meter per second.", ["min_velocity=3"]),
        (
            "Own car having 3 or more foot-goers in its front within 25 meter.",
            ["min_number=3", "within_distance=25"],
        ),
        (
            "Vehicles which perform strong braking, the deceleration is more than 3 meter per second square.",
            ["max_accel=-3"],
        ),
        ("Foot-goers who are located on inside of the crossroad area itself.", ["on_intersection("]),
        ("Vehicles which drive on the lane dedicated for the omnibus.", ["lane_type='BUS'"]),
        (
            "Vehicles which have construction cones around, minimum 3 cones in 8 meter.",
            ["min_objects=3", "distance_thresh=8"],
        ),
    ],
)
def test_a_translated_request_is_read_in_full(translated: str, calls: list[str]) -> None:
    assert_program_has(translated, calls)


def test_literal_words_become_the_tables_words() -> None:
    assert translated_wording("foot-goer whose body front is pointing to the own car") == (
        "pedestrians facing the ego vehicle"
    )
    assert translated_wording("vehicle with 2 meter per second square") == "vehicle with 2 m/s^2"


@pytest.mark.parametrize("text", ["pedestrians on the road", "a car 5 m ahead of the ego vehicle"])
def test_plain_english_comes_back_unchanged(text: str) -> None:
    assert translated_wording(text) == text
