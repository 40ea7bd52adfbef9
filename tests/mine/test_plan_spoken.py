"""Spoken requests and questions in the words the phrase tables read (mine/plan_spoken.py)."""

from __future__ import annotations

import pytest
from plan_checks import assert_program_has

from scenariominer.mine.plan_spoken import spoken_request


@pytest.mark.parametrize(
    ("spoken", "calls"),
    [
        # a wake word before the request
        (
            "Hey Miner, find buses turning right.",
            ["category='BUS'", "turning(subject, log_dir, direction='right')"],
        ),
        ("OK computer, show me parked box trucks", ["category='BOX_TRUCK'", "stationary(subject, log_dir)"]),
        (
            "Hey scenario bot find pedestrians on the road",
            ["category='PEDESTRIAN'", "on_road(subject, log_dir)"],
        ),
        # a question for the road users it describes
        ("Were there any trucks parked in these logs?", ["category='TRUCK'", "stationary(subject, log_dir)"]),
        (
            "Did any vehicle change lanes to the right?",
            ["changing_lanes(subject, log_dir, direction='right')"],
        ),
        ("Was a bus ever driving in a bus lane?", ["on_lane_type(subject, log_dir, lane_type='BUS')"]),
        ("Were any pedestrians walking toward us?", ["heading_toward(subject, related_1, log_dir)"]),
        # a question in the first person: the ego vehicle
        ("When were we stopped?", ["category='EGO_VEHICLE'", "stationary(subject, log_dir)"]),
        ("Did we make any right turns on these drives?", ["category='EGO_VEHICLE'", "direction='right'"]),
        ("When were we driving behind a bus in our lane?", ["following(subject, related_1, log_dir)"]),
        # the one the ego vehicle follows, and a count after "had"
        (
            "When did the car we were following brake hard?",
            ["category='EGO_VEHICLE'", "reverse_relationship(following)", "max_accel="],
        ),
        ("Find every time a bus had at least two pedestrians within 8 meters of it", ["min_objects=2"]),
    ],
)
def test_a_spoken_request_or_question_is_read_in_full(spoken: str, calls: list[str]) -> None:
    program = assert_program_has(spoken, calls)
    if "our lane" in spoken:
        # the ego vehicle's own lane is the lane it follows in: it is not related to itself
        assert program.count("category='EGO_VEHICLE'") == 1, program


def test_the_wake_word_and_the_question_are_dropped() -> None:
    assert (
        spoken_request("hey miner, were there any parked trucks on these drives?")
        == "find any parked trucks?"
    )
    assert spoken_request("ok computer, when were we stopped?") == "we stopped?"
    assert spoken_request("is the ego ever stopped?") == "find the ego stopped?"


@pytest.mark.parametrize(
    "text",
    [
        "vehicles turning left at an intersection",
        "right turning vehicles, within 5 m of a pedestrian",  # "right" is no interjection
        "okay-ish pedestrians",  # no wake word without a comma or a request after it
        "the ego vehicle was stopped",
    ],
)
def test_text_that_is_no_spoken_request_comes_back_unchanged(text: str) -> None:
    assert spoken_request(text) == text
