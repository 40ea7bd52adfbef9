"""One recommendation with the real embedded model and the real embedder (slow)."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import pytest

from scenariominer.cbr.cases import Case, CaseBase
from scenariominer.cbr.recommend import Query, RecommendSettings, recommend
from scenariominer.cbr.vocab import load_manoeuvres, load_risk_types
from scenariominer.config import load_config
from scenariominer.llm.factory import make_chat_client, make_embedder
from scenariominer.store import ScenarioStore


@pytest.mark.slow
def test_real_model_recommends_a_configured_manoeuvre(tmp_path: Path) -> None:
    cfg = load_config(environ={})
    cfg = dataclasses.replace(
        cfg,
        llm=dataclasses.replace(cfg.llm, cache=False, prefix_cache=False),
        embedding=dataclasses.replace(cfg.embedding, cache=False),
    )
    store = ScenarioStore.open(tmp_path / "store")
    base = CaseBase(store, "cbr_cases", load_risk_types(), load_manoeuvres())
    embedder = make_embedder(cfg)
    base.add(
        [
            Case(
                "s1",
                "vehicle_ahead",
                "A car stopped in the lane 40 m ahead; the ego drives at 50 km/h.",
                "urban road",
                "ahead in the ego lane",
                "stopped",
                "the ego closes in on a stopped car",
                "emergency_braking",
                "braking stops the ego well before the car",
            ),
        ],
        embedder,
        0.97,
    )
    client = make_chat_client(cfg)
    try:
        rec = recommend(
            Query(
                "q1",
                "The ego drives at 45 km/h; a van is stopped in its lane about 35 m ahead.",
                "vehicle_ahead",
            ),
            base,
            client,
            embedder,
            RecommendSettings(k=1, max_field_chars=80, max_tokens=200),
        )
    finally:
        client.close()
    assert rec.manoeuvre in load_manoeuvres().names
    assert [r.case.case_id for r in rec.retrieved] == ["s1"]
    assert all(0 < len(rec.answer[f]) <= 80 for f in ("road_context", "event_context", "justification"))
    assert rec.latency_s > 0 and not rec.cached
