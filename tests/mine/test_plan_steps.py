"""Step-by-step procedures in the one phrase the phrase tables read (mine/plan_steps.py)."""

from __future__ import annotations

import pytest
from plan_checks import assert_program_has

from scenariominer.mine.plan_steps import procedure_wording


@pytest.mark.parametrize(
    ("procedure", "calls"),
    [
        (
            "1. Take all trucks. 2. Keep only the ones turning right. 3. Done.",
            ["category='TRUCK'", "'right'"],
        ),
        (
            "Step 1: take all dogs. Step 2: throw out the ones inside the drivable area. Step 3: finish.",
            ["category='DOG'", "scenario_not(in_drivable_area)"],
        ),
        (
            "1) Take all strollers. 2) Take all vehicles."
            " 3) Keep the strollers with a vehicle within 4 m of them.",
            ["category='STROLLER'", "near_objects(subject, related_1, log_dir, distance_thresh=4)"],
        ),
        (
            "1. Take all buses. 2. Take all box trucks. 3. Merge the two groups into one set. "
            "4. Keep the moments they move at 6 m/s or more. 5. Done.",
            ["category='BUS'", "category='BOX_TRUCK'", "min_velocity=6"],
        ),
        (
            "1. Take all vehicles. 2. Drop the ego vehicle from them. "
            "3. Keep the remaining vehicles on an intersection. 4. Done.",
            ["is_category", "on_intersection("],
        ),
        (
            "Step 1: get the ego vehicle. Step 2: keep the timestamps where it speeds up at 2 m/s² or more.",
            ["category='EGO_VEHICLE'", "accelerating(subject, log_dir, min_accel=2"],
        ),
    ],
)
def test_a_procedure_is_read_in_full(procedure: str, calls: list[str]) -> None:
    assert_program_has(procedure, calls)


def test_a_procedure_is_put_in_one_phrase() -> None:
    assert procedure_wording("1. Take all pedestrians. 2. Throw out the ones on the road. 3. Done.") == (
        "pedestrians not on the road"
    )
    # a set taken only to name another's condition is not the one found
    assert procedure_wording(
        "1. Take all bollards. 2. Take all vehicles and keep the moving ones. "
        "3. Keep the bollards within 3 m of a moving vehicle. 4. Output the bollards."
    ) == ("bollards within 3 m of a moving vehicle")
    # a drop of sets with a road user: with none of them
    assert procedure_wording("1. Take all vans. 2. Drop those with any car ahead of them. 3. Done.") == (
        "vans with no car ahead"
    )


@pytest.mark.parametrize(
    "text",
    [
        "buses turning left",
        "1. Take all buses.",  # one step
        "2. Keep the buses. 3. Done.",  # not from the first step
        "1. Take all buses. 2. Paint them blue.",  # a step this reading does not follow
    ],
)
def test_text_that_is_no_procedure_comes_back_unchanged(text: str) -> None:
    assert procedure_wording(text) == text
