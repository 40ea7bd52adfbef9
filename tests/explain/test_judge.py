"""Who decides the category: allowed names per judge, the schema the LLM gets, rules-only answers."""

from __future__ import annotations

import dataclasses
import json
import math

import pytest

from scenariominer.eval.braking import pedestrian_confusion
from scenariominer.explain.baseline import rule_candidates
from scenariominer.explain.categories import CategorySet
from scenariominer.explain.classify import ClassificationStatus
from scenariominer.explain.facts import EventFacts, rules_explanation
from scenariominer.explain.judge import (
    Judge,
    allowed_categories,
    copied_definition,
    judge_event,
    rules_only,
    tidy_cut_text,
    ungrounded_numbers,
)
from scenariominer.llm import ChatClient
from scenariominer.tags.vocab import HeadingTag, PositionTag
from scenariominer.testing import ScriptedBackend

from .braking_builders import make_pair

CATS = CategorySet.default()


def _facts(pedestrian: bool = False) -> EventFacts:
    return EventFacts(
        guest="pedestrian" if pedestrian else "regular vehicle",
        guest_is_pedestrian=pedestrian,
        ego_speed_kmh=32.4,
        guest_speed_kmh=5.0,
        position_start="FRONT_RIGHT",
        position_closest="FRONT",
        heading="LEFT",
        ego_lateral="",
        guest_lateral="",
        min_gap_m=3.25,
        min_ttc_s=1.4,
        headway_s=math.nan,
        peak_decel_mps2=4.2,
    )


def test_allowed_categories_per_judge() -> None:
    assert allowed_categories(Judge.LLM, ["cut_in"], CATS) == CATS.names
    assert allowed_categories(Judge.HYBRID, ["cut_in"], CATS) == ("cut_in",)
    assert allowed_categories(Judge.HYBRID, ["cut_in", "obj_crossing"], CATS) == ("cut_in", "obj_crossing")
    assert allowed_categories(Judge.HYBRID, [], CATS) == ("unknown_but_relevant", "not_relevant")
    assert allowed_categories(Judge.RULES, ["cut_in", "obj_crossing"], CATS) == ("cut_in",)
    assert allowed_categories(Judge.RULES, [], CATS) == ("not_relevant",)


def test_a_crossing_pedestrian_is_never_an_obj_crossing_candidate() -> None:
    rows = {
        "pair_heading": [HeadingTag.LEFT.value] * 30,
        "pair_position": [PositionTag.FRONT.value] * 30,
        "pair_traj_overlap": ["LOW"] * 30,
    }
    assert "obj_crossing" not in rule_candidates(make_pair("PEDESTRIAN", **rows))
    assert rule_candidates(make_pair("REGULAR_VEHICLE", **rows)) == ("obj_crossing",)


def test_decided_events_get_a_schema_without_category() -> None:
    backend = ScriptedBackend([json.dumps({"description": "A car cuts in.", "explanation": "Gap 3.2 m."})])
    out = judge_event(ChatClient(backend), _facts(), ["cut_in"], CATS, Judge.HYBRID)
    assert out.category == "cut_in" and out.status is ClassificationStatus.OK
    (request,) = backend.requests
    assert "category" not in request.json_schema["properties"]
    assert "The category is cut_in" in request.messages[-1].content
    assert "smallest gap: 3.2 m" in request.messages[-1].content


def test_ambiguous_events_let_the_llm_choose_among_the_candidates_only() -> None:
    answer = {"category": "obj_crossing", "description": "d", "explanation": "e"}
    backend = ScriptedBackend([json.dumps(answer)])
    out = judge_event(ChatClient(backend), _facts(), ["cut_in", "obj_crossing"], CATS, Judge.HYBRID)
    assert out.category == "obj_crossing"
    schema = backend.requests[0].json_schema
    assert json.dumps(schema).count("left_oppo") == 0  # not an allowed name here
    bad = ScriptedBackend([json.dumps({**answer, "category": "left_oppo"})] * 3)
    assert judge_event(ChatClient(bad), _facts(), ["cut_in", "obj_crossing"], CATS).category == "invalid"


def test_rules_judge_needs_no_model_and_states_the_facts() -> None:
    out = rules_only(["obj_crossing"], CATS, _facts())
    assert out.category == "obj_crossing" and out.status is ClassificationStatus.RULES
    assert "3.2 m" in out.explanation and "32 km/h" in out.explanation and "1.4 s" in out.explanation
    assert rules_explanation("not_relevant", _facts(pedestrian=True)).startswith("Not relevant: a pedestrian")
    with pytest.raises(ValueError, match="rules_only"):
        judge_event(ChatClient(ScriptedBackend([])), _facts(), [], CATS, Judge.RULES)


def test_rules_only_without_a_rule_says_none_holds_rather_than_not_relevant() -> None:
    # a pedestrian crossing 7 m ahead with the ego braking at 5 m/s² read "Not relevant: ..."
    out = rules_only([], CATS, _facts(pedestrian=True))
    assert out.category == "not_relevant"
    assert out.explanation.startswith("No category's rule holds: a pedestrian ahead of the ego")


