"""Filter expressions (mine/plan_filters.py) and other wordings met before a hold-out, read by the rules.

Written in session 22: first from wordings of my own, before the fresh41-fresh44 runs were scored
(those were scored with the code of the commit before these rules), then from the spent fresh44
run (a data scientist's filters, 0.357 clean): a filter's syntax must build the program of its
plain English, and text without filter syntax must come through unchanged.
"""

from __future__ import annotations

import pytest
from mining_scenes import rules_program, rules_referred, street_scene

from scenariominer.mine.plan_filters import filter_wording

SCENE = street_scene()


@pytest.mark.parametrize(
    ("written", "plain"),
    [
        ("speed_mps > 10 AND category == REGULAR_VEHICLE", "regular vehicles faster than 10 m/s"),
        ("category IN (BUS, BOX_TRUCK) AND on_intersection", "buses or box trucks on an intersection"),
        (
            "SELECT * FROM tracks WHERE class = 'PEDESTRIAN' AND dist_to_ego < 15 m",
            "pedestrians within 15 m of the ego vehicle",
        ),
        ("category == VEHICLE && is_parked == false", "vehicles that are not parked"),
        (
            "cat=PEDESTRIAN, v > 1.5 m/s, !in_drivable_area",
            "pedestrians faster than 1.5 m/s outside the drivable area",
        ),
        ("where speed < 2 and class = bus", "buses slower than 2 m/s"),
        ("filter: category == VEHICLE && lane_change_left", "vehicles changing lanes to the left"),
        ("distance to ego >= 30 && type == REGULAR_VEHICLE", "cars not within 30 m of the ego vehicle"),
    ],
)
def test_a_filter_builds_the_program_of_its_plain_english(written: str, plain: str) -> None:
    assert rules_program(written) == rules_program(plain)


@pytest.mark.parametrize(
    "text",
    [
        "where are vehicles parked on the road lanes",
        "vehicles stopped at a crosswalk while a pedestrian is crossing",
        "the ego vehicle turning left, with a bus behind it",
    ],
)
def test_text_without_filter_syntax_is_unchanged(text: str) -> None:
    assert filter_wording(text) == text


@pytest.mark.parametrize(
    ("written", "plain"),
    [
        # annotators' instructions: the verb asks for the result
        (
            "Tag every pedestrian who crosses in front of the ego vehicle",
            "pedestrians crossing in front of the ego vehicle",
        ),
        ("Annotate each frame in which a truck is turning left", "trucks turning left"),
        ("Label all parked cars within 10 m of the ego", "parked cars within 10 m of the ego vehicle"),
        # a news story's names for the ego vehicle and for people on foot
        ("a jogger crossing in front of the robotaxi", "a pedestrian crossing in front of the ego vehicle"),
        ("the driverless car turning left", "the ego vehicle turning left"),
        # bounds in words
        ("vehicles moving at most 2 m/s", "vehicles slower than 2 m/s"),
        ("vehicles at least 20 m away from the ego vehicle", "vehicles not within 20 m of the ego vehicle"),
        ("vehicles with acceleration less than -3 m/s^2", "vehicles braking harder than 3 m/s^2"),
        # another road user's own condition in a bare "with" clause stays its own
        (
            "the ego vehicle turning left with oncoming vehicles",
            "the ego vehicle turning left with oncoming vehicles nearby",
        ),
        ("vehicles with a parked car", "vehicles with a parked car nearby"),
        # an annotator's exclusions
        (
            "Tag moving vehicles on the intersection; do not tag parked ones",
            "moving vehicles on the intersection that are not parked",
        ),
        (
            "Tag pedestrians on the crosswalk, excluding those standing still",
            "pedestrians on the crosswalk that are not stationary",
        ),
        (
            "Label vehicles turning left (exclude the ego vehicle)",
            "vehicles turning left other than the ego vehicle",
        ),
        ("Mark cars but skip the parked ones", "cars that are not parked"),
        ("Tag buses only while they are stopped", "buses that are stopped"),
        # a scenario catalogue's titles
        (
            "Cut-in from the left",
            "vehicles changing lanes to the right and cutting in ahead of the ego vehicle",
        ),
        (
            "Truck cut-in from right lane",
            "trucks changing lanes to the left and cutting in ahead of the ego vehicle",
        ),
        ("Vehicle cut-in", "vehicles cutting in ahead of the ego vehicle"),
        ("Lead vehicle braking", "vehicles braking while being followed by the ego vehicle"),
    ],
)
def test_wordings_met_before_the_hold_out(written: str, plain: str) -> None:
    assert rules_program(written) == rules_program(plain)


def test_a_modified_road_user_after_with_is_conditioned_itself_not_the_subject() -> None:
    program = rules_program("vehicles with a parked car")
    assert "stationary(related_1" in program
    assert "stationary(subject" not in program


