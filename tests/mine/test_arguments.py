"""The signature-aware argument check names the argument at fault before anything runs."""

from __future__ import annotations

import pytest

from scenariominer.mine.sandbox import ErrorKind, check_program

VEHICLES = (
    "v = get_objects_of_category(log_dir, 'VEHICLE')\np = get_objects_of_category(log_dir, 'PEDESTRIAN')\n"
)


@pytest.mark.parametrize(
    ("line", "expected"),
    [
        (
            "x = in_same_lane(v, log_dir)",
            "argument 2 (related_candidates) of in_same_lane must be an object set",
        ),
        ("x = in_same_lane(v, related_candidates=p)", "in_same_lane needs log_dir"),
        (
            "x = in_same_lane(v, log_dir, log_dir)",
            "argument 2 (related_candidates) of in_same_lane must be an object set",
        ),
        ("x = turning(log_dir)", "argument 1 (track_candidates) of turning must be an object set"),
        ("x = has_velocity(v, v)", "argument 2 (log_dir) of has_velocity must be log_dir (the log"),
        (
            "x = has_velocity(v, log_dir, min_velocity='fast')",
            "'min_velocity' of has_velocity must be a number",
        ),
        ("x = has_velocity(v, log_dir, speed=3)", "has_velocity has no argument named 'speed'"),
        (
            "x = has_objects_in_relative_direction(v, p, log_dir, direction='diagonal')",
            "direction of has_objects_in_relative_direction must be one of 'left', 'right'",
        ),
        ("x = has_velocity(v, log_dir, 1, 2, 3, 4, 5)", "has_velocity takes at most"),
        ("x = scenario_not(in_same_lane)(v, p)", "in_same_lane needs log_dir"),
        (
            "x = has_velocity(v, log_dir=log_dir, track_candidates=v)",
            "'track_candidates' of has_velocity is given twice",
        ),
    ],
)
def test_a_wrong_call_names_its_argument(line: str, expected: str) -> None:
    error = check_program(VEHICLES + line + "\noutput_scenario(x, description, log_dir)")
    assert error is not None and error.kind is ErrorKind.FORBIDDEN
    assert expected in error.message and error.line == 3


@pytest.mark.parametrize(
    "line",
    [
        "x = in_same_lane(v, p, log_dir)",
        "x = has_objects_in_relative_direction(v, p, log_dir, direction='ahead', within_distance=20)",
        "side = 'left'\nx = has_objects_in_relative_direction(v, p, log_dir, direction=side)",
        "x = heading_in_relative_direction_to(v, p, log_dir, direction='opposite')",
        "x = scenario_not(has_velocity)(v, log_dir, min_velocity=1)",
        "x = has_velocity(v, log_dir, min_velocity=inf)",
    ],
)
def test_well_formed_calls_pass(line: str) -> None:
    assert check_program(VEHICLES + line + "\noutput_scenario(x, description, log_dir)") is None
