"""The canonical Log model: build_log validates, repairs what is safe, and names the cause otherwise."""

from __future__ import annotations

import numpy as np
import pyarrow as pa
import pytest

from scenariominer.data.log import Log, LogFormatError, build_log, time_derivative


def _rows(tracks: dict[str, tuple[str, np.ndarray, np.ndarray]], dt_s: float = 0.1) -> dict[str, np.ndarray]:
    """Long columns from {track_id: (category, frame_indices, x_positions)} (y = 0, yaw = 0)."""
    tid, cat, ts, x = [], [], [], []
    for name, (category, frames, xs) in tracks.items():
        tid += [name] * len(frames)
        cat += [category] * len(frames)
        ts += list((np.asarray(frames) * dt_s * 1e9).astype(np.int64))
        x += list(xs)
    xa = np.asarray(x, dtype=float)
    return {"track_id": np.asarray(tid), "category": np.asarray(cat), "ts": np.asarray(ts), "x": xa}


def _build(cols: dict[str, np.ndarray], **kwargs: object) -> Log:
    x = cols["x"]
    fields = {
        "x_m": x,
        "y_m": np.zeros_like(x),
        "yaw_rad": np.zeros_like(x),
        "length_m": np.full_like(x, 4.0),
        "width_m": np.full_like(x, 2.0),
    }
    return build_log(
        log_id="L",
        track_id=cols["track_id"],
        category=cols["category"],
        timestamp_ns=cols["ts"],
        fields=fields,
        ego_track_id=None,
        source="test.feather",
        **kwargs,
    )  # type: ignore[arg-type]


def test_dense_layout_puts_ego_first_and_marks_absent_cells() -> None:
    frames = np.arange(10)
    cols = _rows(
        {
            "car": ("REGULAR_VEHICLE", frames[2:6], np.arange(4) * 1.0),
            "me": ("EGO_VEHICLE", frames, frames * 2.0),
        }
    )
    log = _build(cols)
    assert log.track_ids.tolist() == ["me", "car"]
    assert log.valid.shape == (2, 10)
    assert log.valid[1].tolist() == [False, False, True, True, True, True, False, False, False, False]
    assert np.isnan(log.x_m[1, 0]) and log.x_m[1, 2] == 0.0
    # Velocity derived by finite differences: ego moves 2 m per 0.1 s.
    np.testing.assert_allclose(log.vx_mps[0], 20.0)
    assert log.duration_s == pytest.approx(0.9)
    assert log.n_frames == 14


def test_unsorted_rows_are_sorted_without_loss() -> None:
    frames = np.arange(5)
    cols = _rows({"me": ("EGO_VEHICLE", frames, frames * 1.0)})
    perm = np.array([3, 0, 4, 1, 2])
    shuffled = {k: v[perm] for k, v in cols.items()}
    log = _build(shuffled)
    np.testing.assert_allclose(log.x_m[0], [0, 1, 2, 3, 4])


def test_conflicting_duplicate_timestamps_are_an_error_naming_the_file_and_track() -> None:
    cols = _rows({"me": ("EGO_VEHICLE", np.array([0, 1, 1, 2]), np.array([0.0, 1.0, 1.5, 2.0]))})
    with pytest.raises(LogFormatError, match=r"test\.feather.*duplicate.*'me'"):
        _build(cols)


def test_exact_duplicates_are_collapsed_with_a_note() -> None:
    cols = _rows({"me": ("EGO_VEHICLE", np.array([0, 1, 1, 2]), np.array([0.0, 1.0, 1.0, 2.0]))})
    log = _build(cols)
    assert log.n_timestamps == 3
    assert any("duplicate" in n for n in log.notes)


def test_one_frame_tracks_are_dropped_with_a_note_but_a_one_frame_ego_is_an_error() -> None:
    frames = np.arange(4)
    cols = _rows({"me": ("EGO_VEHICLE", frames, frames * 1.0), "blip": ("PEDESTRIAN", frames[:1], [5.0])})
    log = _build(cols)
    assert log.track_ids.tolist() == ["me"]
    assert any("fewer than 2 frames" in n and "blip" in n for n in log.notes)
    with pytest.raises(LogFormatError, match="ego track has only 1 frame"):
        _build(_rows({"me": ("EGO_VEHICLE", frames[:1], [0.0])}))


def test_nan_positions_are_dropped_and_counted() -> None:
    frames = np.arange(5)
    cols = _rows(
        {
            "me": ("EGO_VEHICLE", frames, frames * 1.0),
            "p": ("PEDESTRIAN", frames, np.array([0.0, 1.0, np.nan, 3.0, 4.0])),
        }
    )
    log = _build(cols)
    assert log.valid[1].tolist() == [True, True, False, True, True]
    assert any("NaN" in n for n in log.notes)


