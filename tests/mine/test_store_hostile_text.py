"""Text a program controls (error messages) is stored even when it is not valid UTF-8 (issue 12 B2)."""

from __future__ import annotations

from pathlib import Path

from scenariominer import api
from scenariominer.config import Config
from scenariominer.config.llm import EmbeddingConfig
from scenariominer.mine.export import RUNS_TABLE
from scenariominer.store import ScenarioStore


def test_a_lone_surrogate_in_an_error_does_not_lose_the_run(tmp_path: Path) -> None:
    cfg = Config(embedding=EmbeddingConfig(backend="hashing"))  # type: ignore[arg-type]
    api.synth(tmp_path / "synth", 1, seed=2)
    store = ScenarioStore.open(tmp_path / "store")
    assert not api.ingest([tmp_path / "synth"], store, cfg).failed
    # the category name reaches the error message unchanged: a lone surrogate, not encodable as UTF-8
    program = "x = get_objects_of_category(log_dir, category='no\\ud800such')\n"
    program += "output_scenario(x, description, log_dir)"
    result = api.mine(api.MineRequest("hostile text", store=store, program=program), cfg)
    assert result.report.failures and result.stored_logs == list(store.log_ids())
    runs = store.read_table(RUNS_TABLE).to_pylist()
    (row,) = [r for r in runs if r["description"] == "hostile text"]
    stored = str(row["error"])
    stored.encode("utf-8")  # valid UTF-8 now
    assert "no" in stored and "such" in stored
