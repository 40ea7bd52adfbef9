"""Argoverse 2 adapter: discovery, ego-frame → city-frame transform, ego track, bad input, writer."""

from __future__ import annotations

import pickle
import shutil
from pathlib import Path
from typing import Any

import numpy as np
import pyarrow as pa
import pyarrow.feather as feather
import pytest

from scenariominer.config import Config
from scenariominer.data.adapters.av2 import (
    ANNOTATIONS_FILE,
    ANNOTATIONS_WITH_EGO_FILE,
    AV2_EGO_CENTER_OFFSET_M,
    AV2_EGO_SIZE_M,
    POSES_FILE,
    Av2Reader,
    av2_source,
    read_av2_log,
    write_av2_log,
)
from scenariominer.data.log import Log, LogFormatError, build_log
from scenariominer.data.sources import LogReader

EGO = "ego-0000"


# ---------------------------------------------------------------------- helpers


def _annotations(rows: list[dict[str, Any]]) -> pa.Table:
    """Annotation table from rows with t, id, cat, x, y, yaw (ego frame); other columns defaulted."""
    cols: dict[str, list[Any]] = {
        k: []
        for k in (
            "timestamp_ns",
            "track_uuid",
            "category",
            "length_m",
            "width_m",
            "height_m",
            "qw",
            "qx",
            "qy",
            "qz",
            "tx_m",
            "ty_m",
            "tz_m",
            "num_interior_pts",
        )
    }
    for r in rows:
        yaw = r.get("yaw", 0.0)
        cols["timestamp_ns"].append(int(r["t"]))
        cols["track_uuid"].append(r["id"])
        cols["category"].append(r["cat"])
        cols["length_m"].append(r.get("l", 4.0))
        cols["width_m"].append(2.0)
        cols["height_m"].append(1.5)
        cols["qw"].append(np.cos(yaw / 2))
        cols["qx"].append(0.0)
        cols["qy"].append(0.0)
        cols["qz"].append(np.sin(yaw / 2))
        cols["tx_m"].append(r.get("x", 0.0))
        cols["ty_m"].append(r.get("y", 0.0))
        cols["tz_m"].append(0.0)
        cols["num_interior_pts"].append(10)
    return pa.table(
        cols,
        schema=pa.schema(
            [
                ("timestamp_ns", pa.int64()),
                ("track_uuid", pa.string()),
                ("category", pa.string()),
                *[
                    (c, pa.float64())
                    for c in (
                        "length_m",
                        "width_m",
                        "height_m",
                        "qw",
                        "qx",
                        "qy",
                        "qz",
                        "tx_m",
                        "ty_m",
                        "tz_m",
                    )
                ],
                ("num_interior_pts", pa.int64()),
            ]
        ),
    )


def _poses(t: list[int], x: list[float], y: list[float], yaw: list[float]) -> pa.Table:
    yaw_a = np.asarray(yaw, dtype=float)
    return pa.table(
        {
            "timestamp_ns": pa.array(t, type=pa.int64()),
            "qw": np.cos(yaw_a / 2),
            "qx": np.zeros(len(t)),
            "qy": np.zeros(len(t)),
            "qz": np.sin(yaw_a / 2),
            "tx_m": np.asarray(x, dtype=float),
            "ty_m": np.asarray(y, dtype=float),
            "tz_m": np.zeros(len(t)),
        }
    )


def _small_log(folder: Path, *, with_ego: bool = True, pose_t: list[int] | None = None) -> Path:
    """Two timestamps; ego at (10, 20) heading north (+y); a car 5 m ahead (ego x), facing the same way."""
    folder.mkdir(parents=True, exist_ok=True)
    rows = []
    for t in (0, 100_000_000):
        if with_ego:
            rows.append({"t": t, "id": EGO, "cat": "EGO_VEHICLE", "l": 4.877})
        rows.append({"t": t, "id": "car", "cat": "REGULAR_VEHICLE", "x": 5.0, "y": 1.0, "yaw": 0.25})
    feather.write_feather(
        _annotations(rows), folder / (ANNOTATIONS_WITH_EGO_FILE if with_ego else ANNOTATIONS_FILE)
    )
    pose_t = pose_t if pose_t is not None else [0, 50_000_000, 100_000_000]
    n = len(pose_t)
    feather.write_feather(
        _poses(pose_t, [10.0] * n, list(np.linspace(20.0, 21.0, n)), [np.pi / 2] * n), folder / POSES_FILE
    )
    return folder


