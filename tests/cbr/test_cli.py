"""The cbr commands on a tiny store (hashing embedder, no model)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from typer.testing import CliRunner

from scenariominer.cli import app

runner = CliRunner()


@pytest.fixture
def env(tmp_path: Path) -> dict[str, str]:
    return {
        "SCENARIOMINER__EMBEDDING__BACKEND": "hashing",
        "SCENARIOMINER__EMBEDDING__CACHE": "false",
        "SCENARIOMINER_STORE": str(tmp_path / "store"),
    }


def test_add_list_show_remove_and_duplicates(tmp_path: Path, env: dict[str, str]) -> None:
    f = tmp_path / "cases.jsonl"
    rows = [
        {
            "case_id": "k1",
            "risk_type": "pedestrian",
            "caption": "a child runs out between parked cars",
            "manoeuvre": "emergency_braking",
        },
        {
            "case_id": "k2",
            "risk_type": "head_on",
            "caption": "a wrong-way van in the ego lane",
            "manoeuvre": "Evasive Steering Right",
        },
        {
            "case_id": "k3",
            "risk_type": "pedestrian",
            "caption": "A child runs out between parked cars.",
            "manoeuvre": "emergency_braking",
        },
        {"case_id": "k4", "risk_type": "pedestrian", "caption": "a man crosses", "manoeuvre": "teleport"},
    ]
    f.write_text("\n".join(json.dumps(r) for r in rows), encoding="utf-8")
    r = runner.invoke(app, ["cbr", "add", str(f)], env=env)
    assert r.exit_code == 0, r.output
    assert "added 2 case(s)" in r.output
    assert "near-duplicate k3 of k1" in r.output
    assert "rejected k4" in r.output and "unknown manoeuvre 'teleport'" in r.output
    r = runner.invoke(app, ["cbr", "list", "--json"], env=env)
    listed = json.loads(r.output)
    assert [c["case_id"] for c in listed] == ["k1", "k2"]
    assert listed[1]["manoeuvre"] == "evasive_steering_right"
    r = runner.invoke(app, ["cbr", "show", "k2"], env=env)
    assert "wrong-way van" in r.output
    r = runner.invoke(app, ["cbr", "remove", "k2"], env=env)
    assert r.exit_code == 0 and "removed 1 of 1" in r.output
    r = runner.invoke(app, ["cbr", "show", "k2"], env=env)
    assert r.exit_code == 2 and "no case 'k2'" in r.output
    runner.invoke(app, ["cbr", "remove", "k1"], env=env)
    r = runner.invoke(app, ["cbr", "list"], env=env)
    assert "0 case(s)" in r.output and "scenariominer cbr build" in r.output  # says how to fill it


def test_build_writes_balanced_case_base_and_disjoint_holdout(env: dict[str, str]) -> None:
    r = runner.invoke(app, ["cbr", "build", "--per-type", "4", "--holdout", "1", "--json"], env=env)
    assert r.exit_code == 0, r.output
    report = json.loads(r.output)
    assert report["n_holdout"] == 7
    assert report["n_case_base"] <= 21 and report["n_case_base"] >= 14
    assert set(report["labels"]) == {
        "vehicle_ahead",
        "pedestrian",
        "adjacent_vehicle",
        "merging_vehicle",
        "oncoming_vehicle",
        "head_on",
        "opposite_turning_vehicle",
    }
    r = runner.invoke(app, ["cbr", "list", "--json"], env=env)
    ids = {c["case_id"] for c in json.loads(r.output)}
    from scenariominer.cbr.build import read_holdout
    from scenariominer.store import ScenarioStore

    held = {h.case.case_id for h in read_holdout(ScenarioStore.open(env["SCENARIOMINER_STORE"]), "cbr_cases")}
    assert len(held) == 7 and not held & ids
