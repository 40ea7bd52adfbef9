"""Chat shorthand, one-line scenario specifications, planner bug reports and British road words,
read by the phrase rules (mine/plan_notes.py, plan_wording.py, plan_registers.py,
plan_narrative.py, plan_road_users.py).

These wordings are my own, written for plan-reader/49 before the fresh49-fresh52 passes were read;
each must build the program of its plain English.
"""

from __future__ import annotations

import pytest
from mining_scenes import rules_program

from scenariominer.mine.plan_wording import normalised_text


@pytest.mark.parametrize(
    ("written", "plain"),
    [
        # a chat message's abbreviations
        ("peds xing in front of ego", "pedestrians crossing in front of the ego vehicle"),
        ("veh stopped nr intersection", "vehicles stopped near an intersection"),
        ("parked cars nr xwalk", "parked cars near a crosswalk"),
        ("trucks turning L", "trucks turning left"),
        ("need all LCs to the left", "vehicles changing lanes to the left"),
        ("veh LC R pls", "vehicles changing lanes to the right"),
        ("ego decel hard", "the ego vehicle braking hard"),
        ("2+ peds nr ego", "the ego vehicle with at least 2 pedestrians nearby"),
        ("bus RT @ int", "buses turning right at an intersection"),
        # a count first
        ("3 or more pedestrians near the ego", "the ego vehicle with at least 3 pedestrians nearby"),
        # a manoeuvre named with no road user
        ("left turns at intersections", "vehicles turning left at an intersection"),
        ("lane changes to the right", "vehicles changing lanes to the right"),
        # a one-line specification
        ("actor=vehicle, maneuver=lane_change_left", "vehicles changing lanes to the left"),
        (
            "Actor: bus | Action: turning right | Context: intersection",
            "buses turning right at an intersection",
        ),
        (
            "actor: ego; maneuver: hard braking; condition: pedestrian within 10 m",
            "the ego vehicle braking hard with a pedestrian within 10 m",
        ),
        ("actor: pedestrian; condition: ego within 10 m", "pedestrians within 10 m of the ego vehicle"),
        # a planner bug report
        (
            "the planner braked hard because a pedestrian stepped out in front of it",
            "the ego vehicle braking hard with a pedestrian crossing in front of it",
        ),
        (
            "we braked hard for a pedestrian crossing in front of us",
            "the ego vehicle braking hard with a pedestrian crossing in front of it",
        ),
        ("the ego was tailgated by a truck", "the ego vehicle being followed by a truck"),
        ("the ego got cut off by a car", "the ego vehicle with a car crossing its path"),
        # British road words
        ("vehicles queuing at the junction", "vehicles waiting near an intersection"),
        ("cyclists on the footway", "bicycles or cyclists on the sidewalk"),
        ("HGVs near the ego", "trucks near the ego vehicle"),
        ("coaches on the carriageway", "buses on the road"),
        ("vehicles indicating and changing lanes", "vehicles changing lanes"),
    ],
)
def test_a_register_builds_the_program_of_its_plain_english(written: str, plain: str) -> None:
    assert rules_program(written) == rules_program(plain)


def test_a_turn_letter_and_a_lane_change_letter_give_the_direction() -> None:
    assert "turning(subject, log_dir, direction='left')" in rules_program("trucks turning L")
    assert "changing_lanes(subject, log_dir, direction='right')" in rules_program("veh LC R")


def test_a_cut_off_is_a_crossing_of_the_path_ahead() -> None:
    program = rules_program("the ego got cut off by a car")
    assert "being_crossed_by(subject, related_1, log_dir, direction='forward')" in program


@pytest.mark.parametrize(
    ("text", "normalised"),
    [
        # "as" and "for a moment" are no reasons, a passive without "by" keeps its reading
        (
            "vehicles that travel in the same direction as a bus",
            "vehicles that travelling in the same direction as a bus",
        ),
        ("buses that are stopped for a moment but not parked", "buses that are stopped but not parked"),
        ("vehicles getting passed from the right", "vehicles being passed from the right"),
    ],
)
def test_plain_wording_is_not_taken_for_a_reason(text: str, normalised: str) -> None:
    assert normalised_text(text) == normalised
