"""Wordings met in hold-out splits once they were scored (spent), read by the phrase rules.

Each test names the spent split its wordings come from; the street scene's tracks are written in
closed form in tests/mine/mining_scenes.py, so each expected set follows from the numbers there.
"""

from __future__ import annotations

import pytest
from mining_scenes import T_S, rules_program, rules_referred, street_scene

from scenariominer.mine.sandbox import run_trusted_program

SCENE = street_scene()


def _program(description: str) -> str:
    return rules_program(description)


def _referred(description: str) -> set[str]:
    return rules_referred(SCENE, description)


def _cells(description: str) -> int:
    result = run_trusted_program(_program(description), SCENE, description=description)
    assert result.ok and result.scenario is not None, result.error
    return result.scenario.n_referred_cells


def test_a_road_user_ahead_or_behind_in_the_same_lane_is_one_and_the_same() -> None:
    # the changer drives 20 m behind the ego in its lane until it moves over (t = 2-4 s); other
    # vehicles are behind the ego all along, in other lanes, while the lead shares its lane
    with_one = _cells("the ego vehicle with a vehicle behind it in the same lane")
    without = _cells("the ego vehicle with no vehicle behind it in the same lane")
    assert _cells("the ego vehicle with a vehicle behind it") == len(T_S)
    assert 20 <= with_one <= 40
    assert with_one + without == len(T_S)


def test_a_clear_road_ahead_and_a_gap_under_a_distance() -> None:  # from the spent fresh22 run
    negated = (
        "scenario_not(has_objects_in_relative_direction)(subject, related_1, log_dir, direction='forward'"
    )
    assert negated + ")" in _program("the ego vehicle with a clear road ahead")
    assert negated + ", within_distance=30)" in _program(
        "cars with an empty road ahead (no vehicle in front within 30 m)"
    )
    assert _referred("the ego vehicle with a clear road ahead") == set()  # the lead is ahead
    assert "near_objects(step_1, related_1, log_dir, distance_thresh=8)" in _program(
        "vehicles following the ego with a gap of less than 8 m"
    )


@pytest.mark.parametrize(
    ("description", "expected"),
    [
        # from the spent fresh24 run: specification lines ("key: value; key: value"), "where"
        # clauses, "passed by X" without "being", adjectives before a bracketed list of subtypes
        ("actor: vehicle; manoeuvre: right turn; location: on an intersection", {"turner"}),
        ("actor: car; manoeuvre: lane change to the left", {"changer"}),
        ("ego: following a car | speed: above 5 m/s", {"ego"}),
        ("ego: following a car | speed: above 12 m/s", set()),  # the ego drives at 10 m/s
        ("ego where speed is above 8 m/s and a vehicle is following it", {"ego"}),
        ("cars where they are turning right", {"turner"}),
        ("pedestrians where their speed exceeds 1 m/s", {"ped"}),
        ("vehicles where a pedestrian is crossing in front of them", {"lead"}),
        ("vehicles passed on their left by a moving vehicle", {"ego"}),
    ],
)
def test_specification_lines_and_where_clauses_are_read(description: str, expected: set[str]) -> None:
    assert _referred(description) == expected


def test_adjectives_before_a_bracketed_list_of_subtypes_are_kept() -> None:
    program = _program("parked trucks of any kind (truck, box truck or truck cab)")
    assert "'TRUCK_CAB'" in program and "stationary(subject, log_dir)" in program
    assert "within_distance=20" in _program("vehicles where no other vehicle is ahead within 20 m")


@pytest.mark.parametrize(
    ("description", "expected"),
    [
        # from the spent fresh25 run: a story in the past tense, the first person, drivers' idioms
        ("a car that overtook us on the left", {"overtaker"}),
        ("a car that passed us", {"overtaker"}),
        ("we were tailing another car down the road", {"ego"}),
        ("a car that hung a right in the middle of the intersection", {"turner"}),
        ("a car that moved over into the lane on its left", {"changer"}),
        ("vehicles that switched lanes to the left", {"changer"}),
        ("a pedestrian who was looking straight at our car", {"pedA"}),
        ("people walking over the zebra crossing", {"ped"}),
        ("a car that stayed on our tail in our lane", {"changer"}),  # until it moves over
        ("cars that cut across our direction of travel at right angles", {"turner"}),
        ("vehicles that were not cars, like trucks and buses, out on the road", {"bus", "ego"}),
        ("cars that were parked on the road", {"parked"}),
    ],
)
def test_a_story_in_the_past_tense_and_the_first_person_is_read(description: str, expected: set[str]) -> None:
    assert _referred(description) == expected


