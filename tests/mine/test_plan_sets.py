"""A search written in set-builder notation (mine/plan_sets.py), read by the phrase rules.

The wordings are my own, written for plan-reader/51 before the fresh53-fresh56 passes were read;
each must build the program of its plain English.
"""

from __future__ import annotations

import pytest
from mining_scenes import rules_program

from scenariominer.mine.plan_sets import set_wording


@pytest.mark.parametrize(
    ("written", "plain"),
    [
        ("{a in Vehicles : v(a) > 10 m/s}", "vehicles moving faster than 10 m/s"),
        ("{(a, t) : a ∈ Pedestrians, d(a, ego) < 5 m}", "pedestrians within 5 m of the ego vehicle"),
        (
            "the set of all vehicles a such that a is on an intersection and a is turning left",
            "vehicles on an intersection and turning left",
        ),
        ("{a ∈ V | speed(a) = 0 ∧ on_road(a)}", "vehicles stopped on the road"),
        ("{a ∈ V : ∃ p ∈ P : d(a, p) < 5 m}", "vehicles with a pedestrian within 5 m"),
        ("{a ∈ Vehicles | ∃ p ∈ Pedestrians, dist(a, p) ≤ 5}", "vehicles with a pedestrian within 5 m"),
        (
            "{(a,t) : a ∈ V, turning(a, left), near_intersection(a)}",
            "vehicles turning left near an intersection",
        ),
        ("{a ∈ V : accel(a) < -3 m/s²}", "vehicles braking harder than 3 m/s^2"),
        ("{a ∈ buses : d(a, ego) < 20 m}", "buses within 20 m of the ego vehicle"),
    ],
)
def test_a_set_builds_the_program_of_its_plain_english(written: str, plain: str) -> None:
    assert rules_program(written) == rules_program(plain)


@pytest.mark.parametrize(
    "text",
    ["vehicles turning left", "pedestrians (in a group) near the ego", "cars with a speed over 5 m/s"],
)
def test_text_without_a_set_is_unchanged(text: str) -> None:
    assert set_wording(text) == text


def test_a_set_of_unknown_form_is_left_to_the_rest_of_the_reader() -> None:
    # no variable with a road-user set: nothing to name as the subject
    assert set_wording("{x : x > 3}") == "{x : x > 3}"


@pytest.mark.parametrize(
    ("written", "plain"),
    [
        # from the spent fresh54 run (plan-reader/52): a named set, a gloss after it, set differences
        # and unions, places, angles, counts
        (
            "Brake = {(c, t) : c ∈ REGULAR_VEHICLE, a_long(c, t) ≤ −1 m/s²}, passenger cars decelerating"
            " hard",
            "regular vehicles braking harder than 1 m/s^2",
        ),
        (
            "L = {(v, t) : v ∈ VEHICLE and v is in the middle of a lane change toward its right at t}",
            "vehicles changing lanes to the right",
        ),
        (
            "Oncoming = {(v, t) : v ∈ VEHICLE ∖ {ego}, angle(travel(v, t), travel(ego, t)) ≥ 135°}",
            "vehicles other than the ego vehicle travelling in the opposite direction to the ego vehicle",
        ),
        (
            "Perp = {(c, t) : c ∈ REGULAR_VEHICLE, 45° < angle(travel(c, t), travel(ego, t)) < 135°}",
            "regular vehicles moving perpendicular to the ego vehicle",
        ),
        (
            "Lot = {(v, t) : v ∈ VEHICLE, v ∈ DrivableArea(t) ∧ v ∉ Road(t)}",
            "vehicles in the drivable area and not on the road",
        ),
        (
            "Crowd = {(v, t) : v ∈ VEHICLE, |{p ∈ Pedestrians : d(v, p) ≤ 5 m}| ≥ 3}",
            "vehicles with at least 3 pedestrians within 5 m",
        ),
        (
            "Heavy = {(h, t) : h ∈ TRUCK ∪ BOX_TRUCK ∪ LARGE_VEHICLE, d(h, intersection) ≤ 5 m}",
            "trucks or box trucks or large vehicles within 5 m of an intersection",
        ),
        (
            "X = {(p, t) : p ∈ Pedestrians, ∃ v ∈ VEHICLE such that p crosses the half-midplane ahead of v at"
            " t}; the crossing pedestrians themselves",
            "pedestrians crossing in front of a vehicle",
        ),
        (
            "Xwalk = {(p, t) : p ∈ Pedestrians, box(p, t) ∩ crosswalk ≠ ∅ ∧ speed(p, t) ≥ 0.5 m/s}",
            "pedestrians on a crosswalk moving faster than 0.5 m/s",
        ),
        (
            "SameLane = {(v, t) : v ∈ VEHICLE ∖ {ego}, lane(v, t) belongs to the ego's lane at t}",
            "vehicles other than the ego vehicle in the same lane as the ego vehicle",
        ),
        (
            "Ahead = {(v, t) : v ∈ VEHICLE, v lies in front of the ego vehicle with box distance ≤ 20 m};"
            " return the vehicles, not the ego",
            "vehicles in front of the ego vehicle within 20 m",
        ),
    ],
)
def test_a_spent_run_set_builds_the_program_of_its_plain_english(written: str, plain: str) -> None:
    assert rules_program(written) == rules_program(plain)
