"""highD adapter: the published three-file format becomes ego-centred windowed logs, right-handed."""

from __future__ import annotations

import csv
import time
from pathlib import Path

import numpy as np
import pytest
from highd_files import (
    FRAME_RATE_HZ,
    LANE_CENTRE_IMAGE_Y_M,
    LANE_CHANGE_DURATION_S,
    edit_csv,
    highd_config,
    lane_change_y,
    position,
    write_small_highway,
)

from scenariominer.config import Config
from scenariominer.data.adapters.highd import (
    RECORDING_META_COLUMNS,
    TRACKS_COLUMNS,
    TRACKS_META_COLUMNS,
    HighDFiles,
    HighDReader,
    HighDVehicle,
    plan_windows,
    read_highd_recording,
    write_highd_recording,
)
from scenariominer.data.log import Log, LogFormatError
from scenariominer.data.sources import LogReader

# Two-decimal CSV values: positions are exact to half a centimetre.
TOL_M = 0.006


def _rows(path: Path) -> list[dict[str, str]]:
    with path.open(newline="") as fh:
        return list(csv.DictReader(fh))


def _row(path: Path, vehicle_id: int, frame: int) -> dict[str, str]:
    hits = [r for r in _rows(path) if r["id"] == str(vehicle_id) and r["frame"] == str(frame)]
    assert len(hits) == 1
    return hits[0]


def _logs(files: HighDFiles, config: Config | None = None, **reader: object) -> dict[str, Log]:
    r = HighDReader(**reader)  # type: ignore[arg-type]
    (source,) = r.discover(files.tracks)
    return {log.log_id: log for log in r.read(source, config or highd_config())}


@pytest.fixture(scope="module")
def highway(tmp_path_factory: pytest.TempPathFactory) -> HighDFiles:
    return write_small_highway(tmp_path_factory.mktemp("highd"))


@pytest.fixture(scope="module")
def highway_logs(highway: HighDFiles) -> dict[str, Log]:
    return _logs(highway)


# --------------------------------------------------------------------------------------- writer


def test_writer_uses_the_published_columns_and_the_upper_left_box_corner(highway: HighDFiles) -> None:
    for path, columns in (
        (highway.tracks, TRACKS_COLUMNS),
        (highway.tracks_meta, TRACKS_META_COLUMNS),
        (highway.recording_meta, RECORDING_META_COLUMNS),
    ):
        assert path.read_text().splitlines()[0] == ",".join(columns)
    assert [p.name for p in highway.all] == ["01_tracks.csv", "01_tracksMeta.csv", "01_recordingMeta.csv"]
    # Car 1 at frame 1: centre (10, -22.9), 4.5 x 1.9 -> corner (7.75, 22.9 - 0.95) in image coordinates.
    row = _row(highway.tracks, 1, 1)
    assert (row["x"], row["y"], row["width"], row["height"]) == ("7.75", "21.95", "4.50", "1.90")
    assert (row["xVelocity"], row["yVelocity"], row["laneId"]) == ("30.00", "0.00", "5")
    # Car 4 drives towards -x on the upper carriageway.
    assert _row(highway.tracks, 4, 1)["xVelocity"] == "-25.00"
    assert _row(highway.tracks, 4, 1)["laneId"] == "2"


def test_writer_meta_files_describe_classes_directions_and_the_lane_change(highway: HighDFiles) -> None:
    meta = {r["id"]: r for r in _rows(highway.tracks_meta)}
    assert {k: (m["class"], m["drivingDirection"]) for k, m in meta.items()} == {
        "1": ("Car", "2"),
        "2": ("Truck", "2"),
        "3": ("Car", "2"),
        "4": ("Car", "1"),
        "5": ("Car", "2"),
    }
    assert [meta[k]["numLaneChanges"] for k in "12345"] == ["0", "0", "1", "0", "0"]
    assert (meta["3"]["initialFrame"], meta["3"]["finalFrame"], meta["3"]["numFrames"]) == (
        "51",
        "350",
        "300",
    )
    assert (meta["2"]["width"], meta["2"]["height"]) == ("12.00", "2.50")
    # Car 1 never has a vehicle ahead in its lane: minimum headways are -1.
    assert (meta["1"]["minDHW"], meta["1"]["minTTC"]) == ("-1.00", "-1.00")
    (rec,) = _rows(highway.recording_meta)
    assert (rec["frameRate"], rec["numVehicles"], rec["numCars"], rec["numTrucks"]) == ("25", "5", "4", "1")
    assert rec["upperLaneMarkings"] == "8.00;11.80;15.60"
    assert rec["lowerLaneMarkings"] == "21.00;24.80;28.60"
    assert rec["speedLimit"] == "33.33"


