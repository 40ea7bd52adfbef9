"""A witness's account read as the event it reports (mine/plan_witness.py)."""

from __future__ import annotations

import pytest
from plan_checks import assert_program_has

from scenariominer.mine.plan_witness import witness_wording


@pytest.mark.parametrize(
    ("description", "calls"),
    [
        (
            "I was stopped at the lights when a man walked across the road right in front of us.",
            ["category='PEDESTRIAN'", "direction='forward'"],
        ),
        (
            "As we approached the junction, a truck turned left across our path.",
            ["category='TRUCK'", "turning(subject, log_dir, direction='left')"],
        ),
        (
            "We were driving along when the car ahead of us braked hard.",
            ["category='REGULAR_VEHICLE'", "accelerating(", "direction='forward'"],
        ),
        ("There was a pedestrian on the zebra crossing as we slowed down.", ["at_pedestrian_crossing("]),
        (
            "We had just turned right when a pedestrian stepped off the kerb.",
            ["category='PEDESTRIAN'", "on_road("],
        ),
        ("I could see a man standing in the middle of the road.", ["category='PEDESTRIAN'", "on_road("]),
        # the witness alone: "me", "my" are the car they were in
        (
            "The bus in front of me in my lane came to a complete stop.",
            ["category='BUS'", "direction='forward'", "in_same_lane(", "max_velocity=0.5"],
        ),
        ("For a while I was following a truck.", ["category='EGO_VEHICLE'", "following(subject"]),
        (
            "A van coming the other way from me turned off to its right.",
            ["direction='opposite'", "turning(", "direction='right'"],
        ),
    ],
)
def test_the_event_of_a_witness_statement_is_read_in_full(description: str, calls: list[str]) -> None:
    assert_program_has(description, calls)


def test_the_scene_and_the_witness_car_are_dropped() -> None:
    assert witness_wording("i was sitting in the back and saw a bus pull out in front of us") == (
        "a bus pull out in front of us"
    )
    assert witness_wording("a cyclist came up on our left side while we were turning right") == (
        "a cyclist came up on our left"
    )
    assert witness_wording("while we were waiting to turn left, a van went past us") == "a van passed us"


def test_text_without_the_witness_comes_back_unchanged() -> None:
    for text in (
        "a man walking when the light is red",
        "the truck passing a parked car",
        "vehicles turning left",
    ):
        assert witness_wording(text) == text
