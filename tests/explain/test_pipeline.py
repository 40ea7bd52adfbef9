"""The pipeline end to end on synthetic logs with a scripted LLM: tables, incrementality, limit, bad input."""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np
import pytest

from scenariominer import api
from scenariominer.config import Config
from scenariominer.config.tags import StitchConfig, TagConfig
from scenariominer.data.log import Log, build_log
from scenariominer.data.preprocess import preprocess
from scenariominer.explain import pipeline
from scenariominer.explain.categories import load_categories
from scenariominer.explain.pipeline import LogStatus, analyze_store
from scenariominer.explain.records import EMBEDDINGS_TABLE, EVENTS_TABLE, RUNS_TABLE, TAGS_TABLE
from scenariominer.llm import ChatClient, ChatRequest, HashingEmbedder, ResponseCache
from scenariominer.store import ScenarioStore
from scenariominer.synth import ScenarioLabel, read_labels
from scenariominer.testing import ScriptedBackend

CATEGORIES = ["cut_in", "left_oppo", "right_ped", "not_relevant"]


def _reply(request: ChatRequest) -> str:
    """A deterministic fake LLM: picks the first allowed category the facts suggest."""
    text = request.messages[-1].content
    allowed = re.findall(r"Allowed categories: (.*)\.$", text, re.MULTILINE)
    options = allowed[0].split(", ") if allowed else re.findall(r"The category is (\w+);", text)
    if "ego manoeuvre: turns left" in text or "ego manoeuvre: veers left" in text:
        preferred = "left_oppo"
    elif "guest: pedestrian" in text:
        preferred = "right_ped"
    else:
        preferred = "cut_in"
    category = preferred if preferred in options else options[0]
    return json.dumps(
        {
            "description": f"The guest makes the ego brake ({category}).",
            "category": category,
            "explanation": "e",
        }
    )


def _client(reply: object = _reply, cache: ResponseCache | None = None) -> tuple[ChatClient, ScriptedBackend]:
    backend = ScriptedBackend([reply] * 200)  # type: ignore[list-item]
    return ChatClient(backend, cache=cache), backend


