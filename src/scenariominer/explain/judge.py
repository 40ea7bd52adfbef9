"""Who decides an event's category: the rules, the LLM, or both (the hybrid judgement).

* ``rules``: the first rule of :mod:`~scenariominer.explain.baseline` that holds; the explanation
  is written from the event's facts without a model (instant, no LLM loaded).
* ``llm``: the LLM chooses among every category from the event's facts (the paper's setting, with
  facts instead of the tag-by-tag description); kept for comparison.
* ``hybrid`` (default): the rules decide where exactly one rule holds; the LLM chooses only among
  the rules' candidates when several hold, and between ``unknown_but_relevant`` and
  ``not_relevant`` when none holds. In every case the LLM writes the rephrased description and an
  explanation that quotes the facts. A pedestrian can therefore never become ``obj_crossing`` or
  ``cut_in`` (their rules exclude pedestrians), which the LLM alone does in most pedestrian events.

Where the rules decide, the answer's schema has no ``category`` field at all (fewer tokens to
generate); otherwise ``category`` is a JSON-schema enum of the allowed names.
"""

from __future__ import annotations

import dataclasses
import re
from collections.abc import Callable, Sequence
from typing import Any, Literal

import pyarrow as pa
from pydantic import BaseModel, Field, create_model

from scenariominer.explain.categories import NOT_RELEVANT, UNKNOWN_BUT_RELEVANT, CategorySet
from scenariominer.explain.classify import (
    Classification,
    ClassificationStatus,
    ask,
)
from scenariominer.explain.facts import EventFacts, rules_explanation
from scenariominer.explain.prompts import judge_messages
from scenariominer.llm.client import ChatClient
from scenariominer.llm.text import tidy_cut_text
from scenariominer.schema import Judge

#: Longest description (characters) the judgement's schema allows: about 15 words.
JUDGE_DESCRIPTION_MAX_CHARS = 100
#: Longest explanation (characters): about 25 words with numbers.
JUDGE_EXPLANATION_MAX_CHARS = 160

__all__ = [
    "JUDGE_DESCRIPTION_MAX_CHARS",
    "JUDGE_EXPLANATION_MAX_CHARS",
    "Judge",
    "allowed_categories",
    "copied_definition",
    "judge_event",
    "rejudge_events",
    "rules_only",
    "tidy_cut_text",
    "ungrounded_numbers",
]


def allowed_categories(judge: Judge, candidates: Sequence[str], categories: CategorySet) -> tuple[str, ...]:
    """The category names the LLM may answer with for one event.

    Args:
        judge: ``llm`` allows every category; ``hybrid`` the rules' candidates (see the module
            docstring); ``rules`` the first candidate or ``not_relevant``.
        candidates: the categories whose rules hold (:func:`~scenariominer.explain.baseline.rule_candidates`).
        categories: the category set (candidates outside it are ignored).
    """
    if judge is Judge.LLM:
        return categories.names
    known = tuple(c for c in candidates if c in categories.names)
    if judge is Judge.RULES:
        return known[:1] or (NOT_RELEVANT,)
    if known:
        return known
    return tuple(c for c in (UNKNOWN_BUT_RELEVANT, NOT_RELEVANT) if c in categories.names)


def _answer_model(allowed: Sequence[str]) -> type[BaseModel]:
    fields: dict[str, Any] = {
        "description": (str, Field(max_length=JUDGE_DESCRIPTION_MAX_CHARS)),
        "explanation": (str, Field(max_length=JUDGE_EXPLANATION_MAX_CHARS)),
    }
    if len(allowed) > 1:
        category_type: Any = Literal[tuple(allowed)]  # type: ignore[valid-type]
        fields = {"category": (category_type, ...), **fields}
    return create_model("BrakingJudgement", **fields)


def rules_only(candidates: Sequence[str], categories: CategorySet, facts: EventFacts) -> Classification:
    """The rules' category with an explanation written from the facts (no model)."""
    (category,) = allowed_categories(Judge.RULES, candidates, categories)
    explanation = rules_explanation(category, facts)
    if category == NOT_RELEVANT:
        # the rules cannot tell "relevant, but no category fits" from "not why the ego brakes":
        # "Not relevant: a pedestrian ahead ... brakes at up to 5.0 m/s²" read as a verdict
        explanation = "No category's rule holds" + explanation.removeprefix("Not relevant")
    return Classification(
        category=category,
        description="",
        explanation=explanation,
        status=ClassificationStatus.RULES,
    )