def test_unknown_category_names_value_and_file() -> None:
    frames = np.arange(3)
    cols = _rows({"me": ("EGO_VEHICLE", frames, frames * 1.0), "x": ("SPACESHIP", frames, frames * 1.0)})
    with pytest.raises(LogFormatError, match=r"test\.feather.*'SPACESHIP'"):
        _build(cols)


def test_aliases_map_other_datasets_onto_av2_names() -> None:
    frames = np.arange(3)
    cols = _rows({"me": ("EGO_VEHICLE", frames, frames * 1.0), "t": ("Truck", frames, frames * 1.0)})
    assert _build(cols).categories.tolist() == ["EGO_VEHICLE", "TRUCK"]


def test_missing_ego_and_missing_columns_are_errors() -> None:
    frames = np.arange(3)
    cols = _rows({"car": ("REGULAR_VEHICLE", frames, frames * 1.0)})
    with pytest.raises(LogFormatError, match="no ego track"):
        _build(cols)
    with pytest.raises(LogFormatError, match=r"missing required column\(s\) \['width_m'\]"):
        build_log(
            log_id="L",
            track_id=["a"],
            category=["EGO_VEHICLE"],
            timestamp_ns=[0],
            fields={"x_m": [0.0], "y_m": [0.0], "yaw_rad": [0.0], "length_m": [1.0]},
            ego_track_id=None,
            source="f.csv",
        )


def test_nan_timestamps_are_an_error() -> None:
    with pytest.raises(LogFormatError, match="NaN timestamp"):
        build_log(
            log_id="L",
            track_id=["a", "a"],
            category=["EGO_VEHICLE"] * 2,
            timestamp_ns=np.array([0.0, np.nan]),  # type: ignore[arg-type]
            fields={k: [0.0, 1.0] for k in ("x_m", "y_m", "yaw_rad", "length_m", "width_m")},
            ego_track_id=None,
            source="f.csv",
        )


def test_arrow_round_trip_is_lossless() -> None:
    frames = np.arange(6)
    cols = _rows(
        {"me": ("EGO_VEHICLE", frames, frames * 1.5), "p": ("PEDESTRIAN", frames[1:5], [3.0, 3.1, 3.3, 3.4])}
    )
    log = _build(cols)
    back = Log.from_arrow(log.to_arrow(), log_id="L")
    assert back.track_ids.tolist() == log.track_ids.tolist()
    np.testing.assert_array_equal(back.valid, log.valid)
    np.testing.assert_allclose(back.vx_mps, log.vx_mps)
    np.testing.assert_allclose(back.x_m, log.x_m)


def test_slice_time_drops_tracks_absent_from_the_window() -> None:
    frames = np.arange(10)
    cols = _rows(
        {"me": ("EGO_VEHICLE", frames, frames * 1.0), "p": ("PEDESTRIAN", frames[:3], [0.0, 0.1, 0.2])}
    )
    part = _build(cols).slice_time(5, 10, log_id="L-w1")
    assert part.track_ids.tolist() == ["me"]
    assert part.n_timestamps == 5 and part.log_id == "L-w1"


def test_time_derivative_is_nan_aware_and_one_sided_at_span_ends() -> None:
    t_s = np.arange(5) * 0.5
    v = np.array([[np.nan, 0.0, 1.0, 2.0, np.nan]])
    d = time_derivative(v, t_s)
    assert np.isnan(d[0, 0]) and np.isnan(d[0, 4])
    np.testing.assert_allclose(d[0, 1:4], 2.0)


def _rows_with(**overrides: list[float]) -> dict[str, list[float]]:
    fields = {"x_m": [0.0, 1.0, 2.0, 3.0], "y_m": [0.0] * 4, "yaw_rad": [0.0] * 4, "length_m": [4.0] * 4,
              "width_m": [2.0] * 4}  # fmt: skip
    fields.update(overrides)
    return fields


@pytest.mark.parametrize(
    ("overrides", "note"),
    [
        ({"x_m": [0.0, 1.0, 1e300, 3.0]}, "dropped 1 row(s) with a coordinate beyond 1e+07 m"),
        ({"y_m": [0.0, -2e7, 0.0, 0.0]}, "dropped 1 row(s) with a coordinate beyond 1e+07 m"),
    ],
)
def test_implausible_rows_are_dropped_with_a_stated_repair(
    overrides: dict[str, list[float]], note: str
) -> None:
    log = build_log(
        log_id="L",
        track_id=["ego"] * 4,
        category=["EGO_VEHICLE"] * 4,
        timestamp_ns=[0, 100_000_000, 200_000_000, 300_000_000],
        fields=_rows_with(**overrides),
        ego_track_id="ego",
        source="bad.csv",
    )
    assert any(note in n for n in log.notes), log.notes
    assert log.n_frames == 3 and np.all(np.abs(log.x_m[log.valid]) < 1e7)


