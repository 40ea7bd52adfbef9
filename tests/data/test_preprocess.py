"""Preprocessing keeps short, sharp events while removing jitter (braking paper, section III-A)."""

from __future__ import annotations

import numpy as np
import pytest

from scenariominer.config import PreprocessConfig
from scenariominer.data.log import Log, build_log
from scenariominer.data.preprocess import interpolate_gaps, preprocess, window_samples

DT_S = 0.1


def _ego_log(x: np.ndarray, y: np.ndarray | None = None, keep: np.ndarray | None = None) -> Log:
    """A log whose ego follows ``x``; with ``keep``, the ego is complete and a pedestrian
    follows the same ``x`` only where ``keep`` is True (row 1 then has the gaps)."""
    n = x.size
    frames = np.arange(n)
    y = np.zeros(n) if y is None else y
    tracks = [("ego", "EGO_VEHICLE", np.ones(n, dtype=bool))]
    if keep is not None:
        tracks.append(("ped", "PEDESTRIAN", keep))
    tid, cat, ts, xs, ys = [], [], [], [], []
    for name, category, mask in tracks:
        k = int(mask.sum())
        tid += [name] * k
        cat += [category] * k
        ts.append(frames[mask])
        xs.append(x[mask])
        ys.append(y[mask])
    xa, ya, fr = np.concatenate(xs), np.concatenate(ys), np.concatenate(ts)
    fields = {
        "x_m": xa,
        "y_m": ya,
        "yaw_rad": np.zeros_like(xa),
        "length_m": np.full_like(xa, 4.0),
        "width_m": np.full_like(xa, 2.0),
    }
    return build_log(
        log_id="L",
        track_id=tid,
        category=cat,
        timestamp_ns=(fr * DT_S * 1e9).astype(np.int64),
        fields=fields,
        ego_track_id="ego",
        source="<test>",
    )


def test_a_hard_braking_step_survives_smoothing() -> None:
    # 10 m/s for 5 s, then an abrupt drop to 2 m/s (a step in speed), jitter of 0.08 m on top.
    t = np.arange(100) * DT_S
    speed = np.where(t < 5.0, 10.0, 2.0)
    x_true = np.concatenate([[0.0], np.cumsum(speed[:-1] * DT_S)])
    rng = np.random.default_rng(0)
    log = preprocess(_ego_log(x_true + rng.normal(0, 0.08, t.size)))
    v = log.vx_mps[0]
    # Half a second either side of the step the two speed levels are intact ...
    assert np.all(np.abs(v[(t > 1.0) & (t < 4.4)] - 10.0) < 1.0)
    assert np.all(np.abs(v[(t > 5.6) & (t < 9.0)] - 2.0) < 1.0)
    # ... and the transition stays sharp: from >9 m/s to <3 m/s within 1 s.
    above = t[v > 9.0]
    below = t[v < 3.0]
    assert below.min() - above[above < 5.0].max() < 1.0
    # The deceleration peak is strong (a spline would flatten it to about -1 m/s^2).
    assert log.ax_mps2[0].min() < -6.0


def test_smoothing_reduces_jitter_in_derived_speed() -> None:
    t = np.arange(150) * DT_S
    rng = np.random.default_rng(1)
    x = 8.0 * t + rng.normal(0, 0.1, t.size)
    raw = _ego_log(x)
    smooth = preprocess(raw)
    raw_err = np.std(raw.vx_mps[0, 10:-10] - 8.0)
    smooth_err = np.std(smooth.vx_mps[0, 10:-10] - 8.0)
    assert smooth_err < raw_err / 3


def test_gaps_inside_the_lifespan_are_interpolated_linearly() -> None:
    x = np.arange(20) * 1.0
    keep = np.ones(20, dtype=bool)
    keep[[5, 6, 7]] = False
    log = _ego_log(x, keep=keep)
    filled, n = interpolate_gaps(log, max_gap_s=2.0)
    assert n == 3
    np.testing.assert_allclose(filled.x_m[1, 5:8], [5.0, 6.0, 7.0])
    assert filled.valid[1].all()


def test_gaps_longer_than_max_gap_stay_empty() -> None:
    x = np.arange(60) * 1.0
    keep = np.ones(60, dtype=bool)
    keep[10:40] = False  # 3 s gap
    filled, n = interpolate_gaps(_ego_log(x, keep=keep), max_gap_s=2.0)
    assert n == 0 and not filled.valid[1, 10:40].any()


def test_heading_is_interpolated_along_the_short_arc() -> None:
    keep = np.array([True, True, False, True, True])
    log = _ego_log(np.arange(5) * 1.0, keep=keep)
    yaw = log.yaw_rad.copy()
    yaw[1] = [3.0, 3.1, np.nan, -3.1, -3.0]  # crosses +-pi
    filled, _ = interpolate_gaps(log.replace(yaw_rad=yaw), 2.0)
    assert abs(abs(filled.yaw_rad[1, 2]) - np.pi) < 0.01


def test_window_adapts_to_frame_rate_and_short_tracks() -> None:
    assert window_samples(1.0, 0.1, 100, 3) == 11
    assert window_samples(1.0, 0.04, 400, 3) == 25
    assert window_samples(1.0, 0.1, 6, 3) == 5
    assert window_samples(1.0, 0.1, 3, 3) == 0


def test_short_tracks_keep_finite_kinematics() -> None:
    log = preprocess(_ego_log(np.array([0.0, 1.0, 2.0])))
    assert np.all(np.isfinite(log.vx_mps[0])) and log.vx_mps[0, 1] == pytest.approx(10.0)


def test_preprocess_config_is_respected() -> None:
    t = np.arange(100) * DT_S
    x = np.concatenate([[0.0], np.cumsum(np.where(t < 5, 10.0, 2.0)[:-1] * DT_S)])
    wide = preprocess(_ego_log(x), PreprocessConfig(smooth_window_s=3.0))
    narrow = preprocess(_ego_log(x), PreprocessConfig(smooth_window_s=0.5))
    assert wide.ax_mps2[0].min() > narrow.ax_mps2[0].min()


@pytest.mark.parametrize("length", [5, 6, 11, 12, 37, 150])
@pytest.mark.parametrize(("window", "order"), [(5, 2), (5, 3), (11, 3), (11, 4)])
@pytest.mark.parametrize("deriv", [0, 1, 2])
def test_vectorised_savitzky_golay_matches_scipy(length: int, window: int, order: int, deriv: int) -> None:
    from scipy.signal import savgol_filter

    from scenariominer.data.preprocess import savgol_rows

    if window > length:
        pytest.skip("window longer than the span")
    rng = np.random.default_rng(length * 100 + window * 10 + deriv)
    block = np.cumsum(rng.normal(size=(4, length)), axis=1)
    expected = savgol_filter(block, window, order, deriv=deriv, delta=0.1, axis=1, mode="interp")
    np.testing.assert_allclose(savgol_rows(block, window, order, deriv, 0.1), expected, rtol=1e-9, atol=1e-7)
