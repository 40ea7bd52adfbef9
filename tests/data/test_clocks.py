"""Tracks on their own clocks: snapped onto one clock in bounded time and memory, or refused."""

from __future__ import annotations

import time
import tracemalloc

import numpy as np
import pytest

from scenariominer.data.clocks import align_track_clocks
from scenariominer.data.log import Log, LogFormatError, build_log
from scenariominer.data.preprocess import preprocess
from scenariominer.testing import LogBuilder, times

PERIOD_NS = 100_000_000
T0_NS = 1_700_000_000_000_000_000


def _clock_log(offset_ns: np.ndarray, n_frames: int = 100, **kwargs: object) -> Log:
    """Track ``i`` (``ego`` first) at 10 Hz, stamped ``offset_ns[i]`` after the common grid."""
    n = offset_ns.size
    k = np.arange(n_frames)
    ids = np.repeat(["ego", *(f"t{i}" for i in range(1, n))], n_frames)
    ts = (T0_NS + k[None, :] * PERIOD_NS + offset_ns[:, None]).ravel()
    x = (k[None, :] * 1.0 + 7.0 * np.arange(n)[:, None]).ravel()
    return build_log(
        log_id="clocks",
        track_id=ids,
        category=np.where(ids == "ego", "EGO_VEHICLE", "REGULAR_VEHICLE"),
        timestamp_ns=ts,
        fields={
            "x_m": x,
            "y_m": np.zeros(x.size),
            "yaw_rad": np.zeros(x.size),
            "length_m": np.full(x.size, 4.5),
            "width_m": np.full(x.size, 1.9),
        },
        ego_track_id="ego",
        source="clocks.parquet",
        **kwargs,  # type: ignore[arg-type]
    )


def test_tracks_1us_apart_are_snapped_to_one_clock_in_bounded_time_and_memory() -> None:
    tracemalloc.start()
    start = time.perf_counter()
    log = preprocess(_clock_log(np.arange(200) * 1000))
    elapsed = time.perf_counter() - start
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    assert log.n_timestamps == 100 and log.n_tracks == 200
    assert log.valid.all()
    np.testing.assert_array_equal(log.timestamps_ns, T0_NS + np.arange(100) * PERIOD_NS)  # the ego's clock
    np.testing.assert_allclose(log.vx_mps, 10.0, atol=1e-6)  # 1 m per 0.1 s: the frame period survived
    assert log.notes[0] == (
        "snapped 19900 timestamp(s) of 199 track(s) on their own clocks (shifts up to 199 µs) to one clock "
        "of 100 timestamps (frame period 100 ms)"
    )
    # Before: 20,000 timestamps 1 µs apart, 25 s and 10 GB; now a few MB and well under a second.
    assert elapsed < 5.0, f"{elapsed:.1f} s"
    assert peak < 100e6, f"peak {peak / 1e6:.0f} MB"


def test_rows_rounded_apart_by_float_seconds_are_snapped() -> None:
    jitter = np.random.default_rng(1).integers(-256, 256, 30)
    log = _clock_log(jitter, n_frames=20)
    assert log.n_timestamps == 20 and "snapped" in log.notes[0]


def test_tracks_sharing_timestamps_are_untouched() -> None:
    t = times(3.0)
    log = LogBuilder(t).ego(speed_mps=5.0).add("car", "BUS", speed_mps=3.0, x0_m=10.0).build()
    assert log.notes == () and log.n_timestamps == t.size


