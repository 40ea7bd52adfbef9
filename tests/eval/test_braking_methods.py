"""KeyIdent recall per key-object method and noise level, on hand-built yields in a store."""

from __future__ import annotations

from pathlib import Path

import pyarrow as pa
from yield_scenarios import left_turn_yield, pedestrian_yield

from scenariominer.config import Config
from scenariominer.eval.braking import Label, resolve_aliases
from scenariominer.eval.braking_methods import keyident_by_method, read_noise_levels
from scenariominer.store import ScenarioStore
from scenariominer.tags.stitch import ALIAS_NOTE_PREFIX


def test_methods_side_by_side_with_noise_levels(tmp_path: Path) -> None:
    store = ScenarioStore.open(tmp_path / "store")
    ped = pedestrian_yield(split_at_s=3.0).build(smooth=True)  # an id switch on the key object
    turn = left_turn_yield()
    store.replace_source("src", "h", [ped, turn])
    labels = [
        Label("ped_yield", "ped", "ped_crossing"),
        Label("left_yield", "oncoming", "left_oppo"),
        Label("left_yield", "parked", "not_relevant"),
    ]
    levels = {"ped_yield": "high", "left_yield": "clean"}
    scores = {(m.method, m.noise_level): m for m in keyident_by_method(store, labels, Config(), levels)}
    assert set(scores) == {
        (m, lv) for m in ("tags", "counterfactual", "combined") for lv in ("all", "clean", "high")
    }
    recall = {key: {r.category: r.n_found for r in m.rows} for key, m in scores.items()}
    assert recall[("tags", "all")] == {"left_oppo": 0, "ped_crossing": 0, "overall": 0}
    assert recall[("counterfactual", "all")] == {"left_oppo": 1, "ped_crossing": 1, "overall": 2}
    assert recall[("combined", "high")] == {"ped_crossing": 1, "overall": 1}
    assert scores[("combined", "all")].overall.fp == 0  # neither the parked car nor the id ped_b


def test_noise_levels_are_optional(tmp_path: Path) -> None:
    with_level = tmp_path / "a.csv"
    with_level.write_text("log_id,guest_id,scenario_category,noise_level\nL1,g,cut_in,low\n")
    without = tmp_path / "b.csv"
    without.write_text("log_id,guest_id,scenario_category\nL1,g,cut_in\n")
    assert read_noise_levels(with_level) == {"L1": "low"}
    assert read_noise_levels(without) == {}


def test_stitched_aliases_count_once_as_the_labelled_pair() -> None:
    events = pa.table(
        {
            "log_id": ["L1", "L1", "L1"],
            "guest_id": ["a", "c", "d"],
            "category": ["cut_in", "lead_brake", "cut_in"],
            "notes": [f"{ALIAS_NOTE_PREFIX}b", "", f"{ALIAS_NOTE_PREFIX}e,f"],
        }
    )
    resolved = resolve_aliases(events, {("L1", "b"), ("L1", "c")})
    assert resolved.column("guest_id").to_pylist() == ["b", "c", "d"]
    assert resolved.column("category").to_pylist() == ["cut_in", "lead_brake", "cut_in"]
