"""Commit messages of a scenario library in the words the phrase tables read (mine/plan_commit.py)."""

from __future__ import annotations

import pytest
from plan_checks import assert_program_has

from scenariominer.mine.plan_commit import commit_message


@pytest.mark.parametrize(
    ("message", "calls"),
    [
        (
            "feat(scenarios): add buses turning left at an intersection",
            ["category='BUS'", "direction='left'"],
        ),
        (
            "feat: add scenario for trucks changing lanes to the right",
            ["changing_lanes(subject, log_dir, direction='right')"],
        ),
        ("feat!: add parked box trucks", ["category='BOX_TRUCK'", "stationary(subject, log_dir)"]),
        ("fix(mining): cone near ego scenario now requires < 8 m to ego", ["distance_thresh=8"]),
        # a fixed scenario that now finds more: both states
        (
            "fix: stopped bus scenario now counts parked buses too",
            [
                "stationary(subject, log_dir)",
                "has_velocity(subject, log_dir, min_velocity=0, max_velocity=0.5)",
            ],
        ),
        (
            "feat(scenarios): add vehicles crossed by a pedestrian walking from right to left in front",
            [
                "being_crossed_by(subject, related_1, log_dir, direction='forward',"
                " in_direction='counterclockwise')"
            ],
        ),
    ],
)
def test_a_commit_message_is_read_as_its_scenario(message: str, calls: list[str]) -> None:
    assert_program_has(message, calls)


def test_the_commit_type_and_the_adding_verb_are_dropped() -> None:
    assert commit_message("feat(scenarios): add moving buses") == "find moving buses"
    assert (
        commit_message("fix: ped near ego scenario now requires < 5 m to ego") == "ped near ego < 5 m of ego"
    )
    assert commit_message("fix: stopped truck scenario now counts parked trucks too") == (
        "stopped trucks or parked trucks"
    )


@pytest.mark.parametrize(
    "text", ["vehicles that fix their lane", "Fixed objects: bollards on the road", "add pedestrians"]
)
def test_text_that_is_no_commit_message_comes_back_unchanged(text: str) -> None:
    assert commit_message(text) == text
