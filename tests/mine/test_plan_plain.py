"""Plain wordings put in the form the phrase tables read (mine/plan_plain.py)."""

from __future__ import annotations

import pytest
from plan_checks import assert_program_has

from scenariominer.mine.plan_plain import plain_wording
from scenariominer.mine.plan_program import compile_plan
from scenariominer.mine.plan_reader import read_plan


@pytest.mark.parametrize(
    ("description", "call"),
    [
        (
            "pedestrian inside three meters of the ego vehicle",
            "near_objects(subject, related_1, log_dir, distance_thresh=3)",
        ),
        (
            "pedestrians ahead of the ego vehicle with a gap of 20 m",
            "direction='forward', within_distance=20",
        ),
        (
            "cars behind the ego vehicle with a gap of 15 m or less",
            "direction='backward', within_distance=15",
        ),
        ("cars turning left with a minimum speed of 5 m/s", "min_velocity=5"),
        ("cars turning right at a maximum speed of 5 m/s", "max_velocity=5"),
        (
            "trucks with negative acceleration",
            "accelerating(subject, log_dir, min_accel=-inf, max_accel=-1.0)",
        ),
        ("the ego vehicle with acceleration greater than 1.5 m/s^2", "min_accel=1.5"),
        (
            "vehicle tracks with lane changes to the right",
            "changing_lanes(subject, log_dir, direction='right')",
        ),
        ("orange cones on the road", "CONSTRUCTION_CONE"),
    ],
)
def test_a_plain_wording_is_read_in_full_with_its_setting(description: str, call: str) -> None:
    plan = read_plan(description)
    assert plan is not None, description
    assert call in compile_plan(plan).program


def test_a_bound_the_tables_cannot_state_stays_unread() -> None:
    # "a gap of at least 20 m" is no "within 20 m": left as written, so not read in full
    assert (
        plain_wording("pedestrians ahead with a gap of at least 20 m")
        == "pedestrians ahead with a gap of at least 20 m"
    )
    assert read_plan("pedestrians ahead of the ego vehicle with a gap of at least 20 m") is None


def test_with_before_anything_but_a_manoeuvre_stays() -> None:
    assert plain_wording("vehicles with pedestrians nearby") == "vehicles with pedestrians nearby"
    assert plain_wording("vehicle with changing lanes") == "vehicle changing lanes"


@pytest.mark.parametrize(
    ("description", "call"),
    [
        (
            "count each truck that is stopped",
            "has_velocity(subject, log_dir, min_velocity=0, max_velocity=0.5)",
        ),
        (
            "Junction trucks: count every truck observed near an intersection.",
            "near_intersection(subject, log_dir)",
        ),
        ("Parked-truck tally: each truck that stays parked for the whole log counts as one.", "stationary("),
        ("Lane-change rate: one event per truck changing lanes to the left", "direction='left'"),
    ],
)
def test_a_counting_request_is_read_as_the_search_it_counts(description: str, call: str) -> None:
    plan = read_plan(description)
    assert plan is not None, description
    assert plan["subject_category"] == "TRUCK"
    assert call in compile_plan(plan).program


@pytest.mark.parametrize(
    ("description", "calls"),
    [
        (
            "Our planner logs look odd near bus stops. If you have a moment, could you pull up buses that are"
            " stopped? Cheers.",
            ["category='BUS'", "max_velocity=0.5"],
        ),
        (
            "I'm preparing a demo for Friday. Would you kindly find times when there's a dog on the road?"
            " Thanks again.",
            ["category='DOG'", "on_road("],
        ),
        (
            "Quick favour. If it's not too much trouble, I'd like to see trucks turning left. You're a star.",
            ["category='TRUCK'", "direction='left'"],
        ),
        (
            "Braking KPI: count each occasion a bus decelerates at more than 3 m/s².",
            ["category='BUS'", "max_accel=-3"],
        ),
        (
            "Exposure metric: one event each time another vehicle is within 4 metres of the ego vehicle.",
            ["category='VEHICLE'", "distance_thresh=4"],
        ),
        (
            "strollers, things like prams, that have a pedestrian nearby",
            ["category='STROLLER'", "near_objects("],
        ),
        ("cars waiting near an intersection, not the parked ones", ["scenario_not(stationary)"]),
        # the distance after "near X" is the distance to X, not to the ego vehicle
        (
            "buses near at least 3 pedestrians within 15 m",
            ["near_objects(subject, related_1, log_dir, distance_thresh=15, min_objects=3)"],
        ),
        (
            "the ego vehicle near a truck within 20 m",
            [
                "related_1 = get_objects_of_category(log_dir, category='TRUCK')\n"
                "step_1 = near_objects(subject, related_1, log_dir, distance_thresh=20)"
            ],
        ),
    ],
)
def test_a_request_among_polite_sentences_or_a_count_is_read_in_full(
    description: str, calls: list[str]
) -> None:
    assert_program_has(description, calls)