def test_writer_lane_ids_follow_the_lane_change(highway: HighDFiles) -> None:
    lanes = {int(r["frame"]): r["laneId"] for r in _rows(highway.tracks) if r["id"] == "3"}
    # Car 3 crosses the marking at image-y 24.8 half-way through its 4 s manoeuvre (frame 151).
    assert lanes[150] == "6" and lanes[151] == "6"
    assert lanes[152] == "5" and lanes[350] == "5"


def test_writer_fills_surrounding_vehicles_and_headways(highway: HighDFiles) -> None:
    # Frame 51: car 3 at x 0 (lane 6) behind the truck at x 94 (lane 6); car 1 at x 70 in lane 5 (its left).
    car3 = _row(highway.tracks, 3, 51)
    assert (car3["precedingId"], car3["followingId"], car3["leftPrecedingId"]) == ("2", "0", "1")
    assert car3["dhw"] == "85.75"  # (94 - 6) - (0 + 2.25)
    assert car3["thw"] == "3.06"  # 85.75 / 28
    assert car3["ttc"] == "14.29"  # 85.75 / (28 - 22)
    assert car3["precedingXVelocity"] == "22.00"
    assert _row(highway.tracks, 2, 51)["followingId"] == "3"
    # Frame 126: car 1 and the truck are side by side (both centres at x 160).
    car1 = _row(highway.tracks, 1, 126)
    assert (car1["rightAlongsideId"], car1["rightPrecedingId"], car1["rightFollowingId"]) == ("2", "0", "3")
    assert _row(highway.tracks, 2, 126)["leftAlongsideId"] == "1"


def test_writer_rejects_bad_vehicles(tmp_path: Path) -> None:
    car = HighDVehicle(1, "Car", 1, np.arange(3.0), np.full(3, -20.0), 4.0, 1.8)
    marks = {"upper_lane_markings_m": (8.0, 12.0), "lower_lane_markings_m": (18.0, 22.0)}
    with pytest.raises(ValueError, match="class must be 'Car' or 'Truck'"):
        write_highd_recording(
            tmp_path, 1, [HighDVehicle(1, "Bus", 1, np.arange(3.0), np.zeros(3), 4, 2)], **marks
        )
    with pytest.raises(ValueError, match="unique"):
        write_highd_recording(tmp_path, 1, [car, car], **marks)


# --------------------------------------------------------------------------------------- reader


def test_reader_satisfies_the_protocol() -> None:
    assert isinstance(HighDReader(), LogReader)
    assert HighDReader.format == "highd"


