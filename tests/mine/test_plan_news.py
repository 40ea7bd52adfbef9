"""A news story's wording (mine/plan_news.py) and a scenario catalogue's titles, read by the rules.

The wordings come from the spent fresh43 run (a journalist's captions, 0.330 clean with
plan-reader/43) and the spent fresh41 run (a test-track engineer's catalogue, 0.848 clean); each must
build the program of its plain English, and the street scene of tests/mine/mining_scenes.py checks
one end to end.
"""

from __future__ import annotations

import pytest
from mining_scenes import rules_program, rules_referred, street_scene

from scenariominer.mine.plan_news import news_wording

SCENE = street_scene()


@pytest.mark.parametrize(
    ("news", "plain"),
    [
        ("the robotaxi swinging into a left turn", "the ego vehicle turning left"),
        (
            "a car swinging right with someone on foot close by",
            "a car turning right with a pedestrian nearby",
        ),
        ("cars drifting over one lane to the right", "cars changing lanes to the right"),
        (
            "the robotaxi tagging along behind another car in its lane",
            "the ego vehicle following another car",
        ),
        ("cars stuck trailing behind a bus", "cars following a bus"),
        ("cars hanging on the robotaxi's tail in its lane", "cars following the ego vehicle"),
        (
            "traffic of every kind coming the other way from the robotaxi",
            "vehicles travelling in the opposite direction to the ego vehicle",
        ),
        ("people on foot making their way toward the robotaxi", "pedestrians walking toward the ego vehicle"),
        ("cars sitting still right at a crosswalk", "cars stopped at a crosswalk"),
        (
            "the robotaxi with another car riding right alongside on its left",
            "the ego vehicle with another car right beside it on its left",
        ),
        ("cars sharing the robotaxi's lane", "cars in the same lane as the ego vehicle"),
        (
            "cars over on the far side of the road from the robotaxi",
            "cars on the other side of the road from the ego vehicle",
        ),
        (
            "cars on the move in a parking lot or driveway rather than on a street",
            "cars moving in a parking lot or driveway and not on the road",
        ),
        (
            "people strolling along well away from where cars can drive",
            "pedestrians walking outside the drivable area",
        ),
        ("the robotaxi at a complete standstill", "the ego vehicle stopped"),
        ("cars stepping on the gas near an intersection", "cars accelerating near an intersection"),
        (
            "cars with someone walking across just in front of the bumper",
            "cars being crossed by a pedestrian",
        ),
        (
            "the robotaxi with an open road ahead: no car in front within 30 metres",
            "the ego vehicle with no car in front within 30 m",
        ),
        ("cars in a lane set aside for bicycles", "cars in a bike lane"),
        ("a big rig's cab with no trailer attached", "truck cabs"),
        # the catalogue's titles (fresh41)
        ("Ego acceleration event (above 1 m/s²)", "the ego vehicle accelerating more than 1 m/s^2"),
        (
            "Pedestrian cluster - three or more other pedestrians within 5 m",
            "pedestrians with at least 3 other pedestrians within 5 m",
        ),
        ("Pedestrian on the right-hand side of ego", "pedestrians to the right of the ego vehicle"),
        (
            "Vehicle swerve to the right (lateral acceleration below -2 m/s²)",
            "vehicles swerving to the right with a rightward lateral acceleration of more than 2 m/s^2",
        ),
        (
            "Left-turning vehicle with a crosswalk pedestrian within 20 m",
            "vehicles turning left within 20 m of a pedestrian who is at a crosswalk",
        ),
        (
            "Straight-through vehicle in an intersection (moving, no turn)",
            "vehicles going straight in an intersection moving not turning",
        ),
    ],
)
def test_a_news_wording_builds_the_program_of_its_plain_english(news: str, plain: str) -> None:
    assert rules_program(news) == rules_program(plain)


def test_turning_right_at_an_intersection_keeps_its_direction() -> None:
    assert "direction='right'" in rules_program("vehicles turning right at an intersection")


def test_waiting_at_a_standstill_stays_a_momentary_stop() -> None:
    assert "stationary" not in rules_program("vehicles waiting at a standstill in traffic")


def test_text_without_news_wording_is_unchanged() -> None:
    text = "vehicles turning right at an intersection with a pedestrian nearby"
    assert news_wording(text) == text


def test_a_news_wording_finds_what_its_plain_english_finds() -> None:
    found = rules_referred(SCENE, "people on foot making their way toward the robotaxi")
    assert found == rules_referred(SCENE, "pedestrians walking toward the ego vehicle")