def judge_event(
    client: ChatClient,
    facts: EventFacts | str,
    candidates: Sequence[str],
    categories: CategorySet,
    judge: Judge = Judge.HYBRID,
    *,
    max_tokens: int | None = None,
) -> Classification:
    """Ask the LLM to decide one event's category (where allowed) and to describe and explain it.

    Args:
        client: the LLM.
        facts: the event's facts (or their stored text).
        candidates: the categories whose rules hold.
        categories: the category set.
        judge: ``hybrid`` or ``llm`` (the rules need no model: :func:`rules_only`).
        max_tokens: bound on each answer's tokens.

    Returns:
        The classification; never raises for an invalid answer or a backend failure.

    Raises:
        ValueError: ``judge`` is ``rules``.
    """
    if judge is Judge.RULES:
        raise ValueError("the rules judge needs no model: use rules_only()")
    allowed = allowed_categories(judge, candidates, categories)
    text = facts if isinstance(facts, str) else facts.text()
    messages = judge_messages(text, allowed, categories)
    outcome = ask(client, messages, _answer_model(allowed), max_tokens=max_tokens)
    if outcome.is_valid:
        # the model sometimes copies its (length-capped, so possibly cut) description as explanation
        repeated = outcome.explanation.strip() == outcome.description.strip()
        outcome = dataclasses.replace(
            outcome,
            category=allowed[0] if len(allowed) == 1 else outcome.category,
            description=tidy_cut_text(outcome.description, JUDGE_DESCRIPTION_MAX_CHARS),
            explanation=tidy_cut_text(outcome.explanation, JUDGE_EXPLANATION_MAX_CHARS),
        )
        outcome = _checked_texts(outcome, facts, text, categories, repeated=repeated)
    return outcome


def _checked_texts(
    outcome: Classification,
    facts: EventFacts | str,
    facts_text: str,
    categories: CategorySet,
    *,
    repeated: bool = False,
) -> Classification:
    """The answer with a text that does not describe the event replaced, and a note saying why.

    An explanation that quotes numbers absent from the facts, names a time to collision or a
    headway the facts do not have, says the ego does not brake while it clearly does
    (:data:`CLEAR_BRAKING_MPS2`), has a garbled word ("timeTo"), repeats a category's definition or
    is the description again (``repeated``) becomes one written from the facts (when the facts are
    at hand); a description that repeats a definition is dropped, so the tag description is
    embedded instead. A small model often copies the prompt's definition ("a vehicle, cyclist or
    motorcyclist (not a pedestrian) crosses its path"), whose words would then match searches for
    what it excludes.
    """
    notes = list(outcome.notes)
    description, explanation = outcome.description, outcome.explanation
    copied = copied_definition(description, categories)
    if copied:
        description = ""
        notes.append(f"the LLM's description repeated the definition of {copied}; the tags' is embedded")
    if isinstance(facts, EventFacts):  # stored facts' text alone cannot write a replacement
        why = _explanation_fault(explanation, facts, facts_text, categories, repeated)
        if why:
            notes.append(f"the LLM's explanation {why}; replaced by one written from the facts")
            explanation = rules_explanation(outcome.category, facts)
    return dataclasses.replace(outcome, description=description, explanation=explanation, notes=tuple(notes))


#: Quantities the facts state only when they exist (no collision predicted: no time to collision),
#: with the words an explanation names them by.
_OPTIONAL_QUANTITIES = (
    ("time to collision", re.compile(r"time[ -]to[ -](?:collision|crash)|\bttc\b")),
    ("time headway", re.compile(r"headway")),
)


#: Words that say the ego did not brake.
_NO_BRAKING = re.compile(
    r"\bwithout (?:any |the need (?:for|to) |needing to |having to )?brak|\bno (?:need (?:for|to) )?brak"
    r"|\b(?:does|did|do|need|needs|needed)(?: not|n't)(?: need to| have to)? brake|\bnever brakes?\b"
)
#: A deceleration (m/s²) beyond which the ego clearly brakes.
CLEAR_BRAKING_MPS2 = 1.0
#: Two words run together with a capital inside ("timeTo collision"): a small model's garbled token.
_RUN_TOGETHER = re.compile(r"\b[a-z]+[A-Z][a-z]+\b")


