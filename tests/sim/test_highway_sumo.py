"""SUMO really runs: a short, small highway set read back through the highD adapter."""

from __future__ import annotations

import json
import stat
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from scenariominer.data.adapters.highd import HighDFiles, read_highd_recording
from scenariominer.sim.highway import MANIFEST_FILE, HighwaySetResult, simulate_highway_set
from scenariominer.sim.highway_scenario import HighwaySettings, HighwaySimError
from scenariominer.sim.highway_truth import read_highway_truth

sumolib = pytest.importorskip("sumolib", reason="the sim extra (SUMO) is not installed")
if not Path(sumolib.checkBinary("sumo")).is_file():
    pytest.skip("SUMO's sumo program is not installed (eclipse-sumo)", allow_module_level=True)

# 3 lanes + acceleration lane, no speed limit, dense traffic: lane changes both ways in a minute.
SMALL = HighwaySettings(
    recordings=2,
    minutes=1.0,
    seed=11,
    lanes=3,
    demand_vph=4500.0,
    speed_limit_kmh=0.0,
    on_ramp=True,
    lane_drop=False,
    section_m=500.0,
    warmup_s=45.0,
)


@pytest.fixture(scope="module")
def sim_set(tmp_path_factory: pytest.TempPathFactory) -> HighwaySetResult:
    return simulate_highway_set(tmp_path_factory.mktemp("highway"), SMALL)


def _rows_by_key(rec_lane: np.ndarray, vid: np.ndarray, frame: np.ndarray) -> dict[tuple[int, int], int]:
    return {(int(v), int(f)): int(lane) for v, f, lane in zip(vid, frame, rec_lane, strict=True)}


def test_recordings_are_written_and_read_back_by_the_highd_adapter(sim_set: HighwaySetResult) -> None:
    assert [r.ok for r in sim_set.recordings] == [True, True], [r.error for r in sim_set.recordings]
    for r in sim_set.recordings:
        rec = read_highd_recording(HighDFiles.for_recording(sim_set.out_dir, r.recording_id))
        assert rec.notes == ()  # nothing repaired
        assert rec.n_vehicles == r.n_vehicles > 20
        assert rec.meta.frame_rate_hz == 10.0
        assert rec.meta.speed_limit_mps is None  # unlimited is highD's -1
        # 3 lanes + the acceleration lane: ids 2 (next to the median) .. 5 (acceleration lane)
        assert len(rec.meta.lower_lane_markings_m) == 5 and rec.meta.upper_lane_markings_m == ()
        assert set(np.unique(rec.lane_id).tolist()) <= {2, 3, 4, 5}
        assert np.all(rec.driving_direction == 2)
        # highD convention: x along the section, canonical y = -image y, lanes below the median
        assert rec.x_m.min() >= -10.0 and rec.x_m.max() <= SMALL.section_m + 10.0
        assert np.all(rec.y_m < 0)
        assert np.median(rec.vx_mps) > 0
        assert {"REGULAR_VEHICLE", "TRUCK"} <= set(rec.vehicle_categories.tolist())


def test_every_ground_truth_lane_change_shows_in_the_recordings_lane_ids(sim_set: HighwaySetResult) -> None:
    truth = read_highway_truth(sim_set.out_dir)
    assert truth.recording_ids == (1, 2)
    directions = set()
    for r in sim_set.recordings:
        rec = read_highd_recording(HighDFiles.for_recording(sim_set.out_dir, r.recording_id))
        lane_at = _rows_by_key(rec.lane_id, rec.vehicle_ids[rec.row_vehicle], rec.frame)
        changes = truth.of_recording(r.recording_id)
        assert len(changes) >= 10
        for c in changes:
            assert lane_at[(c.vehicle_id, c.frame - 1)] == c.from_lane
            assert lane_at[(c.vehicle_id, c.frame)] == c.to_lane
            assert c.direction == ("left" if c.to_lane < c.from_lane else "right")
            assert abs(c.to_lane - c.from_lane) == 1
            assert c.t_s == pytest.approx(c.frame / 10.0)
            directions.add(c.direction)
        # ... and the recording has no lane switch the truth does not list
        same_vehicle = rec.row_vehicle[1:] == rec.row_vehicle[:-1]
        switch = np.flatnonzero(same_vehicle & (rec.lane_id[1:] != rec.lane_id[:-1])) + 1
        listed = {(c.vehicle_id, c.frame) for c in changes}
        found = {(int(rec.vehicle_ids[rec.row_vehicle[i]]), int(rec.frame[i])) for i in switch}
        assert found == listed
        # the merge: vehicles leave the acceleration lane (5) to the left
        assert any(c.from_lane == 5 and c.direction == "left" for c in changes)
    assert directions == {"left", "right"}