def test_a_finished_stop_is_stopped_and_walking_past_is_walking_near() -> None:
    assert "scenario_or([stationary(subject, log_dir), has_velocity(subject" in _program(
        "buses that had come to a stop"
    )
    program = _program("a pedestrian strolling past a parked car")
    assert "has_velocity(subject, log_dir, min_velocity=0.5)" in program
    assert "related_1 = stationary(related_1, log_dir)" in program
    assert "near_intersection(subject, log_dir)" in _program(
        "a car speeding up as it left the intersection area"
    )


def test_ranges_counts_and_places_of_a_data_curators_wording() -> None:  # from the spent fresh26
    assert _referred("people within 2 m of a pedestrian crossing") == {"ped"}
    assert "at_pedestrian_crossing(subject, log_dir, within_distance=2)" in _program(
        "people within 2 m of a pedestrian crossing"
    )
    assert "scenario_not(on_intersection)(subject, log_dir)" in _program(
        "vehicles turning right somewhere other than on an intersection"
    )
    assert _referred("cars surrounded by at least 6 other vehicles within 20 m") == set()
    assert "distance_thresh=20, min_objects=2" in _program(
        "cars surrounded by at least 2 other vehicles within 20 m"
    )
    assert "direction='forward', lateral_thresh=1" in _program(
        "vehicles with a vehicle ahead of them in roughly their own lane"
    )
    closing = "cars approaching the ego vehicle within 50 m, closing the gap at {} m/s or more"
    assert _referred(closing.format(3)) == {"oncoming", "overtaker"}
    assert _referred(closing.format(30)) == set()
    assert "accelerating(subject, log_dir, min_accel=-3, max_accel=-1)" in _program(
        "cars decelerating at between 1 and 3 m/s²"
    )
    assert "accelerating(subject, log_dir, min_accel=0.5, max_accel=2)" in _program(
        "cars speeding up at between 0.5 and 2 m/s²"
    )


@pytest.mark.parametrize(
    ("description", "expected"),
    [
        # from the spent fresh25 run: the first in line, a driver called "someone", hanging back
        ("the car right in front of us", {"lead"}),
        ("the nearest vehicle ahead of the ego vehicle", {"lead"}),
        ("the vehicle immediately behind the ego vehicle", {"changer"}),  # 20 m behind in its lane
        ("someone hanging back behind the ego vehicle in the same lane", {"changer"}),
        ("vehicles that a pedestrian crossed in front of", {"lead"}),
    ],
)
def test_the_first_in_line_and_a_driver_hanging_back(description: str, expected: set[str]) -> None:
    assert _referred(description) == expected


def test_a_road_user_crossing_behind_another_and_an_object_relative_clause() -> None:
    behind = "being_crossed_by(subject, related_1, log_dir, direction='backward')"
    assert behind in _program("a car that a pedestrian walked across the back of")
    assert behind in _program("cars with a pedestrian walking across behind them")
    assert behind in _program("cars being crossed from behind by a pedestrian")
    reverse = "reverse_relationship(being_crossed_by)(related_1, subject, log_dir, direction='backward')"
    assert reverse in _program("pedestrians crossing behind a bus")
    # walking behind a bus is not crossing its rear: a direction relation
    assert "being_crossed_by" not in _program("pedestrians walking behind a bus")