@pytest.fixture(scope="module")
def real_log(av2_log_dir: Path) -> Log:
    return read_av2_log(av2_log_dir)


# ---------------------------------------------------------------------- discovery


def test_reader_satisfies_the_log_reader_protocol() -> None:
    assert isinstance(Av2Reader(), LogReader)
    assert Av2Reader.format == "av2"


def test_discover_a_log_folder_lists_annotations_poses_and_map(av2_log_dir: Path) -> None:
    (source,) = Av2Reader().discover(av2_log_dir)
    names = sorted(f.name for f in source.files)
    assert names[:2] == [ANNOTATIONS_WITH_EGO_FILE, POSES_FILE]
    assert len(names) == 3 and names[2].startswith("log_map_archive_")
    assert source.format == "av2" and source.path == av2_log_dir.resolve()


def test_discover_finds_logs_at_any_depth_of_a_dataset_root(tmp_path: Path) -> None:
    _small_log(tmp_path / "root" / "train" / "log-a")
    _small_log(tmp_path / "root" / "val" / "log-b", with_ego=False)
    _small_log(tmp_path / "root" / "deep" / "a" / "b" / "log-c")
    (tmp_path / "root" / "notes").mkdir()
    found = Av2Reader().discover(tmp_path / "root")
    assert [s.path.name for s in found] == ["log-c", "log-a", "log-b"]
    assert (
        Av2Reader().discover(tmp_path / "root" / "train" / "log-a" / ANNOTATIONS_WITH_EGO_FILE)[0].path.name
        == "log-a"
    )


def test_discover_counts_a_log_folder_nested_in_another_log_folder_once(tmp_path: Path) -> None:
    _small_log(tmp_path / "root" / "log-a")
    _small_log(tmp_path / "root" / "log-a" / "copy" / "log-inner")
    _small_log(tmp_path / "root" / "log-b")
    found = Av2Reader().discover(tmp_path / "root")
    assert [s.path.name for s in found] == ["log-a", "log-b"]


def test_discover_ignores_other_things(tmp_path: Path) -> None:
    (tmp_path / "table.csv").write_text("a,b\n1,2\n")
    assert Av2Reader().discover(tmp_path) == []
    assert Av2Reader().discover(tmp_path / "table.csv") == []
    assert Av2Reader().discover(tmp_path / "missing") == []


# ---------------------------------------------------------------------- reading the real log


def test_real_log_shape_and_metadata(real_log: Log, av2_log_dir: Path) -> None:
    # 120 track uuids in the file (the ego included); one is annotated at a single timestamp only.
    assert real_log.n_timestamps == 157
    assert real_log.n_tracks == 119
    assert any("fewer than 2 frames" in n for n in real_log.notes)
    assert real_log.track_ids[0] == "9d57813a-2d04-40e6-9694-20dfa13295dc"
    assert real_log.categories[0] == "EGO_VEHICLE"
    assert real_log.dataset == "av2" and real_log.log_id == av2_log_dir.name
    assert real_log.map_dir == av2_log_dir / "map"
    assert real_log.source_path == av2_log_dir
    assert real_log.source_hash == av2_source(av2_log_dir).content_hash()


def test_reader_read_uses_the_ingest_min_track_frames(av2_log_dir: Path) -> None:
    (source,) = Av2Reader().discover(av2_log_dir)
    (log,) = list(Av2Reader().read(source, Config()))
    assert log.n_tracks == 119 and log.source_hash == source.content_hash()


