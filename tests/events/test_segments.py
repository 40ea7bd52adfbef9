"""Duration segments: run-length encoding of a pair's tags, window cutting, flicker merging."""

from __future__ import annotations

import numpy as np
import pytest

from scenariominer.events.segments import (
    PAIR_FEATURES,
    Actor,
    PairFeature,
    PairTags,
    pair_tags,
    run_lengths,
    segment_pair,
)
from scenariominer.tags import LogTags, tag_log
from scenariominer.tags.vocab import ABSENT, TAG_FAMILIES, names_to_codes
from scenariominer.testing import LogBuilder, times

DT_NS = 100_000_000


def _log_tags(t: int, ego: dict[str, list[str]], guest: dict[str, list[str]], t0_ns: int = 0) -> LogTags:
    """Tags of a two-track log; ``ego``/``guest`` map a family to per-frame names (None = absent)."""
    arrays = {}
    for family, enum_cls in TAG_FAMILIES.items():
        rows = np.empty((2, t), dtype=object)
        rows[0] = ego.get(family, [None] * t)
        rows[1] = guest.get(family, [None] * t)
        arrays[family] = names_to_codes(enum_cls, rows)
    return LogTags(
        log_id="log",
        track_ids=np.array(["ego", "g"]),
        categories=np.array(["EGO_VEHICLE", "REGULAR_VEHICLE"]),
        timestamps_ns=t0_ns + np.arange(t, dtype=np.int64) * DT_NS,
        ttc_s=np.full((2, t), np.inf),
        distance_m=np.full((2, t), 20.0),
        **arrays,
    )


def _runs(*parts: tuple[str, int]) -> list[str]:
    return [name for name, n in parts for _ in range(n)]


def test_run_lengths_encodes_each_row_separately() -> None:
    codes = np.array([[0, 0, 1, 1, 1], [2, 2, 2, 2, 2], [1, 0, 1, 1, -1]], dtype=np.int8)
    runs = run_lengths(codes)
    assert runs.row.tolist() == [0, 0, 1, 2, 2, 2, 2]
    assert runs.start.tolist() == [0, 2, 0, 0, 1, 2, 4]
    assert runs.stop.tolist() == [2, 5, 5, 1, 2, 4, 5]
    assert runs.code.tolist() == [0, 1, 2, 1, 0, 1, -1]
    assert runs.run_of_cell[2].tolist() == [3, 4, 5, 5, 6]


def test_rows_follow_pair_features_and_window_adds_context() -> None:
    t = 40
    tags = _log_tags(
        t,
        ego={"longitude": _runs(("CRUISING", 10), ("DECELERATING", 30)), "latitude": ["FACING_FORWARD"] * t},
        guest={
            "longitude": ["CRUISING"] * t,
            "latitude": ["FACING_FORWARD"] * t,
            "collision": _runs(("NO", 15), ("LOW", 25)),
            "heading": ["SAME"] * t,
            "position": ["FRONT"] * t,
            "distance": ["MEDIUM"] * t,
            "traj_overlap": ["NO"] * t,
        },
    )
    pair = pair_tags(tags, "g", 15 * DT_NS, 25 * DT_NS, context_before_s=0.5, context_after_s=0.3)
    assert pair.timestamps_ns.tolist() == [i * DT_NS for i in range(10, 29)]
    assert pair.codes.shape == (len(PAIR_FEATURES), 19)
    ego_lon = PAIR_FEATURES.index(PairFeature(Actor.EGO, "longitude"))
    collision = PAIR_FEATURES.index(PairFeature(Actor.PAIR, "collision"))
    assert set(pair.codes[ego_lon].tolist()) == {3}  # DECELERATING from frame 10 on
    assert pair.codes[collision, :5].tolist() == [0] * 5 and pair.codes[collision, 5:].tolist() == [1] * 14
    assert pair.event_start_ns == 15 * DT_NS
    assert pair.duration_s == pytest.approx(1.9)


def test_segments_split_where_any_tag_changes_and_know_value_durations() -> None:
    t = 20
    tags = _log_tags(
        t,
        ego={"longitude": _runs(("CRUISING", 5), ("DECELERATING", 15)), "latitude": ["FACING_FORWARD"] * t},
        guest={
            "longitude": ["CRUISING"] * t,
            "latitude": ["FACING_FORWARD"] * t,
            "collision": _runs(("NO", 10), ("HIGH", 10)),
            "heading": ["SAME"] * t,
            "position": ["FRONT"] * t,
            "distance": ["MEDIUM"] * t,
            "traj_overlap": ["NO"] * t,
        },
    )
    segs = segment_pair(pair_tags(tags, "g", 0, 19 * DT_NS))
    assert segs.start_s.tolist() == pytest.approx([0.0, 0.5, 1.0])
    assert segs.duration_s.tolist() == pytest.approx([0.5, 0.5, 1.0])
    assert segs.duration_s.sum() == pytest.approx(segs.pair.duration_s) == pytest.approx(2.0)
    ego_lon = PAIR_FEATURES.index(PairFeature(Actor.EGO, "longitude"))
    collision = PAIR_FEATURES.index(PairFeature(Actor.PAIR, "collision"))
    assert segs.changed[:, 0].all()
    assert segs.changed[:, 1].tolist() == [i == ego_lon for i in range(len(PAIR_FEATURES))]
    assert segs.changed[:, 2].tolist() == [i == collision for i in range(len(PAIR_FEATURES))]
    # DECELERATING starts at 0.5 s and lasts to the end (1.5 s), across the collision change.
    assert segs.value_duration_s[ego_lon, 1] == pytest.approx(1.5)
    assert segs.value(ego_lon, 1) == "DECELERATING"
    assert segs.value(collision, 2) == "HIGH"


