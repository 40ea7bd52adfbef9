"""LLM classification with canned replies: valid, repaired, unknown category, garbage, backend failure."""

from __future__ import annotations

import json

import pytest
from braking_builders import answer

from scenariominer.config import Config
from scenariominer.explain.categories import CategoryDef, CategorySet
from scenariominer.explain.classify import ClassificationStatus, classify_description, understanding_model
from scenariominer.llm import BackendError, ChatClient
from scenariominer.testing import ScriptedBackend

DESCRIPTION = "Overview: a 4.0-second scenario between the ego vehicle and a guest REGULAR_VEHICLE."


def _client(*replies: object) -> tuple[ChatClient, ScriptedBackend]:
    backend = ScriptedBackend(list(replies))  # type: ignore[arg-type]
    return ChatClient(backend), backend


def test_valid_answer_is_returned_with_its_fields() -> None:
    client, backend = _client(answer("cut_in", " A car cuts in. ", "It moved in front."))
    c = classify_description(client, DESCRIPTION, CategorySet.default())
    assert (c.category, c.description, c.explanation) == ("cut_in", "A car cuts in.", "It moved in front.")
    assert c.status is ClassificationStatus.OK and c.is_valid and c.attempts == 1
    request = backend.requests[0]
    assert request.json_schema is not None
    assert request.json_schema["properties"]["category"]["enum"] == list(CategorySet.default().names)
    assert request.messages[-1].content.endswith(DESCRIPTION)


def test_invalid_then_valid_answer_is_repaired() -> None:
    client, backend = _client('{"description": "x"}', answer("left_oppo"))
    c = classify_description(client, DESCRIPTION, CategorySet.default())
    assert c.category == "left_oppo"
    assert c.status is ClassificationStatus.REPAIRED and c.attempts == 2
    assert "previous answer is invalid" in backend.requests[1].messages[-1].content


def test_unknown_category_twice_is_recorded_as_invalid_with_the_raw_answer() -> None:
    bad = answer("lead_brake", "The lead brakes.", "It brakes.")
    client, _ = _client(bad, bad)
    c = classify_description(client, DESCRIPTION, CategorySet.default())
    assert c.category == "invalid" and c.status is ClassificationStatus.INVALID
    assert not c.is_valid
    assert c.raw_answer == bad
    assert "category" in c.error
    assert (c.description, c.explanation) == ("The lead brakes.", "It brakes.")
    assert c.attempts == 2


def test_garbage_is_recorded_and_never_raises() -> None:
    client, _ = _client("I think it is a cut-in.", "```\nnot json either\n```")
    c = classify_description(client, DESCRIPTION, CategorySet.default())
    assert c.category == "invalid"
    assert c.raw_answer == "```\nnot json either\n```"
    assert (c.description, c.explanation) == ("", "")
    assert "not valid JSON" in c.error


def test_backend_failure_is_recorded_as_error() -> None:
    client, _ = _client(BackendError("server down"))
    c = classify_description(client, DESCRIPTION, CategorySet.default())
    assert c.category == "error" and c.status is ClassificationStatus.ERROR
    assert "server down" in c.error


def test_user_categories_restrict_the_enum() -> None:
    cats = CategorySet((CategoryDef("lead_brake", "The lead brakes."), CategoryDef("not_relevant", "No.")))
    model = understanding_model(cats)
    assert model.model_json_schema()["properties"]["category"]["enum"] == ["lead_brake", "not_relevant"]
    client, _ = _client(answer("lead_brake"))
    assert classify_description(client, DESCRIPTION, cats).category == "lead_brake"
    client, _ = _client(answer("cut_in"), answer("cut_in"))
    assert classify_description(client, DESCRIPTION, cats).category == "invalid"


def test_max_tokens_is_passed_to_the_backend() -> None:
    client, backend = _client(answer("cut_in"))
    classify_description(client, DESCRIPTION, CategorySet.default(), max_tokens=77)
    assert backend.requests[0].params.max_tokens == 77


@pytest.mark.slow
def test_embedded_model_classifies_a_description() -> None:
    pytest.importorskip("llama_cpp")
    from scenariominer.llm import make_chat_client

    client = make_chat_client(Config(), use_cache=False)
    try:
        description = (
            "Overview: a 5.0-second scenario between the ego vehicle and a guest REGULAR_VEHICLE. "
            "The ego brakes while the guest poses a risk from 1.5 s to 3.5 s.\n"
            "Initial tags (at 0.0 s):\n"
            "- ego: longitudinal CRUISING, lateral FACING_FORWARD\n"
            "- guest: longitudinal CRUISING, lateral FACING_FORWARD\n"
            "- guest relative to ego: collision risk NO, relative heading SAME, relative position "
            "FRONT_RIGHT, distance CLOSE, trajectory overlap risk NO\n"
            "Changes:\n"
            "- at 0.8 s: guest lateral VEERING_LEFT (for 1.5 s)\n"
            "- at 1.3 s: guest relative position FRONT (for 3.7 s)\n"
            "- at 1.5 s: ego longitudinal DECELERATING (for 3.5 s); guest collision risk HIGH (for 1.5 s)\n"
            "End at 5.0 s."
        )
        c = classify_description(client, description, CategorySet.default(), max_tokens=200)
    finally:
        client.close()
    assert c.is_valid, (c.error, c.raw_answer)
    assert c.category in CategorySet.default().names
    assert c.explanation.strip()
    json.dumps(c.description)