def test_city_frame_boxes_match_the_scenario_mining_ground_truth(real_log: Log, av2_gt_pkl: Path) -> None:
    with av2_gt_pkl.open("rb") as fh:
        frames = next(iter(pickle.load(fh).values()))
    n_boxes = 0
    for frame in frames:
        col = int(np.flatnonzero(real_log.timestamps_ns == frame["timestamp_ns"])[0])
        ok = real_log.valid[:, col]
        xyz = np.stack([real_log.x_m[ok, col], real_log.y_m[ok, col], real_log.z_m[ok, col]], axis=1)
        # The GT lists the ego as a box (name OTHER_OBJECT) placed at the pose (rear axle), as the
        # exporter writes it; the log holds the ego's box centre (checked below).
        pose_x, pose_y = real_log.ego_pose_xy_m()
        xyz[0, :2] = pose_x[col], pose_y[col]
        yaw = real_log.yaw_rad[ok, col]
        gt_xyz = np.asarray(frame["translation_m"], dtype=float)
        dist = np.linalg.norm(gt_xyz[:, None, :] - xyz[None, :, :], axis=2)
        nearest = dist.argmin(axis=1)
        assert dist[np.arange(len(gt_xyz)), nearest].max() < 1e-3  # within 1 mm
        dyaw = np.angle(np.exp(1j * (yaw[nearest] - np.asarray(frame["yaw"], dtype=float))))
        assert np.abs(dyaw).max() < 1e-3  # GT yaw is float32 and composed slightly differently
        # The GT's ego_translation_m is the AV2 pose (rear axle); the log holds the ego's box
        # centre, AV2_EGO_CENTER_OFFSET_M ahead of it along the ego's heading.
        gt_ego = np.asarray(frame["ego_translation_m"], dtype=float)
        np.testing.assert_allclose([pose_x[col], pose_y[col], real_log.z_m[0, col]], gt_ego, atol=1e-6)
        heading = np.array([np.cos(real_log.yaw_rad[0, col]), np.sin(real_log.yaw_rad[0, col])])
        centre = np.array([real_log.x_m[0, col], real_log.y_m[0, col]])
        np.testing.assert_allclose(centre - gt_ego[:2], AV2_EGO_CENTER_OFFSET_M * heading, atol=1e-6)
        assert real_log.ego_pose_offset_m == AV2_EGO_CENTER_OFFSET_M
        n_boxes += len(gt_xyz)
    assert n_boxes > 2000


# ---------------------------------------------------------------------- transform on hand-built logs


def test_box_is_rotated_and_translated_by_the_pose_of_its_timestamp(tmp_path: Path) -> None:
    log = read_av2_log(_small_log(tmp_path / "L"))
    car = log.track_index("car")
    # Ego at (10, 20) then (10, 21), heading +y: ego-frame (5, 1) is 5 m north and 1 m west.
    np.testing.assert_allclose(log.x_m[car], [9.0, 9.0], atol=1e-12)
    np.testing.assert_allclose(log.y_m[car], [25.0, 26.0], atol=1e-12)
    np.testing.assert_allclose(log.yaw_rad[car], [np.pi / 2 + 0.25] * 2, atol=1e-12)
    np.testing.assert_allclose(log.x_m[0], [10.0, 10.0], atol=1e-12)
    # The ego is stored at its box centre, 1.422 m ahead (north) of the pose (rear axle).
    np.testing.assert_allclose(log.y_m[0], [20.0 + AV2_EGO_CENTER_OFFSET_M, 21.0 + AV2_EGO_CENTER_OFFSET_M])
    np.testing.assert_allclose(log.ego_pose_xy_m()[1], [20.0, 21.0], atol=1e-12)
    assert log.notes == ()


def test_missing_pose_timestamp_is_interpolated_and_noted(tmp_path: Path) -> None:
    folder = _small_log(tmp_path / "L", pose_t=[-100_000_000, 200_000_000])
    # Pose y goes 20 → 21 over t = -0.1 s .. 0.2 s; at t = 0 it is 20 + 1/3.
    log = read_av2_log(folder)
    np.testing.assert_allclose(log.ego_pose_xy_m()[1], [20.0 + 1 / 3, 20.0 + 2 / 3], atol=1e-9)
    assert any("interpolated the ego pose at 2" in n for n in log.notes)


def test_slerp_interpolates_the_heading(tmp_path: Path) -> None:
    folder = _small_log(tmp_path / "L")
    feather.write_feather(
        _poses([0, 200_000_000], [10.0, 10.0], [20.0, 20.0], [0.0, 1.0]), folder / POSES_FILE
    )
    log = read_av2_log(folder)
    np.testing.assert_allclose(log.yaw_rad[0], [0.0, 0.5], atol=1e-9)


def test_annotation_outside_the_pose_range_is_an_error(tmp_path: Path) -> None:
    folder = _small_log(tmp_path / "L", pose_t=[0, 50_000_000])
    with pytest.raises(LogFormatError, match="outside the pose range") as err:
        read_av2_log(folder)
    assert err.value.source.endswith(POSES_FILE)


