"""Braking evaluation: labels file, Table IV-VI scores on hand-made predictions, and the store path."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pyarrow as pa
import pytest

from scenariominer.data.log import build_log
from scenariominer.eval.braking import (
    Label,
    LabelFileError,
    classification_scores,
    evaluate_braking,
    keyident_scores,
    read_labels,
    retrieval_row,
)
from scenariominer.explain.records import EMBEDDINGS_TABLE, EVENTS_SCHEMA, EVENTS_TABLE, RUNS_TABLE
from scenariominer.explain.search import NoEventsError
from scenariominer.llm import HashingEmbedder
from scenariominer.store import EmbeddingMismatchError, ScenarioStore
from scenariominer.store.vectors import embeddings_table

LABELS = (
    Label("L1", "a", "cut_in"),
    Label("L1", "b", "not_relevant"),
    Label("L2", "c", "lead_brake"),
    Label("L2", "d", "obj_crossing"),
)
# (log, guest, llm category, baseline category, embedded text); guest z is unlabelled, d is missed.
EVENTS = (
    ("L1", "a", "cut_in", "obj_crossing", "a car cuts in from the right"),
    ("L1", "b", "not_relevant", "cut_in", "a parked car at the kerb"),
    ("L1", "z", "obj_crossing", "not_relevant", "a bicycle crosses the street"),
    ("L2", "c", "unknown_but_relevant", "cut_in", "the lead vehicle suddenly brakes hard"),
    ("L2", "c", "cut_in", "cut_in", "the lead vehicle brakes again"),
)


def test_read_labels_ignores_extra_columns(tmp_path: Path) -> None:
    path = tmp_path / "labels.csv"
    path.write_text("log_id,guest_id,scenario_category,start_ns,note\nL1,a,cut_in,5,x\nL1,b,not_relevant,,\n")
    assert read_labels(path) == (Label("L1", "a", "cut_in"), Label("L1", "b", "not_relevant"))


@pytest.mark.parametrize(
    ("content", "problem"),
    [
        ("log_id,guest_id\nL1,a\n", "missing column"),
        ("log_id,guest_id,scenario_category\nL1,,cut_in\n", "line 2: empty guest_id"),
        ("log_id,guest_id,scenario_category\nL1,a,cut_in\nL1,a,obj_crossing\n", "labelled 'cut_in' and"),
    ],
)
def test_bad_label_files(tmp_path: Path, content: str, problem: str) -> None:
    path = tmp_path / "labels.csv"
    path.write_text(content)
    with pytest.raises(LabelFileError, match=problem):
        read_labels(path)
    with pytest.raises(LabelFileError, match="does not exist"):
        read_labels(tmp_path / "missing.csv")


def _predictions(column: int) -> dict[tuple[str, str], list[str]]:
    out: dict[tuple[str, str], list[str]] = {}
    for e in EVENTS:
        out.setdefault((e[0], e[1]), []).append(e[column])
    return out


def test_keyident_scores() -> None:
    rows, overall = keyident_scores(LABELS, list(_predictions(2)))
    assert [(r.category, r.n_labels, r.n_found) for r in rows] == [
        ("cut_in", 1, 1),
        ("lead_brake", 1, 1),
        ("obj_crossing", 1, 0),
        ("overall", 3, 2),
    ]
    # Detected pairs a, b, z, c: a and c are relevant labels; b (not_relevant) and z are not.
    assert overall.precision == pytest.approx(0.5)
    assert overall.recall == pytest.approx(2 / 3)


def test_classification_scores_side_by_side() -> None:
    cats = ["cut_in", "left_oppo", "right_ped", "obj_crossing"]
    rows = classification_scores(LABELS, {"rules": _predictions(3), "llm": _predictions(2)}, cats)
    by = {r.category: r for r in rows}
    llm = {c: r.scores["llm"] for c, r in by.items()}
    assert [r.category for r in rows] == [*cats, "overall"]
    assert (llm["cut_in"].tp, llm["cut_in"].fp, llm["cut_in"].fn) == (1, 1, 0)
    assert (by["cut_in"].baseline.tp, by["cut_in"].baseline.fp, by["cut_in"].baseline.fn) == (0, 2, 1)
    assert (llm["obj_crossing"].tp, llm["obj_crossing"].fp, llm["obj_crossing"].fn) == (0, 1, 1)
    assert math.isnan(llm["left_oppo"].precision) and math.isnan(llm["left_oppo"].recall)
    assert by["overall"].scores["llm"].precision == pytest.approx(1 / 3)
    assert by["overall"].scores["llm"].recall == pytest.approx(1 / 2)
    assert by["overall"].scores["llm"].f1 == pytest.approx(0.4)
    assert by["overall"].baseline.precision == 0.0 and by["overall"].baseline.f1 == 0.0


def test_retrieval_row() -> None:
    ranked = [("L1", "a"), ("L2", "c"), ("L1", "b")]
    row = retrieval_row(LABELS, ranked, "lead_brake", "q", k_precision=2, k_recall=1)
    assert row.n_relevant == 1
    assert row.precision_at_k == pytest.approx(0.5)
    assert row.recall_at_k == 0.0


def _store(root: Path, embedder: HashingEmbedder, incomplete: frozenset[str] = frozenset()) -> ScenarioStore:
    store = ScenarioStore.open(root)
    logs = []
    for log_id in ("L1", "L2", "L3"):
        t = np.arange(5, dtype=np.int64) * 100_000_000
        logs.append(
            build_log(
                log_id=log_id,
                track_id=["ego"] * 5,
                category=["EGO_VEHICLE"] * 5,
                timestamp_ns=t,
                fields={
                    "x_m": t * 1e-8,
                    "y_m": 0 * t,
                    "yaw_rad": 0 * t,
                    "length_m": 4 + 0 * t,
                    "width_m": 2 + 0 * t,
                },
                ego_track_id="ego",
                source="<test>",
            )
        )
    store.replace_source("src", "h", logs)
    for log_id in ("L1", "L2"):
        rows = [e for e in EVENTS if e[0] == log_id]
        columns = {f.name: [] for f in EVENTS_SCHEMA}
        for i, (_, guest, llm, base, _text) in enumerate(rows):
            for f in EVENTS_SCHEMA:
                default = {pa.string(): "", pa.int64(): 0, pa.float64(): 0.0}[f.type]
                columns[f.name].append(default)
            columns["event_id"][-1] = f"{log_id}:{guest}:{i}"
            columns["guest_id"][-1] = guest
            columns["category"][-1] = llm
            columns["baseline_category"][-1] = base
            columns["llm_status"][-1] = "ok"
        emb = embedder.embed([e[4] for e in rows])
        store.write_tables(
            log_id,
            {
                EVENTS_TABLE: pa.table(columns, schema=EVENTS_SCHEMA),
                EMBEDDINGS_TABLE: embeddings_table(columns["event_id"], emb.vectors, emb.model),
                RUNS_TABLE: pa.table({"fingerprint": ["f"], "complete": [log_id not in incomplete]}),
            },
        )
    return store


def test_evaluate_store(tmp_path: Path) -> None:
    embedder = HashingEmbedder(64)
    store = _store(tmp_path / "store", embedder)
    labels = (*LABELS, Label("L3", "e", "cut_in"), Label("L9", "f", "cut_in"))
    ev = evaluate_braking(
        store, labels, embedder, queries={"lead_brake": "lead vehicle brakes", "absent": "x"}
    )
    assert (ev.n_logs, ev.n_logs_not_analyzed, ev.n_labels, ev.n_events) == (2, 2, 4, 5)
    assert ev.llm_status == {"ok": 5}
    assert ev.keyident_overall.precision == pytest.approx(0.5)
    overall = ev.classification[-1]
    assert (overall.scores["llm"].tp, overall.scores["llm"].fp, overall.scores["llm"].fn) == (1, 2, 1)
    assert [r.category for r in ev.retrieval] == ["lead_brake"]
    lead = ev.retrieval[0]
    assert lead.precision_at_k == pytest.approx(0.1)  # 1 relevant pair among 10 slots
    assert lead.recall_at_k == 1.0
    assert ev.embedding_model == "hashing-64"
    data = ev.to_json_dict()
    assert data["classification"][1]["llm"]["precision"] is None  # left_oppo: nothing retrieved
    assert data["retrieval"][0]["p_at_10"] == 0.1
    top1 = evaluate_braking(
        store, labels, embedder, queries={"lead_brake": "lead vehicle brakes"}, k_precision=1
    )
    assert top1.retrieval[0].precision_at_k == 1.0
    with pytest.raises(EmbeddingMismatchError):
        evaluate_braking(store, labels, HashingEmbedder(32))
    no_text = evaluate_braking(store, labels, None)
    assert no_text.retrieval == ()


def test_only_complete_logs(tmp_path: Path) -> None:
    store = _store(tmp_path / "store", HashingEmbedder(16), incomplete=frozenset({"L2"}))
    ev = evaluate_braking(store, LABELS, None, only_complete=True)
    assert (ev.n_logs, ev.n_logs_not_analyzed, ev.n_labels, ev.n_events) == (1, 1, 2, 3)
    assert [(r.category, r.n_labels, r.n_found) for r in ev.keyident] == [("cut_in", 1, 1), ("overall", 1, 1)]
    assert evaluate_braking(store, LABELS, None).n_logs == 2


def test_unanalysed_store_is_a_clear_error(tmp_path: Path) -> None:
    with pytest.raises(NoEventsError, match="analyze"):
        evaluate_braking(ScenarioStore.open(tmp_path / "empty"), LABELS)
