"""The command line: the documented command shapes work as written and fail with clear messages."""

from __future__ import annotations

import json
from pathlib import Path

from typer.testing import CliRunner

from scenariominer.cli import app
from scenariominer.store import ScenarioStore

runner = CliRunner()


def test_synth_ingest_info_round_trip(tmp_path: Path) -> None:
    out = tmp_path / "synth"
    result = runner.invoke(app, ["synth", "--out", str(out), "--n", "3"])
    assert result.exit_code == 0, result.output
    assert (out / "labels.csv").read_text().splitlines()[0].startswith("log_id,guest_id,scenario_category")
    store = tmp_path / "store"
    result = runner.invoke(app, ["ingest", str(out), "--store", str(store)])
    assert result.exit_code == 0, result.output
    assert "ingested 3 source(s)" in result.output
    result = runner.invoke(app, ["info", "--store", str(store)])
    assert result.exit_code == 0, result.output
    assert "EGO_VEHICLE" in result.output and "│ logs" in result.output


def test_ingest_of_a_missing_path_names_it(tmp_path: Path) -> None:
    result = runner.invoke(app, ["ingest", str(tmp_path / "nope"), "--store", str(tmp_path / "s")])
    assert result.exit_code == 1  # reported as a failed source, not a crash
    assert "nope" in result.output and "no such file" in result.output
    assert "Traceback" not in result.output


def test_store_defaults_to_the_environment_variable(tmp_path: Path) -> None:
    store = tmp_path / "envstore"
    ScenarioStore.open(store, create=True)
    result = runner.invoke(app, ["info", "--json"], env={"SCENARIOMINER_STORE": str(store)})
    assert result.exit_code == 0, result.output
    assert json.loads(result.output)["n_logs"] == 0


def test_info_never_creates_a_store(tmp_path: Path) -> None:
    store = tmp_path / "none"
    result = runner.invoke(app, ["info", "--store", str(store)])
    assert result.exit_code == 2
    assert "none" in result.output and not store.exists()


def test_bad_config_file_is_reported(tmp_path: Path) -> None:
    cfg = tmp_path / "c.toml"
    cfg.write_text("[preprocess]\nwindow = 3\n")
    result = runner.invoke(app, ["info", "--config", str(cfg), "--store", str(tmp_path / "s")])
    assert result.exit_code == 2
    assert "unknown key" in result.output


def test_store_check_and_vacuum(tmp_path: Path) -> None:
    store = ScenarioStore.open(tmp_path / "s", create=True)
    orphan = store.root / "logs" / "X" / "v1"
    orphan.mkdir(parents=True)
    (orphan / "tracks.parquet").write_bytes(b"partial")
    result = runner.invoke(app, ["store", "check", "--store", str(store.root), "--json"])
    assert result.exit_code == 0, result.output
    report = json.loads(result.output)
    assert report["ok"] and report["orphaned_files"] == ["logs/X/v1"]
    result = runner.invoke(app, ["store", "vacuum", "--store", str(store.root)])
    assert result.exit_code == 0 and "removed 1" in result.output
    assert not orphan.exists()
    result = runner.invoke(app, ["store", "check", "--store", str(tmp_path / "none")])
    assert result.exit_code == 2


def test_ingest_report_shows_real_repair_notes_not_placeholders(tmp_path: Path) -> None:
    from scenariominer.data.adapters.tabular import write_tabular
    from scenariominer.data.log import build_log

    log = build_log(
        log_id="short",
        track_id=["ego", "ego", "ego", "blip"],
        category=["EGO_VEHICLE", "EGO_VEHICLE", "EGO_VEHICLE", "PEDESTRIAN"],
        timestamp_ns=[0, 100_000_000, 200_000_000, 100_000_000],
        fields={
            "x_m": [0.0, 1.0, 2.0, 5.0],
            "y_m": [0.0] * 4,
            "yaw_rad": [0.0] * 4,
            "length_m": [4.0] * 4,
            "width_m": [2.0] * 4,
        },  # fmt: skip
        ego_track_id="ego",
        source="<test>",
        min_track_frames=1,
    )
    data = write_tabular([log], tmp_path / "fleet.csv")
    result = runner.invoke(app, ["ingest", str(data), "--store", str(tmp_path / "s")])
    assert result.exit_code == 0, result.output
    flat = " ".join(result.output.split())
    assert "repaired 1 log(s), e.g. short: dropped 1 track(s) with fewer than 2 frames" in flat
    assert " N " not in flat


def test_bad_paths_and_special_files_fail_alone_and_the_batch_goes_on(tmp_path: Path) -> None:
    import os

    good = tmp_path / "synth"
    assert runner.invoke(app, ["synth", "--out", str(good), "--n", "2"]).exit_code == 0
    loop = tmp_path / "loop"
    os.symlink(loop, loop)  # a symlink loop
    fifo_log = tmp_path / "fifo_log"
    first = sorted(p for p in good.iterdir() if p.is_dir())[0]
    fifo_log.mkdir()
    for f in first.iterdir():  # a copy of a real log whose annotation file is a FIFO
        if f.name != "annotations_with_ego.feather":
            os.symlink(f, fifo_log / f.name)
    os.mkfifo(fifo_log / "annotations_with_ego.feather")
    store = tmp_path / "s"
    args = ["ingest", str(tmp_path / "missing"), str(loop), str(fifo_log), str(good), "--store", str(store)]
    result = runner.invoke(app, [*args, "--json"])
    assert result.exit_code == 1
    report = json.loads(result.stdout)
    failed = {Path(r["key"]).name: r["error"] for r in report["failed"]}
    assert set(failed) == {"missing", "loop", "fifo_log"}
    assert "no such file" in failed["missing"] and "not a recognised log" in failed["fifo_log"]
    assert report["store"]["n_logs"] == 2  # the good logs landed


def test_a_fifo_among_a_sources_files_is_refused_without_being_opened(tmp_path: Path) -> None:
    import os

    import pytest

    from scenariominer.data.log import LogFormatError
    from scenariominer.data.sources import LogSource

    fifo = tmp_path / "01_tracks.csv"
    os.mkfifo(fifo)  # opening it for reading would block forever
    with pytest.raises(LogFormatError, match="not a regular file"):
        LogSource(str(tmp_path), "highd", tmp_path, (fifo,)).content_hash()
