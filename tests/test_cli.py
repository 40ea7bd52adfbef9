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
    assert result.exit_code == 2  # the user's to fix: one line, no traceback
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
