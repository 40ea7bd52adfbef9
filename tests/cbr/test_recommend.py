"""Retrieval restricted to the risk type, prompt structure, schema violations, the evolving base."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from scenariominer.api.cbr import _recommend_notes
from scenariominer.cbr.cases import Case
from scenariominer.cbr.recommend import Query, RecommendSettings, recommend
from scenariominer.cbr.retrieve import retrieve
from scenariominer.cbr.rollout import RECORDED, RolloutOutcome
from scenariominer.cbr.vocab import CbrError
from scenariominer.llm.base import Role
from scenariominer.llm.client import ChatClient
from scenariominer.testing import ScriptedBackend

from .helpers import EMBEDDER, answer, case_base

QUERY = Query("ev1", "a stopped truck blocks the lane ahead", "vehicle_ahead")


def test_similarity_retrieval_stays_within_the_risk_type(tmp_path: Path) -> None:
    base = case_base(tmp_path)
    # "stopped truck" also describes the pedestrian case p1, but only vehicle_ahead cases may come back.
    hits = retrieve(base, QUERY.caption, "vehicle_ahead", 5, selection="similarity", embedder=EMBEDDER)
    assert {h.case.case_id for h in hits} == {"a1", "a2", "a3"}
    assert hits[0].case.case_id in {"a1", "a3"}  # the two truck captions rank first
    assert hits[0].score >= hits[1].score >= hits[2].score


def test_random_retrieval_is_seeded_and_restricted(tmp_path: Path) -> None:
    base = case_base(tmp_path)
    a = retrieve(base, QUERY.caption, "pedestrian", 1, selection="random", embedder=EMBEDDER, seed=3)
    b = retrieve(base, QUERY.caption, "pedestrian", 1, selection="random", embedder=EMBEDDER, seed=3)
    assert [h.case.case_id for h in a] == [h.case.case_id for h in b]
    assert a[0].case.risk_type == "pedestrian"
    assert retrieve(base, QUERY.caption, "pedestrian", 0, selection="random", embedder=EMBEDDER) == []


def test_prompt_has_system_task_examples_then_reasoning_order(tmp_path: Path) -> None:
    base = case_base(tmp_path)
    backend = ScriptedBackend([answer()])
    rec = recommend(QUERY, base, ChatClient(backend), EMBEDDER, RecommendSettings(k=2))
    request = backend.requests[0]
    assert [m.role for m in request.messages] == [Role.SYSTEM, Role.USER]
    sys_text, user_text = request.messages[0].content, request.messages[1].content
    assert "Conflict with Pedestrian" in sys_text and "evasive_steering_left" in sys_text
    order = [user_text.index(s) for s in ("## Task", "## Similar past cases", "## How to answer")]
    assert order == sorted(order)
    assert "Risk type: Conflict with Vehicle Ahead" in user_text
    cot = [
        user_text.index(s, order[2])
        for s in ("road context", "position and action", "event context", "manoeuvre", "justify")
    ]
    assert cot == sorted(cot)
    assert user_text.count("Case ") == 2 and "Case 3" not in user_text
    assert rec.manoeuvre == "emergency_braking" and len(rec.retrieved) == 2
    schema = request.json_schema
    assert schema is not None
    assert list(schema["properties"]) == [
        "road_context",
        "other_vehicle_position",
        "other_vehicle_action",
        "event_context",
        "manoeuvre",
        "justification",
    ]
    assert schema["properties"]["manoeuvre"]["enum"][0] == "emergency_braking"


def test_risk_unaware_prompt_names_no_risk_type(tmp_path: Path) -> None:
    base = case_base(tmp_path)
    backend = ScriptedBackend([answer()])
    recommend(QUERY, base, ChatClient(backend), EMBEDDER, RecommendSettings(k=1, risk_aware=False))
    user_text = backend.requests[0].messages[1].content
    assert "Risk type" not in user_text and "## Similar past cases" in user_text


def test_zero_shot_prompt_has_no_examples(tmp_path: Path) -> None:
    base = case_base(tmp_path)
    backend = ScriptedBackend([answer()])
    rec = recommend(QUERY, base, ChatClient(backend), EMBEDDER, RecommendSettings(k=0))
    assert "## Similar past cases" not in backend.requests[0].messages[1].content
    assert rec.retrieved == ()


def test_a_field_written_up_to_its_cap_ends_at_a_full_sentence(tmp_path: Path) -> None:
    # the real model's justification ended "... at a junction. This manoeuvre will be" (120 characters)
    cut = "The ego should turn left to avoid the oncoming vehicle turning across its path. This manoeuvre w"
    backend = ScriptedBackend([answer("evasive_steering_left", justification=cut)])
    settings = RecommendSettings(k=0, max_field_chars=len(cut))
    rec = recommend(QUERY, case_base(tmp_path), ChatClient(backend), EMBEDDER, settings)
    assert rec.answer["justification"] == (
        "The ego should turn left to avoid the oncoming vehicle turning across its path."
    )
    assert rec.answer["road_context"] == "two-lane road" and rec.manoeuvre == "evasive_steering_left"


def test_schema_violation_is_repaired_once(tmp_path: Path) -> None:
    base = case_base(tmp_path)
    backend = ScriptedBackend([answer("swerve_wildly"), answer("evasive_steering_left")])
    rec = recommend(QUERY, base, ChatClient(backend, repair_rounds=1), EMBEDDER, RecommendSettings(k=0))
    assert rec.manoeuvre == "evasive_steering_left" and rec.attempts == 2
    assert "invalid" in backend.requests[1].messages[-1].content


@pytest.mark.parametrize(
    "bad",
    [
        answer("swerve_wildly"),  # not in the enum
        answer(justification="x" * 500),  # over the length cap
        json.dumps({"manoeuvre": "emergency_braking"}),  # fields missing
        "not json at all",
    ],
)
def test_persistent_schema_violation_raises_a_clear_error(tmp_path: Path, bad: str) -> None:
    base = case_base(tmp_path)
    backend = ScriptedBackend([bad, bad])
    with pytest.raises(CbrError, match="violates the answer schema after 2 attempt"):
        recommend(QUERY, base, ChatClient(backend, repair_rounds=1), EMBEDDER, RecommendSettings(k=0))


def test_added_case_is_retrieved_next_time(tmp_path: Path) -> None:
    base = case_base(tmp_path)
    new = Case(
        "n1",
        "vehicle_ahead",
        "a fallen mattress lies across the motorway lane",
        manoeuvre="evasive_steering_right",
    )
    caption = "a mattress lies on the motorway lane ahead"
    before = retrieve(base, caption, "vehicle_ahead", 1, selection="similarity", embedder=EMBEDDER)
    assert before[0].case.case_id != "n1"
    assert base.add([new], EMBEDDER, 0.97).added == ("n1",)
    after = retrieve(base, caption, "vehicle_ahead", 1, selection="similarity", embedder=EMBEDDER)
    assert after[0].case.case_id == "n1"


def _outcome(name: str, collision: bool) -> RolloutOutcome:
    path = np.zeros(3)
    first_s = 2.4 if collision else math.nan
    return RolloutOutcome(name, 0.0 if collision else 2.0, math.inf, collision, first_s, "car", path, path)


def test_a_recommendation_warns_of_an_empty_case_base_and_of_a_collision_the_recording_avoided() -> None:
    # `recommend` on a store without a case base said only "retrieved cases none (zero-shot)", and a
    # manoeuvre that collides in the rollout check where the recorded ego did not was shown unflagged
    notes = _recommend_notes(0, 3, _outcome("evasive_steering_left", True), _outcome(RECORDED, False))
    assert len(notes) == 2
    assert notes[0].startswith("the store has no case base") and "cbr build" in notes[0]
    assert notes[1].startswith("the recommended evasive_steering_left collides in the rollout check at 2.4 s")
    assert _recommend_notes(0, 0, _outcome("brake", False), _outcome(RECORDED, False)) == ()  # k=0 asked
    assert _recommend_notes(5, 3, _outcome("brake", True), _outcome(RECORDED, True)) == ()  # unavoidable
