"""Logic-programming rules (Prolog, Datalog) in the words the phrase tables read (mine/plan_logic.py)."""

from __future__ import annotations

import pytest
from plan_checks import assert_program_has

from scenariominer.mine.plan_logic import logic_rule


@pytest.mark.parametrize(
    ("rule", "calls"),
    [
        (
            "find(X) :- bus(X), turning(X, left).",
            ["category='BUS'", "turning(subject, log_dir, direction='left')"],
        ),
        (
            "match(X, T) :- pedestrian(X), near(X, E, T), ego(E).",
            ["category='PEDESTRIAN'", "category='EGO_VEHICLE'", "near_objects(subject, related_1"],
        ),
        ("q(V) :- vehicle(V), speed(V, S), S > 10.", ["has_velocity(subject, log_dir, min_velocity=10.0)"]),
        ("q(V) :- vehicle(V), speed(V, S), 10 < S.", ["has_velocity(subject, log_dir, min_velocity=10.0)"]),
        (
            "find(P) :- pedestrian(P), crossing_in_front_of(P, V), vehicle(V).",
            ["reverse_relationship(being_crossed_by)(related_1, subject, log_dir, direction='forward')"],
        ),
        ("find(X) :- truck(X), \\+ stationary(X).", ["category='TRUCK'", "scenario_not(stationary)(subject"]),
        ("find(X) :- vehicle(X), follows(X, Y), bus(Y).", ["following(subject, related_1, log_dir)"]),
        (
            "find(X) :- category(X, box_truck), in_intersection(X).",
            ["category='BOX_TRUCK'", "on_intersection("],
        ),
        (
            "ans(X) :- ego(X), distance(X, P, D), pedestrian(P), D < 5.",
            ["category='PEDESTRIAN'", "near_objects(subject, related_1, log_dir, distance_thresh=5)"],
        ),
        (
            "find(X) :- vehicle(X), changing_lanes(X, right).",
            ["changing_lanes(subject, log_dir, direction='right')"],
        ),
        (
            "find(X) :- regular_vehicle(X), accel(X, A), A =< -3.",
            ["accelerating(subject, log_dir, min_accel=-inf, max_accel=-3"],
        ),
        (
            "find(X) :- vehicle(X), not near(X, Y), pedestrian(Y).",
            ["scenario_not(near_objects)(subject, related_1, log_dir"],
        ),
        (
            "find(X) :- vehicle(X), ahead_of(X, ego).",
            ["get_objects_in_relative_direction(related_1, subject"],
        ),
        ("hit(X) :- type(X, 'BUS'), parked(X).", ["category='BUS'", "stationary(subject, log_dir)"]),
        ("?- school_bus(X), moving(X).", ["category='SCHOOL_BUS'"]),
        # a negated kind, a distance to a place, an anonymous variable, a test of its speed
        (
            "find(X) :- vehicle(X), \\+ bus(X), lane_type_at(X, bus).",
            ["category='VEHICLE'", "is_category", "lane_type='BUS'"],
        ),
        (
            "find(X) :- truck(X), distance_to_intersection(X, D), D =< 10.",
            ["near_intersection(", "threshold=10"],
        ),
        ("find(X) :- vehicle(X), changes_lane(X, _Dir).", ["changing_lanes(subject, log_dir)"]),
        ("match(X, T) :- vehicle(X), speed(X, T, S), S >= 15.", ["min_velocity=15"]),
        ("m(X, T) :- vehicle(X), longitudinal_accel(X, T, A), A =< -2.", ["max_accel=-2"]),
        (
            "find(V) :- vehicle(V), pedestrian(P), in_front_of(P, V), distance(V, P, D), D < 15.",
            ["has_objects_in_relative_direction(", "direction='forward', within_distance=15"],
        ),
        (
            "find(E) :- ego(E), count(P, (pedestrian(P), near(E, P, 20)), N), N >= 3.",
            ["near_objects(subject, related_1, log_dir, distance_thresh=20, min_objects=3)"],
        ),
        # a kind and an action as constants, a distance variable, a relation's other name
        ("scenario(X) :- object(X, bus), action(X, turn_left).", ["category='BUS'", "direction='left'"]),
        ("find(X) :- truck(X), turns(X, right).", ["turning(subject, log_dir, direction='right')"]),
        ("find(X) :- vehicle(X), near(X, Y, D), pedestrian(Y), D < 5.", ["distance_thresh=5"]),
        ("find(X) :- vehicle(X), within_distance(X, Y, 10), bicycle(Y).", ["distance_thresh=10"]),
        ("find(X) :- car(X), in_same_lane(X, ego).", ["in_same_lane(subject, related_1, log_dir)"]),
        ("find(X) :- vehicle(X), in_lane(X, bus_lane).", ["lane_type='BUS'"]),
        (
            "find(E) :- ego(E), aggregate_all(count, (pedestrian(P), near(E, P)), N), N > 1.",
            ["min_objects=2"],
        ),
    ],
)
def test_a_rule_is_read_in_full(rule: str, calls: list[str]) -> None:
    assert_program_has(rule, calls)


def test_a_rule_is_put_in_words_about_the_road_user_in_its_head() -> None:
    assert logic_rule("find(X) :- bus(X), turning(X, left).") == "bus turning left"
    # the head's variable is the one found, whichever goal names it first
    assert logic_rule("find(Y) :- follows(X, Y), bus(Y), truck(X).") == "bus being followed by a truck"
    # a time variable beside the road user is not a road user
    assert (
        logic_rule("m(X, T) :- timestamp(T), pedestrian(X), on_crosswalk(X, T).")
        == "pedestrian on a crosswalk"
    )
    # but a truck named T is one
    assert logic_rule("f(T) :- truck(T), parked(T).") == "truck parked"


@pytest.mark.parametrize(
    "rule",
    [
        "find(X) :- bus(X) ; truck(X).",  # alternatives
        "find(X) :- bus(X), frobnicated(X, Y, Z, W).",  # a goal of four arguments
        "find(X) :- bus(X), speed(X, S), S > D.",  # a value compared with a variable
        "find(X) :- bus(X), \\+ (truck(X), parked(X)).",  # a negated conjunction
        "find(X) :- bus(X), speed(Y, S), S > 3, car(Y).",  # a test of another road user
    ],
)
def test_a_rule_this_reading_does_not_know_comes_back_unchanged(rule: str) -> None:
    assert logic_rule(rule) == rule


def test_text_that_is_no_rule_comes_back_unchanged() -> None:
    for text in ("buses turning left", "find buses: turning left", "f(x) = 3"):
        assert logic_rule(text) == text
