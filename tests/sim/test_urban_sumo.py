"""SUMO really runs: small urban braking sets read back by the AV2 reader and the label readers."""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from scenariominer.data.adapters.av2 import read_av2_log
from scenariominer.data.adapters.av2.map import read_av2_map
from scenariominer.eval.braking import read_labels as read_eval_labels
from scenariominer.sim.urban import (
    EXTRA_LABEL_COLUMNS,
    LABELS_FILE,
    UrbanSetResult,
    UrbanSettings,
    simulate_urban_set,
)
from scenariominer.sim.urban_net import UrbanNetSpec, UrbanSimError, build_network, network_map
from scenariominer.synth import LABEL_COLUMNS, read_labels

sumolib = pytest.importorskip("sumolib", reason="the sim extra (SUMO) is not installed")
pytest.importorskip("traci", reason="the sim extra (traci) is not installed")
if not Path(sumolib.checkBinary("sumo")).is_file():
    pytest.skip("SUMO's sumo program is not installed (eclipse-sumo)", allow_module_level=True)

ONE_PED = UrbanSettings(n=1, seed=3, noise="medium", categories=("ped_crossing",))


@pytest.fixture(scope="module")
def ped_set(tmp_path_factory: pytest.TempPathFactory) -> UrbanSetResult:
    return simulate_urban_set(tmp_path_factory.mktemp("urban"), ONE_PED)


def _rows(path: Path) -> list[dict[str, str]]:
    with path.open(newline="", encoding="utf-8") as fh:
        return list(csv.DictReader(fh))


def test_a_pedestrian_scenario_is_written_labelled_and_read_back(ped_set: UrbanSetResult) -> None:
    assert [r.ok for r in ped_set.logs] == [True], [r.error for r in ped_set.logs]
    rows = _rows(ped_set.labels_csv)
    assert list(rows[0]) == [*LABEL_COLUMNS, *EXTRA_LABEL_COLUMNS]
    row = rows[0]
    assert row["scenario_category"] == "ped_crossing" and row["noise_level"] == "medium"
    log = read_av2_log(ped_set.out_dir / row["log_id"])
    assert log.log_id == row["log_id"] and 100 <= log.n_timestamps <= 150
    onset = int(row["onset_ns"])
    k = int(np.flatnonzero(log.timestamps_ns == onset)[0])
    assert int(row["start_ns"]) <= onset <= int(row["end_ns"])
    # the labelled key object is an observed pedestrian at the braking onset
    g = int(np.flatnonzero(log.track_ids == row["guest_id"])[0])
    assert log.categories[g] == "PEDESTRIAN" and log.valid[g, k]
    # the ego brakes from the onset on: a clear speed drop within the window
    e = log.ego_index
    t_s = (log.timestamps_ns - log.timestamps_ns[0]) * 1e-9
    speed = np.hypot(np.gradient(log.x_m[e], t_s), np.gradient(log.y_m[e], t_s))
    assert speed[k] - speed[k:].min() > 2.0
    # ... and drives towards the pedestrian before it stops
    gap = np.hypot(log.x_m[g] - log.x_m[e], log.y_m[g] - log.y_m[e])
    assert gap[k] < 120.0


def test_the_map_has_lanes_a_junction_and_crossings(ped_set: UrbanSetResult) -> None:
    row = _rows(ped_set.labels_csv)[0]
    av2_map = read_av2_map(ped_set.out_dir / row["log_id"])
    assert av2_map.n_lanes >= 20 and av2_map.lane_is_intersection.any()
    assert len(av2_map.pedestrian_crossings) == 4 and av2_map.drivable_areas
    ids = set(av2_map.lane_ids.tolist())
    assert all(set(ls.successors) <= ids for ls in av2_map.lane_segments)
    # the ego drives on mapped lanes most of the time
    log = read_av2_log(ped_set.out_dir / row["log_id"])
    e = log.ego_index
    on_lane = av2_map.lane_index_at(np.column_stack([log.x_m[e], log.y_m[e]]), log.yaw_rad[e]) >= 0
    assert on_lane.mean() > 0.9


def test_both_label_readers_accept_the_labels_file(ped_set: UrbanSetResult) -> None:
    synth_rows = read_labels(ped_set.labels_csv)
    eval_rows = read_eval_labels(ped_set.labels_csv)
    assert [r.log_id for r in synth_rows] == [r.log_id for r in eval_rows] == [ped_set.logs[0].log_id]
    assert eval_rows[0].category == "ped_crossing" and eval_rows[0].guest_id == ped_set.logs[0].guest_id


def test_the_same_seed_gives_the_same_files(ped_set: UrbanSetResult, tmp_path: Path) -> None:
    again = simulate_urban_set(tmp_path, ONE_PED)
    log_id = ped_set.logs[0].log_id
    assert again.logs[0].log_id == log_id
    for rel in ("annotations_with_ego.feather", "city_SE3_egovehicle.feather"):
        assert (tmp_path / log_id / rel).read_bytes() == (ped_set.out_dir / log_id / rel).read_bytes()
    maps = sorted((tmp_path / log_id / "map").glob("*.json"))
    assert [m.read_bytes() for m in maps] == [
        m.read_bytes() for m in sorted((ped_set.out_dir / log_id / "map").glob("*.json"))
    ]
    assert (tmp_path / LABELS_FILE).read_bytes() == ped_set.labels_csv.read_bytes()


