"""Prompt texts of the dynamic prompt generator (section 3.3) and the answer's JSON schema.

Order of the conversation: the system prompt (role, risk types with definitions, manoeuvre list,
JSON output format; shared by every call, so the embedded model's prefix cache reuses it), then one
user message holding the task prompt (event id, caption and, when risk-aware, the risk type), the
retrieved cases as few-shot examples, and the chain-of-thought instruction (road context -> other
vehicle position and action -> event context -> manoeuvre -> justification). The JSON schema lists
the fields in that order, so constrained decoding writes them in that order too.
"""

from __future__ import annotations

import json
from collections.abc import Sequence
from typing import Any

from scenariominer.cbr.cases import VALUE_FIELDS, Case
from scenariominer.cbr.vocab import ManoeuvreSet, RiskType, RiskTypeSet

__all__ = ["PROMPT_VERSION", "answer_schema", "system_prompt", "user_prompt"]

#: Version of the texts below (part of every cached answer's key through the prompt itself).
PROMPT_VERSION = "cbr-1"

_ROLE = (
    "You are a driving-safety expert assisting the driver of the ego car in a safety-critical "
    "moment. You read a short description of a risky traffic scene and recommend the one evasive "
    "manoeuvre that best avoids a collision, like an experienced human driver would, and explain why."
)

_FIELD_HELP = {
    "road_context": "the road and traffic situation in a few words",
    "other_vehicle_position": "where the other road user is relative to the ego car",
    "other_vehicle_action": "what the other road user is doing",
    "event_context": "one sentence on how the risk arises",
    "manoeuvre": "one manoeuvre identifier from the list",
    "justification": "one sentence on why this manoeuvre avoids the collision",
}

_COT = (
    "Reason in this order and write the JSON fields in the same order: first the road context, then "
    "the other road user's position and action, then the event context, then choose the manoeuvre, "
    "then justify it. Keep every text field short."
)


def system_prompt(risk_types: RiskTypeSet, manoeuvres: ManoeuvreSet) -> str:
    """Role, risk types with definitions, manoeuvres and the output format."""
    risks = "\n".join(f"- {t.label}: {t.definition}" for t in risk_types.types)
    moves = "\n".join(f"- {m.name}: {m.label}" for m in manoeuvres.manoeuvres)
    fields = "\n".join(f'  "{f}": {_FIELD_HELP[f]}' for f in VALUE_FIELDS)
    return (
        f"{_ROLE}\n\nRisk types of safety-critical driving scenarios:\n{risks}\n\n"
        f"Evasive manoeuvres (answer with the identifier before the colon):\n{moves}\n\n"
        f"Answer with one JSON object with these fields, in this order:\n{fields}"
    )


def _task(event_id: str, caption: str, risk: RiskType | None) -> str:
    lines = [f"Event: {event_id}", f"Scene event caption: {caption}"]
    if risk is not None:
        lines.append(f"Risk type: {risk.label} ({risk.definition})")
    return "\n".join(lines)


def _example(i: int, case: Case, risk: RiskType | None) -> str:
    head = f"Case {i}: {case.caption}"
    if risk is not None:
        head += f"\nRisk type: {risk.label}"
    return f"{head}\nAnswer: {json.dumps(case.answer(), ensure_ascii=False)}"


def user_prompt(
    event_id: str,
    caption: str,
    risk: RiskType | None,
    examples: Sequence[Case],
    risk_types: RiskTypeSet,
) -> str:
    """Task prompt, few-shot cases (if any) and the chain-of-thought instruction, in that order.

    Args:
        event_id: the query's id.
        caption: the scene event caption.
        risk: the risk type (risk-aware prompt) or ``None`` (risk-unaware: not shown anywhere).
        examples: retrieved cases, most similar first.
        risk_types: to name each example's risk type in a risk-aware prompt.
    """
    parts = ["## Task", _task(event_id, caption, risk)]
    if examples:
        parts.append("## Similar past cases and what the drivers did")
        for i, c in enumerate(examples, start=1):
            parts.append(_example(i, c, risk_types.get(c.risk_type) if risk is not None else None))
    parts += ["## How to answer", _COT]
    return "\n\n".join(parts)


def answer_schema(manoeuvres: ManoeuvreSet, max_chars: int) -> dict[str, Any]:
    """JSON schema of the answer: the value fields in prompt order, the manoeuvre an enum."""
    props: dict[str, Any] = {}
    for f in VALUE_FIELDS:
        if f == "manoeuvre":
            props[f] = {"type": "string", "enum": list(manoeuvres.names)}
        else:
            props[f] = {"type": "string", "minLength": 1, "maxLength": max_chars}
    return {
        "title": "EvasiveManoeuvre",
        "type": "object",
        "properties": props,
        "required": list(VALUE_FIELDS),
        "additionalProperties": False,
    }
