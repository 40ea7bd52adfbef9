"""Typing slips in a description put right before the phrase rules read it (mine/plan_spelling.py).

The wordings are my own, written for plan-reader/55 before the fresh61 pass was read.
"""

from __future__ import annotations

import pytest
from mining_scenes import rules_program

from scenariominer.mine.plan_spelling import corrected_spelling

pytest.importorskip(
    "spellchecker", reason="the English word list comes with pip install 'scenariominer[mine]'"
)


@pytest.mark.parametrize(
    ("typed", "meant"),
    [
        (
            "pedestrains crosing infront of the ego vehcile",
            "pedestrians crossing in front of the ego vehicle",
        ),
        ("vehicels turnign lefft at the interesction", "vehicles turning left at the intersection"),
        ("truks stoped near a bus", "trucks stopped near a bus"),
        ("a car chaning lanes to the rihgt", "a car changing lanes to the right"),
        ("pedestriansnear the ego", "pedestrians near the ego"),
        ("bollards and constrcution cones on the raod", "bollards and construction cones on the road"),
        ("cars folowing the ego vehicel closley", "cars following the ego vehicle closely"),
        ("parkd cars", "parked cars"),
    ],
)
def test_slips_are_put_right(typed: str, meant: str) -> None:
    assert corrected_spelling(typed) == meant
    assert rules_program(typed) == rules_program(meant)


@pytest.mark.parametrize(
    "text",
    [
        # words either vocabulary knows, shorthand the rules read, contractions without apostrophes
        "peds at xwalk",
        "large veh that arent parked",
        "jaywalkers near a bollard",
        "a kerb-side bus stop",
        "vehicles doing over 10 m/s",
        "actor: vehicle; manoeuvre: lane change",
    ],
)
def test_known_words_are_never_changed(text: str) -> None:
    assert corrected_spelling(text) == text


@pytest.mark.parametrize(
    ("typed", "meant"),
    [
        # from the spent fresh61 run (plan-reader/55): short slips, a slip that spells another word
        ("vehicles in the same lane as teh ego", "vehicles in the same lane as the ego vehicle"),
        ("busses on the intersection", "buses on an intersection"),
        (
            "cars that get a pedestrian crossing in frnot of them",
            "cars with a pedestrian crossing in front of them",
        ),
        ("vehicels driving around in a parkinglot", "vehicles in a parking lot"),
    ],
)
def test_slips_from_the_spent_run_are_put_right(typed: str, meant: str) -> None:
    assert rules_program(typed) == rules_program(meant)
