"""The shipped builders and fakes, and the Log contract checked on random logs (hypothesis)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from scenariominer.data.log import STATE_FIELDS, Log
from scenariominer.testing import FakeClock, LogBuilder, braking_speed, integrate, times


def test_integrate_follows_closed_form_motion() -> None:
    t = times(4.0)
    x, y, yaw = integrate(t, 10.0)
    np.testing.assert_allclose(x, 10.0 * t, atol=1e-9)
    np.testing.assert_allclose(y, 0.0, atol=1e-12)
    # a quarter circle of radius 10 m at 5 m/s takes pi seconds
    t = np.linspace(0.0, math.pi, 101)
    x, y, yaw = integrate(t, 5.0, 0.5)
    assert (x[-1], y[-1]) == (pytest.approx(10.0, abs=1e-4), pytest.approx(10.0, abs=1e-4))
    assert yaw[-1] == pytest.approx(math.pi / 2, abs=1e-9)


def test_braking_speed_stops_and_stays_stopped() -> None:
    v = braking_speed(times(6.0), 10.0, brake_at_s=2.0, decel_mps2=5.0)
    assert v[0] == 10.0 and v[20] == 10.0 and v[30] == pytest.approx(5.0) and v[-1] == 0.0


def test_log_builder_puts_the_ego_first_and_keeps_missing_frames() -> None:
    t = times(3.0)
    present = np.ones(t.size, bool)
    present[5:8] = False
    log = (
        LogBuilder(t, log_id="L")
        .ego(speed_mps=8.0)
        .add("ped", "PEDESTRIAN", speed_mps=1.4, x0_m=20.0, y0_m=-4.0, yaw0_rad=math.pi / 2, present=present)
        .build()
    )
    assert log.log_id == "L" and log.track_ids.tolist() == ["ego", "ped"]
    assert log.categories[0] == "EGO_VEHICLE" and log.valid[0].all()
    assert log.valid[1].sum() == t.size - 3 and np.isnan(log.x_m[1, 6])
    assert log.y_m[1, -1] == pytest.approx(-4.0 + 1.4 * 3.0, abs=1e-6)
    with pytest.raises(ValueError, match="first"):
        LogBuilder(t).add("car", "REGULAR_VEHICLE").ego()
    with pytest.raises(ValueError, match="ego first"):
        LogBuilder(t).add("car", "REGULAR_VEHICLE").build()


def test_fake_clock_records_waits_without_waiting() -> None:
    clock = FakeClock(100.0)
    clock.sleep(0.5)
    clock.advance(2.0)
    clock.sleep(1.0)
    assert clock.sleeps == [0.5, 1.0] and clock.time() == 103.5
    with pytest.raises(ValueError):
        clock.sleep(-1.0)


track = st.fixed_dictionaries(
    {
        "speed": st.floats(0.0, 30.0),
        "rate": st.floats(-0.5, 0.5),
        "x0": st.floats(-100.0, 100.0),
        "y0": st.floats(-100.0, 100.0),
        "yaw0": st.floats(-10.0, 10.0),
        "first": st.integers(0, 10),
        "length": st.integers(2, 30),
    }
)


@given(st.lists(track, min_size=0, max_size=5), st.integers(0, 6))
@settings(max_examples=60, deadline=None)
def test_built_logs_keep_the_log_contract(others: list[dict[str, float]], n_ego_rest: int) -> None:
    t = times(3.0)
    b = LogBuilder(t).ego(speed_mps=5.0)
    for i, o in enumerate(others):
        present = np.zeros(t.size, bool)
        present[int(o["first"]) : int(o["first"]) + int(o["length"])] = True
        b.add(
            f"t{i}", "REGULAR_VEHICLE", speed_mps=o["speed"], yaw_rate_radps=o["rate"],
            x0_m=o["x0"], y0_m=o["y0"], yaw0_rad=o["yaw0"], present=present,
        )  # fmt: skip
    log: Log = b.build()
    n, t_n = log.n_tracks, log.n_timestamps
    assert log.ego_index == 0 and log.categories[0] == "EGO_VEHICLE"
    assert log.timestamps_ns.dtype == np.int64 and np.all(np.diff(log.timestamps_ns) > 0)
    assert len(set(log.track_ids.tolist())) == n
    assert log.valid.shape == (n, t_n)
    for name in STATE_FIELDS:
        arr = getattr(log, name)
        assert arr.shape == (n, t_n)
        assert np.isnan(arr[~log.valid]).all()
    assert np.isfinite(log.x_m[log.valid]).all()
    yaw = log.yaw_rad[log.valid]
    assert ((yaw >= -math.pi) & (yaw < math.pi)).all()
    assert log.valid.any(axis=1).all()  # no track without an observation
