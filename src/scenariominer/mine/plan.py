"""Understanding before writing: a structured plan of a description, extracted before the program.

One schema-constrained model call reads the description and fills a :class:`DescriptionPlan`:
the subject (the objects the result refers to) with its Argoverse 2 category or group, the other
objects it is related to, the relations between them (as mining-function names), the conditions
on the subject alone (motion and map predicates), and the numbers the description actually
states with their units (the model: :func:`plan_model`). Category, function and unit fields
are enums of the JSON schema, so the model can only name things that exist; plural/singular and
synonyms collapse onto the category.

The plan is shown to the program writer as part of its request (:func:`plan_text`), stored with
the generation report and printed by ``mine``, so a user sees how the description was read.
"""

from __future__ import annotations

import inspect
from enum import StrEnum
from functools import cache
from typing import Any

from pydantic import BaseModel, ConfigDict, Field, create_model

from scenariominer.llm.base import Message, system, user
from scenariominer.llm.client import ChatClient

__all__ = ["Unit", "extract_plan", "plan_messages", "plan_model", "plan_text"]

_NOT_PLANNED = frozenset(
    {"get_objects_of_category", "is_category", "scenario_and", "scenario_or", "scenario_not"}
    | {"reverse_relationship", "output_scenario"}
)


class Unit(StrEnum):
    """Units of the numbers a description states."""

    METRES = "m"
    METRES_PER_SECOND = "m/s"
    METRES_PER_SECOND_SQUARED = "m/s2"
    DEGREES = "deg"
    SECONDS = "s"
    COUNT = "count"


def _functions() -> dict[str, Any]:
    from scenariominer.mine.dsl import DSL_FUNCTIONS

    return {n: f for n, f in DSL_FUNCTIONS.items() if n not in _NOT_PLANNED}


def _is_relation(func: Any) -> bool:
    return "related_candidates" in inspect.signature(func).parameters


@cache
def plan_model() -> type[BaseModel]:
    """The pydantic model of a plan whose enums list the categories and functions that exist."""
    from scenariominer.data.categories import AV2_CATEGORIES, CATEGORY_GROUPS

    category = StrEnum("Category", {c: c for c in sorted({*AV2_CATEGORIES, *CATEGORY_GROUPS})})  # type: ignore[misc]
    funcs = _functions()
    relation = StrEnum("Relation", {n: n for n, f in funcs.items() if _is_relation(f)})  # type: ignore[misc]
    condition = StrEnum("Condition", {n: n for n, f in funcs.items() if not _is_relation(f)})  # type: ignore[misc]
    words = (str, Field(max_length=60))
    obj = create_model(
        "PlannedObject", words=words, category=(category, ...), __config__=ConfigDict(extra="forbid")
    )
    rel = create_model(
        "PlannedRelation",
        subject_words=words,
        function=(relation, ...),
        other_words=words,
        direction=(str | None, Field(default=None, max_length=20)),
        argument=(str | None, Field(default=None, max_length=60)),
        __config__=ConfigDict(extra="forbid"),
    )
    cond = create_model(
        "PlannedCondition",
        function=(condition, ...),
        negated=(bool, False),
        argument=(str | None, Field(default=None, max_length=40)),
        __config__=ConfigDict(extra="forbid"),
    )
    num = create_model(
        "PlannedNumber",
        value=(float, ...),
        unit=(Unit, ...),
        meaning=words,
        __config__=ConfigDict(extra="forbid"),
    )
    return create_model(
        "DescriptionPlan",
        subject_words=words,
        subject_category=(category, ...),
        related=(list[obj], Field(default_factory=list, max_length=3)),  # type: ignore[valid-type]
        relations=(list[rel], Field(default_factory=list, max_length=3)),  # type: ignore[valid-type]
        conditions=(list[cond], Field(default_factory=list, max_length=3)),  # type: ignore[valid-type]
        numbers=(list[num], Field(default_factory=list, max_length=3)),  # type: ignore[valid-type]
        __config__=ConfigDict(extra="forbid"),
    )


def plan_messages(description: str) -> list[Message]:
    """The request that extracts a plan (prompt text in :mod:`scenariominer.mine.plan_prompts`)."""
    from scenariominer.mine.plan_documents import request_text
    from scenariominer.mine.plan_prompts import plan_system_prompt, plan_user_prompt

    return [system(plan_system_prompt(_functions())), user(plan_user_prompt(request_text(description)))]


def extract_plan(client: ChatClient, description: str, *, max_tokens: int = 300) -> dict[str, Any]:
    """One schema-constrained call: the plan of ``description`` as plain JSON data.

    Raises:
        StructuredOutputError: no valid plan after the client's repair rounds.
        BackendError: the model call failed.
    """
    plan = client.chat(plan_messages(description), plan_model(), max_tokens=max_tokens)
    data: dict[str, Any] = plan.model_dump(mode="json")
    return data


def plan_text(plan: dict[str, Any]) -> str:
    """The plan as the lines shown to the program writer and to the user."""
    reader = " (read by the phrase rules)" if plan.get("read_by") == "rules" else ""
    subject = _categories_text(plan["subject_category"])
    lines = [f"- subject: {plan['subject_words']} -> category {subject}{reader}"]
    if plan.get("reworded"):  # read from the model's plain rewording (mine/plan_reword.py)
        lines.insert(0, f"- read as (the model's plain rewording): {plan['reworded']}")
    for obj in plan.get("related", []):
        own = "".join(f", {c['function']}({c.get('argument') or ''})" for c in obj.get("conditions", []))
        lines.append(f"- other objects: {obj['words']} -> category {_categories_text(obj['category'])}{own}")
    for rel in plan.get("relations", []):
        settings = f", direction={rel['direction']!r}" if rel.get("direction") else ""
        if rel.get("any_direction"):  # "on either side": the relation in any of these directions
            settings += f", direction={' or '.join(repr(d) for d in rel['any_direction'])}"
        settings += f", {rel['argument']}" if rel.get("argument") else ""
        negated = "scenario_not(...) of " if rel.get("negated") else ""
        lines.append(
            f"- relation: {negated}{rel['function']}({rel['subject_words']}, {rel['other_words']}{settings})"
        )
    for cond in plan.get("conditions", []):
        lines.append(f"- condition: {_condition_text(cond, plan['subject_words'])}")
    for num in plan.get("numbers", []):
        lines.append(f"- number stated: {num['value']:g} {num['unit']} ({num['meaning']})")
    if plan.get("unread"):  # a partial reading by the phrase rules: say what it left out
        lines.append(f"- not read (left out, check the result): {' '.join(plan['unread'])}")
    if plan.get("assumed"):
        lines.append(f"- assumed from the words not read: {'; '.join(plan['assumed'])}")
    return "\n".join(lines)


def _condition_text(cond: dict[str, Any], subject: str) -> str:
    """One condition as shown: ``f(subject, settings)``, negated or one of several alternatives."""
    if cond.get("any_of"):  # "either A or B" (phrase rules): each alternative, all of its parts
        return " or ".join(
            " and ".join(_condition_text(part, subject) for part in chain) for chain in cond["any_of"]
        )
    arg = f", {cond['argument']}" if cond.get("argument") else ""
    call = f"{cond['function']}({subject}{arg})"
    return f"{'scenario_not(...) of ' if cond.get('negated') else ''}{call}"


def _categories_text(category: Any) -> str:
    """One category, or the union of several (the phrase rules read "buses" as three)."""
    return " or ".join(category) if isinstance(category, list) else str(category)