@pytest.mark.parametrize(
    ("note", "plain"),
    [
        # from the spent fresh28 run: a claims analyst's terse notes
        ("peds facing ego, 20 m or less", "pedestrians facing the ego vehicle within 20 m"),
        ("vehicle closing on a ped, under 15 m", "vehicle closing in on a pedestrian within 15 m"),
        ("car w/ 3+ peds close by", "cars with at least 3 pedestrians nearby"),
        (
            "ego at a standstill, vehicle in front within 10 m",
            "the ego vehicle stopped with a vehicle in front within 10 m",
        ),
        ("car pointed at a ped within 10 m; car moving", "cars moving and facing a pedestrian within 10 m"),
        ("cones/barrels on the road", "cones or barrels on the road"),
        ("third-party vehicles turning left (excl. ego)", "vehicles turning left other than the ego vehicle"),
        (
            "vehicle turning right w/ ped crossing its front",
            "vehicles turning right with a pedestrian crossing in front of them",
        ),
        ("vehicle moving across to right-hand lane", "vehicles changing lanes to the right"),
        (
            "moving vehicle off-road but in drivable area (car park / driveway)",
            "moving vehicles not on the road but in the drivable area",
        ),
        (
            "car braking >1 m/s² with another car following",
            "cars braking harder than 1 m/s² being followed by another car",
        ),
        ("box van stopped momentarily", "box trucks coming to a momentary stop"),
    ],
)
def test_a_terse_note_is_read_as_its_plain_wording(note: str, plain: str) -> None:
    assert _program(note) == _program(plain).replace(repr(plain), repr(note))


def test_a_crossing_from_one_side_to_the_other_and_a_comma_after_a_list() -> None:
    assert "in_direction='clockwise'" in _program("vehicle crossed left-to-right by ped")
    assert "in_direction='counterclockwise'" in _program(
        "cars being crossed from right to left by a pedestrian"
    )
    # a list of road users keeps its commas: not a note's "with" clause
    assert _program("cars, trucks and buses turning left").count("get_objects_of_category") == 5
    assert _referred("vehicles moving, pedestrian crossing in front of them") == {"lead"}
    assert _referred("vehicles moving, pedestrian crossing in front of them") == _referred(
        "vehicles moving with a pedestrian crossing in front of them"
    )


def test_a_count_of_road_users_is_a_condition_on_the_one_they_are_around() -> None:
    # from the spent fresh28 run: "2+ vehicles ahead of ego within 30 m" is about the ego
    counted = (
        "has_objects_in_relative_direction(subject, related_1, log_dir, direction='forward',"
        " within_distance=30, min_number=2)"
    )
    assert counted in _program("2+ vehicles ahead of ego within 30 m")
    assert counted in _program("the ego vehicle with at least 2 vehicles in front of it within 30 m")
    assert "distance_thresh=20, min_objects=2" in _program("at least 2 vehicles near the ego within 20 m")
    # "with 2 vehicles ahead" counts them; "two cars ahead" is a place in the line
    assert "line_1" not in _program("the ego with 2 vehicles ahead")
    assert "line_1" in _program("vehicle two cars ahead")
    assert _referred("the ego vehicle with at least 1 vehicle ahead of it within 30 m") == {"ego"}


@pytest.mark.parametrize(
    ("written", "plain"),
    [
        # from the spent fresh27, fresh29, fresh30 and fresh31 runs
        ("moving vehicles off the road (not on any mapped lane)", "moving vehicles not on the road"),
        ("moving vehicles that are off the mapped road lanes", "moving vehicles not on the road"),
        (
            "vehicles driving through a car park rather than on the road",
            "vehicles in a parking lot and not on the road",
        ),
        ("cars with >=3 peds within 10 m", "cars with at least 3 pedestrians within 10 m"),
        ("host vehicle speeding up", "the ego vehicle speeding up"),
        ("veh lane change to the right", "vehicles changing lanes to the right"),
        ("ego car doing a turn to left", "the ego vehicle turning left"),
        (
            "pedestrians in front of the ego car, maximal 15 meters away",
            "pedestrians within 15 m in front of the ego vehicle",
        ),
        ("construction cones in near of the intersection", "construction cones near an intersection"),
        (
            "pedestrians who are looking in direction to the ego vehicle",
            "pedestrians looking toward the ego vehicle",
        ),
        ("cars which accelerate but are still slower as 5 m/s", "cars accelerating and slower than 5 m/s"),
        ("ego car standing at the zebra crossing", "the ego vehicle stopped at a crosswalk"),
        (
            "vehicles which point to a pedestrian at less than 10 meter",
            "vehicles facing a pedestrian within 10 m",
        ),
        ("vehicles stopped on top of a pedestrian crossing, blocking it", "vehicles stopped on a crosswalk"),
        (
            "the ego vehicle sharing its lane with a parked vehicle",
            "the ego vehicle in the same lane as a parked vehicle",
        ),
        (
            "vehicles changing lanes near an intersection, which is where weaving is most risky",
            "vehicles changing lanes near an intersection",
        ),
        ("does the ego vehicle make any right turns?", "the ego vehicle turning right"),
        ("vehicles following behind a bus in the same lane", "vehicles following a bus"),
        ("which vehicles pass through the middle of an intersection?", "vehicles on an intersection"),
    ],
)
def test_wordings_of_the_session_20_splits_build_the_program_of_their_plain_english(
    written: str, plain: str
) -> None:
    assert _program(written) == _program(plain)


