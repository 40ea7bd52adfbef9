"""Synthetic labelled scenarios: written as Argoverse 2 logs + maps, read back, physically consistent."""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np
import pyarrow.feather as feather
import pytest

from scenariominer.config import Config
from scenariominer.config.tags import TagConfig
from scenariominer.data.adapters.av2 import AV2_EGO_CENTER_OFFSET_M, Av2Reader
from scenariominer.data.adapters.av2.map import read_av2_map
from scenariominer.data.log import Log
from scenariominer.data.preprocess import preprocess
from scenariominer.events.keyident import find_key_objects
from scenariominer.synth import (
    LABEL_COLUMNS,
    ScenarioCategory,
    ScenarioLabel,
    SynthResult,
    generate,
    generate_log,
    read_labels,
    write_labels,
)
from scenariominer.tags import tag_log

ALL = list(ScenarioCategory)
BRAKING = [c for c in ALL if c is not ScenarioCategory.NOT_RELEVANT]
INTERSECTION_CATEGORIES = {
    ScenarioCategory.PED_CROSSING,
    ScenarioCategory.OBJ_CROSSING,
    ScenarioCategory.LEFT_OPPO,
    ScenarioCategory.RIGHT_PED,
}


@pytest.fixture(scope="module")
def written(tmp_path_factory: pytest.TempPathFactory) -> tuple[SynthResult, dict[str, Log]]:
    """One log of every category (seed 0), written to disk and read back with the AV2 reader."""
    result = generate(tmp_path_factory.mktemp("synth"), n=len(ALL), seed=0)
    reader = Av2Reader()
    logs = {}
    for source in reader.discover(result.out_dir):
        (log,) = reader.read(source, Config())
        logs[log.log_id] = log
    return result, logs


def _window(log: Log, label: ScenarioLabel) -> tuple[int, int]:
    i0, i1 = np.searchsorted(log.timestamps_ns, [label.start_ns, label.end_ns])
    return int(i0), int(i1)


# ---------------------------------------------------------------------- files and labels


