"""Requests written as EARS requirements, tag paths and in OpenSCENARIO's names (mine/plan_documents.py).

The wordings are my own, written for plan-reader/55 before the fresh62-fresh64 passes were read;
each must build the program of its plain English.
"""

from __future__ import annotations

import pytest
from mining_scenes import rules_program

from scenariominer.mine.plan_documents import camel_words, document_wording


@pytest.mark.parametrize(
    ("written", "plain"),
    [
        (
            "When a pedestrian is within 5 m of the ego vehicle, the system shall return the pedestrian.",
            "pedestrians within 5 m of the ego vehicle",
        ),
        (
            "The system shall return all vehicles that are changing lanes to the left.",
            "vehicles changing lanes left",
        ),
        ("While a bus is stopped, the system shall return that bus.", "stopped buses"),
        (
            "If a vehicle is travelling faster than 15 m/s, the system shall flag the vehicle.",
            "vehicles faster than 15 m/s",
        ),
        (
            "Where the object is a truck, when it is turning right, the system shall return it.",
            "trucks turning right",
        ),
        (
            "While the ego vehicle is turning left, the system shall return pedestrians in front of the ego"
            " vehicle.",
            "pedestrians in front of the ego vehicle while the ego vehicle is turning left",
        ),
        (
            "The scenario search shall return every stationary vehicle on the road.",
            "stationary vehicles on the road",
        ),
    ],
)
def test_a_requirement_builds_the_program_of_its_request(written: str, plain: str) -> None:
    assert rules_program(written) == rules_program(plain)


@pytest.mark.parametrize(
    ("written", "plain"),
    [
        ("vehicle/lane_change/left", "vehicles changing lanes to the left"),
        ("ped.crossing.in_front_of_ego", "pedestrians crossing in front of the ego vehicle"),
        ("ego/following/regular_vehicle", "the ego vehicle following a car"),
        ("vehicle.speed.above_10mps", "vehicles faster than 10 m/s"),
        ("bus/stopped/near_intersection", "buses stopped near an intersection"),
        ("pedestrian/near_ego/within_5m", "pedestrians within 5 m of the ego vehicle"),
        ("truck.turning.right", "trucks turning right"),
    ],
)
def test_a_tag_path_builds_the_program_of_its_words(written: str, plain: str) -> None:
    assert rules_program(written) == rules_program(plain)


@pytest.mark.parametrize(
    ("written", "plain"),
    [
        (
            "Entity: pedestrian. Condition: RelativeDistanceCondition to ego less than 5 m.",
            "pedestrians within 5 m of the ego vehicle",
        ),
        ("Actor vehicle performs LaneChangeAction to the left.", "vehicles changing lanes to the left"),
        ("Entity bus with SpeedCondition equal to 0.", "stopped buses"),
        ("Entity vehicle, SpeedCondition greaterThan 10 m/s.", "vehicles faster than 10 m/s"),
        (
            "Entity: truck; Action: RoutingAction turn right at Junction.",
            "trucks turning right at an intersection",
        ),
        (
            "EntityRef vehicle; RelativeLanePosition: same lane as ego, ahead.",
            "vehicles in the same lane as the ego vehicle and ahead of the ego vehicle",
        ),
    ],
)
def test_openscenario_names_build_the_program_of_the_plain_english(written: str, plain: str) -> None:
    assert rules_program(written) == rules_program(plain)


def test_camel_case_is_split_only_in_openscenario_names() -> None:
    assert camel_words("SpeedCondition greaterThan 10") == "Speed Condition greater Than 10"
    assert camel_words("iPhone McDonald vehicles") == "iPhone McDonald vehicles"


@pytest.mark.parametrize(
    "text",
    ["vehicles turning left", "3 pedestrians near the ego vehicle", "while turning left, vehicles slow down"],
)
def test_text_that_is_no_requirement_or_tag_path_is_unchanged(text: str) -> None:
    assert document_wording(text) == text
