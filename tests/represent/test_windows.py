"""Window extraction on hand-built logs with known answers (agent frame, neighbours, padding, scales)."""

from __future__ import annotations

from pathlib import Path

import highd_files  # tests/data, on the test path (pyproject.toml)
import numpy as np
import pytest

from scenariominer.config import Config
from scenariominer.config.represent import WindowConfig
from scenariominer.data.adapters.highd import HighDReader
from scenariominer.represent.lanes import log_lane_ids
from scenariominer.represent.windows import ROAD_USER_CATEGORIES, extract_windows, window_id
from scenariominer.testing import LogBuilder, times


def _north_log(duration_s: float = 10.0, dt_s: float = 0.1) -> LogBuilder:
    """Ego heading north (yaw pi/2) at 10 m/s from (100, 50); a car 3.5 m to its left, one 20 m ahead."""
    t = times(duration_s, dt_s)
    return (
        LogBuilder(t, log_id="north")
        .ego(speed_mps=10.0, x0_m=100.0, y0_m=50.0, yaw0_rad=np.pi / 2)
        .add("lead", "REGULAR_VEHICLE", speed_mps=10.0, x0_m=100.0, y0_m=70.0, yaw0_rad=np.pi / 2)
        .add("left", "REGULAR_VEHICLE", speed_mps=10.0, x0_m=96.5, y0_m=50.0, yaw0_rad=np.pi / 2)
    )


def test_positions_are_in_the_agent_frame_at_the_window_start() -> None:
    log = _north_log().build()
    ws = extract_windows(log, WindowConfig(lengths_s=(4.0,), n_steps=5, k_neighbours=2))
    first = ws.select([0])
    assert first.window_ids[0] == window_id("north", "ego", 0.0, 4.0) == "north|ego|0|4000"
    np.testing.assert_allclose(first.xy_m[0, 0, :, 0], [0.0, 10.0, 20.0, 30.0, 40.0], atol=1e-3)
    np.testing.assert_allclose(first.xy_m[0, 0, :, 1], 0.0, atol=1e-3)
    # nearest first: the car on the left (3.5 m), then the lead car (20 m)
    assert first.track_ids[0].tolist() == ["ego", "left", "lead"]
    np.testing.assert_allclose(first.xy_m[0, 1, 0], [0.0, 3.5], atol=1e-3)
    np.testing.assert_allclose(first.xy_m[0, 2, -1], [60.0, 0.0], atol=1e-3)
    np.testing.assert_allclose(first.vxy_mps[0, :, 2], [[10.0, 0.0]] * 3, atol=1e-2)
    # a later window is expressed in the ego's frame at ITS start: the ego starts at the origin again
    second = ws.select([1])
    assert second.start_s[0] == pytest.approx(4.0)
    np.testing.assert_allclose(second.xy_m[0, 0, 0], [0.0, 0.0], atol=1e-6)
    assert second.start_ns[0] == log.timestamps_ns[0] + 4_000_000_000


def test_missing_neighbours_are_padded_and_masked() -> None:
    t = times(10.0)
    present = t < 2.0  # 'short' leaves after 2 s
    log = (
        _north_log()
        .add(
            "short",
            "REGULAR_VEHICLE",
            speed_mps=10.0,
            x0_m=100.0,
            y0_m=45.0,
            yaw0_rad=np.pi / 2,
            present=present,
        )
        .add("cone", "CONSTRUCTION_CONE", x0_m=100.0, y0_m=51.0)
        .add("far", "REGULAR_VEHICLE", speed_mps=10.0, x0_m=100.0, y0_m=500.0, yaw0_rad=np.pi / 2)
        .build()
    )
    ws = extract_windows(
        log, WindowConfig(lengths_s=(4.0,), n_steps=9, k_neighbours=5, neighbour_radius_m=100.0)
    )
    w0 = ws.select([0])
    # the cone is not a road user, 'far' is beyond the radius: two padded rows
    assert w0.track_ids[0].tolist() == ["ego", "left", "short", "lead", "", ""]
    assert not w0.valid[0, 4:].any()
    np.testing.assert_array_equal(w0.xy_m[0, 4:], 0.0)
    assert w0.categories[0, 4] == ""
    # 'short' is observed for the first 2 s of the window only (steps at 0, 0.5, ..., 4 s)
    assert w0.valid[0, 2].tolist() == [True] * 4 + [False] * 5
    np.testing.assert_array_equal(w0.xy_m[0, 2, 4:], 0.0)
    # in the next window (4-8 s) it is gone entirely
    assert "short" not in ws.select([1]).track_ids[0].tolist()


