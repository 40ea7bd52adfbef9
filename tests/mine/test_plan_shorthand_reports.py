"""Chat shorthand, one-line scenario specifications, planner bug reports and British road words,
read by the phrase rules (mine/plan_notes.py, plan_wording.py, plan_registers.py,
plan_narrative.py, plan_road_users.py).

These wordings are my own, written for plan-reader/49 before the fresh49-fresh52 passes were read;
each must build the program of its plain English.
"""

from __future__ import annotations

import pytest
from mining_scenes import rules_program

from scenariominer.mine.plan_wording import normalised_text


@pytest.mark.parametrize(
    ("written", "plain"),
    [
        # a chat message's abbreviations
        ("peds xing in front of ego", "pedestrians crossing in front of the ego vehicle"),
        ("veh stopped nr intersection", "vehicles stopped near an intersection"),
        ("parked cars nr xwalk", "parked cars near a crosswalk"),
        ("trucks turning L", "trucks turning left"),
        ("need all LCs to the left", "vehicles changing lanes to the left"),
        ("veh LC R pls", "vehicles changing lanes to the right"),
        ("ego decel hard", "the ego vehicle braking hard"),
        ("2+ peds nr ego", "the ego vehicle with at least 2 pedestrians nearby"),
        ("bus RT @ int", "buses turning right at an intersection"),
        # a count first
        ("3 or more pedestrians near the ego", "the ego vehicle with at least 3 pedestrians nearby"),
        # a manoeuvre named with no road user
        ("left turns at intersections", "vehicles turning left at an intersection"),
        ("lane changes to the right", "vehicles changing lanes to the right"),
        # a one-line specification
        ("actor=vehicle, maneuver=lane_change_left", "vehicles changing lanes to the left"),
        (
            "Actor: bus | Action: turning right | Context: intersection",
            "buses turning right at an intersection",
        ),
        (
            "actor: ego; maneuver: hard braking; condition: pedestrian within 10 m",
            "the ego vehicle braking hard with a pedestrian within 10 m",
        ),
        ("actor: pedestrian; condition: ego within 10 m", "pedestrians within 10 m of the ego vehicle"),
        # a planner bug report
        (
            "the planner braked hard because a pedestrian stepped out in front of it",
            "the ego vehicle braking hard with a pedestrian crossing in front of it",
        ),
        (
            "we braked hard for a pedestrian crossing in front of us",
            "the ego vehicle braking hard with a pedestrian crossing in front of it",
        ),
        ("the ego was tailgated by a truck", "the ego vehicle being followed by a truck"),
        ("the ego got cut off by a car", "the ego vehicle with a car crossing its path"),
        # British road words
        ("vehicles queuing at the junction", "vehicles waiting near an intersection"),
        ("cyclists on the footway", "bicycles or cyclists on the sidewalk"),
        ("HGVs near the ego", "trucks or box trucks or truck cabs near the ego vehicle"),
        ("coaches on the carriageway", "buses on the road"),
        ("vehicles indicating and changing lanes", "vehicles changing lanes"),
    ],
)
def test_a_register_builds_the_program_of_its_plain_english(written: str, plain: str) -> None:
    assert rules_program(written) == rules_program(plain)


def test_a_turn_letter_and_a_lane_change_letter_give_the_direction() -> None:
    assert "turning(subject, log_dir, direction='left')" in rules_program("trucks turning L")
    assert "changing_lanes(subject, log_dir, direction='right')" in rules_program("veh LC R")


def test_a_cut_off_is_a_crossing_of_the_path_ahead() -> None:
    program = rules_program("the ego got cut off by a car")
    assert "being_crossed_by(subject, related_1, log_dir, direction='forward')" in program


@pytest.mark.parametrize(
    ("text", "normalised"),
    [
        # "as" and "for a moment" are no reasons, a passive without "by" keeps its reading
        (
            "vehicles that travel in the same direction as a bus",
            "vehicles that travelling in the same direction as a bus",
        ),
        ("buses that are stopped for a moment but not parked", "buses that are stopped but not parked"),
        ("vehicles getting passed from the right", "vehicles being passed from the right"),
    ],
)
def test_plain_wording_is_not_taken_for_a_reason(text: str, normalised: str) -> None:
    assert normalised_text(text) == normalised