def test_a_while_clause_naming_another_road_user_is_a_with_clause() -> None:
    from scenariominer.mine.plan_wording import normalised_text

    assert normalised_text("the ego vehicle turning left while an oncoming vehicle is within 30 metres") == (
        normalised_text("the ego vehicle turning left with an oncoming vehicle within 30 metres")
    )
    assert "not turning" in normalised_text("vehicles going straight across an intersection without turning")


@pytest.mark.parametrize(
    ("written", "plain"),
    [
        # from the spent fresh27-fresh32 runs (read in session 21)
        (
            "vehicles going straight across an intersection without turning",
            "vehicles going straight on an intersection",
        ),
        ("vehicles going straight on an intersection", "vehicles going straight and on an intersection"),
        (
            "swerving vehicles, |lateral accel| > 3 m/s^2",
            "vehicles with a lateral acceleration above 3 m/s^2",
        ),
        ("swerving vehicles", "vehicles swerving"),
        (
            "which vehicles swing to the left with a sideways acceleration of more than 2 m/s²?",
            "vehicles with a leftward lateral acceleration of more than 2 m/s^2",
        ),
        (
            "vehicles on the other side of road compared with the ego",
            "vehicles on the other side of the road from the ego",
        ),
        (
            "pedestrians that the ego vehicle is driving toward, within 20 metres",
            "pedestrians with the ego vehicle heading toward them within 20 m",
        ),
        (
            "groups of pedestrians, at least 2 other pedestrians within 3 meter",
            "pedestrians with at least 2 other pedestrians within 3 m",
        ),
        (
            "a vehicle following another vehicle in its lane with less than 10 m to the one ahead",
            "a vehicle following another vehicle closer than 10 m",
        ),
        (
            "any object in ego's path, 5 m ahead, one-lane corridor",
            "objects in the path of the ego vehicle within 5 m",
        ),
        (
            "vehicles having three or more pedestrians in the near, inside 5 meters",
            "vehicles with at least 3 pedestrians within 5 m",
        ),
        ("vehicles braking as they approach a pedestrian crossing", "vehicles braking near a crosswalk"),
        ("vehicle occupying a bus lane", "vehicles in a bus lane"),
        (
            "ego vehicle with two or more vehicles ahead in its lane corridor within 30 m",
            "ego vehicle with at least 2 vehicles directly ahead within 30 m",
        ),
        (
            "ego vehicle at a standstill with a stopped lead vehicle in its lane less than 10 m ahead",
            "ego vehicle at a standstill with a stopped vehicle directly ahead within 10 m",
        ),
        (
            "moving vehicles with a clear lane ahead, meaning no other vehicle in front of them within 30"
            " metres inside about one lane's width",
            "moving vehicles with no other vehicle directly in front of them within 30 m",
        ),
        (
            "cars in ego's lane and in front of it, <= 40 m",
            "cars in the same lane as the ego vehicle and in front of the ego vehicle within 40 m",
        ),
        (
            "bollards that a moving vehicle passes within 2 metres of",
            "bollards with a moving vehicle within 2 m",
        ),
        ("vehicles the ego overtakes on their left side", "vehicles being overtaken on the left by the ego"),
        (
            "moving vehicle in a parking lot or driveway (drivable area but not a road)",
            "moving vehicles in a parking lot or driveway",
        ),
        (
            "regular vehicles the ego heading points at, within 10 m",
            "regular vehicles with the ego vehicle facing toward them within 10 m",
        ),
        (
            "ped in the drivable area near a veh that is moving toward it",
            "pedestrians in the drivable area near a vehicle with a vehicle heading toward them",
        ),
        (
            "ped crossing in front of a car (within 10 m of its bumper)",
            "pedestrians crossing in front of a car within 10 m",
        ),
        # from the spent fresh37-fresh40 runs (a researcher, an HD-map engineer, a dispatcher's texts,
        # a driving-school lesson in the second person)
        (
            "I am interested in the moments when the ego vehicle is making a left turn.",
            "the ego vehicle turning left",
        ),
        ("Identify vehicles that change lanes towards their right.", "vehicles changing lanes to the right"),
        (
            "Find vehicles that share a lane with the ego vehicle.",
            "vehicles in the same lane as the ego vehicle",
        ),
        (
            "Find vehicles that change lanes while another vehicle is on their left within five metres.",
            "vehicles changing lanes with another vehicle on their left within 5 m",
        ),
        (
            "vehicles turning right more than 5 m away from any intersection",
            "vehicles turning right more than 5 m from an intersection",
        ),
        ("vulnerable road users on an intersection lane segment", "vulnerable road users on an intersection"),
        (
            "anybody merging over to the right lane? vehicles changing lanes right",
            "vehicles changing lanes to the right",
        ),
        (
            "oncoming traffic for the ego - vehicles going the opposite way",
            "vehicles going in the opposite direction",
        ),
        ("is the ego ever stopped?", "the ego vehicle stopped"),
        (
            "peds out in the road but not at a crosswalk. jaywalkers basically",
            "pedestrians on the road but not at a crosswalk",
        ),
        (
            "ego got anyone on its tail? vehicle behind within 10m",
            "the ego vehicle with a vehicle behind it within 10 m",
        ),
        (
            "you are making a left turn through an intersection",
            "the ego vehicle turning left on an intersection",
        ),
        (
            "parked vehicles on your right within 10 metres",
            "parked vehicles on the right of the ego vehicle within 10 m",
        ),
        ("a vehicle overtaking you on your left", "a vehicle overtaking the ego vehicle on its left"),
        (
            "you have at least two pedestrians ahead of you",
            "the ego vehicle with at least 2 pedestrians ahead of it",
        ),
        (
            "vehicles turning right somewhere ahead of you",
            "vehicles turning right and ahead of the ego vehicle",
        ),
        (
            "you are driving past parked cars less than 3 metres to your right",
            "the ego vehicle moving with parked cars on its right within 3 m",
        ),
        # from the spent fresh33 run (a safety driver's end-of-shift report)
        (
            "I saw a few pedestrians walking out on the road itself instead of the sidewalk",
            "pedestrians walking on the road",
        ),
        ("I watched some cars hop over into the lane on their left", "cars changing lanes to the left"),
        ("at one point we made a right turn", "the ego vehicle making a right turn"),
        ("there were construction cones sitting out on the road", "construction cones on the road"),
        ("I saw other vehicles doing over 30 mph", "vehicles doing more than 30 mph"),
        ("cars turned left somewhere ahead of us", "cars turning left ahead of the ego vehicle"),
        ("some vehicle ahead of us changed lanes", "a vehicle ahead of the ego vehicle changing lanes"),
        ("cars were behind us, within 20 metres", "cars behind the ego vehicle within 20 m"),
        (
            "there was a moment when we had at least three pedestrians out in front of us",
            "the ego vehicle with at least 3 pedestrians in front of it",
        ),
        (
            "a pedestrian was walking straight toward us",
            "a pedestrian walking straight toward the ego vehicle",
        ),
        ("some parked cars were pointed right at us", "parked cars facing the ego vehicle"),
        ("a car was tailing us for a while", "a car tailing the ego vehicle"),
        ("I saw a car following behind a box truck in its lane", "a car following a box truck"),
        ("we squeezed by within 2 m of a parked car", "the ego vehicle within 2 m of a parked car"),
        (
            "cars went straight through the intersection without turning",
            "cars going straight on an intersection",
        ),
        ("a bus or a truck got within 10 m of us", "a bus or truck within 10 m of the ego vehicle"),
        (
            "a pedestrian was walking in the same direction we were driving",
            "a pedestrian walking in the same direction as the ego vehicle",
        ),
        (
            "we drove through the intersection while a pedestrian was on the crosswalk nearby",
            "the ego vehicle on an intersection near a pedestrian who is at a crosswalk",
        ),
        # from the spent fresh35 run (a tracking engineer's words)
        ("all TRUCK_CAB tracks (semi-tractor units) in the scene", "truck cabs"),
        ("LARGE_VEHICLE tracks that stay put for the entire log", "parked large vehicles"),
        (
            "vehicles momentarily held at under 0.5 m/s while on an intersection",
            "vehicles under 0.5 m/s on an intersection",
        ),
        ("vehicles executing a lane change into the right-hand lane", "vehicles changing lanes to the right"),
        (
            "vehicles with a bicycle off their left flank within 5 metres",
            "vehicles with a bicycle on their left within 5 m",
        ),
        (
            "pedestrians oriented toward the ego, within 30 degrees of their heading",
            "pedestrians facing the ego vehicle within 30 degrees",
        ),
        ("the ego tracking behind a lead vehicle in its own lane", "the ego vehicle following a vehicle"),
        (
            "vehicles sharing the ego's lane and no more than 30 m ahead of it",
            "vehicles in the same lane as the ego vehicle and ahead of the ego vehicle within 30 m",
        ),
        (
            "construction cones or bollards sitting on a mapped lane",
            "construction cones or bollards on the road",
        ),
        (
            "moving vehicles with no vehicle within 20 m ahead in a one-lane corridor",
            "moving vehicles with no vehicle directly ahead within 20 m",
        ),
        ("any annotated object within 2 m of the ego's box", "objects within 2 m of the ego vehicle"),
        (
            "the ego with a vehicle off its right side within 3 m and at most 1 m ahead of or behind its box",
            "the ego vehicle with a vehicle directly on its right within 3 m",
        ),
        (
            "vehicles overtaking the ego along its left flank, passing back to front within 4 m",
            "vehicles overtaking the ego vehicle on its left within 4 m",
        ),
        # from the spent fresh34 run (search-box queries)
        ("ego left turn", "the ego vehicle turning left"),
        ("trucks left of ego", "trucks to the left of the ego vehicle"),
        ("non vehicles on road", "objects other than vehicles on the road"),
        ("cars changing lanes right", "cars changing lanes to the right"),
        (
            "vehicles that have another vehicle ahead of them within 30 feet, in roughly the same lane width",
            "vehicles with another vehicle directly ahead of them within 9.144 m",
        ),
    ],
)
def test_wordings_of_the_session_21_rules_build_the_program_of_their_plain_english(
    written: str, plain: str
) -> None:
    assert _program(written) == _program(plain)