@pytest.mark.parametrize(
    ("lengths", "overlap", "expected_starts"),
    [
        ((4.0,), 0.0, {4.0: [0.0, 4.0]}),
        ((4.0,), 0.5, {4.0: [0.0, 2.0, 4.0, 6.0]}),
        ((2.0, 4.0, 8.0), 0.0, {2.0: [0.0, 2.0, 4.0, 6.0, 8.0], 4.0: [0.0, 4.0], 8.0: [0.0]}),
        ((15.0,), 0.0, {}),
    ],
)
def test_overlap_and_multiple_scales(
    lengths: tuple[float, ...], overlap: float, expected_starts: dict[float, list[float]]
) -> None:
    log = _north_log(10.0).build()
    ws = extract_windows(log, WindowConfig(lengths_s=lengths, overlap=overlap, n_steps=6, k_neighbours=1))
    got: dict[float, list[float]] = {}
    for length, start in zip(ws.length_s.tolist(), ws.start_s.tolist(), strict=True):
        got.setdefault(length, []).append(start)
    assert got == expected_starts
    assert ws.xy_m.shape == (len(ws), 2, 6, 2)
    assert len(set(ws.window_ids.tolist())) == len(ws)


def test_a_window_may_end_within_the_tolerance_after_the_last_timestamp() -> None:
    log = _north_log(9.96, 0.04).build()  # a 10 s highD cut at 25 Hz: last timestamp at 9.96 s
    assert len(extract_windows(log, WindowConfig(lengths_s=(10.0,), end_tolerance_s=0.1))) == 1
    assert len(extract_windows(log, WindowConfig(lengths_s=(10.0,), end_tolerance_s=0.0))) == 0


def test_every_vehicle_observed_over_a_window_is_a_chosen_agent() -> None:
    t = times(10.0)
    log = _north_log().add("late", "REGULAR_VEHICLE", x0_m=0.0, y0_m=0.0, present=t >= 5.0).build()
    ws = extract_windows(log, WindowConfig(lengths_s=(10.0,), agents="vehicles", k_neighbours=1))
    assert sorted(ws.agent_ids.tolist()) == ["ego", "lead", "left"]  # 'late' is not there the whole time
    lead = ws.select(np.flatnonzero(ws.agent_ids == "lead"))
    assert lead.track_ids[0].tolist() == ["lead", "ego"]  # ego 20 m behind, left about 20.3 m
    np.testing.assert_allclose(lead.xy_m[0, 1, 0], [-20.0, 0.0], atol=1e-3)


def test_lane_ids_must_match_the_log_shape() -> None:
    log = _north_log().build()
    with pytest.raises(ValueError, match="lane_ids must have shape"):
        extract_windows(log, WindowConfig(), np.zeros((1, 1), dtype=np.int64))


def test_highd_lane_ids_follow_a_lane_change(tmp_path: Path) -> None:
    highd_files.write_small_highway(tmp_path)
    cfg: Config = highd_files.highd_config(window_s=10.0)
    reader = HighDReader()
    logs = {log.log_id: log for log in reader.read(reader.discover(tmp_path)[0], cfg)}
    log = logs["highd-01-ego3-w0"]  # car 3 moves from lane 6 to lane 5 between 2 and 6 s
    lanes = log_lane_ids(log)
    assert lanes is not None
    ws = extract_windows(log, WindowConfig(lengths_s=(10.0,), n_steps=11, k_neighbours=2), lanes)
    ego_lanes = ws.lane_ids[0, 0].tolist()
    assert ego_lanes[0] == 6 and ego_lanes[-1] == 5
    assert set(ego_lanes) == {5, 6}
    # car 3 drives towards +x: the lane change to lane 5 is a move to the LEFT in its own frame
    assert ws.xy_m[0, 0, -1, 1] == pytest.approx(3.8, abs=0.05)


def test_a_log_without_lanes_gets_none() -> None:
    assert log_lane_ids(_north_log().build()) is None


def test_windows_of_the_real_av2_log(av2_log_dir: Path, tmp_path: Path) -> None:
    from scenariominer.api import ingest, open_store
    from scenariominer.config import load_config
    from scenariominer.represent.pipeline import build_store_windows
    from scenariominer.represent.window_table import load_windows

    store = open_store(tmp_path / "store")
    ingest([av2_log_dir], store, load_config())
    log = store.load_log(store.log_ids()[0])
    assert 15.0 < log.duration_s < 16.0
    config = WindowConfig(lengths_s=(5.0, 15.0), overlap=0.5)
    report = build_store_windows(store, config)
    assert report.logs[0].has_lanes
    ws = load_windows(store)
    assert sorted(zip(ws.length_s.tolist(), ws.start_s.tolist(), strict=True)) == [
        (5.0, 0.0),
        (5.0, 2.5),
        (5.0, 5.0),
        (5.0, 7.5),
        (5.0, 10.0),
        (15.0, 0.0),
    ]
    assert (ws.agent_ids == log.track_ids[0]).all()
    # the ego drives on mapped lanes: a lane segment id at every step of every window
    assert (ws.lane_ids[:, 0] > 0).all()
    # neighbours are nearest first: mean distance over the commonly observed steps grows with the row
    w = ws.select([int(np.argmax(ws.length_s))])
    d = np.linalg.norm(w.xy_m[0, 1:] - w.xy_m[0, :1], axis=-1)
    both = w.valid[0, 1:] & w.valid[0, :1]
    mean_d = (d * both).sum(axis=1) / np.maximum(both.sum(axis=1), 1)
    assert np.all(np.diff(mean_d[both.any(axis=1)]) >= -1e-3)
    assert set(w.categories[0, 1:].tolist()) <= set(ROAD_USER_CATEGORIES) | {""}
