"""Graph build over a store, asking with a fake embedder and a scripted model, summaries cache."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from scenariominer.config.represent import WindowConfig
from scenariominer.llm.client import ChatClient
from scenariominer.represent.ask import AskSettings, ask_graph, open_graph
from scenariominer.represent.graph import ELEMENTS_TABLE, GRAPH_SCHEMA, SAMPLES_TABLE, load_graph
from scenariominer.represent.graph_build import build_store_graph, load_communities
from scenariominer.represent.graph_store import GraphNotBuiltError
from scenariominer.represent.summaries import SummarySettings, cluster_summaries, load_summaries
from scenariominer.represent.window_table import save_logs_windows
from scenariominer.store import ScenarioStore
from scenariominer.testing import HashingEmbedder, ScriptedBackend

from .helpers import Agent, window_of

EMBEDDER = HashingEmbedder(256)
CONFIG = WindowConfig(lengths_s=(15.0,), n_steps=31, k_neighbours=3)
PLANTED = "highd-01-ego1-w0"


def _windows(log_id: str, kind: str):  # type: ignore[no-untyped-def]
    ego = log_id.split("-ego")[1].split("-")[0]
    if kind == "left":
        agents = [
            Agent(ego, 0.0, 30.0, 8, change_at_step=12, change_lanes=1),
            Agent("90", 200.0, 30.0, 6, y0_m=7.6),
        ]
    else:
        agents = [Agent(ego, 0.0, 22.0, 7), Agent("91", 30.0, 22.0, 7), Agent("92", 10.0, 22.0, 6, y0_m=3.8)]
    return window_of(agents, log_id=log_id)


def _store(tmp_path: Path, logs: dict[str, str]) -> ScenarioStore:
    store = ScenarioStore.open(tmp_path / "store")
    _add(store, logs)
    return store


def _add(store: ScenarioStore, logs: dict[str, str]) -> None:
    save_logs_windows(store, {lid: (_windows(lid, kind), "h1") for lid, kind in logs.items()}, CONFIG)


FOLLOWING = {f"highd-01-ego{i}-w0": "follow" for i in range(2, 7)}


def test_ask_returns_the_planted_sample_first_and_checks_the_citations(tmp_path: Path) -> None:
    store = _store(tmp_path, {PLANTED: "left", **FOLLOWING})
    report = build_store_graph(store, "windows", EMBEDDER)
    assert report.n_samples == 6 and report.n_logs_built == 6 and not report.failed
    og = open_graph(store, "windows")
    reply = {
        "answer": "Vehicle 1 changes from lane 8 to lane 7 to the left at frame 151 [S1][R1].",
        "samples": [1],
        "relationships": [1],
        "reports": [4],
    }
    backend = ScriptedBackend([json.dumps(reply)])
    res = ask_graph(
        og.graph, og.index, "lane change to the left", EMBEDDER, ChatClient(backend), AskSettings(k=3)
    )
    planted_window = f"{PLANTED}|1|0|15000"
    assert res.samples[0].window_id == planted_window
    assert res.samples[0].track_ids == ("1", "90") and res.samples[0].start_frame == 1
    assert res.cited_samples == (planted_window,)
    assert res.cited_entities == (f"S:{planted_window}", f"V:{PLANTED}/1")
    assert res.cited_relationships == (res.context_relationships[0][0],)
    assert "changes lane" in res.context_relationships[0][1]
    assert res.invalid_citations == ("C4",)
    assert res.answer == reply["answer"] and res.llm_status == "answered"
    prompt = backend.requests[0].messages[-1].content
    assert "[S1] Sample " + planted_window in prompt and "[R1]" in prompt
    # the plain vector baseline over the descriptions works on the same index
    plain = og.index.search(
        EMBEDDER.embed(["lane change to the left"]).vectors[0], AskSettings(k=6, graph=False)
    )
    assert len(plain.samples) == 6 and plain.relationships == ()


def test_adding_a_log_extends_the_graph_without_recomputing_the_rest(tmp_path: Path) -> None:
    store = _store(tmp_path, FOLLOWING)
    first = build_store_graph(store, "windows", EMBEDDER)
    key = "windows|highd-01-ego2-w0"
    before = {t: store.corpus(t, GRAPH_SCHEMA).get(key).version for t in (SAMPLES_TABLE, ELEMENTS_TABLE)}  # type: ignore[union-attr]
    _add(store, {PLANTED: "left"})
    second = build_store_graph(store, "windows", EMBEDDER)
    assert (first.n_logs_built, second.n_logs_built) == (5, 1)
    assert second.n_samples == first.n_samples + 1 and second.n_logs == 6
    after = {t: store.corpus(t, GRAPH_SCHEMA).get(key).version for t in (SAMPLES_TABLE, ELEMENTS_TABLE)}  # type: ignore[union-attr]
    assert after == before
    graph = load_graph(store, "windows")
    assert f"V:{PLANTED}/1" in graph.entity_index()
    levels = load_communities(store, "windows")
    assert len(levels) == 3 and all(f"V:{PLANTED}/1" in lv.membership for lv in levels)
    assert build_store_graph(store, "windows", EMBEDDER).n_logs_built == 0


def test_cluster_summaries_use_the_nearest_samples_and_are_cached(tmp_path: Path) -> None:
    logs = {PLANTED: "left", **FOLLOWING}
    store = _store(tmp_path, logs)
    build_store_graph(store, "windows", EMBEDDER)
    graph = load_graph(store, "windows")
    wids = np.asarray([str(s["window_id"]) for s in graph.samples])
    z = np.asarray([[0.0, 0.0], [5.0, 5.0], [1.0, 0.0], [0.0, 1.0], [9.0, 9.0], [9.5, 9.0]], np.float32)
    labels = np.asarray([0, 1, 0, 0, 1, 1], np.int64)
    summary = {"title": "steady following", "traffic": "moderate, 22 m/s", "behaviour": "vehicles keep lanes"}
    contrast = {"others": "lane changes", "difference": "no lane change"}
    backend = ScriptedBackend([json.dumps(summary), json.dumps(contrast)] * 2)
    settings = SummarySettings(n_neighbours=2, n_contrast=1)
    out = cluster_summaries(store, graph, wids, z, labels, ChatClient(backend), EMBEDDER, settings)
    assert [(s.kind, s.subject) for s in out] == [
        ("cluster", "0"),
        ("contrast", "0"),
        ("cluster", "1"),
        ("contrast", "1"),
    ]
    # cluster 0's centre is (1/3, 1/3): its two nearest members are rows 0 and 2 or 3, never row 1
    assert len(out[0].window_ids) == 2 and wids[1] not in out[0].window_ids
    assert not any(s.cached for s in out)
    again = cluster_summaries(
        store, graph, wids, z, labels, ChatClient(ScriptedBackend([])), EMBEDDER, settings
    )
    assert all(s.cached for s in again) and [s.text for s in again] == [s.text for s in out]
    stored, vectors = load_summaries(store, "windows")
    assert len(stored) == 4 and vectors.shape == (4, 256)


def test_asking_an_unbuilt_graph_names_the_command(tmp_path: Path) -> None:
    store = ScenarioStore.open(tmp_path / "store")
    with pytest.raises(GraphNotBuiltError, match="graph build"):
        open_graph(store, "windows")


def test_a_garbled_summary_answer_costs_that_summary_only(tmp_path: Path) -> None:
    store = _store(tmp_path, {PLANTED: "left", **FOLLOWING})
    build_store_graph(store, "windows", EMBEDDER)
    graph = load_graph(store, "windows")
    wids = np.asarray([str(s["window_id"]) for s in graph.samples])
    z = np.asarray([[0.0, 0.0], [5.0, 5.0], [1.0, 0.0], [0.0, 1.0], [9.0, 9.0], [9.5, 9.0]], np.float32)
    labels = np.asarray([0, 1, 0, 0, 1, 1], np.int64)
    # a raw line break inside a JSON string (small models write them) is accepted
    summary = '{"title": "steady\nfollowing", "traffic": "moderate", "behaviour": "lanes kept"}'
    contrast = json.dumps({"others": "lane changes", "difference": "no lane change"})
    garbage = "the cluster is about cars"  # no JSON: the client's two attempts both fail
    backend = ScriptedBackend([garbage, garbage, summary, contrast])
    settings = SummarySettings(n_neighbours=2, n_contrast=1)
    failures: list[tuple[str, str]] = []
    out = cluster_summaries(
        store, graph, wids, z, labels, ChatClient(backend), EMBEDDER, settings, failures=failures
    )
    assert [(s.kind, s.subject) for s in out] == [("cluster", "1"), ("contrast", "1")]
    assert out[0].title == "steady\nfollowing"
    assert [subject for subject, _why in failures] == ["cluster 0 summary"]
    assert "not valid JSON" in failures[0][1]
    # the next build asks only for what is missing
    again = cluster_summaries(
        store, graph, wids, z, labels, ChatClient(ScriptedBackend([summary, contrast])), EMBEDDER, settings
    )
    assert [(s.subject, s.cached) for s in again] == [("0", False), ("0", False), ("1", True), ("1", True)]