def test_plain_annotations_get_an_ego_track_from_the_poses(tmp_path: Path) -> None:
    log = read_av2_log(_small_log(tmp_path / "L", with_ego=False))
    assert log.n_tracks == 2 and log.categories[0] == "EGO_VEHICLE"
    np.testing.assert_allclose(log.ego_pose_xy_m()[1], [20.0, 21.0])  # pose = rear axle
    np.testing.assert_allclose(log.y_m[0], np.array([20.0, 21.0]) + AV2_EGO_CENTER_OFFSET_M)  # box centre
    np.testing.assert_allclose(log.length_m[0], AV2_EGO_SIZE_M[0])
    assert any("synthesised" in n for n in log.notes)
    assert read_av2_log(_small_log(tmp_path / "L2", with_ego=False)).track_ids[0] != log.track_ids[0]


# ---------------------------------------------------------------------- bad input


def _rewrite(path: Path, change: Any) -> None:
    feather.write_feather(change(feather.read_table(path)), path)


def _set(table: pa.Table, name: str, values: Any) -> pa.Table:
    return table.set_column(table.column_names.index(name), name, pa.array(values))


@pytest.mark.parametrize(
    ("file", "change", "message"),
    [
        (
            ANNOTATIONS_WITH_EGO_FILE,
            lambda t: t.drop_columns(["qz", "tx_m"]),
            r"missing column\(s\) \['qz', 'tx_m'\]",
        ),
        (
            ANNOTATIONS_WITH_EGO_FILE,
            lambda t: _set(t, "qw", ["a"] * t.num_rows),
            "column 'qw' has type string",
        ),
        (
            ANNOTATIONS_WITH_EGO_FILE,
            lambda t: _set(t, "timestamp_ns", t.column("timestamp_ns").to_numpy() * 1.0),
            "integer nanoseconds",
        ),
        (
            ANNOTATIONS_WITH_EGO_FILE,
            lambda t: _set(t, "qx", [np.nan] + [0.0] * (t.num_rows - 1)),
            "non-finite, zero or overflowing rotation quaternion",
        ),
        (
            ANNOTATIONS_WITH_EGO_FILE,
            lambda t: _set(t, "track_uuid", [None] + ["x"] * (t.num_rows - 1)),
            "'track_uuid' has 1 missing value",
        ),
        (ANNOTATIONS_WITH_EGO_FILE, lambda t: t.slice(0, 0), "no rows"),
        (
            ANNOTATIONS_WITH_EGO_FILE,
            lambda t: _set(t, "category", ["SPACESHIP"] * t.num_rows),
            "unknown object category",
        ),
        (
            POSES_FILE,
            lambda t: _set(t, "qz", np.full(t.num_rows, np.inf)),
            "non-finite, zero or overflowing rotation quaternion",
        ),
        (POSES_FILE, lambda t: _set(t, "timestamp_ns", [0, 0, 100_000_000]), "duplicate pose timestamp"),
        (POSES_FILE, lambda t: t.slice(0, 0), "no rows"),
    ],
)
def test_broken_files_raise_a_format_error_naming_the_file(
    tmp_path: Path, file: str, change: Any, message: str
) -> None:
    folder = _small_log(tmp_path / "L")
    _rewrite(folder / file, change)
    with pytest.raises(LogFormatError, match=message) as err:
        read_av2_log(folder)
    assert err.value.source == str(folder / file)


def test_missing_or_unreadable_files_are_named(tmp_path: Path) -> None:
    folder = _small_log(tmp_path / "L")
    (folder / POSES_FILE).unlink()
    with pytest.raises(LogFormatError, match="missing file") as err:
        read_av2_log(folder)
    assert err.value.source == str(folder / POSES_FILE)
    (folder / POSES_FILE).write_bytes(b"not a feather file")
    with pytest.raises(LogFormatError, match="not a readable Feather file"):
        read_av2_log(folder)
    shutil.rmtree(folder)
    folder.mkdir()
    with pytest.raises(LogFormatError, match="missing file"):
        read_av2_log(folder)


def test_a_broken_map_leaves_the_log_without_its_map_and_says_why(tmp_path: Path) -> None:
    folder = _small_log(tmp_path / "L")
    (folder / "map").mkdir()
    (folder / "map" / "log_map_archive_L____X_city_0.json").write_text('{"lane_segments": {}}')
    log = read_av2_log(folder)
    assert log.map_dir is None
    assert log.notes == (
        "loaded without its vector map: log_map_archive_L____X_city_0.json: vector map lacks the "
        "'pedestrian_crossings' layer (an object keyed by id)",
    )


def test_real_log_keeps_its_map(real_log: Log, av2_log_dir: Path) -> None:
    assert real_log.map_dir == av2_log_dir / "map"
    assert not any("vector map" in n for n in real_log.notes)