def test_manoeuvres_group_consecutive_crossings(sim_set: HighwaySetResult) -> None:
    truth = read_highway_truth(sim_set.out_dir)
    for rid in truth.recording_ids:
        groups: dict[int, list[int]] = {}
        for c in truth.of_recording(rid):
            groups.setdefault(c.manoeuvre, []).append(c.vehicle_id)
            assert c.lanes_crossed >= 1
        for c in truth.of_recording(rid):
            members = groups[c.manoeuvre]
            assert c.lanes_crossed == len(members) and set(members) == {c.vehicle_id}


def test_truth_frames_match_the_recording_row_for_row(sim_set: HighwaySetResult) -> None:
    truth = read_highway_truth(sim_set.out_dir)
    for r in sim_set.recordings:
        rec = read_highd_recording(HighDFiles.for_recording(sim_set.out_dir, r.recording_id))
        frames = truth.frames(r.recording_id)
        order = np.lexsort((frames.frame, frames.vehicle_id))
        assert np.array_equal(frames.vehicle_id[order], rec.vehicle_ids[rec.row_vehicle])
        assert np.array_equal(frames.frame[order], rec.frame)
        assert np.array_equal(frames.lane_id[order], rec.lane_id)
        assert np.allclose(frames.speed_mps[order], np.hypot(rec.vx_mps, rec.vy_mps), atol=0.02)
        # SUMO's leader is one of the recording's vehicles at that frame, ahead of the follower
        lead = frames.leader_id > 0
        assert lead.mean() > 0.5
        x_at = {(int(v), int(f)): float(x) for v, f, x in zip(
            rec.vehicle_ids[rec.row_vehicle], rec.frame, rec.x_m, strict=True)}  # fmt: skip
        for i in np.flatnonzero(lead)[:: max(1, int(lead.sum()) // 300)]:
            me = x_at[(int(frames.vehicle_id[i]), int(frames.frame[i]))]
            assert x_at[(int(frames.leader_id[i]), int(frames.frame[i]))] > me
        # follower is the inverse relation
        has_f = frames.follower_id > 0
        key = {(int(v), int(f)): int(lead_id) for v, f, lead_id in zip(
            frames.vehicle_id, frames.frame, frames.leader_id, strict=True)}  # fmt: skip
        for i in np.flatnonzero(has_f)[:200]:
            assert key[(int(frames.follower_id[i]), int(frames.frame[i]))] == int(frames.vehicle_id[i])


def test_the_same_seed_gives_identical_files_whatever_the_set_size(
    sim_set: HighwaySetResult, tmp_path: Path
) -> None:
    alone = simulate_highway_set(tmp_path, HighwaySettings(**{**SMALL.__dict__, "recordings": 1}))
    assert alone.recordings[0].ok
    for name in ("01_tracks.csv", "01_tracksMeta.csv", "01_recordingMeta.csv", "01_laneChanges.csv",
                 "01_truthFrames.csv"):  # fmt: skip
        assert (tmp_path / name).read_bytes() == (sim_set.out_dir / name).read_bytes(), name
    assert (sim_set.out_dir / "01_tracks.csv").read_bytes() != (
        sim_set.out_dir / "02_tracks.csv"
    ).read_bytes()
    manifest = json.loads((sim_set.out_dir / MANIFEST_FILE).read_text())
    assert [r["recording_id"] for r in manifest["recordings"]] == [1, 2]
    assert manifest["recordings"][0]["on_ramp"] is True


def test_existing_recordings_are_not_overwritten_unless_asked(sim_set: HighwaySetResult) -> None:
    before = (sim_set.out_dir / "01_tracks.csv").read_bytes()
    with pytest.raises(HighwaySimError, match="already holds recording files.*--overwrite"):
        simulate_highway_set(sim_set.out_dir, SMALL)
    assert (sim_set.out_dir / "01_tracks.csv").read_bytes() == before


def test_a_failing_sumo_is_reported_per_recording_and_the_batch_goes_on(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    fake = tmp_path / "sumo"
    fake.write_text("#!/bin/sh\necho 'Error: the fake simulator always fails' >&2\nexit 3\n")
    fake.chmod(fake.stat().st_mode | stat.S_IEXEC)
    monkeypatch.setenv("SUMO_BINARY", str(fake))
    out = tmp_path / "out"
    result = simulate_highway_set(out, HighwaySettings(recordings=2, minutes=0.1, warmup_s=0.0))
    assert [r.ok for r in result.recordings] == [False, False]
    for r in result.recordings:
        assert "SUMO failed on recording" in r.error and "the fake simulator always fails" in r.error
    assert not list(out.glob("*_tracks.csv"))
    assert json.loads((out / MANIFEST_FILE).read_text())["recordings"][1]["written"] is False


def test_a_failed_rerun_keeps_the_older_recording(tmp_path: Path) -> None:
    tiny = HighwaySettings(
        recordings=1, minutes=0.25, variety="fixed", lanes=2, section_m=400.0, warmup_s=30.0
    )
    first = simulate_highway_set(tmp_path, tiny)
    assert first.recordings[0].ok
    before = {p.name: p.read_bytes() for p in tmp_path.glob("01_*.csv")}
    assert len(before) == 5
    # 3 simulated seconds: nobody reaches the section 600 m downstream -> the conversion fails
    again = simulate_highway_set(
        tmp_path, HighwaySettings(**{**tiny.__dict__, "minutes": 0.05, "warmup_s": 0.0}), overwrite=True
    )
    assert not again.recordings[0].ok
    assert "no vehicle drove through the recorded section" in again.recordings[0].error
    assert {p.name: p.read_bytes() for p in tmp_path.glob("01_*.csv")} == before
    entry = json.loads((tmp_path / MANIFEST_FILE).read_text())["recordings"][0]
    assert entry["written"] is True and entry["record_s"] == 15.0
    assert "no vehicle drove through" in entry["last_attempt_error"]


def test_a_missing_sumo_program_is_named(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    # sumolib.checkBinary answers the bare name when it finds nothing
    monkeypatch.setattr("sumolib.checkBinary", lambda name, bindir=None: f"{name}-absent-for-this-test")
    with pytest.raises(HighwaySimError, match="'sumo' program was not found.*SUMO_HOME"):
        simulate_highway_set(tmp_path / "out", HighwaySettings(recordings=1))
    assert not (tmp_path / "out").exists()


def test_cli_simulates_and_rejects_a_bad_argument(tmp_path: Path) -> None:
    from scenariominer.cli import app

    runner = CliRunner()
    bad = runner.invoke(app, ["simulate", "highway", "--out", str(tmp_path / "x"), "--lanes", "7"])
    assert bad.exit_code == 2
    assert "lanes must be 2, 3 or 4, got 7" in bad.output
    assert not (tmp_path / "x").exists()
    ok = runner.invoke(
        app,
        ["simulate", "highway", "--out", str(tmp_path / "y"), "--minutes", "0.25", "--recordings", "1",
         "--variety", "fixed", "--lanes", "2", "--section-m", "400", "--json"],
    )  # fmt: skip
    assert ok.exit_code == 0, ok.output
    report = json.loads(ok.output)
    assert report["recordings"][0]["ok"] is True and report["recordings"][0]["lanes"] == 2
    assert (tmp_path / "y" / "01_tracks.csv").is_file()
    table = runner.invoke(
        app,
        ["simulate", "highway", "--out", str(tmp_path / "y"), "--minutes", "0.25", "--recordings", "1",
         "--variety", "fixed", "--lanes", "2", "--section-m", "400", "--overwrite"],
    )  # fmt: skip
    assert table.exit_code == 0, table.output
    assert "1 recording(s) written, 0 failed" in table.output
    assert f"scenariominer ingest {tmp_path / 'y'}" in table.output.replace("\n", "")


def test_the_set_ingests_like_real_highd_recordings(sim_set: HighwaySetResult, tmp_path: Path) -> None:
    from scenariominer import api

    store = api.open_store(tmp_path / "store")
    report = api.ingest([sim_set.out_dir], store)  # the ground-truth CSVs beside them are not logs
    assert not report.failed and report.n_ingested == 2
    ids = store.log_ids()
    assert report.n_logs_ingested == len(ids) > 0
    assert all(i.startswith(("highd-01-ego", "highd-02-ego")) for i in ids)
    assert report.store.categories["EGO_VEHICLE"] == len(ids)
