"""Spreadsheet formulas over a table of tracks in the words the phrase tables read (mine/plan_formula.py)."""

from __future__ import annotations

import pytest
from plan_checks import assert_program_has

from scenariominer.mine.plan_formula import spreadsheet_formula


@pytest.mark.parametrize(
    ("formula", "calls"),
    [
        (
            "=FILTER(Tracks, Tracks[category]='BUS', Tracks[turn]='left')",
            ["category='BUS'", "turning(subject, log_dir, direction='left')"],
        ),
        (
            "=COUNTIFS(category,'PEDESTRIAN',dist_to_ego_m,'<5')",
            ["category='PEDESTRIAN'", "category='EGO_VEHICLE'", "distance_thresh=5"],
        ),
        (
            "=FILTER(objects, AND(category='REGULAR_VEHICLE', speed_mps>10))",
            ["category='REGULAR_VEHICLE'", "has_velocity(subject, log_dir, min_velocity=10.0)"],
        ),
        (
            "=FILTER(data, (data[class]='TRUCK')*(data[is_parked]=TRUE))",
            ["category='TRUCK'", "stationary(subject, log_dir)"],
        ),
        (
            "=COUNTIFS(Objects[category],'VEHICLE',Objects[lane_change],'right')",
            ["changing_lanes(subject, log_dir, direction='right')"],
        ),
        (
            "=FILTER(tracks, tracks[category]='PEDESTRIAN', tracks[on_crosswalk]=TRUE)",
            ["at_pedestrian_crossing("],
        ),
        (
            "=FILTER(A2:K500, category='BOX_TRUCK', in_intersection=1)",
            ["category='BOX_TRUCK'", "on_intersection("],
        ),
        ("=COUNTIF(category, 'STROLLER')", ["category='STROLLER'"]),
        (
            "=FILTER(tracks, category='VEHICLE', NOT(is_stationary=TRUE))",
            ["scenario_not(stationary)(subject"],
        ),
        ("=FILTER(tracks, category='VEHICLE', accel_mps2<-2)", ["max_accel=-2"]),
        (
            "=ROWS(FILTER(tracks, category='EGO_VEHICLE', pedestrians_within_20m>=3))",
            ["category='PEDESTRIAN'", "distance_thresh=20, min_objects=3"],
        ),
        ("=FILTER(tracks, category='BUS', lane_type='BUS')", ["category='BUS'", "lane_type='BUS'"]),
        ("=COUNTIFS(type,'BICYCLE',speed_kmh,'>15')", ["category='BICYCLE'", "min_velocity=4.17"]),
        ("=QUERY(Tracks, 'select * where category = \"BUS\" and speed > 10')", ["min_velocity=10.0"]),
        # a column of flags on its own, a position relative to the ego vehicle with a distance
        (
            '=FILTER(tracks, tracks[object_type]="PEDESTRIAN", tracks[on_crosswalk])',
            ["at_pedestrian_crossing("],
        ),
        (
            '=FILTER(tracks, category="VEHICLE", distance_to_ego<20, relative_position="ahead")',
            ["direction='forward', within_distance=20"],
        ),
        ('=FILTER(tracks, category="VEHICLE", position_rel_ego="left")', ["direction='left'"]),
        # a category group, a count of other rows, a lead vehicle's kind, the side of the road
        ("=FILTER(t, t[category_group]='VULNERABLE_ROAD_USER', t[speed_mps]>=2)", ["'VULNERABLE_ROAD_USER'"]),
        (
            "=FILTER(t, t[category_group]='VEHICLE',"
            " COUNTIFS(t[category], 'PEDESTRIAN', t[position], 'ahead', t[gap_m], '<=15')>=1)",
            ["has_objects_in_relative_direction(", "direction='forward', within_distance=15"],
        ),
        (
            "=FILTER(t, t[category]='EGO_VEHICLE',"
            " COUNTIFS(t[category], 'PEDESTRIAN', t[dist_to_ego_m], '<=15')>=3)",
            ["near_objects(subject, related_1, log_dir, distance_thresh=15, min_objects=3)"],
        ),
        (
            "=FILTER(t, t[category_group]='VEHICLE', t[lead_vehicle_category]='BUS')",
            ["following(subject, related_1"],
        ),
        ("=FILTER(t, t[category]='BUS', t[road_side_vs_ego]='opposite')", ["side='opposite'"]),
        ("=FILTER(t, t[category]='CAR', ABS(t[lat_accel_mps2])>=2)", ["has_lateral_acceleration(subject"]),
        ("=FILTER(t, t[category]='CAR', t[long_accel_mps2]<=-1)", ["max_accel=-1"]),
        ("=FILTER(t, t[category]='PEDESTRIAN', t[dist_to_crosswalk_m]=0)", ["within_distance=0"]),
        (
            "=FILTER(t, t[category]='PEDESTRIAN', t[on_road]=TRUE, NOT(t[dist_to_crosswalk_m]<=1))",
            ["scenario_not(at_pedestrian_crossing)(subject, log_dir, within_distance=1)"],
        ),
        ("=FILTER(t, t[category]='CAR', t[same_lane_as_ego]=TRUE)", ["in_same_lane(subject, related_1"]),
        ("=FILTER(t, t[category]='CAR', t[travel_dir_vs_ego]='opposite')", ["direction='opposite'"]),
    ],
)
def test_a_formula_is_read_in_full(formula: str, calls: list[str]) -> None:
    assert_program_has(formula, calls)


def test_a_formula_is_put_in_words_about_one_road_user() -> None:
    assert (
        spreadsheet_formula("=FILTER(Tracks, Tracks[category]='BUS', Tracks[turn]='left')")
        == "bus turning left"
    )
    assert spreadsheet_formula("=COUNTIFS(category,'PEDESTRIAN',dist_to_ego_m,'<5')") == (
        "pedestrian within 5 m of the ego vehicle"
    )
    # a criterion's comparison sits inside its text; "<>" negates a flag
    assert spreadsheet_formula("=COUNTIFS(category,'CAR',is_parked,'<>TRUE')") == "car not parked"
    # a flag that another test narrows is said once
    assert (
        spreadsheet_formula('=COUNTIFS(category,"BUS",is_turning,TRUE,turn_direction,"left")')
        == "bus turning left"
    )


@pytest.mark.parametrize(
    "formula",
    [
        "=FILTER(data, OR(category='BUS', category='TRUCK'))",  # alternatives
        "=FILTER(data, (category='BUS')+(category='TRUCK'))",  # alternatives as a sum
        "=FILTER(A2:K99, C2:C99='BUS')",  # cell ranges, no column names
        "=FILTER(data, category='BUS', dist_to_ego_m=7)",  # a distance equal to a number
        "=SUMPRODUCT(speed, weight)",  # a function this reading does not know
    ],
)
def test_a_formula_this_reading_does_not_know_comes_back_unchanged(formula: str) -> None:
    assert spreadsheet_formula(formula) == formula


def test_text_that_is_no_formula_comes_back_unchanged() -> None:
    for text in ("buses turning left", "= buses turning left", "speed > 10"):
        assert spreadsheet_formula(text) == text