def test_reader_converts_a_literal_highd_row_to_the_box_centre_in_a_right_handed_frame(
    tmp_path: Path,
) -> None:
    # Two frames of a car as published (upper-left corner, y down), plus one truck driving left.
    header = ",".join(TRACKS_COLUMNS)
    tail = ",40.00,5.00,0.00,0.00,0.00,0.00,0,0,0,0,0,0,0,0"
    (tmp_path / "07_tracks.csv").write_text(
        f"{header}\n"
        f"1,1,362.26,21.68,4.85,2.12,40.85,-0.40,0.30,0.10{tail},6\n"
        f"2,1,363.89,21.70,4.85,2.12,40.86,-0.40,0.30,0.10{tail},6\n"
        f"1,2,100.00,10.00,16.00,2.50,-20.00,0.00,0.00,0.00{tail},2\n"
        f"2,2,99.20,10.00,16.00,2.50,-20.00,0.00,0.00,0.00{tail},2\n"
    )
    (tmp_path / "07_tracksMeta.csv").write_text(
        ",".join(TRACKS_META_COLUMNS) + "\n"
        "1,4.85,2.12,1,2,2,Car,2,1.63,40.85,40.86,40.85,-1,-1,-1,0\n"
        "2,16.00,2.50,1,2,2,Truck,1,0.80,20.00,20.00,20.00,-1,-1,-1,0\n"
    )
    (tmp_path / "07_recordingMeta.csv").write_text(
        ",".join(RECORDING_META_COLUMNS) + "\n"
        "7,25,2,-1.00,09.2017,Tue,08:38,901.56,418549.19,13908.12,2,1,1,8.51;12.59;16.43,21.00;24.96;28.80\n"
    )
    files = HighDFiles.from_path(tmp_path / "07_tracks.csv")
    assert files is not None
    rec = read_highd_recording(files)
    assert rec.meta.speed_limit_mps is None
    assert rec.meta.upper_lane_markings_m == (8.51, 12.59, 16.43)
    car = rec.vehicle_rows(1)
    np.testing.assert_allclose(rec.x_m[car], [362.26 + 2.425, 363.89 + 2.425])
    np.testing.assert_allclose(rec.y_m[car], [-(21.68 + 1.06), -(21.70 + 1.06)])
    np.testing.assert_allclose(rec.length_m[car], 4.85)
    np.testing.assert_allclose(rec.width_m[car], 2.12)
    # yVelocity -0.40 (moving up the image) is +0.40 in the y-up frame: a left-ward drift.
    np.testing.assert_allclose(rec.vy_mps[car], 0.40)
    np.testing.assert_allclose(rec.ay_mps2[car], -0.10)
    np.testing.assert_allclose(rec.yaw_rad[car], np.arctan2(0.40, [40.85, 40.86]))
    truck = rec.vehicle_rows(2)
    np.testing.assert_allclose(rec.yaw_rad[truck], np.pi)
    assert rec.vehicle_categories.tolist() == ["REGULAR_VEHICLE", "TRUCK"]
    assert rec.t_ns[car].tolist() == [40_000_000, 80_000_000]


def test_read_after_write_recovers_positions_sizes_velocities_and_categories(
    highway_logs: dict[str, Log],
) -> None:
    log = highway_logs["highd-01-ego1-w0"]
    assert log.dataset == "highd"
    assert log.track_ids.tolist() == ["1", "2", "3"]  # car 4 is more than 150 m away all window
    assert log.categories.tolist() == ["EGO_VEHICLE", "TRUCK", "REGULAR_VEHICLE"]
    assert log.n_timestamps == 100  # 4 s at 25 Hz
    assert log.timestamps_ns[0] == 40_000_000 and np.all(np.diff(log.timestamps_ns) == 40_000_000)
    frames = np.arange(1, 101)
    for row, vid in enumerate((1, 2)):
        x, y = position(vid, frames)
        np.testing.assert_allclose(log.x_m[row], x, atol=TOL_M)
        np.testing.assert_allclose(log.y_m[row], y, atol=TOL_M)
    np.testing.assert_allclose(log.vx_mps[0], 30.0)
    np.testing.assert_allclose(log.vx_mps[1], 22.0)
    np.testing.assert_allclose(log.vy_mps[:2], 0.0)
    np.testing.assert_allclose(log.yaw_rad[:2], 0.0)
    np.testing.assert_allclose(log.length_m[:2, 0], [4.5, 12.0])
    np.testing.assert_allclose(log.width_m[:2, 0], [1.9, 2.5])
    np.testing.assert_allclose(log.height_m[:2, 0], [1.6, 3.8])
    # Car 3 appears at frame 51 (row 50 of the window).
    assert not log.valid[2, :50].any() and log.valid[2, 50:].all()