def test_a_filter_finds_what_its_plain_english_finds() -> None:
    assert rules_referred(SCENE, "category == PEDESTRIAN AND dist_to_ego < 20 m") == rules_referred(
        SCENE, "pedestrians within 20 m of the ego vehicle"
    )
    assert rules_referred(SCENE, "category == PEDESTRIAN AND dist_to_ego < 20 m")


def test_a_lead_vehicle_related_to_the_ego_in_words_is_read_as_written() -> None:
    assert rules_program("lead vehicle in the ego's lane less than 20 m ahead") == rules_program(
        "vehicle in the same lane as the ego vehicle within 20 m ahead"
    )


@pytest.mark.parametrize(
    ("written", "plain"),
    [
        ("vehicles WHERE speed > 15 m/s", "vehicles faster than 15 m/s"),
        (
            "category=REGULAR_VEHICLE AND accel_long <= -2 m/s^2 (hard braking)",
            "cars braking harder than 2 m/s^2",
        ),
        ("BUS with accel_long >= 1 m/s^2", "buses accelerating more than 1 m/s^2"),
        ("ego WHERE turn_dir == 'left'", "the ego vehicle turning left"),
        ("REGULAR_VEHICLE where lane_change = right", "cars changing lanes to the right"),
        ("bus | on_intersection == True", "buses on an intersection"),
        ("vehicle WHERE following(lead = ego)", "vehicles following the ego vehicle"),
        ("ego WHERE count(peds within 15 m) >= 3", "the ego vehicle with at least 3 pedestrians within 15 m"),
        (
            "ped WHERE n_other_peds(dist <= 2 m) >= 2  -- walking in a group",
            "pedestrians with at least 2 other pedestrians within 2 m",
        ),
        (
            "vehicles WHERE travel_dir relative_to(ego) == opposite  /* oncoming traffic */",
            "vehicles travelling in the opposite direction to the ego vehicle",
        ),
        (
            "vehicles WHERE dir_rel(ego) == perpendicular AND on_intersection",
            "vehicles travelling perpendicular to the ego vehicle on an intersection",
        ),
        ("peds WHERE facing(ego), angle <= 30 deg", "pedestrians facing the ego vehicle within 30 degrees"),
        ("vehicle WHERE crossed_by(pedestrian, side=front)", "vehicles being crossed by a pedestrian"),
        (
            "vehicles: parked for whole log AND NOT on_road (e.g. lots/driveways)",
            "vehicles parked and not on road",
        ),
        (
            "vehicles WHERE 5 m/s <= speed <= 10 m/s AND dist_to_intersection <= 10 m",
            "vehicles moving between 5 and 10 m/s within 10 m of an intersection",
        ),
        (
            "(TRUCK OR BOX_TRUCK) WHERE same_lane_as(ego)",
            "trucks or box trucks in the same lane as the ego vehicle",
        ),
        ("vehicles WHERE lane_type == 'BUS'", "vehicles in a bus lane"),
        (
            "vehicles WHERE lat_accel >= 2 m/s^2 OR lat_accel <= -2 m/s^2",
            "vehicles with a lateral acceleration of more than 2 m/s^2 in either direction",
        ),
        (
            "vehicles located LEFT of ego, box_dist <= 5 m",
            "vehicles to the left of the ego vehicle within 5 m",
        ),
        (
            "vehicles WHERE another vehicle BEHIND within 10 m AND lateral <= 1 m (tailgated)",
            "vehicles with another vehicle directly behind within 10 m",
        ),
        (
            "ego WHERE vehicle on RIGHT side, box_dist <= 3 m, lateral <= 1 m",
            "the ego vehicle with a vehicle directly on its right within 3 m",
        ),
        (
            "ego WHERE ped IN direction=forward AND dist <= 30 m",
            "the ego vehicle with a pedestrian ahead within 30 m",
        ),
        ("objects(category=ANY) WHERE box_dist_to_ego <= 2 m", "objects within 2 m of the ego vehicle"),
        (
            "PEDESTRIAN WHERE dist(box, crosswalk) == 0 m  -- i.e. on the crosswalk",
            "pedestrians on a crosswalk",
        ),
        ("bicycles WHERE near(vehicle, dist <= 5 m)", "bicycles within 5 m of a vehicle"),
        (
            "vehicles near_intersection (<= 5 m) AND NOT turning",
            "vehicles not turning near an intersection within 5 m",
        ),
    ],
)
def test_the_spent_fresh44_filters_build_the_program_of_their_plain_english(written: str, plain: str) -> None:
    assert rules_program(written) == rules_program(plain)


def test_a_stated_distance_to_an_intersection_sets_its_threshold() -> None:
    assert "near_intersection(subject, log_dir, threshold=8)" in rules_program(
        "vehicles near an intersection within 8 m"
    )


def test_a_speed_of_zero_is_at_rest_not_a_false_flag() -> None:
    assert rules_program("vehicles WHERE speed == 0") == rules_program("stopped vehicles")
    assert rules_program("peds where v = 0 and on_road") == rules_program("pedestrians stopped and on road")
