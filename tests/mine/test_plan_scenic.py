"""Scenic programs in the words the phrase tables read (mine/plan_scenic.py)."""

from __future__ import annotations

import pytest
from plan_checks import assert_program_has

from scenariominer.mine.plan_reader import read_plan
from scenariominer.mine.plan_scenic import scenic_program


@pytest.mark.parametrize(
    ("program", "calls"),
    [
        (
            "truck = new Truck in drivableArea; find truck",
            ["category='TRUCK'", "in_drivable_area(subject, log_dir)"],
        ),
        (
            "v = new Vehicle; require (speed of v) > 12; find v",
            ["has_velocity(subject, log_dir, min_velocity=12"],
        ),
        ("bus = new Bus; require (acceleration of bus) < -2; find bus", ["max_accel=-2"]),
        ("c = new Car with behavior TurnRight; find c", ["turning(subject, log_dir, direction='right')"]),
        # a behaviour defined before it is used
        (
            "behavior GoLeft(): do TurnLeft; t = new BoxTruck with behavior GoLeft; find t",
            ["direction='left'"],
        ),
        (
            "ego = new Car; cone = new ConstructionCone ahead of ego by (0, 10);"
            " require (distance from ego to cone)"
            " < 20; find cone",
            [
                "get_objects_in_relative_direction(related_1, subject, log_dir, direction='forward',"
                " within_distance=20)"
            ],
        ),
        (
            "ego = new Car; bike = new Bicycle left of ego; require (distance from ego to bike) < 10;"
            " find bike",
            ["direction='left'", "within_distance=10"],
        ),
        (
            "ego = new Car; require at least 4 Pedestrian objects within 20 of ego; find ego",
            ["min_objects=4"],
        ),
        # the object found is the one another is related to
        (
            "v = new Vehicle; ped = new Pedestrian crossing in front of v; find v",
            ["being_crossed_by(subject, related_1, log_dir, direction='forward')"],
        ),
        (
            "ego = new Car; lead = new Truck ahead of ego; require ego follows lead in its lane; find lead",
            ["reverse_relationship(following)(related_1, subject, log_dir)"],
        ),
        (
            "ped = new Pedestrian; require not (ped in drivableArea); find ped",
            ["scenario_not(in_drivable_area)"],
        ),
        (
            "obj = new Bollard or new ConstructionCone; find obj",
            ["category='BOLLARD'", "category='CONSTRUCTION_CONE'"],
        ),
    ],
)
def test_a_scenic_program_is_read_as_the_object_it_finds(program: str, calls: list[str]) -> None:
    assert_program_has(program, calls)


def test_the_object_found_is_worded_with_what_is_said_of_it() -> None:
    assert scenic_program(
        "ego = new Car; ped = new Pedestrian right of ego; require (distance from ego to ped) < 25; find ped"
    ) == ("pedestrian to the right of the ego vehicle within 25 m.")


@pytest.mark.parametrize(
    "text",
    [
        "vehicles turning left; pedestrians nearby",  # no object created
        "car = new Car; find bus",  # the object found was never created
    ],
)
def test_text_this_reading_does_not_know_comes_back_unchanged(text: str) -> None:
    assert scenic_program(text) == text


def test_a_scenic_program_it_cannot_read_is_not_taken_for_its_bare_find() -> None:
    # "find car" alone would read as every car: the request is left to the model instead
    program = "car = new Car; require car does a barrel roll; find car"
    assert scenic_program(program) == "car = new Car; require car does a barrel roll"
    assert read_plan(program) is None
    assert scenic_program("x = new Spaceship; find x") == "x = new Spaceship"  # a class it does not know


@pytest.mark.parametrize(
    ("program", "calls"),
    [
        ("bus = new Bus; require bus turns left; find bus", ["turning(subject, log_dir, direction='left')"]),
        (
            "t = new Truck; require t changes lanes to the right; find t",
            ["changing_lanes(subject, log_dir, direction='right')"],
        ),
    ],
)
def test_a_condition_on_the_action_is_read(program: str, calls: list[str]) -> None:
    assert_program_has(program, calls)