def test_vehicles_driving_left_have_yaw_minus_pi(highway_logs: dict[str, Log]) -> None:
    log = highway_logs["highd-01-ego4-w0"]
    assert log.track_ids[0] == "4"
    np.testing.assert_allclose(log.yaw_rad[0], -np.pi)  # headings are wrapped to [-pi, pi)
    np.testing.assert_allclose(log.vx_mps[0], -25.0)
    np.testing.assert_allclose(log.y_m[0], -LANE_CENTRE_IMAGE_Y_M[2], atol=TOL_M)


def test_lane_change_heading_follows_the_velocity(highway_logs: dict[str, Log]) -> None:
    log = highway_logs["highd-01-ego3-w0"]  # frames 51..150: the manoeuvre's first half
    t_local = np.arange(100) / FRAME_RATE_HZ
    _, vy = lane_change_y(t_local)
    np.testing.assert_allclose(log.vy_mps[0], vy, atol=0.006)
    np.testing.assert_allclose(log.yaw_rad[0], np.arctan2(vy, 28.0), atol=3e-4)
    # Peak lateral speed of the half-cosine: 3.8 m * pi / (2 * 4 s), a left turn (yaw > 0).
    peak = 3.8 * np.pi / (2 * LANE_CHANGE_DURATION_S)
    assert log.vy_mps[0].max() == pytest.approx(peak, abs=0.006)


def test_windows_cover_each_vehicle_visible_for_a_full_window(highway_logs: dict[str, Log]) -> None:
    # 4 s windows = 100 frames: car 1 (300 frames) 3, truck (500) 5, car 3 (300) 3, car 4 (400) 4,
    # car 5 (21) none.
    expected = {f"highd-01-ego{e}-w{k}" for e, n in ((1, 3), (2, 5), (3, 3), (4, 4)) for k in range(n)}
    assert set(highway_logs) == expected
    w2 = highway_logs["highd-01-ego2-w2"]
    assert w2.timestamps_ns[0] == 201 * 40_000_000 and w2.n_timestamps == 100
    assert all(log.track_ids[0] == log.log_id.split("ego")[1].split("-")[0] for log in highway_logs.values())


def test_automatic_egos_are_capped_evenly_and_explicit_egos_are_honoured(highway: HighDFiles) -> None:
    rec = read_highd_recording(highway)
    capped = plan_windows(rec, 4.0, max_egos=2)
    assert sorted({w.ego_id for w in capped}) == [1, 4]  # first and last of the eligible 1, 2, 3, 4
    explicit = plan_windows(rec, 4.0, ego_ids=(3, 5, 99))  # 5 is too short, 99 absent
    assert [(w.ego_id, w.index, w.first_frame, w.stop_frame) for w in explicit] == [
        (3, 0, 51, 151),
        (3, 1, 151, 251),
        (3, 2, 251, 351),
    ]
    logs = _logs(highway, highd_config(highd_max_egos_per_recording=2))
    assert sorted(logs) == sorted({w.log_id(1) for w in capped})
    with pytest.raises(ValueError, match="positive"):
        plan_windows(rec, 0.0)


def test_other_vehicles_appear_only_within_the_radius(
    highway_logs: dict[str, Log], highway: HighDFiles
) -> None:
    assert "4" not in highway_logs["highd-01-ego1-w0"].track_ids
    log = highway_logs["highd-01-ego1-w1"]  # frames 101..200, car 4 approaches from the other side
    frames = np.arange(101, 201)
    ex, ey = position(1, frames)
    ox, oy = position(4, frames)
    within = np.hypot(ox - ex, oy - ey) <= 150.0
    assert 0 < within.sum() < within.size
    row = log.track_index("4")
    np.testing.assert_array_equal(log.valid[row], within)
    unlimited = _logs(highway, radius_m=None)["highd-01-ego1-w1"]
    assert unlimited.valid[unlimited.track_index("4")].all()


# --------------------------------------------------------------------------------------- discovery


