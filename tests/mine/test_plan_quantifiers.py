"""Sets stated with quantifiers in the words the phrase tables read (mine/plan_quantifiers.py)."""

from __future__ import annotations

import pytest
from plan_checks import assert_program_has

from scenariominer.mine.plan_quantifiers import quantified_set


@pytest.mark.parametrize(
    ("formula", "calls"),
    [
        ("S = {x ∈ Obj | cat(x) = BOX_TRUCK}", ["category='BOX_TRUCK'"]),
        (
            "{v ∈ Vehicles | ∃p ∈ Pedestrians: ahead(p, v) ∧ dist(p, v) ≤ 12 m}",
            ["has_objects_in_relative_direction(", "direction='forward', within_distance=12"],
        ),
        ("{p ∈ Pedestrians | ∃b ∈ Buses: dist(p, b) ≤ 10 m}", ["near_objects(subject, related_1", "=10"]),
        ("{v ∈ Vehicles | v ≠ ego ∧ sameLane(v, ego)}", ["in_same_lane(subject, related_1"]),
        ("{v ∈ Trucks | pos(v) ∉ DrivableArea}", ["scenario_not(in_drivable_area)"]),
        ("{ego | a_long(ego) ≥ 1 m/s²}", ["category='EGO_VEHICLE'", "min_accel=1"]),
        ("{b ∈ Buses | speed(b) ≥ 0.5 m/s ∧ onIntersection(b)}", ["min_velocity=0.5", "on_intersection("]),
        ("{v ∈ Vehicles | ∃p ∈ Pedestrians: crossesInFront(p, v)}", ["being_crossed_by(subject, related_1"]),
    ],
)
def test_a_quantified_set_is_read_in_full(formula: str, calls: list[str]) -> None:
    assert_program_has(formula, calls)


@pytest.mark.parametrize(
    "formula",
    [
        "{v ∈ Vehicles | ∠(dir(v), dir(ego)) ≥ 135°}",  # an angle
        "{c ∈ Cones ∪ Bollards | onRoad(c)}",  # a union of kinds
        "{v ∈ Vehicles | ¬∃u ∈ Vehicles: ahead(u, v)}",  # a negated quantifier
        "buses turning left",
    ],
)
def test_a_set_this_reading_does_not_know_comes_back_unchanged(formula: str) -> None:
    assert quantified_set(formula) == formula