def test_wrapped_unsigned_timestamps_are_an_error() -> None:
    ts = np.array([0, 100, 2**64 - 100], dtype=np.uint64)  # the last one wrapped below zero
    with pytest.raises(LogFormatError, match="outside the int64 range"):
        build_log(
            log_id="L",
            track_id=["ego"] * 3,
            category=["EGO_VEHICLE"] * 3,
            timestamp_ns=ts,
            fields={k: v[:3] for k, v in _rows_with().items()},
            ego_track_id="ego",
            source="bad.csv",
        )


def test_zero_or_negative_sizes_are_repaired_with_a_note() -> None:
    log = build_log(
        log_id="L",
        track_id=["ego"] * 4,
        category=["EGO_VEHICLE"] * 4,
        timestamp_ns=[0, 100_000_000, 200_000_000, 300_000_000],
        fields=_rows_with(length_m=[4.0, 0.0, 4.0, 4.0], width_m=[2.0, 2.0, -2.0, 2.0]),
        ego_track_id="ego",
        source="bad.csv",
    )
    assert "set length_m of 1 row(s) from zero or negative to 0.1 m" in log.notes
    assert "set width_m of 1 row(s) from zero or negative to 0.1 m" in log.notes
    assert log.n_frames == 4 and log.length_m[0, 1] == 0.1 and log.width_m[0, 2] == 0.1


def test_an_ego_given_by_id_among_short_category_names_keeps_its_full_category() -> None:
    # every row "TRUCK" (5 characters): the ego's category must not be cut to "EGO_V"
    cols = _rows(
        {"7": ("TRUCK", np.arange(5), np.arange(5.0)), "8": ("TRUCK", np.arange(5), np.arange(5.0) + 20)}
    )
    x = cols["x"]
    log = build_log(
        log_id="L",
        track_id=cols["track_id"],
        category=cols["category"],
        timestamp_ns=cols["ts"],
        fields={
            "x_m": x,
            "y_m": np.zeros_like(x),
            "yaw_rad": np.zeros_like(x),
            "length_m": np.full_like(x, 12.0),
            "width_m": np.full_like(x, 2.5),
        },
        ego_track_id="7",
        source="test.csv",
    )
    assert log.categories.tolist() == ["EGO_VEHICLE", "TRUCK"]


def test_arrow_text_columns_build_the_same_log_as_python_strings() -> None:
    # The AV2 adapter and the store hand Arrow columns to build_log (codes instead of strings per row);
    # a dictionary column may repeat a text or hold texts no row uses.
    ids = ["ego", "b\x00x", "a", "ego", "b\x00x", "a"]
    cats = ["EGO_VEHICLE", "BUS", "PEDESTRIAN"] * 2
    fields = {"x_m": [0.0, 5.0, 9.0, 1.0, 6.0, 9.5], "y_m": [0.0] * 6, "yaw_rad": [0.0] * 6}
    fields.update(length_m=[4.0] * 6, width_m=[2.0] * 6)
    common = {"log_id": "L", "timestamp_ns": [0, 0, 0, 1, 1, 1], "fields": fields, "source": "t"}
    plain = build_log(track_id=ids, category=cats, ego_track_id=None, **common)  # type: ignore[arg-type]
    dictionary = pa.DictionaryArray.from_arrays(
        pa.array([0, 1, 2, 3, 1, 2], type=pa.int32()), pa.array(["ego", "b\x00x", "a", "ego", "unused"])
    )
    arrow = build_log(
        track_id=dictionary, category=pa.chunked_array([cats[:2], cats[2:]]), ego_track_id="ego", **common
    )  # type: ignore[arg-type]
    assert plain.track_ids.tolist() == arrow.track_ids.tolist() == ["ego", "a", "b\ufffdx"]
    assert plain.categories.tolist() == arrow.categories.tolist() == ["EGO_VEHICLE", "PEDESTRIAN", "BUS"]
    np.testing.assert_array_equal(plain.x_m, arrow.x_m)
    assert plain.notes == arrow.notes and "U+FFFD" in arrow.notes[0]
    with pytest.raises(LogFormatError, match="ego track 'unused' does not occur"):
        build_log(track_id=dictionary, category=cats, ego_track_id="unused", **common)  # type: ignore[arg-type]
