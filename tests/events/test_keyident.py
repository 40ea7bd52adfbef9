"""KeyIdent: objects with collision or overlap risk while the ego brakes become braking events."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from scenariominer.config.tags import KeyIdentConfig
from scenariominer.data.log import Log, build_log
from scenariominer.data.preprocess import preprocess
from scenariominer.events import KeyEvent, find_key_objects, key_candidates
from scenariominer.tags import CollisionTag, LogTags, LongitudeTag, TrajOverlapTag, tag_log
from scenariominer.tags.vocab import ABSENT, code_of

DT_S = 0.1


def _straight(t: np.ndarray, x0: float, y0: float, v0: float, brake_at_s: float, decel: float) -> np.ndarray:
    """x positions of a car driving +x at v0 that brakes at ``decel`` from ``brake_at_s`` to a stop."""
    tb = np.clip(t - brake_at_s, 0.0, v0 / decel if decel > 0 else 0.0)
    return x0 + v0 * np.minimum(t, brake_at_s) + v0 * tb - 0.5 * decel * tb**2


def _braking_lead_log() -> Log:
    """Ego follows a lead at 10 m/s; the lead brakes hard at 3 s, the ego at 4 s; plus a car in
    parallel 30 m to the left and a car parked 5 m to the right of the lane."""
    t = np.arange(101) * DT_S
    tracks = {
        "ego": ("EGO_VEHICLE", _straight(t, 0.0, 0.0, 10.0, 4.0, 5.0), 0.0),
        "lead": ("REGULAR_VEHICLE", _straight(t, 20.0, 0.0, 10.0, 3.0, 6.0), 0.0),
        "far": ("REGULAR_VEHICLE", _straight(t, 0.0, 0.0, 10.0, 99.0, 0.0), 30.0),
        "parked": ("REGULAR_VEHICLE", np.full(t.size, 30.0), -5.0),
    }
    n = t.size
    tid = np.repeat(list(tracks), n)
    cat = np.repeat([v[0] for v in tracks.values()], n)
    x = np.concatenate([v[1] for v in tracks.values()])
    y = np.concatenate([np.full(n, v[2]) for v in tracks.values()])
    log = build_log(
        log_id="braking",
        track_id=tid,
        category=cat,
        timestamp_ns=np.tile(np.round(t * 1e9).astype(np.int64), len(tracks)),
        fields={
            "x_m": x,
            "y_m": y,
            "yaw_rad": np.zeros_like(x),
            "length_m": np.full_like(x, 4.5),
            "width_m": np.full_like(x, 2.0),
        },
        ego_track_id="ego",
        source="<test>",
    )
    return preprocess(log)


@pytest.fixture(scope="module")
def braking_tags() -> LogTags:
    return tag_log(_braking_lead_log())


def _hand_tags(ego_long: list[str], collision: list[str], overlap: list[str], dt_s: float = DT_S) -> LogTags:
    """Tags of an ego and one object, given per timestamp ('' = absent)."""
    t = len(ego_long)

    def codes(enum_cls: type, names: list[str]) -> np.ndarray:
        return np.array([code_of(enum_cls(v)) if v else ABSENT for v in names], dtype=np.int8)

    absent = np.full(t, ABSENT, dtype=np.int8)
    cruising = np.full(t, code_of(LongitudeTag.CRUISING), dtype=np.int8)
    zeros = np.zeros(t, dtype=np.int8)
    return LogTags(
        log_id="hand",
        track_ids=np.array(["ego", "obj"]),
        categories=np.array(["EGO_VEHICLE", "BICYCLIST"]),
        timestamps_ns=(np.arange(t) * dt_s * 1e9).astype(np.int64),
        longitude=np.stack([codes(LongitudeTag, ego_long), cruising]),
        latitude=np.stack([zeros, zeros]),
        collision=np.stack([absent, codes(CollisionTag, collision)]),
        heading=np.stack([absent, zeros]),
        position=np.stack([absent, zeros]),
        distance=np.stack([absent, zeros]),
        traj_overlap=np.stack([absent, codes(TrajOverlapTag, overlap)]),
        ttc_s=np.stack([np.full(t, np.nan), np.linspace(3.0, 0.5, t)]),
        distance_m=np.stack([np.full(t, np.nan), np.linspace(20.0, 5.0, t)]),
    )


def test_the_braking_lead_is_the_key_object_and_the_far_cars_are_not(braking_tags: LogTags) -> None:
    events = find_key_objects(braking_tags)
    assert [e.track_id for e in events] == ["lead"]
    (event,) = events
    assert event.category == "REGULAR_VEHICLE"
    assert event.peak_collision is CollisionTag.HIGH
    assert event.min_ttc_s < 1.5
    # The event lies inside the time the ego brakes or stands (it brakes from 4 s).
    assert 3.5 <= event.start_ns * 1e-9 <= 4.5
    assert event.end_ns > event.start_ns
    assert event.event_id == f"braking:lead:{event.start_ns}"


def test_candidates_need_ego_braking_at_the_same_timestamp() -> None:
    tags = _hand_tags(
        ["CRUISING", "CRUISING", "DECELERATING", "DECELERATING", "STANDING_STILL", "CRUISING"],
        ["HIGH", "HIGH", "NO", "LOW", "NO", "HIGH"],
        ["NO", "NO", "NO", "NO", "HIGH", "NO"],
    )
    assert key_candidates(tags)[1].tolist() == [False, False, False, True, True, False]
    assert not key_candidates(tags)[0].any()


def test_consecutive_candidates_merge_into_one_event_with_peak_levels() -> None:
    tags = _hand_tags(
        ["DECELERATING"] * 6,
        ["LOW", "LOW", "HIGH", "NO", "LOW", "NO"],
        ["NO", "NO", "NO", "LOW", "NO", "NO"],
    )
    (event,) = find_key_objects(tags)
    assert (event.start_ns, event.end_ns, event.n_frames) == (0, 400_000_000, 5)
    assert event.peak_collision is CollisionTag.HIGH
    assert event.peak_traj_overlap is TrajOverlapTag.LOW
    assert event.min_ttc_s == pytest.approx(tags.ttc_s[1, 4])
    assert event.min_distance_m == pytest.approx(tags.distance_m[1, 4])
    assert isinstance(event, KeyEvent)


def test_gaps_longer_than_max_gap_split_events() -> None:
    ego = ["STANDING_STILL"] * 30
    risk = ["HIGH"] * 5 + ["NO"] * 4 + ["HIGH"] * 5 + ["NO"] * 15 + ["LOW"]
    tags = _hand_tags(ego, risk, ["NO"] * 30)
    # A 0.5 s hole (timestamps 0.4 s -> 0.9 s) is bridged by the default 1 s, a 1.6 s one is not.
    events = find_key_objects(tags)
    assert [(e.start_ns, e.end_ns) for e in events] == [(0, 1_300_000_000), (2_900_000_000, 2_900_000_000)]
    strict = find_key_objects(tags, KeyIdentConfig(max_gap_s=0.2))
    assert len(strict) == 3


def test_minimum_duration_drops_short_events() -> None:
    tags = _hand_tags(["DECELERATING"] * 16, ["HIGH"] * 3 + ["NO"] * 12 + ["HIGH"], ["NO"] * 16)
    assert len(find_key_objects(tags)) == 2
    long_only = find_key_objects(tags, KeyIdentConfig(min_duration_s=0.2))
    assert [(e.start_ns, e.end_ns) for e in long_only] == [(0, 200_000_000)]


def test_no_braking_means_no_events() -> None:
    tags = _hand_tags(["CRUISING"] * 5, ["HIGH"] * 5, ["HIGH"] * 5)
    assert find_key_objects(tags) == []


def test_real_argoverse_log_yields_the_oncoming_car_the_ego_yields_to(av2_log_dir: Path) -> None:
    from scenariominer.data.adapters.av2 import read_av2_log

    tags = tag_log(preprocess(read_av2_log(av2_log_dir)))
    events = find_key_objects(tags)
    assert events, "the ego brakes to a stop before a left turn with oncoming traffic"
    oncoming = []
    for event in events:
        row = tags.track_index(event.track_id)
        cols = (tags.timestamps_ns >= event.start_ns) & (tags.timestamps_ns <= event.end_ns)
        assert set(tags.names("longitude")[0, cols]) <= {"DECELERATING", "STANDING_STILL"}
        assert event.peak_collision is not CollisionTag.NO or event.peak_traj_overlap is not TrajOverlapTag.NO
        if event.category == "REGULAR_VEHICLE" and set(tags.names("heading")[row, cols]) == {"OPPOSITE"}:
            oncoming.append(event)
    assert oncoming, f"no oncoming vehicle among the key objects: {events}"