def test_two_clocks_half_a_frame_apart_are_kept_as_they_are() -> None:
    # A legitimate case (two sensors at 10 Hz, interleaved): 2x the timestamps, nothing to snap or refuse.
    log = _clock_log(np.array([0, PERIOD_NS // 2, 0, PERIOD_NS // 2]), n_frames=10)
    assert log.n_timestamps == 20 and log.notes == ()


def test_a_faster_ego_sets_the_period_and_is_not_refused() -> None:
    ego_t = np.arange(100) * 10_000_000  # 100 Hz ego
    car_t = np.arange(10) * PERIOD_NS + 3  # 10 Hz car, 3 ns off the ego's clock
    ts = np.concatenate([ego_t, car_t])
    start = np.zeros(ts.size, dtype=bool)
    start[[0, 100]] = True
    is_ego = np.arange(ts.size) < 100
    result = align_track_clocks(ts, start, is_ego)
    assert not result.problem
    np.testing.assert_array_equal(
        result.timestamps_ns[100:], np.arange(10) * PERIOD_NS
    )  # onto the ego's clock


def test_clocks_too_far_apart_to_snap_are_refused_with_the_sizes() -> None:
    offsets = np.random.default_rng(0).integers(0, PERIOD_NS, 50)
    offsets[0] = 0
    with pytest.raises(
        LogFormatError, match=r"clocks\.parquet: the tracks are on different clocks: \d+ distinct"
    ):
        _clock_log(offsets, n_frames=20)


def test_a_track_sampled_twice_within_the_snap_tolerance_is_not_snapped() -> None:
    ts = np.array([0, 100, 200, 0, 1, 100, 200]) * 1_000_000  # track 2 has rows 1 ms apart
    start = np.array([True, False, False, True, False, False, False])
    result = align_track_clocks(ts, start, start.cumsum() == 1)
    assert not result.note and np.array_equal(result.timestamps_ns, ts)


def test_a_grid_over_the_cell_limit_is_refused() -> None:
    with pytest.raises(LogFormatError, match=r"4 tracks x 100 timestamps = 400 cells, over the limit of 300"):
        _clock_log(np.zeros(4, dtype=np.int64), max_cells=300)


def test_nul_in_track_ids_is_replaced_so_storage_cannot_merge_them() -> None:
    fields = {k: [0.0, 1.0, 5.0, 6.0, 9.0, 9.5] for k in ("x_m", "y_m", "yaw_rad")}
    fields.update(length_m=[4.0] * 6, width_m=[2.0] * 6)
    common = {
        "log_id": "L",
        "category": ["EGO_VEHICLE"] * 2 + ["BUS"] * 4,
        "timestamp_ns": [0, 1, 0, 1, 0, 1],
        "fields": fields,
        "ego_track_id": "ego",
        "source": "nul.csv",
    }
    log = build_log(track_id=["ego", "ego", "a\x00x", "a\x00x", "a\x00y", "a\x00y"], **common)  # type: ignore[arg-type]
    assert log.track_ids.tolist() == ["ego", "a\ufffdx", "a\ufffdy"]
    assert log.to_arrow().column("track_id").unique().to_pylist() == ["ego", "a\ufffdx", "a\ufffdy"]
    assert "replaced NUL characters with U+FFFD in 2 track id(s)" in log.notes[0]
    with pytest.raises(LogFormatError, match="differ only by NUL"):
        build_log(track_id=["ego", "ego", "a\x00x", "a\x00x", "a\ufffdx", "a\ufffdx"], **common)  # type: ignore[arg-type]


def _slow_ego_rows(car_offsets_ns: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A 1 Hz ego over 10 s and one 10 Hz car per offset, rows sorted by (track, time)."""
    ego_t = np.arange(11) * 10 * PERIOD_NS
    cars = [np.arange(100) * PERIOD_NS + off for off in car_offsets_ns]
    ts = np.concatenate([ego_t, *cars])
    start = np.zeros(ts.size, dtype=bool)
    start[np.cumsum([0, ego_t.size, *(c.size for c in cars)])[:-1]] = True
    return ts, start, np.arange(ts.size) < ego_t.size


def test_a_slower_ego_does_not_hide_faster_tracks_on_their_own_clocks() -> None:
    # The shortcut for logs on one clock bounds the period by the ego's step (here 1 s, ten times the
    # cars'); it must still snap the cars' 1 µs offsets and refuse clocks too far apart.
    ts, start, is_ego = _slow_ego_rows(np.arange(1, 6) * 1000)
    snapped = align_track_clocks(ts, start, is_ego)
    assert "snapped" in snapped.note and "frame period 100 ms" in snapped.note
    assert np.unique(snapped.timestamps_ns).size == 101  # the cars' 100 frames and the ego's last at 10 s
    offsets = np.random.default_rng(3).integers(1, PERIOD_NS, 40)
    refused = align_track_clocks(*_slow_ego_rows(offsets))
    assert "different clocks" in refused.problem
