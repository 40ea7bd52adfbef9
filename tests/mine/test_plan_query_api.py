"""GraphQL queries and MongoDB filters in the words the phrase tables read (mine/plan_query_api.py)."""

from __future__ import annotations

import pytest
from plan_checks import assert_program_has

from scenariominer.mine.plan_query_api import query_api_request


@pytest.mark.parametrize(
    ("query", "calls"),
    [
        ("{ objects(category: BUS, turning: LEFT) { trackId } }", ["category='BUS'", "direction='left'"]),
        ("{ objects(categoryGroup: VEHICLE, speed: {minMps: 8, maxMps: 12}) { trackId } }",
         ["min_velocity=8", "max_velocity=12"]),
        ("{ objects(category: TRUCK, near: {category: PEDESTRIAN, withinMeters: 6, minCount: 2}) { id } }",
         ["distance_thresh=6", "min_objects=2"]),
        ("{ objectsInDirection(of: EGO_VEHICLE, direction: RIGHT, category: BICYCLE, withinMeters: 9) {id} }",
         ["direction='right'", "within_distance=9"]),
        ("db.tracks.find({category: 'BOX_TRUCK', 'map.on_road': false})", ["scenario_not(on_road)"]),
        ("db.tracks.find({category_group: 'VEHICLE', 'motion.long_accel_mps2': {$lte: -2.5}})",
         ["max_accel=-2.5"]),
        ("db.tracks.find({category: 'BUS', nearby: {$elemMatch:"
         " {category: 'PEDESTRIAN', distance_m: {$lt: 7}}}})",
         ["near_objects(subject, related_1, log_dir, distance_thresh=7)"]),
        ("db.tracks.find({$and: [{category: 'REGULAR_VEHICLE'}, {'map.on_intersection': true},"
         " {'motion.turn': {$exists: false}}]})", ["on_intersection(", "scenario_not(turning)"]),
        ("db.tracks.find({category: 'EGO_VEHICLE', 'nearby.pedestrian.count_within_12m': {$gte: 4}})",
         ["distance_thresh=12", "min_objects=4"]),
    ],
)  # fmt: skip
def test_a_query_is_read_as_the_road_users_it_asks_for(query: str, calls: list[str]) -> None:
    assert_program_has(query, calls)


def test_each_field_is_worded() -> None:
    assert query_api_request("{ objects(categoryGroup: VEHICLE, laneChange: LEFT) { trackId } }") == (
        "vehicle and changing lanes to the left."
    )
    assert query_api_request(
        "db.tracks.find({category: 'PEDESTRIAN', 'map.pedestrian_crossing.distance_m': {$lte: 0}})"
    ) == ("pedestrian and within 0 m of a crosswalk.")


@pytest.mark.parametrize(
    "text",
    [
        "buses turning left",
        "{ objects(category: BUS, wibble: {foo: [1, 2]}) { trackId } }",  # a field this reading does not know
        "db.tracks.find({category: 'BUS'",  # does not parse
        '{"category": "BUS"}',  # plain JSON: another reader's
    ],
)
def test_text_this_reading_does_not_know_comes_back_unchanged(text: str) -> None:
    assert query_api_request(text) == text