def test_discover_finds_recordings_in_a_folder_or_its_data_subfolder(tmp_path: Path) -> None:
    write_small_highway(tmp_path / "highD" / "data", recording_id=1)
    write_small_highway(tmp_path / "highD" / "data", recording_id=12)
    reader = HighDReader()
    for path in (tmp_path / "highD", tmp_path / "highD" / "data"):
        sources = reader.discover(path)
        assert [s.path.name for s in sources] == ["01_tracks.csv", "12_tracks.csv"]
        assert [f.name for f in sources[1].files] == [
            "12_tracks.csv",
            "12_tracksMeta.csv",
            "12_recordingMeta.csv",
        ]
        assert all(s.format == "highd" for s in sources)
    # A meta file stands for its recording; other files are not highD.
    (meta_src,) = reader.discover(tmp_path / "highD" / "data" / "12_recordingMeta.csv")
    assert meta_src.path.name == "12_tracks.csv"
    (tmp_path / "other.csv").write_text("a,b\n1,2\n")
    assert reader.discover(tmp_path / "other.csv") == []
    assert reader.discover(tmp_path / "missing") == []
    logs = list(reader.read(meta_src, highd_config()))
    assert logs[0].log_id == "highd-12-ego1-w0"


def test_a_tracks_file_without_its_meta_file_names_the_missing_file(tmp_path: Path) -> None:
    files = write_small_highway(tmp_path)
    files.recording_meta.unlink()
    with pytest.raises(LogFormatError, match="01_recordingMeta.csv is missing"):
        HighDReader().discover(tmp_path)


# --------------------------------------------------------------------------------------- bad input


def test_missing_column_is_an_error_naming_file_and_column(tmp_path: Path) -> None:
    files = write_small_highway(tmp_path)
    edit_csv(files.tracks, lambda rows: [r[:6] + r[7:] for r in rows])  # drop xVelocity
    with pytest.raises(LogFormatError, match=r"01_tracks\.csv: missing column\(s\) \['xVelocity'\]"):
        _logs(files)


def test_nan_position_is_an_error_naming_the_vehicle_and_frame(tmp_path: Path) -> None:
    files = write_small_highway(tmp_path)
    edit_csv(files.tracks, lambda rows: [r[:2] + [""] + r[3:] if r[:2] == ["7", "2"] else r for r in rows])
    with pytest.raises(LogFormatError, match=r"01_tracks\.csv: column 'x' has 1 missing.*id 2, frame 7"):
        _logs(files)


def test_unsorted_rows_are_sorted_with_a_note(tmp_path: Path, highway_logs: dict[str, Log]) -> None:
    files = write_small_highway(tmp_path)
    edit_csv(files.tracks, lambda rows: rows[:1] + rows[1:][::-1])
    logs = _logs(files)
    ref = highway_logs["highd-01-ego3-w1"]
    log = logs["highd-01-ego3-w1"]
    np.testing.assert_array_equal(log.x_m, ref.x_m)
    np.testing.assert_array_equal(log.track_ids, ref.track_ids)
    assert log.notes[0] == "01_tracks.csv: rows were not sorted by (id, frame); sorted them"


def test_duplicate_id_frame_rows_conflicting_are_an_error_exact_ones_collapse(tmp_path: Path) -> None:
    files = write_small_highway(tmp_path)
    edit_csv(files.tracks, lambda rows: rows + [rows[10]])
    assert "collapsed 1 exact duplicate" in _logs(files)["highd-01-ego1-w0"].notes[0]
    edit_csv(files.tracks, lambda rows: rows[:-1] + [[rows[10][0], rows[10][1], "999.00", *rows[10][3:]]])
    with pytest.raises(LogFormatError, match=r"01_tracks\.csv: 1 duplicate \(id, frame\).*id 1 at frame 10"):
        _logs(files)


def test_vehicle_absent_from_the_meta_file_is_an_error(tmp_path: Path) -> None:
    files = write_small_highway(tmp_path)
    edit_csv(files.tracks_meta, lambda rows: [r for r in rows if r[0] != "3"])
    with pytest.raises(
        LogFormatError, match=r"01_tracks\.csv: 1 vehicle id\(s\).*01_tracksMeta\.csv, e\.g\. \[3\]"
    ):
        _logs(files)


