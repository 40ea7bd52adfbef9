"""One question answered by the real embedded model over a graph embedded with the real embedder (slow)."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import pytest

from scenariominer.api import ingest, open_store
from scenariominer.config import load_config
from scenariominer.config.represent import WindowConfig
from scenariominer.llm.factory import make_chat_client, make_embedder
from scenariominer.represent.ask import AskSettings, ask_graph, open_graph
from scenariominer.represent.graph_build import build_store_graph
from scenariominer.represent.pipeline import build_store_windows

from .helpers import write_highway


@pytest.mark.slow
def test_real_model_answers_with_citations_of_the_context(tmp_path: Path) -> None:
    cfg = load_config(environ={})
    cfg = dataclasses.replace(
        cfg,
        llm=dataclasses.replace(cfg.llm, cache=False, prefix_cache=False),
        embedding=dataclasses.replace(cfg.embedding, cache=False),
    )
    write_highway(tmp_path / "rec")
    store = open_store(tmp_path / "store")
    ingest([tmp_path / "rec"], store, cfg)
    build_store_windows(store, WindowConfig(lengths_s=(15.0,), overlap=0.0))
    embedder = make_embedder(cfg)
    build_store_graph(store, "windows", embedder)
    og = open_graph(store, "windows")
    client = make_chat_client(cfg)
    try:
        res = ask_graph(
            og.graph,
            og.index,
            "a vehicle changes lane to the left",
            embedder,
            client,
            AskSettings(k=3, max_tokens=200),
        )
    finally:
        client.close()
    assert res.llm_status == "answered", res.llm_status
    assert res.answer.strip()
    # graph retrieval with the real embedder ranks vehicle 7's own lane-change window first
    assert res.samples[0].window_id == "highd-01-ego7-w1|7|0|15000"
    ranked = {s.window_id for s in res.samples}
    assert set(res.cited_samples) <= ranked
    assert set(res.cited_relationships) <= {r for r, _ in res.context_relationships}
