"""An annotator's instructions (mine/plan_instructions.py), read by the phrase rules.

The wordings come from the spent fresh42 run (an annotation QA lead's labelling instructions, 0.736
clean with plan-reader/43, scored before these rules existed); each must build the program of its
plain English, and the street scene of tests/mine/mining_scenes.py checks one end to end.
"""

from __future__ import annotations

import pytest
from mining_scenes import rules_program, rules_referred, street_scene

from scenariominer.mine.plan_instructions import instruction_wording

SCENE = street_scene()


@pytest.mark.parametrize(
    ("instruction", "plain"),
    [
        (
            "Tag every pedestrian for the frames in which they are inside the drivable area; pedestrians on"
            " the sidewalk do not get this tag.",
            "pedestrians in the drivable area",
        ),
        (
            "Label each bus only in the frames where it is travelling faster than 18 km/h.",
            "buses faster than 5 m/s",
        ),
        ("Mark every vehicle for the duration of a left turn.", "vehicles turning left"),
        (
            "Annotate parked cars: regular vehicles that never move during the whole sequence. Do not"
            " tag cars"
            " that only pause briefly.",
            "stationary cars",
        ),
        (
            "Tag vehicles that have another vehicle directly ahead of them in their lane corridor, no"
            " more than"
            " 10 m away.",
            "vehicles with another vehicle directly ahead of them within 10 m",
        ),
        (
            "Tag vehicles whose nose points at the ego vehicle within 30 degrees, whether they are moving or"
            " parked.",
            "vehicles facing the ego vehicle within 30 degrees",
        ),
        (
            "Tag trucks of any kind (box trucks, trucks, truck cabs) while they are moving.",
            "moving box trucks or trucks or truck cabs",
        ),
        (
            "Tag pedestrians who are standing still; include people who never move at all as well as people"
            " pausing for a moment.",
            "pedestrians standing still",
        ),
        (
            "Tag the ego vehicle during a right turn, but only in frames where it is on the"
            " intersection itself.",
            "the ego vehicle turning right on an intersection",
        ),
        (
            "Tag the lead vehicle the ego vehicle is following in its lane; the tag goes on the lead,"
            " not on the"
            " ego.",
            "vehicles that the ego vehicle is following in its lane",
        ),
        (
            "Tag vehicles cornering or swerving hard to the right, with sideways acceleration above 2 m/s²"
            " toward their right.",
            "vehicles swerving hard to the right with a rightward lateral acceleration of more than 2 m/s^2",
        ),
        ("Tag moving vehicles in frames where they are not turning.", "moving vehicles that are not turning"),
        (
            "Tag vehicles overtaking the ego vehicle on its left, passing from behind it to ahead of"
            " it along its"
            " left side.",
            "vehicles overtaking the ego vehicle on its left",
        ),
        (
            "Tag vehicles for the whole manoeuvre whenever they move over into the lane on their right.",
            "vehicles changing lanes to the right",
        ),
        (
            "Tag pedestrians at the moments they cross in front of any vehicle; tag the pedestrian, not the"
            " vehicle.",
            "pedestrians crossing in front of a vehicle",
        ),
        (
            "Tag the ego vehicle whenever at least two pedestrians are within 15 m of it.",
            "the ego vehicle with at least 2 pedestrians within 15 m",
        ),
        (
            "Tag oncoming vehicles: ones travelling in the opposite direction to the ego vehicle while"
            " within 30 m"
            " of it.",
            "vehicles travelling in the opposite direction to the ego vehicle within 30 m of it",
        ),
        (
            "Tag each pedestrian who has at least three other pedestrians within 3 m, i.e. people in a"
            " group.",
            "pedestrians with at least 3 other pedestrians within 3 m",
        ),
        (
            "Tag every vehicle other than a bus that shares a lane with a bus.",
            "vehicles other than buses in the same lane as a bus",
        ),
    ],
)
def test_an_instruction_builds_the_program_of_its_plain_english(instruction: str, plain: str) -> None:
    assert rules_program(instruction) == rules_program(plain)


def test_a_note_about_the_tag_is_dropped_and_the_scene_kept() -> None:
    text = "tag pedestrians on a crosswalk; pedestrians on the sidewalk do not get this tag"
    assert instruction_wording(text) == "pedestrians on a crosswalk"
    # a later clause about the scene stays
    assert (
        instruction_wording("vehicles turning left; a bus is nearby")
        == "vehicles turning left; a bus is nearby"
    )


def test_an_instruction_finds_what_its_plain_english_finds() -> None:
    found = rules_referred(
        SCENE, "Tag every pedestrian for the frames in which they are inside the drivable area."
    )
    assert found == rules_referred(SCENE, "pedestrians in the drivable area")
    assert found