def test_labels_csv_has_one_row_per_log_with_the_documented_columns(
    written: tuple[SynthResult, dict[str, Log]],
) -> None:
    result, logs = written
    with result.labels_csv.open(newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert tuple(rows[0].keys()) == LABEL_COLUMNS
    assert [r["scenario_category"] for r in rows] == [c.value for c in ALL]
    assert {r["log_id"] for r in rows} == set(logs) == {d.name for d in result.log_dirs}
    assert all(int(r["start_ns"]) < int(r["end_ns"]) for r in rows)
    assert read_labels(result.labels_csv) == result.labels


def test_every_log_folder_has_annotations_poses_and_a_readable_map(
    written: tuple[SynthResult, dict[str, Log]],
) -> None:
    result, logs = written
    for log_dir, label in zip(result.log_dirs, result.labels, strict=True):
        assert (log_dir / "annotations_with_ego.feather").is_file()
        assert (log_dir / "city_SE3_egovehicle.feather").is_file()
        table = feather.read_table(log_dir / "annotations_with_ego.feather")
        assert "num_interior_pts" in table.column_names
        log = logs[log_dir.name]
        assert log.map_dir == log_dir / "map"
        av2_map = read_av2_map(log_dir)
        # The ego (read back at its box centre) stays on the drivable surface.
        assert av2_map.in_drivable_area(np.column_stack([log.x_m[0], log.y_m[0]])).all(), (
            label.scenario_category
        )
        if label.scenario_category in INTERSECTION_CATEGORIES:
            assert len(av2_map.pedestrian_crossings) == 4
            assert int(av2_map.lane_is_intersection.sum()) == 16  # 4 arms x (2 through + left + right)
        elif label.scenario_category is not ScenarioCategory.NOT_RELEVANT:
            assert len(av2_map.pedestrian_crossings) == 0 and not av2_map.lane_is_intersection.any()


def test_read_back_logs_have_the_expected_tracks_and_the_guest(
    written: tuple[SynthResult, dict[str, Log]],
) -> None:
    result, logs = written
    for label, n_tracks in zip(result.labels, result.n_tracks, strict=True):
        log = logs[label.log_id]
        assert log.n_tracks == n_tracks >= 6  # ego + guest + at least four background objects
        assert log.n_timestamps == 150 and 14.8 < log.duration_s < 15.0
        guest = log.track_index(label.guest_id)
        i0, i1 = _window(log, label)
        assert log.valid[guest, i0 : i1 + 1].mean() > 0.9
        assert log.categories[0] == "EGO_VEHICLE" and log.dataset == "av2"


def test_ego_brakes_during_the_labelled_window(written: tuple[SynthResult, dict[str, Log]]) -> None:
    result, logs = written
    for label in result.labels:
        log = preprocess(logs[label.log_id])
        speed = log.speed_mps[0]
        i0, i1 = _window(log, label)
        drop = speed[i0] - speed[i1]
        if label.scenario_category is ScenarioCategory.NOT_RELEVANT:
            assert speed[i0 : i1 + 1].min() > speed[i0] - 0.5, "not_relevant: the ego must not brake"
        else:
            assert drop > 1.5, f"{label.scenario_category.value}: ego speed only fell by {drop:.2f} m/s"


def test_guest_ids_and_log_ids_look_like_av2_uuids(written: tuple[SynthResult, dict[str, Log]]) -> None:
    result, _ = written
    for label in result.labels:
        for value in (label.log_id, label.guest_id):
            parts = value.split("-")
            assert [len(p) for p in parts] == [8, 4, 4, 4, 12] and parts[2][0] == "4"


def test_written_log_reads_back_as_the_in_memory_one(
    written: tuple[SynthResult, dict[str, Log]],
) -> None:
    result, logs = written
    # Log i of generate(seed=s) is generate_log(category_i, default_rng([s, i])).
    synth = generate_log(ALL[2], np.random.default_rng([0, 2]))
    disk = logs[synth.log.log_id]
    assert disk.track_ids.tolist() == synth.log.track_ids.tolist()
    # Every track, the ego included, comes back at its box centre (the file holds the rear axle).
    np.testing.assert_allclose(disk.x_m, synth.log.x_m, atol=1e-6, equal_nan=True)
    np.testing.assert_allclose(disk.y_m, synth.log.y_m, atol=1e-6, equal_nan=True)
    assert disk.ego_pose_offset_m == AV2_EGO_CENTER_OFFSET_M
    pose_x, pose_y = disk.ego_pose_xy_m()
    poses = feather.read_table(result.out_dir / synth.log.log_id / "city_SE3_egovehicle.feather")
    assert poses.num_rows == synth.log.n_timestamps
    np.testing.assert_allclose(poses.column("tx_m").to_numpy(), pose_x, atol=1e-6)
    np.testing.assert_allclose(poses.column("ty_m").to_numpy(), pose_y, atol=1e-6)
    assert synth.label == result.labels[2]


# ---------------------------------------------------------------------- physics and determinism


def _key_objects(log: Log) -> set[str]:
    return {e.track_id for e in find_key_objects(tag_log(preprocess(log), TagConfig()))}


def test_the_key_object_identification_finds_the_labelled_guest_in_every_braking_category() -> None:
    # The generator's physics must make the labelled guest the reason for the ego's braking: the
    # project's own tag-based KeyIdent (seed 000, III-C) names it in every category.
    missed = []
    for j, category in enumerate(BRAKING):
        synth = generate_log(category, np.random.default_rng([11, j]))
        if synth.label.guest_id not in _key_objects(synth.log):
            missed.append(category.value)
    assert missed == []


def test_not_relevant_guests_are_not_key_objects() -> None:
    for i in range(2):
        synth = generate_log(ScenarioCategory.NOT_RELEVANT, np.random.default_rng([12, i]))
        assert synth.label.guest_id not in _key_objects(synth.log)


def test_same_seed_same_logs_other_seed_other_logs(tmp_path: Path) -> None:
    seen: list[int] = []
    a = generate(tmp_path / "a", n=2, seed=5, categories=["cut_in", "right_ped"], progress=seen.append)
    b = generate(tmp_path / "b", n=2, seed=5, categories=["cut_in", "right_ped"])
    c = generate(tmp_path / "c", n=1, seed=6, categories=["cut_in"])
    assert seen == [1, 2]
    assert a.labels == b.labels and a.n_tracks == b.n_tracks
    for da, db in zip(a.log_dirs, b.log_dirs, strict=True):
        for name in ("annotations_with_ego.feather", "city_SE3_egovehicle.feather"):
            assert feather.read_table(da / name).equals(feather.read_table(db / name))
    assert a.labels_csv.read_bytes() == b.labels_csv.read_bytes()
    assert c.labels[0].log_id != a.labels[0].log_id
    assert [lab.scenario_category for lab in a.labels] == [
        ScenarioCategory.CUT_IN,
        ScenarioCategory.RIGHT_PED,
    ]


def test_scenarios_vary_with_the_random_state() -> None:
    speeds = [generate_log("lead_brake", np.random.default_rng([3, i])).log.speed_mps[0, 0] for i in range(4)]
    assert len({round(float(s), 1) for s in speeds}) == 4


def test_crossing_guests_walk_through_a_crosswalk_of_the_map() -> None:
    for category in (ScenarioCategory.PED_CROSSING, ScenarioCategory.RIGHT_PED):
        synth = generate_log(category, np.random.default_rng([4, 0]))
        log, g = synth.log, synth.log.track_index(synth.label.guest_id)
        i0, i1 = _window(log, synth.label)
        xy = np.column_stack([log.x_m[g, i0 : i1 + 1], log.y_m[g, i0 : i1 + 1]])
        assert synth.av2_map.in_crosswalk(xy[np.isfinite(xy).all(axis=1)]).mean() > 0.5


def test_left_turn_passes_through_an_intersection_lane() -> None:
    synth = generate_log(ScenarioCategory.LEFT_OPPO, np.random.default_rng([4, 1]))
    log = synth.log
    lanes = synth.av2_map.lane_index_at(np.column_stack([log.x_m[0], log.y_m[0]]), yaw_rad=log.yaw_rad[0])
    assert synth.av2_map.is_intersection(lanes).any() and (lanes >= 0).all()
    heading_change = np.angle(np.exp(1j * (log.yaw_rad[0, -1] - log.yaw_rad[0, 0])))
    assert heading_change == pytest.approx(np.pi / 2, abs=0.1)  # a left turn is counter-clockwise


# ---------------------------------------------------------------------- bad input


def test_bad_arguments_are_rejected(tmp_path: Path) -> None:
    with pytest.raises(ValueError, match="unknown scenario category"):
        generate(tmp_path, n=1, categories=["teleport"])
    with pytest.raises(ValueError, match="n must be >= 0"):
        generate(tmp_path, n=-1)
    with pytest.raises(ValueError, match="must not be empty"):
        generate(tmp_path, n=1, categories=[])


def test_labels_round_trip_and_missing_columns(tmp_path: Path) -> None:
    labels = (ScenarioLabel("log", "guest", ScenarioCategory.CUT_IN, 1, 2),)
    assert read_labels(write_labels(labels, tmp_path / "l.csv")) == labels
    (tmp_path / "bad.csv").write_text("log_id,guest_id\nx,y\n")
    with pytest.raises(ValueError, match="missing label column"):
        read_labels(tmp_path / "bad.csv")
    (tmp_path / "bad2.csv").write_text(",".join(LABEL_COLUMNS) + "\nx,y,flying,1,2\n")
    with pytest.raises(ValueError, match="bad2.csv:2"):
        read_labels(tmp_path / "bad2.csv")