@pytest.fixture(scope="module")
def synth_dir(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("synth")
    api.synth(out, len(CATEGORIES), seed=3, categories=CATEGORIES)
    return out


@pytest.fixture
def store(synth_dir: Path, tmp_path: Path) -> ScenarioStore:
    st = ScenarioStore.open(tmp_path / "store")
    report = api.ingest([synth_dir], st, Config())
    assert not report.failed
    return st


def _labels(synth_dir: Path) -> dict[tuple[str, str], str]:
    labels: tuple[ScenarioLabel, ...] = read_labels(synth_dir / "labels.csv")
    return {(lab.log_id, lab.guest_id): lab.scenario_category.value for lab in labels}


def test_end_to_end_tables(store: ScenarioStore, synth_dir: Path) -> None:
    client, backend = _client()
    report = analyze_store(store, Config(), client, HashingEmbedder(32))
    assert report.n_analyzed == len(CATEGORIES) and report.n_failed == 0
    events = store.read_table(EVENTS_TABLE).to_pylist()
    assert len(events) == report.n_events == len(backend.requests) == report.n_llm_calls
    found = {(e["log_id"], e["guest_id"]) for e in events}
    for pair, category in _labels(synth_dir).items():
        if category != "not_relevant":
            assert pair in found, category
    llm: dict[tuple[str, str], set[str]] = {}
    baseline: dict[tuple[str, str], set[str]] = {}
    for e in events:
        llm.setdefault((e["log_id"], e["guest_id"]), set()).add(e["category"])
        baseline.setdefault((e["log_id"], e["guest_id"]), set()).add(e["baseline_category"])
    for pair, category in _labels(synth_dir).items():
        if category in ("left_oppo", "right_ped"):  # a pair may have several events
            assert category in llm[pair] and category in baseline[pair]
    for e in events:
        assert e["llm_status"] == "ok" and e["embedded_text"] == "llm" and e["judge"] == "hybrid"
        assert "smallest gap:" in e["facts"] and e["facts"].startswith("guest: ")
        if "," not in e["rule_candidates"] and e["rule_candidates"]:  # the rules decided
            assert e["category"] == e["baseline_category"] and e["llm_category"] == ""
        assert e["tag_description"].startswith("Overview: a ")
        assert e["peak_decel_mps2"] > 0.5
        assert e["window_start_ns"] <= e["start_ns"] <= e["closest_ns"] <= e["end_ns"] <= e["window_end_ns"]
        assert e["embedding_model"] == "hashing-32" and e["embedding_dim"] == 32
        assert e["fingerprint"] == report.fingerprint
    emb = store.read_table(EMBEDDINGS_TABLE)
    assert sorted(emb.column("item_id").to_pylist()) == sorted(e["event_id"] for e in events)
    runs = store.read_table(RUNS_TABLE).to_pylist()
    assert {r["status"] for r in runs} == {"analyzed"} and all(r["complete"] for r in runs)
    assert set(store.read_table(TAGS_TABLE).column("log_id").to_pylist()) == set(store.log_ids())


def test_rerun_skips_current_logs_and_force_uses_the_cache(store: ScenarioStore, tmp_path: Path) -> None:
    cache = ResponseCache.in_dir(tmp_path / "cache")
    client, backend = _client(cache=cache)
    first = analyze_store(store, Config(), client, HashingEmbedder(32))
    calls = len(backend.requests)
    again = analyze_store(store, Config(), client, HashingEmbedder(32))
    assert again.n_unchanged == len(CATEGORIES) and again.n_events == 0
    assert len(backend.requests) == calls
    forced = analyze_store(store, Config(), client, HashingEmbedder(32), force=True)
    assert forced.n_analyzed == len(CATEGORIES)
    assert forced.n_llm_calls == 0 and len(backend.requests) == calls  # every answer from the cache
    assert forced.n_events == first.n_events
    other_model = analyze_store(store, Config(), client, HashingEmbedder(16))
    assert other_model.n_analyzed == len(CATEGORIES)  # a new embedder changes the fingerprint


def test_limit_leaves_events_pending_and_a_later_run_finishes_them(store: ScenarioStore) -> None:
    client, backend = _client()
    first = analyze_store(store, Config(), client, HashingEmbedder(32), limit=1)
    assert first.n_llm_calls == 1 and first.n_pending == first.n_events - 1
    events = store.read_table(EVENTS_TABLE).to_pylist()
    pending = [e for e in events if e["llm_status"] == "pending"]
    assert len(pending) == first.n_events - 1
    # the rules' result is stored at once; the LLM's part waits for a later run
    assert all(e["category"] == e["baseline_category"] and e["explanation"] for e in pending)
    assert all(e["embedded_text"] == "tags" and e["llm_model"] == "" for e in pending)
    second = analyze_store(store, Config(), client, HashingEmbedder(32))
    assert second.n_pending == 0
    assert "pending" not in store.read_table(EVENTS_TABLE).column("llm_status").to_pylist()
    assert len(backend.requests) == 1 + second.n_llm_calls


def test_garbage_answers_are_recorded_and_do_not_stop_the_batch(store: ScenarioStore) -> None:
    client, _ = _client(reply="no idea, sorry")
    report = analyze_store(store, Config(), client, HashingEmbedder(32))
    assert report.n_failed == 0 and report.n_invalid == report.n_events > 0
    events = store.read_table(EVENTS_TABLE).to_pylist()
    assert {e["category"] for e in events} == {"invalid"}
    assert all(e["llm_raw_answer"] == "no idea, sorry" and e["embedded_text"] == "tags" for e in events)
    assert all("invalid" in e["notes"] for e in events)


def _log(log_id: str, ego_x: np.ndarray, guests: dict[str, tuple[np.ndarray, np.ndarray, np.ndarray]]) -> Log:
    """Ego along +x at positions ``ego_x`` (10 Hz); guests as (frame indices, x, y)."""
    t = ego_x.size
    ts = np.arange(t, dtype=np.int64) * 100_000_000
    ids, cats, stamps, xs, ys = ["ego"] * t, ["EGO_VEHICLE"] * t, [ts], [ego_x], [np.zeros(t)]
    for gid, (frames, x, y) in guests.items():
        ids += [gid] * frames.size
        cats += ["REGULAR_VEHICLE"] * frames.size
        stamps.append(ts[frames])
        xs.append(x)
        ys.append(y)
    x_all = np.concatenate(xs)
    log = build_log(
        log_id=log_id,
        track_id=ids,
        category=cats,
        timestamp_ns=np.concatenate(stamps),
        fields={
            "x_m": x_all,
            "y_m": np.concatenate(ys),
            "yaw_rad": np.zeros(x_all.size),
            "length_m": np.full(x_all.size, 4.5),
            "width_m": np.full(x_all.size, 2.0),
        },
        ego_track_id="ego",
        source="<test>",
    )
    return preprocess(log)


def test_bad_input_is_recorded_per_log(store: ScenarioStore, monkeypatch: pytest.MonkeyPatch) -> None:
    t = np.arange(60) * 0.1
    parked = _log("parked-ego", np.zeros(60), {"car": (np.arange(60), np.full(60, 8.0), np.zeros(60))})
    # The ego brakes from 10 m/s at 3 m/s^2; a car appears right in its path for two frames.
    braking_x = 10.0 * t - 1.5 * t**2
    flash = _log(
        "flash-guest", braking_x, {"ghost": (np.array([20, 21]), np.array([14.0, 14.0]), np.zeros(2))}
    )
    store.replace_source("extra", "h", [parked, flash])
    broken = store.log_ids()[0]
    real_tag_log = pipeline.tag_log

    def flaky_tag_log(log: Log, cfg: object = None) -> object:
        if log.log_id == broken:
            raise ValueError("tag matrices exploded")
        return real_tag_log(log, cfg)  # type: ignore[arg-type]

    monkeypatch.setattr(pipeline, "tag_log", flaky_tag_log)
    client, _ = _client()
    report = analyze_store(store, Config(), client, HashingEmbedder(32))
    status = {r.log_id: r for r in report.logs}
    assert status[broken].status is LogStatus.FAILED
    assert "ValueError: tag matrices exploded" in status[broken].error
    assert status["parked-ego"].status is LogStatus.NO_EGO_MOTION and status["parked-ego"].n_events == 0
    assert "never reaches" in "; ".join(status["parked-ego"].notes)
    # The two-frame flash is a ghost detection: dropped before tagging, the run says so.
    assert store.read_table(EVENTS_TABLE, ["flash-guest"]).num_rows == 0
    runs = {r["log_id"]: r for r in store.read_table(RUNS_TABLE).to_pylist()}
    assert "ghost detection" in runs["flash-guest"]["notes"]
    # Without the tracker-noise repair it becomes an event whose note names the thin evidence.
    no_stitch = Config(tags=TagConfig(stitch=StitchConfig(enabled=False)))
    outcome = pipeline.analyze_log(store.load_log("flash-guest"), no_stitch, load_categories(""), None)
    assert [r.guest_id for r in outcome.records] == ["ghost"]
    assert "observed in only 2 frame(s)" in outcome.records[0].notes
    assert runs[broken]["status"] == "failed" and not runs[broken]["complete"]
    assert runs["parked-ego"]["status"] == "no_ego_motion" and runs["parked-ego"]["complete"]
    # The other synthetic logs and the flash log are analysed as usual.
    assert sum(r.status is LogStatus.ANALYZED for r in report.logs) == len(CATEGORIES)


def test_an_interrupted_run_keeps_the_rule_results_and_a_rerun_continues(
    store: ScenarioStore, tmp_path: Path
) -> None:
    calls = {"n": 0}

    def interrupted(request: ChatRequest) -> str:
        calls["n"] += 1
        if calls["n"] == 3:
            raise KeyboardInterrupt  # the user presses Ctrl-C during the third LLM call
        return _reply(request)

    cache = ResponseCache.in_dir(tmp_path / "cache")
    client, _ = _client(reply=interrupted, cache=cache)
    with pytest.raises(KeyboardInterrupt):
        analyze_store(store, Config(), client, HashingEmbedder(32))
    events = store.read_table(EVENTS_TABLE).to_pylist()
    runs = store.read_table(RUNS_TABLE).to_pylist()
    assert {r["log_id"] for r in runs} == set(store.log_ids())  # every log has its rule results
    assert all(e["category"] == e["baseline_category"] for e in events if e["llm_status"] == "pending")
    waiting = sum(e["llm_status"] == "pending" for e in events)
    assert waiting >= 1 and calls["n"] == 3  # the interrupted log still waits for the LLM

    again, backend = _client(cache=cache)
    second = analyze_store(store, Config(), again, HashingEmbedder(32))
    assert second.n_pending == 0 and second.n_failed == 0
    assert second.n_unchanged == sum(r["complete"] for r in runs)  # finished logs are not redone
    assert "pending" not in store.read_table(EVENTS_TABLE).column("llm_status").to_pylist()
    assert len(backend.requests) <= waiting  # answers given before the interruption are not asked again


def test_an_early_yield_becomes_a_counterfactual_event() -> None:
    from yield_scenarios import pedestrian_yield

    log = pedestrian_yield(split_at_s=3.0).build(smooth=True)  # the pedestrian's id switches too
    outcome = pipeline.analyze_log(log, Config(), load_categories(""), None)
    assert [r.guest_id for r in outcome.records] == ["ped"]
    notes = outcome.records[0].notes
    assert "counterfactual conflict" in notes and "same object as track(s) ped_b" in notes
    assert any("stitched 1 object" in n for n in outcome.notes)
