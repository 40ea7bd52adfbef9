"""Graph pattern queries (Cypher-like) put in the words the phrase tables read (mine/plan_graph.py)."""

from __future__ import annotations

import pytest
from plan_checks import assert_program_has

from scenariominer.mine.plan_graph import graph_pattern


@pytest.mark.parametrize(
    ("query", "calls"),
    [
        (
            "MATCH (p:Pedestrian)-[:NEAR {max_m: 5}]->(e:Ego) RETURN p",
            ["category='PEDESTRIAN'", "near_objects(subject, related_1, log_dir, distance_thresh=5)"],
        ),
        (
            "MATCH (t:Truck)<-[:FOLLOWS]-(e:Ego) RETURN t",
            ["category='TRUCK'", "reverse_relationship(following)(related_1, subject, log_dir)"],
        ),
        (
            "MATCH (e:EgoVehicle)-[:OVERTAKES]->(t:Truck) RETURN t",
            ["category='TRUCK'", "being_crossed_by"],
        ),
        (
            "MATCH (v:Vehicle) WHERE NOT (v)-[:ON]->(:DrivableArea) RETURN v",
            ["scenario_not(in_drivable_area)(subject, log_dir)"],
        ),
        (
            "MATCH (v:Vehicle)-[:IN]->(l:Lane)<-[:IN]-(e:Ego) RETURN v",
            ["in_same_lane(subject, related_1, log_dir)"],
        ),
        (
            "MATCH (v:Vehicle)-[r:NEAR]->(p:Pedestrian) WHERE r.distance < 5 RETURN v",
            ["category='PEDESTRIAN'", "near_objects(subject, related_1, log_dir, distance_thresh=5)"],
        ),
        (
            "MATCH (b:BoxTruck)-[:NEAR]->(v:Vehicle {parked: true}) RETURN b",
            ["category='BOX_TRUCK'", "related_1 = stationary(related_1, log_dir)"],
        ),
        (
            "MATCH (v:RegularVehicle) WHERE v.speed_kmh > 50 AND v.turning = 'left' RETURN v",
            ["min_velocity=13.89", "turning(step_1, log_dir, direction='left')"],
        ),
        (
            "match (v:vehicle) where v.acceleration < -3 return v",
            ["accelerating(subject, log_dir, min_accel=-inf, max_accel=-3"],
        ),
        (
            "MATCH (v:Vehicle) WHERE NOT v.is_stationary AND (v)-[:IN]->(:Intersection) RETURN DISTINCT v;",
            ["scenario_not(stationary)", "on_intersection"],
        ),
        ("MATCH (p:Pedestrian)-[:CROSSING_IN_FRONT_OF]->(e:Ego) RETURN p.track_id", ["being_crossed_by"]),
        ("MATCH (d:Dog) RETURN d", ["category='DOG'"]),
        # a relationship's direction, a relative direction, an inverse with the other road user named
        (
            "MATCH (t:Truck)-[:TURNS {dir: 'left'}]->(:Junction) RETURN t",
            ["category='TRUCK'", "turning(", "direction='left'", "on_intersection("],
        ),
        (
            "MATCH (b:Bus)-[:MOVES {relative_direction: 'opposite'}]->(e:Ego) RETURN b",
            ["heading_in_relative_direction_to(", "direction='opposite'"],
        ),
        (
            "MATCH (p:Pedestrian)-[:CROSSES_IN_FRONT_OF]->(t:Truck) RETURN t",
            ["category='TRUCK'", "being_crossed_by("],
        ),
        # "HAS_AHEAD": the other road user ahead of the returned one; a count with WITH
        (
            "MATCH (t:Truck) WHERE NOT (t)-[:HAS_AHEAD {max_m: 25}]->(:Vehicle) RETURN t",
            ["scenario_not(has_objects_in_relative_direction)", "direction='forward', within_distance=25"],
        ),
        (
            "MATCH (b:Bus)-[:CLOSE_TO {within_m: 15}]->(p:Pedestrian)"
            " WITH b, count(p) AS k WHERE k > 2 RETURN b",
            ["near_objects(subject, related_1, log_dir, distance_thresh=15, min_objects=3)"],
        ),
    ],
)
def test_a_pattern_query_is_read_in_full(query: str, calls: list[str]) -> None:
    assert_program_has(query, calls)


def test_a_pattern_is_put_in_words_about_the_returned_node() -> None:
    assert graph_pattern("MATCH (v:Vehicle)-[:BEHIND {max_distance: 15}]->(e:Ego) RETURN v") == (
        "vehicle behind the ego vehicle within 15 m"
    )
    # the same relationship, the other node returned: its inverse, in the returned node's own frame
    assert (
        graph_pattern("MATCH (v:Vehicle)-[:BEHIND]->(e:Ego) RETURN e")
        == "the ego vehicle with a vehicle behind it"
    )
    assert graph_pattern("MATCH (p:Pedestrian), (e:Ego) WHERE (p)-[:NEAR {distance_m: 10}]-(e) RETURN p") == (
        "pedestrian within 10 m of the ego vehicle"
    )


@pytest.mark.parametrize(
    "query",
    [
        # alternatives
        "MATCH (v:Vehicle) WHERE v.speed > 10 OR v.turning = 'left' RETURN v",
        # a test on a road user other than the returned one (beyond a one-word state)
        "MATCH (v:Vehicle)-[:NEAR]->(p:Pedestrian) WHERE p.speed > 2 RETURN v",
        # a label that names no road user
        "MATCH (v:Vehicle)-[:CHANGES_LANE_TO]->(:Left) RETURN v",
        # a property this reading does not know
        "MATCH (v:Vehicle) WHERE v.heading_change > 30 RETURN v",
        # a relationship between two nodes that are not returned
        "MATCH (v:Vehicle), (p:Pedestrian)-[:ON]->(c:Crosswalk) WHERE (v)-[:NEAR]->(p) RETURN v",
        # an angle is no distance
        "MATCH (e:Ego)-[:FACES {max_angle_deg: 15}]->(p:Pedestrian) RETURN e",
        # the returned node as the target of a relationship without a known inverse
        "MATCH (v:Vehicle)-[:YIELDS_TO]->(p:Pedestrian) RETURN p",
    ],
)
def test_a_query_this_reading_does_not_know_comes_back_unchanged(query: str) -> None:
    assert graph_pattern(query) == query


def test_text_that_is_no_pattern_query_comes_back_unchanged() -> None:
    for text in (
        "match the cars turning left",
        "vehicles (parked) near the ego vehicle",
        "MATCH cars RETURN them",
    ):
        assert graph_pattern(text) == text
