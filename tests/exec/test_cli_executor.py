"""``--executor``, ``--workers`` and ``--ray-address`` on ingest, analyze and mine (a real CLI subprocess)."""

from __future__ import annotations

import importlib.util
import json
import subprocess
import sys
from pathlib import Path

import pyarrow as pa
import pyarrow.compute as pc
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


def _stored(store: str) -> dict[str, pa.Table]:
    """The tables the three commands wrote, without the columns that time the run."""
    st = ScenarioStore.open(store, create=False)
    out = {}
    for name in ("events", "mining_results", "mining_runs"):
        table = st.read_table(name)
        keep = [
            c for c in table.column_names if c not in {"seconds", "analyzed_at", "execution_s", "mined_at"}
        ]
        table = table.select(keep)
        for i, field in enumerate(table.schema):  # NaN != NaN in Table.equals: compare NaN as null
            if pa.types.is_floating(field.type):
                table = table.set_column(
                    i, field, pc.if_else(pc.is_nan(table.column(i)), None, table.column(i))
                )
        out[name] = table.sort_by(
            [(c, "ascending") for c in keep if pa.types.is_string(table.schema.field(c).type)]
        )
    return out


def test_ingest_analyze_mine_store_the_same_on_every_executor(workspace: Path) -> None:
    stored = {}
    executors = ["local", "process"] + (["ray"] if importlib.util.find_spec("ray") else [])
    for executor in executors:
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
        stored[executor] = _stored(store)
        assert stored[executor]["mining_runs"].num_rows == 6 and stored[executor]["events"].num_rows > 0
    for executor in executors[1:]:
        for name, table in stored["local"].items():
            assert stored[executor][name].equals(table), (executor, name)


def test_an_unknown_executor_is_a_config_error(workspace: Path) -> None:
    run = _cli("ingest", str(workspace / "logs"), "--store", str(workspace / "s"), "--executor", "dask")
    assert run.returncode == 2
    assert "executor must be one of local, process, ray, got 'dask'" in " ".join(run.stderr.split())