def test_rules_explanation_of_a_standing_ego_says_so() -> None:
    # KeyIdent's events include frames where the ego stands, held by the guest (ego at 0.2 km/h)
    text = rules_explanation("right_ped", dataclasses.replace(_facts(pedestrian=True), ego_speed_kmh=0.2))
    assert "brakes from" not in text
    assert text.endswith("the ego is standing still (its hardest deceleration around it: 4.2 m/s²).")
    moving = rules_explanation("right_ped", dataclasses.replace(_facts(pedestrian=True), ego_speed_kmh=0.6))
    assert moving.endswith("the ego brakes from 1 km/h at up to 4.2 m/s².")
    unknown = rules_explanation(
        "right_ped", dataclasses.replace(_facts(pedestrian=True), ego_speed_kmh=math.nan)
    )
    assert unknown.endswith("; the ego brakes at up to 4.2 m/s².")  # a missing speed is left out


def test_rules_explanation_says_where_the_guest_is_in_plain_english() -> None:
    # it read "a regular vehicle front of the ego" and "back-left of the ego"
    ahead = rules_explanation("obj_crossing", _facts())
    assert ahead.startswith("Obj crossing: a regular vehicle ahead of the ego, moving across")
    behind = rules_explanation("rear_end", dataclasses.replace(_facts(), position_closest="BACK_LEFT"))
    assert "a regular vehicle behind and to the left of the ego," in behind
    ped_right = dataclasses.replace(_facts(pedestrian=True), position_closest="RIGHT")
    right = rules_explanation("right_ped", ped_right)
    assert "a pedestrian to the right of the ego," in right
    unseen = rules_explanation("right_ped", dataclasses.replace(_facts(), position_closest=""))
    assert "a regular vehicle near the ego," in unseen


def test_pedestrian_confusion_counts_per_judge() -> None:
    peds = {("L", "p1"), ("L", "p2")}
    preds = {
        "rules": {("L", "p1"): ["right_ped"]},
        "llm": {("L", "p1"): ["obj_crossing"], ("L", "p2"): ["x"]},
    }
    assert pedestrian_confusion(preds, peds, "obj_crossing") == {"rules": (0, 1), "llm": (1, 2)}


def test_cut_off_texts_end_at_a_sentence_or_clause() -> None:
    assert tidy_cut_text("Short one.", 100) == "Short one."
    long = "A car at 41.5 km/h moves in from the left lane ahead of the ego. It is 3 m aw"
    assert (
        tidy_cut_text(long, len(long)) == "A car at 41.5 km/h moves in from the left lane ahead of the ego."
    )
    clause = "The pedestrian walks across the road ahead of the ego, 4 m away and the ego"
    assert tidy_cut_text(clause, len(clause)) == "The pedestrian walks across the road ahead of the ego …"


def test_numbers_not_in_the_facts_are_found() -> None:
    facts = _facts().text()  # 32 km/h, gap 3.2 m (3.25), TTC 1.4 s, 4.2 m/s²
    assert ungrounded_numbers("It is 3.2 m ahead at 32 km/h; time to collision 1.4 s.", facts) == []
    assert ungrounded_numbers("It is 3 m ahead, braking at 4.2 m/s².", facts) == []  # rounding is fine
    assert ungrounded_numbers("It is 6.2 m ahead at 41 km/h.", facts) == ["6.2", "41"]


def test_an_explanation_with_invented_numbers_is_replaced_by_the_facts() -> None:
    answer = {"description": "A car cuts in.", "explanation": "The car is 6.2 m ahead at 41 km/h."}
    out = judge_event(ChatClient(ScriptedBackend([json.dumps(answer)])), _facts(), ["cut_in"], CATS)
    assert out.category == "cut_in" and out.description == "A car cuts in."
    assert "6.2" not in out.explanation and "3.2 m" in out.explanation
    assert out.notes and "6.2, 41" in out.notes[0]


def test_a_text_copying_a_category_definition_is_not_kept() -> None:
    # What the embedded 1.5B model wrote for two demo events: the obj_crossing definition, whose
    # "(not a pedestrian)" then ranked them first for "pedestrian crossing in front of the ego".
    answer = {
        "description": "The ego drives straight while a vehicle, cyclist or motorcyclist (not a pedestrian) "
        "crosses its path",
        "explanation": "The guest is a vehicle, cyclist or motorcyclist (not a pedestrian) that crosses the "
        "ego's path in front of it",
    }
    out = judge_event(ChatClient(ScriptedBackend([json.dumps(answer)])), _facts(), ["obj_crossing"], CATS)
    assert out.category == "obj_crossing" and out.description == ""  # the tags' description is embedded
    assert out.explanation == rules_explanation("obj_crossing", _facts())
    assert [n.split(";")[0] for n in out.notes] == [
        "the LLM's description repeated the definition of obj_crossing",
        "the LLM's explanation repeated the definition of obj_crossing",
    ]