@pytest.mark.parametrize(
    ("written", "plain"),
    [
        # from the spent fresh49-fresh52 runs (plan-reader/50): a bug report's request sentence
        (
            "Cut-in prediction failed when a car moved over to its left. Find vehicles changing lanes to"
            " the left.",
            "vehicles changing lanes to the left",
        ),
        (
            "Find vehicles that have a pedestrian ahead of them within 15 m; we saw late braking in this"
            " situation.",
            "vehicles with a pedestrian ahead of them within 15 m",
        ),
        (
            "Lateral planning got squeezed between two cars. Find the ego vehicle with a vehicle on its left"
            " and another on its right, each within 4 m.",
            "the ego vehicle with a vehicle on its left within 4 m and with another vehicle on its right"
            " within 4 m",
        ),
        (
            "the ego vehicle with a vehicle passing along its left side from behind to ahead",
            "the ego vehicle being passed on its left by a vehicle",
        ),
        # a specification's other keys
        (
            "actor: pedestrian | facing: toward the ego vehicle | range: 20 m",
            "pedestrians facing toward the ego vehicle within 20 m",
        ),
        (
            "actor: vehicle | relation: oncoming traffic relative to ego | range: within 30 m of ego",
            "vehicles travelling in the opposite direction to the ego vehicle within 30 m of the ego vehicle",
        ),
        (
            "actor: ego vehicle | condition: two or more vehicles ahead within 25 m",
            "the ego vehicle with at least 2 vehicles ahead within 25 m",
        ),
        (
            "actor: vehicle | state: parked | condition: pedestrian within 50 ft",
            "parked vehicles with a pedestrian within 15.24 m",
        ),
        (
            "actor: vehicle | condition: another vehicle alongside on its right (within 4 m, lateral 1 m)",
            "vehicles with another vehicle directly on its right within 4 m",
        ),
        (
            "actor: vehicle | heading: perpendicular to ego's travel | map: on intersection",
            "vehicles moving perpendicular to the ego vehicle on an intersection",
        ),
        # chat shorthand
        ("peds on rd but not at xwalk", "pedestrians on the road but not at a crosswalk"),
        ("anything on ego left side w/in 5m", "anything to the left of the ego vehicle within 5 m"),
        ("large veh that arent parked", "large vehicles that are not parked"),
        (
            "moving veh w/ nothing ahead in its lane for 30m",
            "moving vehicles with no objects directly ahead within 30 m",
        ),
        ("cars doing lane change w/in 20m of ego", "cars changing lanes within 20 m of the ego vehicle"),
        ("veh crawling 5 to 10 mph", "vehicles moving between 5 and 10 mph"),
        # British road words
        ("cars parked off the carriageway", "cars parked not on the road"),
        ("people on e-scooters or other wheeled devices", "wheeled riders or wheeled devices"),
        (
            "vehicles with another vehicle close up behind them, within 5 metres",
            "vehicles with another vehicle behind them within 5 m",
        ),
    ],
)
def test_a_spent_run_wording_builds_the_program_of_its_plain_english(written: str, plain: str) -> None:
    assert rules_program(written) == rules_program(plain)


def test_a_text_with_two_requests_or_none_keeps_all_its_sentences() -> None:
    from scenariominer.mine.plan_registers import request_sentence

    two = "Find parked cars. Find moving buses."
    assert request_sentence(two) == two
    none = "A car cut in. The ego braked."
    assert request_sentence(none) == none
    assert request_sentence("the car moved. show me buses.") == "show me buses"


@pytest.mark.parametrize(
    ("written", "plain"),
    [
        # my own wordings for plan-reader/51, before the fresh53-fresh56 passes were read: a hazard
        # worksheet's ratings, a remote-assistance log, a family member's plain words
        (
            "HE-03: pedestrian crossing in front of the ego vehicle (S3, E4, C2), ASIL B",
            "pedestrians crossing in front of the ego vehicle",
        ),
        (
            "RA request: ego blocked by a stopped truck in its lane",
            "the ego vehicle stopped behind a stopped truck in the same lane",
        ),
        (
            "Blocked by double-parked car ahead, needed nudge",
            "the ego vehicle stopped behind a parked car ahead",
        ),
        ("a big truck driving right next to us", "trucks next to the ego vehicle"),
        ("someone on a bike riding near our car", "bicycle riders riding near the ego vehicle"),
        (
            "when our car has to stop because a pedestrian is crossing in front of it",
            "the ego vehicle stopping with a pedestrian crossing in front of it",
        ),
    ],
)
def test_an_own_wording_of_a_new_register_builds_the_program_of_its_plain_english(
    written: str, plain: str
) -> None:
    assert rules_program(written) == rules_program(plain)


@pytest.mark.parametrize(
    ("written", "plain"),
    [
        # from the spent fresh55 and fresh56 runs (plan-reader/52): a hazard worksheet, a
        # remote-assistance log
        (
            "Hazardous event: lead vehicle braking in front of a following vehicle",
            "vehicles braking while being followed by another vehicle",
        ),
        (
            "Hazardous event: vehicle on a crossing path with the ego vehicle inside the intersection",
            "vehicles moving perpendicular to the ego vehicle inside the intersection",
        ),
        ("Hazardous event: non-vehicle object in the roadway", "objects other than vehicles in the roadway"),
        ("moving vehicle leaving the road lanes", "moving vehicles not on the road"),
        ("AV stuck behind a bus", "the ego vehicle following a bus"),
        (
            "vehicles approaching the intersection but not yet in it",
            "vehicles near the intersection but not on it",
        ),
        (
            "vehicle alongside us on the left going our way",
            "vehicles alongside the ego vehicle on the left travelling in the same direction as the ego"
            " vehicle",
        ),
    ],
)
def test_a_second_round_spent_wording_builds_the_program_of_its_plain_english(
    written: str, plain: str
) -> None:
    assert rules_program(written) == rules_program(plain)


@pytest.mark.parametrize(
    ("written", "plain"),
    [
        # from the spent fresh53 run (plan-reader/52): a family member's plain words
        ("people out where cars can drive, parking lots included", "pedestrians in the drivable area"),
        (
            "anyone outside a vehicle, like walkers or bike riders, within 5 meters of our car",
            "vulnerable road users within 5 m of the ego vehicle",
        ),
        ("our car driving through a crosswalk", "the ego vehicle driving across a crosswalk"),
        ("our car creeping along under 10 miles an hour", "the ego vehicle slower than 10 mph"),
        ("someone on a scooter", "wheeled riders"),
    ],
)
def test_a_family_members_wording_builds_the_program_of_its_plain_english(written: str, plain: str) -> None:
    assert rules_program(written) == rules_program(plain)


def test_away_from_where_cars_drive_stays_outside_the_drivable_area() -> None:
    program = rules_program("people strolling along well away from where cars can drive")
    assert "scenario_not(in_drivable_area)" in program
