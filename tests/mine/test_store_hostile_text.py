"""Text a program controls (error messages) is stored even when it is not valid UTF-8 (issue 12 B2)."""

from __future__ import annotations

import dataclasses
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
    program = (
        "x = get_objects_of_category(log_dir, category='NO_SUCH')\noutput_scenario(x, description, log_dir)"
    )
    report = api.mine(api.MineRequest("hostile text", logs=(), store=store, program=program), cfg).report
    (failure,) = report.failures
    # an error text carrying a raw lone surrogate (a syntax error quoting a stray character does)
    hostile = dataclasses.replace(failure.error, message="invalid character '\ud800' (U+D800)")
    report = dataclasses.replace(report, failures=(dataclasses.replace(failure, error=hostile),))
    assert api.store_report(store, report) == list(store.log_ids())
    (row,) = [r for r in store.read_table(RUNS_TABLE).to_pylist() if r["description"] == "hostile text"]
    stored = str(row["error"])
    stored.encode("utf-8")  # valid UTF-8
    assert stored.startswith("runtime error: invalid character '")
