"""A methods section's passive frame dropped around the scenario (mine/plan_methods.py)."""

from __future__ import annotations

import pytest
from plan_checks import assert_program_has

from scenariominer.mine.plan_methods import methods_wording
from scenariominer.mine.plan_reader import read_plan


@pytest.mark.parametrize(
    ("description", "calls"),
    [
        (
            "Segments were retained in which a pedestrian was observed within 5 m of the ego vehicle.",
            ["category='PEDESTRIAN'", "near_objects(subject, related_1, log_dir, distance_thresh=5)"],
        ),
        (
            "Only vehicles with a speed exceeding 10 m/s (approximately 36 km/h) were included.",
            ["has_velocity(subject, log_dir, min_velocity=10.0)"],
        ),
        (
            "We selected all buses that were stationary for the duration of the segment.",
            ["category='BUS'", "stationary(subject, log_dir)"],
        ),
        (
            "Scenarios involving a truck turning right at an intersection were selected.",
            ["category='TRUCK'", "direction='right'"],
        ),
        (
            "A vehicle was classified as tailgating if it followed the ego vehicle within 10 m.",
            ["following(subject, related_1, log_dir)", "distance_thresh=10"],
        ),
        (
            "The analysis was restricted to vehicles facing toward the ego vehicle.",
            ["facing_toward(subject, related_1, log_dir"],
        ),
        (
            "Pedestrians in the immediate vicinity of the instrumented vehicle were annotated for analysis.",
            ["category='PEDESTRIAN'", "category='EGO_VEHICLE'", "near_objects"],
        ),
        (
            "Cases were identified in which a bus decelerated (longitudinal acceleration below -2 m/s²)"
            " while a pedestrian was located behind it within 10 m.",
            ["max_accel=-2", "direction='backward', within_distance=10"],
        ),
        (
            "We retained all trucks for which no other vehicle was present behind within 25 m.",
            ["scenario_not(has_objects_in_relative_direction)", "direction='backward', within_distance=25"],
        ),
        (
            "Segments were retained in which a bus had at least two pedestrians ahead of it"
            " at a distance of no more than 12 m.",
            ["direction='forward', within_distance=12, min_number=2"],
        ),
        (
            "The dataset was filtered for vehicles whose speed exceeded 15 m/s.",
            ["min_velocity=15"],
        ),
    ],
)
def test_the_scenario_inside_a_methods_sentence_is_read_in_full(description: str, calls: list[str]) -> None:
    assert_program_has(description, calls)


def test_the_frame_is_dropped_before_and_after_the_scenario() -> None:
    assert methods_wording(
        "cases in which a truck was overtaken by the ego vehicle were retained for analysis."
    ) == ("a truck was overtaken by the ego vehicle")
    assert methods_wording("it was observed that pedestrians were walking near the ego vehicle") == (
        "pedestrians were walking near the ego vehicle"
    )


def test_a_sentence_that_drops_what_it_names_is_not_read_as_keeping_it() -> None:
    text = "vehicles that were not moving were discarded"
    assert methods_wording(text) == text
    assert read_plan("Trajectories of parked vehicles were excluded from the analysis.") is None


def test_text_without_the_frame_comes_back_unchanged() -> None:
    for text in (
        "pedestrians (about 5 m) near the ego vehicle",
        "vehicles turning left",
        "buses that were stopped",
    ):
        assert methods_wording(text) == text
