"""Rule-based baseline: each filter condition on hand-built scenarios, and the rules' priority."""

from __future__ import annotations

from braking_builders import make_pair, runs

from scenariominer.explain.baseline import (
    baseline_category,
    is_cut_in,
    is_left_oppo,
    is_obj_crossing,
    is_right_ped,
)


def test_cut_in_from_front_right_to_front_with_lateral_motion() -> None:
    pair = make_pair(
        "REGULAR_VEHICLE",
        pair_position=runs(("FRONT_RIGHT", 12), ("FRONT", 18)),
        guest_latitude=runs(("FACING_FORWARD", 8), ("VEERING_LEFT", 8), ("FACING_FORWARD", 14)),
    )
    assert is_cut_in(pair)
    assert baseline_category(pair) == "cut_in"


def test_cut_in_of_a_car_already_inside_the_front_sector() -> None:
    # 20 m ahead in the next lane is within +-22.5 degrees: FRONT throughout; it veers in.
    pair = make_pair(
        "BUS", guest_latitude=runs(("FACING_FORWARD", 5), ("VEERING_RIGHT", 10), ("FACING_FORWARD", 15))
    )
    assert baseline_category(pair) == "cut_in"


def test_no_cut_in_without_lateral_motion_or_while_the_ego_turns_along() -> None:
    lead = make_pair("REGULAR_VEHICLE", pair_position=runs(("FRONT_LEFT", 10), ("FRONT", 20)))
    assert not is_cut_in(lead)  # the position changed because of the road, not the guest
    both_turn = make_pair(
        "REGULAR_VEHICLE", guest_latitude=["TURNING_LEFT"] * 30, ego_latitude=["TURNING_LEFT"] * 30
    )
    assert not is_cut_in(both_turn)
    walker = make_pair("PEDESTRIAN", guest_latitude=["VEERING_LEFT"] * 30)
    assert not is_cut_in(walker)


def test_left_turn_with_oncoming_object_ahead() -> None:
    pair = make_pair(
        "REGULAR_VEHICLE",
        ego_latitude=runs(("FACING_FORWARD", 10), ("TURNING_LEFT", 20)),
        pair_heading=["OPPOSITE"] * 30,
        pair_position=runs(("FRONT", 15), ("FRONT_LEFT", 10), ("LEFT", 5)),
    )
    assert is_left_oppo(pair)
    assert baseline_category(pair) == "left_oppo"
    straight = make_pair("REGULAR_VEHICLE", pair_heading=["OPPOSITE"] * 30)
    assert not is_left_oppo(straight)
    behind = make_pair(
        "REGULAR_VEHICLE",
        ego_latitude=["TURNING_LEFT"] * 30,
        pair_heading=["OPPOSITE"] * 30,
        pair_position=["BACK"] * 30,
    )
    assert not is_left_oppo(behind)


def test_right_turn_with_pedestrian() -> None:
    pair = make_pair(
        "PEDESTRIAN",
        ego_latitude=runs(("VEERING_RIGHT", 5), ("TURNING_RIGHT", 25)),
        pair_heading=["LEFT"] * 30,
        pair_position=["FRONT_RIGHT"] * 30,
    )
    assert is_right_ped(pair)
    assert baseline_category(pair) == "right_ped"
    car = make_pair("REGULAR_VEHICLE", ego_latitude=["TURNING_RIGHT"] * 30)
    assert not is_right_ped(car)


def test_crossing_object_ahead() -> None:
    pair = make_pair(
        "BICYCLIST",
        pair_heading=runs(("RIGHT", 30)),
        pair_position=runs(("FRONT_LEFT", 10), ("FRONT", 10), ("FRONT_RIGHT", 10)),
    )
    assert baseline_category(pair) == "obj_crossing"
    beside = make_pair("BICYCLIST", pair_heading=["RIGHT"] * 30, pair_position=["LEFT"] * 30)
    assert not is_obj_crossing(beside)
    walker = make_pair("PEDESTRIAN", pair_heading=["RIGHT"] * 30, pair_position=["FRONT"] * 30)
    assert not is_obj_crossing(walker)  # pedestrians crossing are ped_crossing, not a known category


def test_anything_else_is_not_relevant() -> None:
    assert baseline_category(make_pair("REGULAR_VEHICLE")) == "not_relevant"
    parked_behind = make_pair(
        "REGULAR_VEHICLE", pair_position=["BACK_RIGHT"] * 30, guest_longitude=["STANDING_STILL"] * 30
    )
    assert baseline_category(parked_behind) == "not_relevant"
