"""Everyday words for what the phrase tables name technically (mine/plan_everyday.py)."""

from __future__ import annotations

import pytest
from plan_checks import assert_program_has

from scenariominer.mine.plan_everyday import everyday_wording, figure_marks


@pytest.mark.parametrize(
    ("description", "calls"),
    [
        (
            "When is the car we are in going faster than 8 meters every second?",
            ["'EGO_VEHICLE'", "min_velocity=8"],
        ),
        (
            "Find the vans that have 2 or more people close to them, 4 meters or closer.",
            ["distance_thresh=4"],
        ),
        ("Show me a truck in front of our car, 30 meters away or closer", ["within_distance=30"]),
        ("Find the cars that are hitting the brakes hard.", ["max_accel=-3"]),
        ("Find the buses scooting over to the lane on their right side.", ["direction='right'"]),
        ("Find the dogs looking right at our car.", ["category='DOG'", "facing_toward("]),
        ("Find people on the white stripes where you cross the street", ["at_pedestrian_crossing("]),
        ("Find the trucks in the middle of the crossroads where the streets meet", ["on_intersection("]),
        ("Find the strollers in the places cars are allowed to drive", ["in_drivable_area("]),
        ("Find the parked vans that never ever move the whole time", ["stationary(subject"]),
        # a dashboard panel's note on what it plots says nothing of what to find
        ("Buses in a bus lane (count over time)", ["lane_type='BUS'"]),
        ("Trucks heading toward a pedestrian (15 m radius) – events per hour", ["heading_toward("]),
        ("Left-turning vans: count per minute", ["direction='left'"]),
    ],
)
def test_an_everyday_description_is_read_in_full(description: str, calls: list[str]) -> None:
    assert_program_has(description, calls)


def test_everyday_phrases_become_the_tables_words() -> None:
    assert everyday_wording("the car we are in going more than 5 meters every second") == (
        "the ego vehicle going more than 5 m/s"
    )
    assert everyday_wording("people who are really close to a bus 3 meters or less") == (
        "people who are within 3 m of a bus"
    )
    # "walking close together" keeps its meaning: only a list's "together" says nothing
    assert everyday_wording("pedestrians walking close together") == "pedestrians walking close together"
    assert everyday_wording("the buses and all the box trucks together") == "the buses and box trucks"
    # a speed in miles or kilometres per hour is no chart's rate
    assert (
        everyday_wording("cars going over 15 kilometers per hour") == "cars going over 15 kilometers per hour"
    )


@pytest.mark.parametrize(
    ("headline", "calls"),
    [
        ("Box Truck Tops 7 Meters per Second", ["category='BOX_TRUCK'", "min_velocity=7"]),
        ("Bus Slams Brakes at Intersection", ["max_accel=-3"]),
        ("Van Sits Parked for Entire Drive", ["stationary(subject"]),
        ("Bus Cuts Across Another Vehicle's Path", ["reverse_relationship(being_crossed_by)"]),
        ("Truck Finds 2 Pedestrians Within 12 Meters Ahead", ["within_distance=12", "min_number=2"]),
    ],
)
def test_a_headline_is_read_in_full(headline: str, calls: list[str]) -> None:
    assert_program_has(headline, calls)


@pytest.mark.parametrize(
    ("definition", "calls"),
    [
        (
            "'Cone-Adjacent Truck' means any truck that is within four (4) metres of a construction cone.",
            ["category='TRUCK'", "distance_thresh=4"],
        ),
        (
            "'Fast Vehicle' means any motor vehicle travelling at a speed of not less than"
            " twelve (12) metres per second.",
            ["category='VEHICLE'", "min_velocity=12"],
        ),
    ],
)
def test_a_defined_term_is_read_as_what_it_means(definition: str, calls: list[str]) -> None:
    assert_program_has(definition, calls)


@pytest.mark.parametrize(
    ("caption", "calls"),
    [
        (
            "Fig. 3: Buses turning left at an intersection (highlighted in red).",
            ["category='BUS'", "direction='left'"],
        ),
        (
            "Figure 6: Trucks moving along the road (yellow boxes).",
            ["has_velocity(subject, log_dir, min_velocity=0.5)"],
        ),
        (
            "Fig. 9: Parked box trucks that remain in place for the whole recording, drawn as grey boxes.",
            ["stationary("],
        ),
        ("Fig. 11: Bollards on the road (examples).", ["category='BOLLARD'", "on_road("]),
        (
            "Fig. 14: Cyclists in a small group, each with at least two other bicycles within 3 m.",
            ["min_objects=2"],
        ),
        (
            "Fig. 15: Buses whose path is crossed by a pedestrian walking in front of them.",
            ["being_crossed_by("],
        ),
        # "stopped or parked": either state
        ("Fig. 16: Stopped or parked trucks.", ["stationary(subject, log_dir)", "max_velocity=0.5"]),
    ],
)
def test_a_figure_caption_is_read_without_its_marks(caption: str, calls: list[str]) -> None:
    assert_program_has(caption, calls)


def test_figure_marks_are_dropped_and_other_colours_kept() -> None:
    assert figure_marks("parked bicycles (green boxes)") == "parked bicycles"
    assert figure_marks("cars turning right (highlighted in orange).") == "cars turning right."
    assert figure_marks("a red car turning left") == "a red car turning left"