def test_short_flicker_is_merged_into_the_preceding_value() -> None:
    t = 20
    position = _runs(("FRONT", 8), ("FRONT_LEFT", 1), ("FRONT", 11))
    tags = _log_tags(
        t,
        ego={"longitude": ["CRUISING"] * t, "latitude": ["FACING_FORWARD"] * t},
        guest={
            "longitude": ["CRUISING"] * t,
            "latitude": ["FACING_FORWARD"] * t,
            "collision": ["NO"] * t,
            "heading": ["SAME"] * t,
            "position": position,
            "distance": ["MEDIUM"] * t,
            "traj_overlap": ["NO"] * t,
        },
    )
    pair = pair_tags(tags, "g", 0, 19 * DT_NS)
    assert segment_pair(pair).n_segments == 3
    merged = segment_pair(pair, min_segment_s=0.3)
    assert merged.n_segments == 1
    assert merged.duration_s.tolist() == pytest.approx([2.0])


def test_absent_guest_is_kept_and_counted() -> None:
    t = 10
    observed = [None] * 3 + ["CRUISING"] * 7
    tags = _log_tags(
        t,
        ego={"longitude": ["CRUISING"] * t, "latitude": ["FACING_FORWARD"] * t},
        guest={"longitude": observed, "latitude": [None] * 3 + ["FACING_FORWARD"] * 7},
    )
    pair = pair_tags(tags, "g", 0, 9 * DT_NS)
    assert pair.guest_frames == 7
    segs = segment_pair(pair, min_segment_s=0.5)
    guest_lon = PAIR_FEATURES.index(PairFeature(Actor.GUEST, "longitude"))
    assert pair.codes[guest_lon, 0] == ABSENT
    assert segs.value(guest_lon, 0) is None
    assert segs.value(guest_lon, 1) == "CRUISING"


def test_bad_windows_are_clear_errors() -> None:
    tags = _log_tags(5, ego={"longitude": ["CRUISING"] * 5}, guest={"longitude": ["CRUISING"] * 5})
    with pytest.raises(ValueError, match="before its start"):
        pair_tags(tags, "g", 3 * DT_NS, 1 * DT_NS)
    with pytest.raises(ValueError, match="no timestamp"):
        pair_tags(tags, "g", 100 * DT_NS, 200 * DT_NS)
    with pytest.raises(KeyError, match="nope"):
        pair_tags(tags, "nope", 0, DT_NS)
    with pytest.raises(ValueError, match="shape"):
        PairTags("log", "g", "CAR", np.arange(3), np.zeros((2, 3), dtype=np.int8), 0.1, 0, 0)


def test_brief_risk_is_never_merged_away() -> None:
    t = 20
    tags = _log_tags(
        t,
        ego={"longitude": ["DECELERATING"] * t, "latitude": ["FACING_FORWARD"] * t},
        guest={
            "longitude": ["CRUISING"] * t,
            "latitude": ["FACING_FORWARD"] * t,
            "collision": _runs(("LOW", 10), ("HIGH", 1), ("LOW", 9)),
            "heading": ["SAME"] * t,
            "position": _runs(("FRONT", 10), ("FRONT_LEFT", 1), ("FRONT", 9)),
            "distance": ["CLOSE"] * t,
            "traj_overlap": ["HIGH"] * t,
        },
    )
    segs = segment_pair(pair_tags(tags, "g", 0, 19 * DT_NS), min_segment_s=0.3)
    collision = PAIR_FEATURES.index(PairFeature(Actor.PAIR, "collision"))
    position = PAIR_FEATURES.index(PairFeature(Actor.PAIR, "position"))
    assert [segs.value(collision, s) for s in range(segs.n_segments)] == ["LOW", "HIGH", "LOW"]
    assert {segs.value(position, s) for s in range(segs.n_segments)} == {"FRONT"}
    assert segs.value_duration_s[collision, 1] == pytest.approx(0.1)


def test_pair_cut_with_the_log_carries_lateral_offset_and_the_turn_after() -> None:
    t = times(12.0)
    turn = np.where((t >= 6.0) & (t < 8.0), np.pi / 4, 0.0)  # 90 degrees left between 6 s and 8 s
    log = (
        LogBuilder(t)
        .ego(speed_mps=5.0, yaw_rate_radps=turn)
        .add("g", "REGULAR_VEHICLE", speed_mps=5.0, x0_m=15.0, y0_m=3.5)
        .build()
    )
    tags = tag_log(log)
    start, end = int(log.timestamps_ns[10]), int(log.timestamps_ns[30])
    pair = pair_tags(tags, "g", start, end, log=log, turn_lookahead_s=6.0)
    assert pair.guest_left_m is not None and pair.guest_left_m.shape == (pair.n_timestamps,)
    assert pair.guest_left_m == pytest.approx(3.5)  # both drive straight, one lane apart
    assert pair.ego_turn_after_rad == pytest.approx(np.pi / 2, abs=0.05)  # window ends at 3 s, turn 6-8 s
    short = pair_tags(tags, "g", start, end, log=log, turn_lookahead_s=1.0)
    assert short.ego_turn_after_rad == pytest.approx(0.0, abs=1e-9)  # the turn starts later
    no_log = pair_tags(tags, "g", start, end)
    assert no_log.guest_left_m is None and no_log.ego_turn_after_rad is None
