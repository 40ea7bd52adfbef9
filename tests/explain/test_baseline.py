"""Rule-based baseline: each filter condition on hand-built scenarios, and the rules' priority."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from braking_builders import make_pair, runs

from scenariominer.explain.baseline import (
    baseline_category,
    is_cut_in,
    is_left_oppo,
    is_obj_crossing,
    is_right_ped,
    lateral_approach_m,
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
        pair_traj_overlap=runs(("NO", 12), ("LOW", 6), ("NO", 12)),
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


def test_crossing_needs_meeting_paths_or_a_lasting_risk() -> None:
    crossing = {"pair_heading": ["LEFT"] * 30, "pair_position": ["FRONT"] * 30}
    # A car crossing a junction far ahead: a 0.5 s collision tag, paths never meet.
    glimpse = make_pair("REGULAR_VEHICLE", pair_collision=runs(("NO", 20), ("LOW", 5), ("NO", 5)), **crossing)
    assert not is_obj_crossing(glimpse)
    # The ego yields early: the paths never meet within 3 s, but the risk lasts 1.2 s.
    early_yield = make_pair(
        "REGULAR_VEHICLE", pair_collision=runs(("NO", 10), ("LOW", 12), ("NO", 8)), **crossing
    )
    assert is_obj_crossing(early_yield)
    meets = make_pair("REGULAR_VEHICLE", pair_traj_overlap=runs(("NO", 25), ("LOW", 5)), **crossing)
    assert is_obj_crossing(meets)


def test_cut_in_needs_a_lateral_approach_when_positions_are_known() -> None:
    wobbling_lead = make_pair(
        "REGULAR_VEHICLE",
        guest_latitude=runs(("FACING_FORWARD", 5), ("VEERING_LEFT", 10), ("FACING_FORWARD", 15)),
    )
    assert is_cut_in(wobbling_lead)  # by its tags alone
    in_lane = np.where(np.arange(30) % 2 == 0, 0.15, -0.1)  # tracker jitter around the ego's axis
    assert not is_cut_in(dataclasses.replace(wobbling_lead, guest_left_m=in_lane))
    merging = np.linspace(3.3, 0.3, 30)  # one lane over, into the ego's lane
    assert is_cut_in(dataclasses.replace(wobbling_lead, guest_left_m=merging))
    from_right = np.concatenate([np.full(5, np.nan), np.linspace(-3.0, -0.5, 25)])
    assert is_cut_in(dataclasses.replace(wobbling_lead, guest_left_m=from_right))


def test_lateral_approach() -> None:
    assert lateral_approach_m(np.array([3.0, 2.0, 2.5, 0.5])) == pytest.approx(2.5)
    assert lateral_approach_m(np.array([0.5, 1.0, 3.0])) == 0.0  # moving away
    assert lateral_approach_m(np.array([-2.0, np.nan, 1.0])) == pytest.approx(1.0)  # |offset|
    assert lateral_approach_m(np.array([np.nan, 2.0])) == 0.0


def test_ego_that_turns_after_the_window_counts_as_turning() -> None:
    waiting = make_pair(
        "REGULAR_VEHICLE",
        pair_heading=["OPPOSITE"] * 30,
        pair_position=runs(("FRONT", 20), ("FRONT_LEFT", 10)),
    )
    assert not is_left_oppo(waiting)  # the ego faces forward throughout the window
    assert is_left_oppo(dataclasses.replace(waiting, ego_turn_after_rad=1.4))  # then turns left
    assert not is_left_oppo(dataclasses.replace(waiting, ego_turn_after_rad=0.1))  # a lane change
    assert not is_left_oppo(dataclasses.replace(waiting, ego_turn_after_rad=-1.4))  # turns right
    walker = make_pair("PEDESTRIAN", pair_heading=["LEFT"] * 30)
    assert is_right_ped(dataclasses.replace(walker, ego_turn_after_rad=-1.2))
    assert not is_right_ped(dataclasses.replace(walker, ego_turn_after_rad=1.2))


def test_oncoming_pedestrian_is_not_left_oppo() -> None:
    walker = make_pair(
        "PEDESTRIAN",
        ego_latitude=["TURNING_LEFT"] * 30,
        pair_heading=["OPPOSITE"] * 30,
        pair_position=["FRONT"] * 30,
    )
    assert not is_left_oppo(walker)
