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


@pytest.mark.parametrize(
    ("written", "plain"),
    [
        # from the spent fresh62 run (plan-reader/55)
        ("Bus entity at standstill.", "stopped buses"),
        (
            "Any entity on the road within 10 m of the ego while the ego turns right.",
            "objects on the road within 10 m of the ego vehicle while the ego vehicle is turning right",
        ),
        (
            "Ego travelling on a lane of type vehicle, outside any junction.",
            "the ego vehicle travelling on a vehicle lane not on an intersection",
        ),
    ],
)
def test_openscenario_wording_from_the_spent_run(written: str, plain: str) -> None:
    assert rules_program(written) == rules_program(plain)


@pytest.mark.parametrize(
    ("written", "plain"),
    [
        # from the spent fresh63 run (plan-reader/55): the response naming the condition's subject
        # with more words, or the condition's other road user
        (
            "When any motor vehicle decelerates at more than 2 m/s², the system shall return that"
            " vehicle while it brakes.",
            "motor vehicles decelerating at more than 2 m/s²",
        ),
        (
            "If a vehicle that is not parked comes to a momentary standstill, then the system shall"
            " return that vehicle while it is standing.",
            "vehicles that are not parked momentarily halted",
        ),
        (
            "While a vehicle has another vehicle on its left side no more than 3 m away, the system"
            " shall return the vehicle that has the neighbour.",
            "vehicles with another vehicle on its left side within 3 m",
        ),
        (
            "When a pedestrian walks across the path directly in front of a vehicle, the system"
            " shall return the vehicle being crossed.",
            "vehicles with a pedestrian crossing in front of them",
        ),
        (
            "While at least three pedestrians are within 15 m of a vehicle, the system shall return that"
            " vehicle.",
            "vehicles with at least 3 pedestrians within 15 m",
        ),
        (
            "While a pedestrian is facing the ego vehicle within a 30-degree half-angle, the system"
            " shall return the pedestrian.",
            "pedestrians facing the ego vehicle within 30 degrees",
        ),
        (
            "While a motor vehicle occupies a bike lane, the system shall return that vehicle.",
            "motor vehicles in a bike lane",
        ),
        (
            "While a pedestrian's footprint overlaps a marked pedestrian crossing, the system shall"
            " return that pedestrian.",
            "pedestrians on a pedestrian crossing",
        ),
        (
            "If a moving vehicle has no other vehicle ahead of it within 30 m, then the system shall"
            " return the moving vehicle.",
            "moving vehicles with no other vehicle ahead of it within 30 m",
        ),
    ],
)
def test_requirements_from_the_spent_run(written: str, plain: str) -> None:
    assert rules_program(written) == rules_program(plain)


@pytest.mark.parametrize(
    ("written", "plain"),
    [
        # from the spent fresh64 run (plan-reader/55): units run into numbers, a bare distance last
        ("regular_vehicle/braking/hard_below_minus_2mps2", "cars braking harder than 2 m/s²"),
        ("ego.near.construction_cone.within_5m", "the ego vehicle within 5 m of a construction cone"),
        ("pedestrian.near_other_pedestrians.min_2", "pedestrians near at least 2 other pedestrians"),
        ("ego/vehicle_ahead/within_10m", "vehicles in front of the ego vehicle within 10 m"),
        (
            "vehicle/same_lane_as_ego/behind_ego",
            "vehicles in the same lane as the ego vehicle behind the ego vehicle",
        ),
        (
            "pedestrian/walking/on_road/off_crosswalk",
            "pedestrians walking on the road not at a pedestrian crossing",
        ),
        (
            "vehicle/lateral_accel/left_over_2mps2",
            "vehicles with a lateral acceleration to the left of more than 2 m/s²",
        ),
        ("vehicle.stopped.near_intersection.10m", "vehicles stopped within 10 m of an intersection"),
        ("vulnerable_road_user/near/ego/5m", "vulnerable road users within 5 m of the ego vehicle"),
        ("vehicle.right_side.pedestrian.within_4m", "vehicles with a pedestrian on its right within 4 m"),
        ("vehicle/ahead/at_least_2_vehicles/20m", "vehicles with at least 2 vehicles ahead within 20 m"),
        ("pedestrian/drivable_area/off_road", "pedestrians in the drivable area not on the road"),
        ("vehicle.non_regular.moving", "vehicles other than regular vehicles moving"),
        ("vehicle/facing/pedestrian/15m", "vehicles facing a pedestrian within 15 m"),
        ("bollard.near.moving_vehicle.2m", "bollards within 2 m of a moving vehicle"),
        ("vehicle_incl_bicycle/moving/on_road", "vehicles or bicycles moving on the road"),
    ],
)
def test_tag_paths_from_the_spent_run(written: str, plain: str) -> None:
    assert rules_program(written) == rules_program(plain)