def test_unknown_class_and_bad_direction_are_errors_naming_the_meta_file(tmp_path: Path) -> None:
    files = write_small_highway(tmp_path)
    original = files.tracks_meta.read_text()
    edit_csv(
        files.tracks_meta, lambda rows: [[*r[:6], "Tractor", *r[7:]] if r[0] == "2" else r for r in rows]
    )
    with pytest.raises(
        LogFormatError, match=r"01_tracksMeta\.csv: column 'class': unknown object category 'Tractor'"
    ):
        _logs(files)
    files.tracks_meta.write_text(original)
    edit_csv(files.tracks_meta, lambda rows: [[*r[:7], "3", *r[8:]] if r[0] == "2" else r for r in rows])
    with pytest.raises(
        LogFormatError, match=r"01_tracksMeta\.csv: drivingDirection must be 1 .* got 3 for vehicle 2"
    ):
        _logs(files)


def test_bad_frame_rate_is_an_error(tmp_path: Path) -> None:
    files = write_small_highway(tmp_path)
    edit_csv(files.recording_meta, lambda rows: [rows[0], ["1", "0", *rows[1][2:]]])
    with pytest.raises(LogFormatError, match=r"01_recordingMeta\.csv: frameRate must be a positive number"):
        _logs(files)


def test_frame_rate_is_checked_only_against_moving_vehicles() -> None:
    from scenariominer.data.adapters.highd.consistency import implied_frame_rate

    frames = np.tile(np.arange(1, 101), 2)
    vid = np.repeat([1, 2], 100)
    crawling = np.full(200, 2.0)  # congestion: 2 m/s says nothing at 1 cm resolution
    x = np.concatenate([np.round(np.arange(100) * 2.0 / 25, 2)] * 2)
    assert implied_frame_rate(vid, frames, x, crawling) is None
    fast = np.full(200, 30.0)
    x = np.concatenate([np.round(np.arange(100) * 30.0 / 25, 2)] * 2)
    assert implied_frame_rate(vid, frames, x, fast) == pytest.approx(25.0, rel=0.01)


# --------------------------------------------------------------------------------------- scale


def _busy_recording(out_dir: Path, n_vehicles: int, seconds: float) -> HighDFiles:
    """``n_vehicles`` entering a 420 m, 3 + 3 lane section over ``seconds`` (seeded)."""
    rng = np.random.default_rng(7)
    upper, lower = (8.0, 11.8, 15.6, 19.4), (24.0, 27.8, 31.6, 35.4)
    vehicles = []
    entry = np.sort(rng.uniform(0, seconds, n_vehicles))
    for i, t0 in enumerate(entry):
        direction = 1 if i % 2 else 2
        lane = int(rng.integers(0, 3))
        y_img = (upper if direction == 1 else lower)[lane] + 1.9
        speed = rng.uniform(22.0, 38.0)
        k = int(420.0 / speed * FRAME_RATE_HZ)
        t = np.arange(k) / FRAME_RATE_HZ
        x = (t * speed) if direction == 2 else (420.0 - t * speed)
        is_truck = rng.random() < 0.2
        vehicles.append(
            HighDVehicle(
                i + 1,
                "Truck" if is_truck else "Car",
                int(t0 * FRAME_RATE_HZ) + 1,
                x,
                np.full(k, -y_img),
                16.0 if is_truck else 4.6,
                2.5 if is_truck else 1.9,
            )
        )
    return write_highd_recording(
        out_dir, 1, vehicles, upper_lane_markings_m=upper, lower_lane_markings_m=lower
    )


@pytest.mark.slow
def test_reading_a_full_size_recording_is_fast(tmp_path: Path) -> None:
    files = _busy_recording(tmp_path, 1000, 900.0)
    reader = HighDReader()
    (source,) = reader.discover(tmp_path)
    start = time.perf_counter()
    logs = list(reader.read(source, Config()))
    elapsed = time.perf_counter() - start
    assert len(logs) == 20  # 15 s windows: each 14-19 s track yields one window; 20 egos
    assert len(_rows(files.tracks_meta)) == 1000
    assert elapsed < 5.0, f"reading took {elapsed:.2f} s"
