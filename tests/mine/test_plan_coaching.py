"""A driving instructor's remarks in the words the phrase tables read (mine/plan_coaching.py)."""

from __future__ import annotations

import pytest
from plan_checks import assert_program_has

from scenariominer.mine.plan_coaching import coaching_remark


@pytest.mark.parametrize(
    ("remark", "calls"),
    [
        # what to watch, without the reason after it
        (
            "Watch out for trucks changing lanes to their right, they swing across late.",
            ["category='TRUCK'", "changing_lanes(subject, log_dir, direction='right')"],
        ),
        ("Keep an eye on buses turning left, they need the whole junction.", ["direction='left'"]),
        ("Mind the construction cones on the road, don't clip them.", ["on_road(subject, log_dir)"]),
        ("Check your mirror for any truck directly behind you within 15 metres.", ["within_distance=15"]),
        ("Give every pedestrian out on the road plenty of room.", ["category='PEDESTRIAN'", "on_road("]),
        # "right" before "on the" is a turn's direction after a turning verb
        ("Be careful of buses turning right while they are on the crosswalk.", ["direction='right'"]),
        # the situation first, the advice after it
        (
            "Whenever you are following a truck in your lane, stay well back.",
            ["category='EGO_VEHICLE'", "following(subject, related_1, log_dir)"],
        ),
        (
            "Before you pull away, always check for pedestrians right on the crosswalk.",
            ["at_pedestrian_crossing("],
        ),
        (
            "Every time you turn left yourself, slow down more.",
            ["category='EGO_VEHICLE'", "direction='left'"],
        ),
        # a question pointing at road users
        ("See the bollards out on the road? Steer around them.", ["category='BOLLARD'", "on_road("]),
        # the learner's car is the ego vehicle
        (
            "Notice the pedestrians facing your car, they have seen you.",
            ["facing_toward(subject, related_1, log_dir)"],
        ),
    ],
)
def test_a_remark_is_read_as_what_it_points_at(remark: str, calls: list[str]) -> None:
    assert_program_has(remark, calls)


def test_the_advice_and_the_reason_are_dropped() -> None:
    assert coaching_remark("watch out for cars changing lanes to their left, they often cut in") == (
        "find cars changing lanes to their left"
    )
    assert coaching_remark("whenever you are following a bus in your lane, stay well back") == (
        "you are following a bus in the same lane"
    )


@pytest.mark.parametrize(
    "text",
    [
        "pedestrians crossing in front of a bus",
        # a situation first without advice after it is a request in its own right
        "when a bus is turning left, the pedestrians crossing in front of it",
        "watching pedestrians near an intersection",
    ],
)
def test_text_that_is_no_remark_comes_back_unchanged(text: str) -> None:
    assert coaching_remark(text) == text