# ---------------------------------------------------------------------- writer


def test_write_then_read_reproduces_the_real_log(real_log: Log, tmp_path: Path) -> None:
    folder = write_av2_log(real_log, tmp_path)
    assert folder == tmp_path / real_log.log_id
    table = feather.read_table(folder / ANNOTATIONS_WITH_EGO_FILE)
    assert "num_interior_pts" in table.column_names and table.num_rows == real_log.n_frames
    back = read_av2_log(folder)
    assert back.track_ids.tolist() == real_log.track_ids.tolist()
    assert back.categories.tolist() == real_log.categories.tolist()
    assert np.array_equal(back.valid, real_log.valid)
    assert np.array_equal(back.timestamps_ns, real_log.timestamps_ns)
    for name in ("x_m", "y_m", "z_m", "length_m", "width_m", "height_m"):
        np.testing.assert_allclose(getattr(back, name), getattr(real_log, name), atol=1e-9, equal_nan=True)
    dyaw = np.angle(np.exp(1j * (back.yaw_rad - real_log.yaw_rad)))
    assert np.nanmax(np.abs(dyaw)) < 1e-9


def test_write_then_read_a_hand_built_log(tmp_path: Path) -> None:
    t = np.arange(5)
    ids = ["me"] * 5 + ["ped"] * 3
    log = build_log(
        log_id="hand",
        track_id=ids,
        category=["EGO_VEHICLE"] * 5 + ["PEDESTRIAN"] * 3,
        timestamp_ns=np.concatenate([t, t[1:4]]) * 100_000_000,
        fields={
            "x_m": np.concatenate([t * 2.0, [5.0, 5.0, 5.0]]),
            "y_m": np.concatenate([t * 1.0, [3.0, 3.5, 4.0]]),
            "yaw_rad": np.concatenate([np.full(5, 0.46), [np.pi / 2] * 3]),
            "length_m": [4.877] * 5 + [0.6] * 3,
            "width_m": [2.0] * 5 + [0.6] * 3,
        },
        ego_track_id="me",
        source="<hand>",
    )
    back = read_av2_log(write_av2_log(log, tmp_path))
    assert back.track_ids.tolist() == ["me", "ped"]
    np.testing.assert_allclose(back.x_m, log.x_m, atol=1e-9, equal_nan=True)
    np.testing.assert_allclose(back.y_m, log.y_m, atol=1e-9, equal_nan=True)
    np.testing.assert_allclose(back.yaw_rad, log.yaw_rad, atol=1e-9, equal_nan=True)
    table = feather.read_table(tmp_path / "hand" / ANNOTATIONS_WITH_EGO_FILE)
    pts = dict(
        zip(table.column("category").to_pylist(), table.column("num_interior_pts").to_pylist(), strict=True)
    )
    assert pts["EGO_VEHICLE"] == 1 and pts["PEDESTRIAN"] > 1


def test_writer_refuses_a_log_whose_ego_is_missing_at_an_observed_timestamp(tmp_path: Path) -> None:
    log = build_log(
        log_id="gap",
        track_id=["me", "me", "car", "car", "car"],
        category=["EGO_VEHICLE"] * 2 + ["BUS"] * 3,
        timestamp_ns=[0, 2, 0, 1, 2],
        fields={
            "x_m": [0.0, 1, 5, 6, 7],
            "y_m": [0.0] * 5,
            "yaw_rad": [0.0] * 5,
            "length_m": [4.0] * 5,
            "width_m": [2.0] * 5,
        },
        ego_track_id="me",
        source="<hand>",
    )
    with pytest.raises(ValueError, match="ego is not observed at timestamp_ns=1"):
        write_av2_log(log, tmp_path)


def test_reading_a_log_on_poses_at_every_timestamp_does_not_import_scipy(tmp_path: Path) -> None:
    # scipy (0.4 s and 30 MB of a fresh `scenariominer ingest`) is needed only to interpolate a pose.
    import subprocess
    import sys

    folder = _small_log(tmp_path / "L")
    code = (
        "import sys; from pathlib import Path; "
        "from scenariominer.data.adapters.av2 import read_av2_log; "
        f"log = read_av2_log(Path({str(folder)!r})); "
        "print(log.n_tracks, 'scipy' in sys.modules)"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.split() == ["2", "False"]
    interpolated = _small_log(tmp_path / "M", pose_t=[-100_000_000, 200_000_000])
    assert any("interpolated the ego pose" in n for n in read_av2_log(interpolated).notes)
