"""A request written as a parameter block in YAML style (mine/plan_yaml.py).

The first wordings are my own, written for plan-reader/53 before the fresh57 pass was read; the
later ones come from that spent run (plan-reader/54). Each must build the program of its plain
English.
"""

from __future__ import annotations

import pytest
from mining_scenes import rules_program

from scenariominer.mine.plan_yaml import yaml_block


@pytest.mark.parametrize(
    ("written", "plain"),
    [
        ("actor: bus\nstate: stopped\nmap: near intersection", "buses stopped near an intersection"),
        ("target:\n  category: truck\n  motion: turning left", "trucks turning left"),
        ("category: PEDESTRIAN\non_road: false", "pedestrians not on the road"),
        ("category: REGULAR_VEHICLE\nchanging_lanes: left", "regular vehicles changing lanes to the left"),
        (
            "subject: vehicle\nlane: same as ego\nposition: ahead\nmax_distance_m: 20",
            "vehicles in the same lane as the ego vehicle and in front of the ego vehicle within 20 m",
        ),
        (
            "objects: [car, box truck]\nwithin_m: 10\nof: ego",
            "cars or box trucks within 10 m of the ego vehicle",
        ),
        ("{actor: pedestrian, on_road: true, speed_max_mps: 1}", "pedestrians on the road slower than 1 m/s"),
        ("actor: car\nmin_speed_kmh: 30\nlane: same as ego", "cars faster than 30 km/h in the ego's lane"),
        ("- actor: bus\n- stationary: true", "stationary buses"),
    ],
)
def test_a_parameter_block_builds_the_program_of_its_plain_english(written: str, plain: str) -> None:
    assert rules_program(written) == rules_program(plain)


@pytest.mark.parametrize(
    ("written", "plain"),
    [
        # from the spent fresh57 run: relations named by their keys, groups naming another road
        # user and its limits, limits on one quantity, sides and angles qualifying the part before
        ("actor: vehicle\nmaneuver: lane_change\ndirection: right", "vehicles changing lanes to the right"),
        ("actor: regular_vehicle\nbraking:\n  decel_min_mps2: 2", "cars braking harder than 2 m/s²"),
        ("subject: vehicle\nfollowing: ego", "vehicles following the ego vehicle"),
        ("subject: ego\nlead_vehicle: regular_vehicle", "the ego vehicle following a car"),
        (
            "object: pedestrian\nnear:\n  target: ego\n  radius_m: 5",
            "pedestrians within 5 m of the ego vehicle",
        ),
        (
            "actor: pedestrian\nlocation: drivable_area\nexclude: pedestrian_crossing",
            "pedestrians in the drivable area and not at a pedestrian crossing",
        ),
        (
            "subject: vehicle\ntravel_direction: opposite\nreference: ego",
            "vehicles travelling in the opposite direction to the ego vehicle",
        ),
        (
            "subject: vehicle\nroad_side: opposite\nrelative_to: ego",
            "vehicles on the opposite side of the road from the ego vehicle",
        ),
        (
            "subject: pedestrian\nfacing: ego\nangle_deg: 30",
            "pedestrians facing the ego vehicle within 30 degrees",
        ),
        (
            "subject: vehicle\nmoving_toward: pedestrian\nmax_distance_m: 20",
            "vehicles heading toward a pedestrian within 20 m",
        ),
        (
            "subject: ego\nobjects_ahead:\n  category: pedestrian\n  within_m: 15",
            "the ego vehicle with a pedestrian ahead within 15 m",
        ),
        (
            "return: pedestrian\nrelative_to: vehicle\ndirection: left\nwithin_m: 10",
            "pedestrians on the left of a vehicle within 10 m",
        ),
        ("subject: vehicle\nlane_type: BUS", "vehicles on a bus lane"),
        ("object: bicycle\nnear:\n  category: vehicle\n  distance_m: 3", "bicycles within 3 m of a vehicle"),
        (
            "subject: vehicle\nlateral_accel:\n  left_min_mps2: 1.5",
            "vehicles with a lateral acceleration to the left of more than 1.5 m/s²",
        ),
        (
            "category: ANY\nexclude_categories: [VEHICLE, PEDESTRIAN]\nlocation: on_road",
            "objects other than vehicles or pedestrians on the road",
        ),
        ("subject: ego\nspeed:\n  min_mph: 20", "the ego vehicle faster than 20 mph"),
        (
            "return: vehicle\nstate: stopped\nposition: ahead_of_ego\nwithin_m: 20",
            "stopped vehicles in front of the ego vehicle within 20 m",
        ),
        (
            "subject: pedestrian\nnearby_pedestrians:\n  min_count: 2\n  radius_m: 3",
            "pedestrians with at least 2 pedestrians within 3 m",
        ),
        ("subject: vehicle\non: intersection\nturning: false", "vehicles on an intersection and not turning"),
        (
            "subject: BUS\nbehind:\n  category: VEHICLE\n  within_m: 10\n  lateral_m: 1",
            "buses with a vehicle directly behind them within 10 m",
        ),
        (
            "subject: ego\ncrossed_by: moving_vehicle\nside: left",
            "the ego vehicle being crossed by a moving vehicle on its left",
        ),
        (
            "subject: vehicle\nrelative_heading:\n  to: ego\n  value: perpendicular\nnear_intersection_m: 10",
            "vehicles travelling perpendicular to the ego vehicle within 10 m of an intersection",
        ),
        (
            "subject: ego\nnearby:\n  category: ANY\n  min_count: 10\n  radius_m: 15",
            "the ego vehicle with at least 10 objects within 15 m",
        ),
    ],
)
def test_a_parameter_block_from_the_spent_run_builds_the_program_of_its_plain_english(
    written: str, plain: str
) -> None:
    assert rules_program(written) == rules_program(plain)


def test_a_lateral_acceleration_with_no_side_is_on_either_side() -> None:
    written = "subject: vehicle\nlateral_accel:\n  min_mps2: 2"
    assert rules_program(written) == rules_program("vehicles with a lateral acceleration of more than 2 m/s²")


@pytest.mark.parametrize(
    "text",
    [
        "vehicles turning left",
        "actor: vehicle; manoeuvre: right turn",
        "situation: a truck\nthat is very long and hard to describe in a key",
    ],
)
def test_text_that_is_no_parameter_block_is_unchanged(text: str) -> None:
    assert yaml_block(text) == text