def _explanation_fault(
    explanation: str, facts: EventFacts, facts_text: str, categories: CategorySet, repeated: bool
) -> str:
    """Why the explanation does not explain the event ("" when it does)."""
    invented = ungrounded_numbers(explanation, facts_text)
    if invented:
        return f"quoted numbers that are not in the facts ({', '.join(invented)})"
    for name, words in _OPTIONAL_QUANTITIES:
        if name not in facts_text and words.search(explanation.lower()):
            return f"named a {name} the facts do not have"
    if facts.peak_decel_mps2 >= CLEAR_BRAKING_MPS2 and _NO_BRAKING.search(explanation.lower()):
        return f"said the ego does not brake, while it decelerates at up to {facts.peak_decel_mps2:.1f} m/s²"
    garbled = _RUN_TOGETHER.search(explanation)
    if garbled:
        return f"has a garbled word ({garbled.group()!r})"
    copied = copied_definition(explanation, categories)
    if copied:
        return f"repeated the definition of {copied}"
    return "repeated the description" if repeated else ""


_WORD = re.compile(r"[a-z0-9]+")
#: Consecutive words shared with a definition that make a text a copy of it rather than a description.
COPIED_RUN_WORDS = 8


def copied_definition(text: str, categories: CategorySet, min_words: int = COPIED_RUN_WORDS) -> str:
    """The first category whose definition ``text`` copies ("" when none).

    A copy shares ``min_words`` consecutive words with the definition, case and punctuation ignored.
    """
    words = _WORD.findall(text.lower())
    runs = {tuple(words[i : i + min_words]) for i in range(len(words) - min_words + 1)}
    if not runs:
        return ""
    for category in categories.categories:
        ref = _WORD.findall(category.definition.lower())
        if any(tuple(ref[i : i + min_words]) in runs for i in range(len(ref) - min_words + 1)):
            return category.name
    return ""


_NUMBER = re.compile(r"(?<![\w.])\d+(?:\.\d+)?")


def ungrounded_numbers(text: str, facts_text: str) -> list[str]:
    """Numbers of ``text`` that no number of the facts rounds to (an invented speed, gap, time).

    A number written with ``d`` decimals matches a fact within half a unit of its last digit
    (``3`` matches 3.3, ``3.2`` matches 3.25), so rounding is not taken for invention.
    """
    known = [float(x) for x in _NUMBER.findall(facts_text)]
    out = []
    for token in _NUMBER.findall(text):
        decimals = len(token.split(".")[1]) if "." in token else 0
        tolerance = 0.5 * 10.0**-decimals + 1e-9
        if not any(abs(float(token) - k) <= tolerance for k in known):
            out.append(token)
    return out


def rejudge_events(
    events: pa.Table,
    client: ChatClient,
    categories: CategorySet,
    judge: Judge,
    *,
    max_tokens: int | None = None,
    on_event: Callable[[Classification], None] | None = None,
) -> dict[str, str]:
    """Judge stored events again from their stored facts and rule candidates (for evaluation).

    Args:
        events: rows of the ``events`` table (``event_id``, ``facts``, ``rule_candidates``).
        client: the LLM (answers already cached, e.g. by an analysis with this judge, are free).
        categories: the category set.
        judge: ``hybrid`` or ``llm``.
        max_tokens: bound on each answer's tokens.
        on_event: called after each event (progress).

    Returns:
        ``event_id → category`` (``invalid`` / ``error`` where the LLM failed).
    """
    out: dict[str, str] = {}
    for row in events.select(["event_id", "facts", "rule_candidates"]).to_pylist():
        candidates = [c for c in str(row["rule_candidates"] or "").split(",") if c]
        outcome = judge_event(client, str(row["facts"]), candidates, categories, judge, max_tokens=max_tokens)
        out[str(row["event_id"])] = outcome.category
        if on_event is not None:
            on_event(outcome)
    return out
