"""Builders shared by the explain tests: hand-made pair tags, event records and small stores."""

from __future__ import annotations

import dataclasses
import json
import math
from collections.abc import Sequence
from pathlib import Path

import numpy as np
import pyarrow as pa

from scenariominer.data.log import Log, build_log
from scenariominer.events.segments import PAIR_FEATURES, PairTags
from scenariominer.explain.records import (
    EMBEDDINGS_TABLE,
    EVENTS_TABLE,
    RUNS_TABLE,
    EventRecord,
    events_table,
)
from scenariominer.llm import HashingEmbedder
from scenariominer.store import ScenarioStore
from scenariominer.store.vectors import embeddings_table
from scenariominer.tags.vocab import TAG_FAMILIES, names_to_codes

DT_NS = 100_000_000

#: A steady, uneventful pair: every feature's value for every frame.
CALM: dict[str, str] = {
    "ego.longitude": "CRUISING",
    "ego.latitude": "FACING_FORWARD",
    "guest.longitude": "CRUISING",
    "guest.latitude": "FACING_FORWARD",
    "pair.collision": "NO",
    "pair.heading": "SAME",
    "pair.position": "FRONT",
    "pair.distance": "MEDIUM",
    "pair.traj_overlap": "NO",
}


def runs(*parts: tuple[str, int]) -> list[str]:
    """Per-frame names from ``(name, n_frames)`` runs."""
    return [name for name, n in parts for _ in range(n)]


def make_pair(category: str, t: int = 30, **rows: list[str]) -> PairTags:
    """A pair over ``t`` frames: :data:`CALM` except the given rows (keys like ``pair_heading``)."""
    codes = []
    for feature in PAIR_FEATURES:
        names = rows.get(feature.key.replace(".", "_"), [CALM[feature.key]] * t)
        assert len(names) == t, feature.key
        codes.append(names_to_codes(TAG_FAMILIES[feature.family], np.asarray(names, dtype=object)))
    return PairTags(
        log_id="log",
        guest_id="guest",
        guest_category=category,
        timestamps_ns=np.arange(t, dtype=np.int64) * DT_NS,
        codes=np.stack(codes).astype(np.int8),
        frame_period_s=0.1,
        event_start_ns=10 * DT_NS,
        event_end_ns=20 * DT_NS,
    )


def record(log_id: str, guest_id: str, **changes: object) -> EventRecord:
    """An event record with plausible defaults."""
    base = EventRecord(
        event_id=f"{log_id}:{guest_id}:{10 * DT_NS}",
        log_id=log_id,
        guest_id=guest_id,
        guest_category="REGULAR_VEHICLE",
        start_ns=10 * DT_NS,
        end_ns=20 * DT_NS,
        start_s=1.0,
        end_s=2.0,
        window_start_ns=0,
        window_end_ns=29 * DT_NS,
        closest_ns=15 * DT_NS,
        n_frames=11,
        peak_collision="LOW",
        peak_traj_overlap="HIGH",
        min_ttc_s=2.0,
        min_distance_m=5.0,
        pet_s=1.0,
        headway_s=math.nan,
        peak_decel_mps2=2.0,
        tag_description="Overview: ...",
        baseline_category="not_relevant",
        rule_candidates="",
        facts="guest: regular vehicle",
        judge="hybrid",
        llm_category="",
        category="not_relevant",
        llm_status="ok",
        llm_description="",
        explanation="",
        llm_raw_answer="",
        llm_error="",
        llm_attempts=1,
        llm_latency_s=0.0,
        llm_model="scripted-model",
        prompt_version="test",
        categories_source="builtin",
        embedded_text="llm",
        embedding_model="",
        embedding_dim=0,
        notes="",
        fingerprint="fp",
    )
    return dataclasses.replace(base, **changes)  # type: ignore[arg-type]


def tiny_log(log_id: str, guest_ids: Sequence[str] = ("guest",), t: int = 30) -> Log:
    """A straight-driving ego with parked guests ahead (just enough to be stored)."""
    ts = np.arange(t, dtype=np.int64) * DT_NS
    ids = ["ego"] + list(guest_ids)
    n = len(ids)
    x = np.concatenate([np.linspace(0.0, 29.0, t)] + [np.full(t, 20.0 + 10 * i) for i in range(n - 1)])
    y = np.concatenate([np.zeros(t)] + [np.full(t, 3.0) for _ in range(n - 1)])
    return build_log(
        log_id=log_id,
        track_id=np.repeat(ids, t),
        category=np.repeat(["EGO_VEHICLE"] + ["REGULAR_VEHICLE"] * (n - 1), t),
        timestamp_ns=np.tile(ts, n),
        fields={
            "x_m": x,
            "y_m": y,
            "yaw_rad": np.zeros(n * t),
            "length_m": np.full(n * t, 4.5),
            "width_m": np.full(n * t, 2.0),
        },
        ego_track_id="ego",
        source="<test>",
        dataset="synthetic",
    )


def store_with_events(root: Path, records: Sequence[EventRecord], embedder: HashingEmbedder) -> ScenarioStore:
    """A store holding one tiny log per distinct log id of ``records``, with events and embeddings.

    Each record's embedded text is its ``llm_description``.
    """
    store = ScenarioStore.open(root)
    by_log: dict[str, list[EventRecord]] = {}
    for r in records:
        by_log.setdefault(r.log_id, []).append(r)
    logs = [tiny_log(log_id, sorted({r.guest_id for r in recs})) for log_id, recs in by_log.items()]
    store.replace_source("test", "hash", logs)
    for log_id, recs in by_log.items():
        emb = embedder.embed([r.llm_description for r in recs])
        recs = [dataclasses.replace(r, embedding_model=emb.model, embedding_dim=emb.dim) for r in recs]
        runs_row = {
            "fingerprint": ["fp"],
            "status": ["analyzed"],
            "complete": [True],
            "n_events": [len(recs)],
        }
        store.write_tables(
            log_id,
            {
                EVENTS_TABLE: events_table(recs),
                EMBEDDINGS_TABLE: embeddings_table([r.event_id for r in recs], emb.vectors, emb.model),
                RUNS_TABLE: pa.table(runs_row),
            },
        )
    return store


def answer(category: str, description: str = "d", explanation: str = "e") -> str:
    """A well-formed LLM answer."""
    return json.dumps({"description": description, "category": category, "explanation": explanation})
