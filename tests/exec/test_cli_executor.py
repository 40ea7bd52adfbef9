"""``--executor``, ``--workers`` and ``--ray-address`` on ingest, analyze and mine (a real CLI subprocess)."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from scenariominer import api
from scenariominer.store import ScenarioStore


def _cli(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "scenariominer", *args],
        capture_output=True,
        text=True,
        timeout=300,
        check=False,
    )


@pytest.fixture(scope="module")
def workspace(tmp_path_factory: pytest.TempPathFactory) -> Path:
    root = tmp_path_factory.mktemp("cli")
    api.synth(root / "logs", 6, seed=9)
    cfg = '[embedding]\nbackend = "hashing"\nhashing_dim = 16\n[exec]\nmin_items = 1\n'
    (root / "cfg.toml").write_text(cfg)
    return root


@pytest.mark.parametrize("executor", ["local", "process"])
def test_ingest_analyze_mine_on_an_executor(workspace: Path, executor: str) -> None:
    store, cfg = str(workspace / f"store-{executor}"), str(workspace / "cfg.toml")
    common = ["--store", store, "--config", cfg, "--executor", executor, "--workers", "2"]
    ingest = _cli("ingest", str(workspace / "logs"), *common, "--json")
    assert ingest.returncode == 0, ingest.stderr
    assert json.loads(ingest.stdout)["store"]["n_logs"] == 6
    analyze = _cli("analyze", *common, "--no-llm", "--json")
    assert analyze.returncode == 0, analyze.stderr
    assert {r["status"] for r in json.loads(analyze.stdout)["logs"]} == {"analyzed"}
    mine = _cli("mine", "vehicle braking hard", *common, "--json")
    assert mine.returncode == 0, mine.stderr
    assert json.loads(mine.stdout)["n_logs"] == 6
    st = ScenarioStore.open(store, create=False)
    assert len(st.log_ids()) == 6 and st.read_table("mining_runs").num_rows == 6


def test_an_unknown_executor_is_a_config_error(workspace: Path) -> None:
    run = _cli("ingest", str(workspace / "logs"), "--store", str(workspace / "s"), "--executor", "dask")
    assert run.returncode == 2
    assert "executor must be one of local, process, ray, got 'dask'" in " ".join(run.stderr.split())