def test_the_network_map_links_the_approach_through_the_junction(tmp_path: Path) -> None:
    spec = UrbanNetSpec((180.0, 70.0, 0.0, 290.0), (200.0, 120.0, 120.0, 120.0), (2, 1, 2, 2), bend_m=20.0)
    net = build_network(spec, tmp_path, str(sumolib.checkBinary("netconvert")))
    av2_map = network_map(net, lambda xy: xy, 0.0)
    by_id = {ls.id: ls for ls in av2_map.lane_segments}
    # the approach lanes (not in the junction, leading into it) continue into junction lanes
    into = [
        ls
        for ls in by_id.values()
        if not ls.is_intersection and any(by_id[s].is_intersection for s in ls.successors)
    ]
    assert len(into) >= 7  # 2 + 1 + 2 + 2 lanes towards the junction
    for ls in into:
        for s in ls.successors:
            assert ls.id in by_id[s].predecessors
    neighbours = [ls for ls in by_id.values() if ls.left_neighbor_id is not None]
    assert neighbours and all(by_id[ls.left_neighbor_id].right_neighbor_id == ls.id for ls in neighbours)


def test_bad_settings_are_named_before_anything_runs(tmp_path: Path) -> None:
    with pytest.raises(UrbanSimError, match="unknown urban scenario category.*'u_turn'"):
        simulate_urban_set(tmp_path / "a", UrbanSettings(n=2, categories=("u_turn",)))
    with pytest.raises(UrbanSimError, match="unknown noise level 'loud'"):
        simulate_urban_set(tmp_path / "b", UrbanSettings(n=2, noise="loud"))
    assert not (tmp_path / "a").exists() and not (tmp_path / "b").exists()


def test_a_missing_sumo_program_is_named(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr("sumolib.checkBinary", lambda name, bindir=None: f"{name}-absent-for-this-test")
    with pytest.raises(UrbanSimError, match="'sumo' program was not found.*SUMO_HOME"):
        simulate_urban_set(tmp_path / "out", UrbanSettings(n=1))


def test_cli_rejects_a_bad_noise_level_in_one_line(tmp_path: Path) -> None:
    from scenariominer.cli import app

    result = CliRunner().invoke(app, ["simulate", "urban", "--out", str(tmp_path / "x"), "--noise", "loud"])
    assert result.exit_code == 2
    assert "unknown noise level 'loud'" in result.output and "Traceback" not in result.output


@pytest.mark.slow
def test_every_family_gives_a_labelled_log(tmp_path: Path) -> None:
    result = simulate_urban_set(tmp_path, UrbanSettings(n=7, seed=5, noise="mixed"))
    assert [r.ok for r in result.logs] == [True] * 7, [r.error for r in result.logs]
    rows = _rows(result.labels_csv)
    assert {r["scenario_category"] for r in rows} == {
        "ped_crossing",
        "left_oppo",
        "cut_in",
        "lead_brake",
        "obj_crossing",
        "right_ped",
        "approach_stop",
    }
    for row in rows:
        log = read_av2_log(tmp_path / row["log_id"])
        k = int(np.flatnonzero(log.timestamps_ns == int(row["onset_ns"]))[0])
        g = np.flatnonzero(log.track_ids == row["guest_id"])
        assert g.size == 1 and log.valid[g[0], k], row


def test_ingest_takes_the_set_like_real_av2_logs(ped_set: UrbanSetResult, tmp_path: Path) -> None:
    from scenariominer import api

    store = api.open_store(tmp_path / "store")
    report = api.ingest([ped_set.out_dir], store)
    assert report.n_logs_ingested == 1 and not report.failed, report
    assert store.log_ids() == [ped_set.logs[0].log_id]


def test_cli_writes_a_set_and_prints_its_table(tmp_path: Path) -> None:
    from scenariominer.cli import app

    out = tmp_path / "set"
    args = ["simulate", "urban", "--out", str(out), "--n", "1", "--seed", "2", "--category", "approach_stop"]
    result = CliRunner().invoke(app, args)
    assert result.exit_code == 0, result.output
    assert "approach_stop" in result.output and "1 log(s) written, 0 failed" in result.output
    rows = _rows(out / LABELS_FILE)
    assert [r["scenario_category"] for r in rows] == ["approach_stop"]
    assert (out / rows[0]["log_id"] / "city_SE3_egovehicle.feather").is_file()
    assert not (out / "sumo").exists()  # SUMO's work files are removed unless kept


def test_an_earlier_set_is_kept_unless_overwrite_and_then_replaced(tmp_path: Path) -> None:
    first = simulate_urban_set(tmp_path, UrbanSettings(n=1, seed=2, categories=("approach_stop",)))
    old_id = first.logs[0].log_id
    with pytest.raises(UrbanSimError, match="already holds a set.*--overwrite"):
        simulate_urban_set(tmp_path, UrbanSettings(n=1, seed=4, categories=("approach_stop",)))
    assert (tmp_path / old_id).is_dir() and _rows(tmp_path / LABELS_FILE)[0]["log_id"] == old_id
    second = simulate_urban_set(
        tmp_path, UrbanSettings(n=1, seed=4, categories=("approach_stop",)), overwrite=True
    )
    new_id = second.logs[0].log_id
    assert new_id != old_id and not (tmp_path / old_id).exists() and (tmp_path / new_id).is_dir()
    assert [r["log_id"] for r in _rows(tmp_path / LABELS_FILE)] == [new_id]
