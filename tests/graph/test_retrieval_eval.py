"""Retrieval evaluation: ground truth from a highD-format recording, rules, metrics, both designs."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from scenariominer.api import ingest, open_store
from scenariominer.config import load_config
from scenariominer.config.represent import WindowConfig
from scenariominer.eval.scenario_retrieval import (
    CATEGORIES,
    RuleError,
    compile_rule,
    design_summary,
    evaluate_retrieval,
    load_queries,
    ndcg_at_k,
    score_ranking,
    store_window_truth,
)
from scenariominer.represent.graph import load_graph
from scenariominer.represent.graph_build import build_store_graph
from scenariominer.represent.pipeline import build_store_windows
from scenariominer.store import ScenarioStore
from scenariominer.testing import HashingEmbedder

from .helpers import write_highway

EMBEDDER = HashingEmbedder(256)


@pytest.fixture(scope="module")
def highway_store(tmp_path_factory: pytest.TempPathFactory) -> ScenarioStore:
    """The hand-built 60 s recording, ingested, cut into 15 s windows, with its graph."""
    root = tmp_path_factory.mktemp("highway")
    write_highway(root / "rec")
    store = open_store(root / "store")
    ingest([root / "rec"], store, load_config())
    build_store_windows(store, WindowConfig(lengths_s=(15.0,), overlap=0.0))
    build_store_graph(store, "windows", EMBEDDER)
    return store


def test_truth_comes_from_the_recording(highway_store: ScenarioStore) -> None:
    truth = store_window_truth(highway_store, load_graph(highway_store, "windows").samples)
    assert len(truth) == 24  # 6 vehicles x 4 windows of 15 s
    # vehicle 7 moves from lane 8 (right) to lane 7 (middle) between 20 s and 24 s: only its
    # second window holds the change
    lefts = {w for w, t in truth.items() if t["lane_changes_left"] == 1}
    assert lefts == {"highd-01-ego7-w1|7|0|15000"}
    assert all(t["lane_changes_right"] == 0 and t["road_lanes"] == 3 for t in truth.values())
    # vehicles 2 and 4 drive in lane 6, the left lane of the lower carriageway
    left_lane = {w.split("|")[0].split("-")[2] for w, t in truth.items() if t["lane_position"] == 2}
    assert left_lane == {"ego2", "ego4"}


def test_frames_follow_the_recording_frame_rate(tmp_path: Path) -> None:
    # SUMO-made recordings run at 10 Hz: descriptions cite, and truth reads, the recording's frames
    write_highway(tmp_path / "rec", frame_rate_hz=10.0)
    store = open_store(tmp_path / "store")
    ingest([tmp_path / "rec"], store, load_config())
    build_store_windows(store, WindowConfig(lengths_s=(15.0,), overlap=0.0))
    build_store_graph(store, "windows", EMBEDDER)
    samples = load_graph(store, "windows").samples
    second = next(s for s in samples if str(s["window_id"]).startswith("highd-01-ego7-w1"))
    assert (second["start_frame"], second["end_frame"]) == (151, 301)  # highD frames count from 1
    assert "7.2 s (frame 223)" in str(second["text"])  # the lane change at 22.2 s in the recording
    truth = store_window_truth(store, samples)
    assert len(truth) == 24
    assert {w for w, t in truth.items() if t["lane_changes_left"] == 1} == {"highd-01-ego7-w1|7|0|15000"}


def test_rules_are_checked_and_evaluated() -> None:
    judge = compile_rule("lane_changes_left >= 1 and not (road_lanes == 2) or abs(accel_mps2) > 3")
    assert judge({"lane_changes_left": 1, "road_lanes": 3, "accel_mps2": 0.0})
    assert not judge({"lane_changes_left": 1, "road_lanes": 2, "accel_mps2": -1.0})
    assert judge({"lane_changes_left": 0, "road_lanes": 2, "accel_mps2": -4.0})
    with pytest.raises(RuleError, match="unknown field 'speed'"):
        compile_rule("speed > 3")
    with pytest.raises(RuleError, match="not allowed"):
        compile_rule("road_lanes.__class__ == 1")
    with pytest.raises(RuleError, match="not an expression"):
        compile_rule("road_lanes ==")


def test_the_shipped_queries_have_the_structure_of_table_1() -> None:
    queries = load_queries()
    assert len(queries) == 33
    cells = {(q.category, q.level) for q in queries}
    assert cells == {(c, lv) for c in CATEGORIES for lv in (1, 2, 3)}
    splits = {q.split for q in queries}
    assert splits == {"dev", "test"}


def test_a_malformed_query_file_names_the_cause(tmp_path: Path) -> None:
    bad = tmp_path / "q.toml"
    bad.write_text(
        '[[query]]\nid = "a"\ncategory = "weather"\nlevel = 1\ntext = "x"\nrule = "road_lanes == 2"\n'
    )
    with pytest.raises(RuleError, match="category/level/split weather/1"):
        load_queries(bad)
    with pytest.raises(RuleError, match="cannot read query file"):
        load_queries(tmp_path / "missing.toml")


def test_ranking_metrics_on_known_rankings() -> None:
    assert ndcg_at_k(["a", "b", "c"], {"b"}, 3) == pytest.approx(1 / math.log2(3))
    assert ndcg_at_k(["b", "a"], {"b"}, 2) == pytest.approx(1.0)
    assert math.isnan(ndcg_at_k(["a"], set(), 1))
    s = score_ranking("q", "d", ["x", "a", "y", "b", "z", "c"], {"a", "b", "c", "w"}, ks=(5, 10))
    assert s.precision_at_5 == pytest.approx(2 / 5)
    assert s.recall == {5: pytest.approx(0.5), 10: pytest.approx(0.75)}


def test_both_designs_are_scored_and_queries_without_relevant_windows_skipped(
    highway_store: ScenarioStore, tmp_path: Path
) -> None:
    qfile = tmp_path / "q.toml"
    qfile.write_text(
        '[[query]]\nid = "left"\ncategory = "ego"\nlevel = 1\ntext = "a lane change to the left"\n'
        'rule = "lane_changes_left >= 1"\n\n'
        '[[query]]\nid = "leftlane"\ncategory = "infrastructure"\nlevel = 1\nsplit = "dev"\n'
        'text = "vehicles in the left lane"\nrule = "lane_position == 2"\n\n'
        '[[query]]\nid = "two"\ncategory = "general"\nlevel = 1\ntext = "a two-lane road"\n'
        'rule = "road_lanes == 2"\n'
    )
    ev = evaluate_retrieval(highway_store, {"windows": "windows"}, EMBEDDER, load_queries(qfile), k_max=24)
    assert ev.designs == ("windows/graph", "windows/vector")
    assert ev.skipped == ("two",)
    assert ev.n_windows == 24 and ev.n_with_truth == 24
    by = {(s.design, s.query_id): s for s in ev.scores}
    assert {k[1] for k in by} == {"left", "leftlane"}
    assert by["windows/vector", "left"].n_relevant == 1
    assert by["windows/graph", "leftlane"].n_relevant == 8
    # every window is ranked (k_max = all), so Recall@24 is complete for both designs
    assert all(s.recall[100] == pytest.approx(1.0) for s in ev.scores)
    rows = design_summary(ev)
    assert [r["design"] for r in rows] == ["windows/graph", "windows/vector"]
    assert ev.grid("windows/graph", "test") == {("ego", 1): by["windows/graph", "left"].precision_at_5}
