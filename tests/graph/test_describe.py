"""Template descriptions and graph relationships on hand-built windows with known manoeuvres."""

from __future__ import annotations

from scenariominer.represent.describe import describe_windows
from scenariominer.represent.graph import graph_elements, leiden_communities

from .helpers import Agent, window_of


def test_a_lane_change_to_the_left_is_described_with_its_track_id_and_time() -> None:
    # vehicle 7 moves from lane 8 to lane 7 (y grows: to the left) at step 12 of 31 over 15 s
    ws = window_of(
        [Agent("7", 0.0, 30.0, 8, change_at_step=12, change_lanes=1), Agent("5", 200.0, 30.0, 6, y0_m=7.6)]
    )
    (d,) = describe_windows(ws)
    (change,) = d.vehicles[0].lane_changes
    assert (change.track_id, change.from_lane, change.to_lane, change.direction) == ("7", 8, 7, "left")
    assert change.t_s == 6.0 and change.frame == 151  # 0.04 s log offset: frame 1 at the start
    assert (
        "Vehicle 7 (car, chosen agent) changes lane from lane 8 to lane 7 to the left at 6.0 s (frame 151)"
        in d.text
    )
    assert d.vehicles[1].lane_changes == ()
    assert "Vehicle 5 (car) keeps lane 6" in d.text
    assert d.window_id in d.text and d.log_id in d.text


def test_a_lane_change_to_the_right_and_a_multi_lane_change() -> None:
    ws = window_of(
        [Agent("4", 0.0, 25.0, 6, change_at_step=10, change_lanes=-1), Agent("9", 0.0, 25.0, 6, y0_m=30.0)]
    )
    assert describe_windows(ws)[0].vehicles[0].lane_changes[0].direction == "right"
    two = window_of([Agent("4", 0.0, 25.0, 6, change_at_step=8, change_lanes=-1)])
    # a second change of the same vehicle, one more lane to the right, built from the first
    two.lane_ids[0, 0, 20:] = 8
    two.xy_m[0, 0, 20:, 1] -= 3.8
    (d,) = describe_windows(two)
    assert [c.direction for c in d.vehicles[0].lane_changes] == ["right", "right"]
    assert "multi-lane change to the right" in d.text


def test_follow_overtake_and_cut_in_become_relationships_with_track_ids() -> None:
    # 7 follows 1 in lane 8 (30 m ahead, same speed); 7 overtakes truck 3 in lane 7 on its left side
    # (3 is to the left of 7 and falls behind); 2 cuts in from lane 7 into lane 8, 15 m ahead of 7
    agents = [
        Agent("7", 0.0, 25.0, 8),
        Agent("1", 30.0, 25.0, 8),
        Agent("3", 40.0, 18.0, 7, y0_m=3.8, category="TRUCK"),
        Agent("2", 15.0, 25.0, 7, y0_m=3.8, change_at_step=20, change_lanes=-1),
    ]
    (d,) = describe_windows(window_of(agents))
    kinds = {(i.kind, i.subject, i.obj) for i in d.interactions}
    assert ("follows", "7", "1") in kinds
    assert ("overtakes", "7", "3") in kinds
    assert ("cuts_in_front_of", "2", "7") in kinds
    cut = next(i for i in d.interactions if i.kind == "cuts_in_front_of")
    assert cut.t_s == 10.0 and 0 < cut.gap_m <= 40
    els = graph_elements([d], "test")
    rels = {(r.kind, r.source, r.target) for r in els.relationships}
    log = d.log_id
    assert ("follows", f"V:{log}/7", f"V:{log}/1") in rels
    assert ("overtakes", f"V:{log}/7", f"V:{log}/3") in rels
    assert ("cuts_in_front_of", f"V:{log}/2", f"V:{log}/7") in rels
    assert ("changes_lane_into", f"V:{log}/2", "L:8") in rels
    assert ("shows", f"S:{d.window_id}", "M:cut-in") in rels
    assert all(r.window_id == d.window_id for r in els.relationships)
    assert len({r.rel_id for r in els.relationships}) == len(els.relationships)


def test_leiden_communities_exist_at_several_levels() -> None:
    descs = []
    for i in range(6):
        lanes = [
            Agent(f"{i}0", 0.0, 25.0, 8, change_at_step=10, change_lanes=1 if i % 2 else -1),
            Agent(f"{i}1", 30.0, 25.0, 8),
        ]
        descs += describe_windows(window_of(lanes, log_id=f"highd-01-ego{i}-w0"))
    els = graph_elements(descs)
    levels = leiden_communities(els, (0.05, 0.5, 2.0))
    assert [lv.level for lv in levels] == [0, 1, 2]
    ids = {e.entity_id for e in els.entities}
    sizes = []
    for lv in levels:
        assert set(lv.membership) == ids
        sizes.append(len(lv.members()))
    assert sizes[0] <= sizes[-1] and sizes[-1] > 1