def test_another_road_users_oncoming_is_relative_to_the_subject() -> None:
    program = _program("the ego vehicle turning left while an oncoming vehicle is within 30 metres")
    assert "heading_in_relative_direction_to(related_1, subject, log_dir, direction='opposite')" in program
    assert "near_objects(step_1, related_1, log_dir, distance_thresh=30)" in program
    # the lead is 15 m ahead of the ego all along; only the westbound cars come toward it, within
    # 20 m only for a while (the oncoming one around t = 4.5 s, the parked one around t = 3 s)
    assert _cells("the ego vehicle with a vehicle within 20 m") == len(T_S)
    assert 0 < _cells("the ego vehicle with an oncoming vehicle within 20 m") < len(T_S)


def test_not_before_a_relation_negates_it() -> None:
    program = _program("moving cars that aren't following any vehicle")
    assert "scenario_not(following)(step_1, related_1, log_dir)" in program
    following = _cells("vehicles following a vehicle")
    assert following > 0
    assert following + _cells("vehicles not following a vehicle") == _cells("vehicles")


def test_a_crossing_within_a_distance_limits_how_far_ahead_of_the_bumper() -> None:
    # the pedestrian crosses 2.75 m ahead of the lead's front bumper, 17.75 m ahead of the ego's
    assert "forward_thresh=10" in _program("pedestrians crossing in front of the ego vehicle within 10 m")
    assert _referred("pedestrians crossing in front of the ego vehicle within 10 m") == set()
    assert _referred("pedestrians crossing in front of the ego vehicle within 20 m") == {"ped"}
    assert _referred("pedestrians crossing in front of a car within 5 m") == {"ped"}


def test_a_past_tense_verb_after_a_negation_or_a_perfect_stays_as_it_is() -> None:
    from scenariominer.mine.plan_narrative import present_tense

    assert present_tense("cars that never moved an inch") == "cars that never moved an inch"
    assert present_tense("object that has not moved") == "object that has not moved"
    assert present_tense("cars turned left") == "cars turning left"
    assert present_tense("vehicles passed on their left by a bus") == "vehicles passed on their left by a bus"
