"""The formal register of standards (mine/plan_formal.py), read by the phrase rules.

The wordings below come from the spent fresh36 run (a regulator's scenario taxonomy, scored before
these rules existed); each must build the same program as its plain English, and the street scene
of tests/mine/mining_scenes.py checks a few of them end to end.
"""

from __future__ import annotations

import pytest
from mining_scenes import rules_program, rules_referred, street_scene

from scenariominer.mine.plan_formal import formal_wording

SCENE = street_scene()


@pytest.mark.parametrize(
    ("formal", "plain"),
    [
        (
            "Regular passenger vehicles, defined as objects of the regular vehicle category, whilst"
            " travelling at a ground speed in excess of 36 km/h.",
            "regular vehicles faster than 10 m/s",
        ),
        (
            "Pedestrians, being vulnerable road users travelling on foot, whose bounding box is observed to"
            " overlap the area of a marked pedestrian crossing.",
            "pedestrians on a crosswalk",
        ),
        (
            "The ego vehicle, for the duration of any manoeuvre in which a turn to the left is being"
            " executed.",
            "the ego vehicle turning left",
        ),
        (
            "Motor vehicles which are observed to be transferring from their present lane into the adjacent"
            " lane on their right-hand side.",
            "vehicles changing lanes to the right",
        ),
        (
            "Pedestrians whose bounding box is situated at a distance of no more than 5 metres from that of"
            " the ego vehicle.",
            "pedestrians within 5 m of the ego vehicle",
        ),
        (
            "Motor vehicles located ahead of the ego vehicle, at a distance not exceeding 20 metres and"
            " within a lateral margin of 1 metre beyond the sides of the ego vehicle.",
            "vehicles directly ahead of the ego vehicle within 20 m",
        ),
        (
            "Motor vehicles which, whilst positioned upon an intersection, are observed to be undertaking a"
            " turn to the right.",
            "vehicles on an intersection turning right",
        ),
        (
            "Motor vehicles which have their forward path crossed by a pedestrian.",
            "vehicles being crossed by a pedestrian",
        ),
        (
            "Motor vehicles, other than the ego vehicle, which are moving so as to approach the ego vehicle,"
            " the separation between the two not exceeding 30 metres.",
            "vehicles other than the ego vehicle heading toward the ego vehicle within 30 m",
        ),
        (
            "Motor vehicles, the ego vehicle excepted, occupying the same lane as the ego vehicle.",
            "vehicles other than the ego vehicle in the same lane as the ego vehicle",
        ),
        (
            "Motor vehicles situated on the side of the road opposite to that on which the ego vehicle is"
            " travelling.",
            "vehicles on the other side of the road from the ego vehicle",
        ),
        (
            "The ego vehicle, at those instants at which no fewer than three pedestrians are present within"
            " 15 metres of it.",
            "the ego vehicle with at least 3 pedestrians within 15 m",
        ),
        (
            "Buses of all types, comprising standard, articulated and school buses, when situated in the"
            " vicinity of an intersection.",
            "buses near an intersection",
        ),
        (
            "Motor vehicles having a further motor vehicle located behind them at a distance of no more than"
            " 10 metres, within a lateral margin of 1 metre.",
            "vehicles with another vehicle directly behind them within 10 m",
        ),
        (
            "Motor vehicles being passed along their left-hand side, from rear to front, by another moving"
            " motor vehicle within 4 metres of that side.",
            "vehicles being overtaken on the left by another moving vehicle",
        ),
        (
            "Bollards, being fixed posts delimiting the roadway, which lie within 3 metres of a motor vehicle"
            " in motion.",
            "bollards within 3 m of a moving vehicle",
        ),
        (
            "Motor vehicles in a stopped condition, whether parked or only momentarily at rest, within 5"
            " metres of a pedestrian crossing.",
            "vehicles stopped within 5 m of a crosswalk",
        ),
        (
            "Motor vehicles momentarily brought to a halt, with a ground speed of no more than 0.5 m/s,"
            " whilst located within 10 metres of an intersection.",
            "vehicles slower than 0.5 m/s within 10 m of an intersection",
        ),
    ],
)
def test_the_formal_register_builds_the_program_of_its_plain_english(formal: str, plain: str) -> None:
    assert rules_program(formal) == rules_program(plain)


def test_plain_english_and_relations_between_commas_are_kept() -> None:
    for text in (
        "vehicles near a bus",
        "cars, being followed by a truck, near an intersection",  # a relation, not a definition
        "pedestrians within 5 m of the ego vehicle",
    ):
        assert formal_wording(text.lower()) == text.lower()
    assert formal_wording("vehicles moving at most 0.5 m/s") == "vehicles moving at most 0.5 m/s"  # a speed


def test_formal_wordings_find_what_their_plain_english_finds() -> None:
    # the lead drives 15 m ahead of the ego in its lane, the ego follows it
    assert rules_referred(
        SCENE,
        "Motor vehicles located ahead of the ego vehicle, at a distance not exceeding 20 metres and"
        " within a lateral margin of 1 metre beyond the sides of the ego vehicle.",
    ) == {"lead"}
    assert rules_referred(
        SCENE, "Motor vehicles, the ego vehicle excepted, occupying the same lane as the ego vehicle."
    ) == rules_referred(SCENE, "vehicles other than the ego vehicle in the same lane as the ego vehicle")