def test_copied_definition_needs_a_long_shared_run() -> None:
    assert copied_definition("A car crosses its path in front of it from the left.", CATS) == ""
    assert copied_definition("while a vehicle, cyclist or motorcyclist (not a pedestrian) crosses", CATS) == (
        "obj_crossing"
    )
    assert copied_definition("", CATS) == ""
    honest = {
        "description": "A cyclist crosses in front of the ego.",
        "explanation": "The cyclist is 3.2 m ahead.",
    }
    out = judge_event(ChatClient(ScriptedBackend([json.dumps(honest)])), _facts(), ["obj_crossing"], CATS)
    assert (out.description, out.explanation, out.notes) == (honest["description"], honest["explanation"], ())


def test_an_explanation_that_repeats_the_description_is_replaced() -> None:
    # The model filled the description up to its 100-character cap (cut mid-word), then copied it.
    cut = (
        "The guest was driving straight and the ego was also driving straight, so the gap was small and the E"
    )
    out = judge_event(
        ChatClient(
            ScriptedBackend(
                [json.dumps({"category": "unknown_but_relevant", "description": cut, "explanation": cut})]
            )
        ),
        _facts(),
        ["unknown_but_relevant", "not_relevant"],
        CATS,
    )
    assert out.description == "The guest was driving straight and the ego was also driving straight …"
    assert out.explanation == rules_explanation(out.category, _facts())
    assert out.notes == (
        "the LLM's explanation repeated the description; replaced by one written from the facts",
    )


@pytest.mark.parametrize(
    ("facts", "explanation", "quantity"),
    [
        # the facts' numbers, but put on a time to collision the facts do not have (none predicted)
        (
            dataclasses.replace(_facts(), min_ttc_s=math.inf),
            "Time to collision 4.2 s, gap 3.2 m.",
            "time to collision",
        ),
        (_facts(), "It keeps a time headway of 1.4 s behind the car.", "time headway"),  # headway is NaN
    ],
)
def test_an_explanation_naming_a_quantity_the_facts_lack_is_replaced(
    facts: EventFacts, explanation: str, quantity: str
) -> None:
    answer = {"description": "A car cuts in.", "explanation": explanation}
    out = judge_event(ChatClient(ScriptedBackend([json.dumps(answer)])), facts, ["cut_in"], CATS)
    assert out.explanation == rules_explanation("cut_in", facts)
    why = f"named a {quantity} the facts do not have"
    assert out.notes == (f"the LLM's explanation {why}; replaced by one written from the facts",)


def test_an_explanation_naming_a_quantity_the_facts_have_is_kept() -> None:
    kept = {"description": "A car cuts in.", "explanation": "Time to collision 1.4 s at a 3.2 m gap."}
    out = judge_event(ChatClient(ScriptedBackend([json.dumps(kept)])), _facts(), ["cut_in"], CATS)
    assert out.explanation == kept["explanation"] and out.notes == ()


@pytest.mark.parametrize(
    ("explanation", "why"),
    [
        # what the embedded 1.5B model wrote for events of the three real logs (peak decel 2.5 m/s²)
        (
            "The car is moving the same way, and the gap is 3.2 m, small enough to allow the ego to turn "
            "right without braking.",
            "said the ego does not brake, while it decelerates at up to 4.2 m/s²",
        ),
        ("The ego did not need to brake for the car 3.2 m away.", "said the ego does not brake"),
        (
            "The car turns, creating a small gap of 3.2 m and a timeTo collision of 1.4 s.",
            "has a garbled word",
        ),
    ],
)
def test_an_explanation_denying_the_braking_or_garbled_is_replaced(explanation: str, why: str) -> None:
    answer = {"description": "A car cuts in.", "explanation": explanation}
    out = judge_event(ChatClient(ScriptedBackend([json.dumps(answer)])), _facts(), ["cut_in"], CATS)
    assert out.explanation == rules_explanation("cut_in", _facts())
    assert len(out.notes) == 1 and out.notes[0].startswith(f"the LLM's explanation {why}")


def test_an_explanation_of_a_gentle_slow_down_may_say_there_was_no_braking() -> None:
    gentle = dataclasses.replace(_facts(), peak_decel_mps2=0.3)  # below CLEAR_BRAKING_MPS2
    answer = {"description": "A car cuts in.", "explanation": "The ego rolls on without braking hard."}
    out = judge_event(ChatClient(ScriptedBackend([json.dumps(answer)])), gentle, ["cut_in"], CATS)
    assert out.explanation == answer["explanation"] and out.notes == ()
    braking = {"description": "A car cuts in.", "explanation": "The ego brakes for the car 3.2 m ahead."}
    out = judge_event(ChatClient(ScriptedBackend([json.dumps(braking)])), _facts(), ["cut_in"], CATS)
    assert out.explanation == braking["explanation"] and out.notes == ()
