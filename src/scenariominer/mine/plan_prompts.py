"""Prompts of the plan step and of the rewording step that may come before it.

The plan step (:mod:`scenariominer.mine.plan`) reads a description and names its parts; the
rewording step (:mod:`scenariominer.mine.plan_reword`) puts an odd wording in plain words.

The worked examples of the plan step use descriptions of the shipped example bank and of the
*dev* split of ``eval/nl2prog_set.toml`` only (never its hold-out split), written by hand for this
prompt; those of the rewording step are wordings of my own (none from any split).
"""

from __future__ import annotations

import inspect
import json
from collections.abc import Callable, Mapping
from typing import Any

__all__ = [
    "PLAN_PROMPT_VERSION",
    "REWORD_EXAMPLES",
    "REWORD_PROMPT_VERSION",
    "plan_system_prompt",
    "plan_user_prompt",
    "reword_system_prompt",
]

#: Version of the texts below; part of the program-cache key through the request text.
PLAN_PROMPT_VERSION = "mining-plan/2"

_ROLE = """You read a description of a driving scenario and write down its parts as JSON, before \
a program is written for it. Name only what the description says:
- subject: the objects the description is about (what would be highlighted), with their \
category; a plural or a synonym maps to the same category ("cars", "a car" -> REGULAR_VEHICLE; \
"vehicles" -> VEHICLE; "people" -> PEDESTRIAN).
- related: other objects the subject is related to, with their categories (empty if none).
- relations: how the subject relates to each other object, as one of the relation functions \
below. subject_words is the object that comes first in the function's call: when the function \
is read from the other object's side ("pedestrians crossing in front of a vehicle": the vehicle \
is crossed), put the other object there. direction only when the description gives one \
(left, right, forward, backward; same, opposite, perpendicular for headings and sides); \
argument holds other settings the description states, as keyword=value.
- conditions: what holds for the subject alone, as one of the condition functions below \
(negated when the description says "not"/"without"/"away from"); argument is a short keyword \
setting of that function such as direction='left', lane_type='BUS' or min_velocity=10 when the \
description implies one.
- numbers: only numbers written in the description, with their unit and what they bound.
Leave a list empty rather than guess."""

_EXAMPLES: tuple[tuple[str, dict[str, Any]], ...] = (
    (
        "vehicle with a bicycle to its right",
        {
            "subject_words": "vehicle",
            "subject_category": "VEHICLE",
            "related": [{"words": "bicycle", "category": "BICYCLE"}],
            "relations": [
                {
                    "subject_words": "vehicle",
                    "function": "has_objects_in_relative_direction",
                    "other_words": "bicycle",
                    "direction": "right",
                }
            ],
            "conditions": [],
            "numbers": [],
        },
    ),
    (
        "moving buses within 15 m of an intersection",
        {
            "subject_words": "buses",
            "subject_category": "BUS",
            "related": [],
            "relations": [],
            "conditions": [
                {"function": "has_velocity", "negated": False, "argument": None},
                {"function": "near_intersection", "negated": False, "argument": "threshold=15"},
            ],
            "numbers": [{"value": 15, "unit": "m", "meaning": "distance to the intersection"}],
        },
    ),
    (
        "pedestrians crossing the road in front of a vehicle",
        {
            "subject_words": "pedestrians",
            "subject_category": "PEDESTRIAN",
            "related": [{"words": "vehicle", "category": "VEHICLE"}],
            "relations": [
                {
                    "subject_words": "vehicle",
                    "function": "being_crossed_by",
                    "other_words": "pedestrians",
                    "direction": "forward",
                    "argument": None,
                }
            ],
            "conditions": [],
            "numbers": [],
        },
    ),
    (
        "vehicles surrounded by three or more people within 5 meters",
        {
            "subject_words": "vehicles",
            "subject_category": "VEHICLE",
            "related": [{"words": "people", "category": "PEDESTRIAN"}],
            "relations": [
                {
                    "subject_words": "vehicles",
                    "function": "near_objects",
                    "other_words": "people",
                    "direction": None,
                    "argument": "distance_thresh=5, min_objects=3",
                }
            ],
            "conditions": [],
            "numbers": [
                {"value": 3, "unit": "count", "meaning": "number of people"},
                {"value": 5, "unit": "m", "meaning": "distance to the people"},
            ],
        },
    ),
    (
        "pedestrians walking on the road away from any crosswalk",
        {
            "subject_words": "pedestrians",
            "subject_category": "PEDESTRIAN",
            "related": [],
            "relations": [],
            "conditions": [
                {"function": "on_road", "negated": False, "argument": None},
                {"function": "at_pedestrian_crossing", "negated": True, "argument": None},
            ],
            "numbers": [],
        },
    ),
)


def _summary(func: Callable[..., Any]) -> str:
    doc = inspect.getdoc(func) or ""
    return doc.splitlines()[0] if doc else ""


def _settings(func: Callable[..., Any]) -> str:
    """The function's own settings with their defaults (``direction, min_number=1``)."""
    skip = {"track_candidates", "related_candidates", "log_dir"}
    params = [p for p in inspect.signature(func).parameters.values() if p.name not in skip]
    return ", ".join(
        p.name if p.default is inspect.Parameter.empty else f"{p.name}={p.default!r}" for p in params
    )


def plan_system_prompt(functions: Mapping[str, Callable[..., Any]]) -> str:
    """The system message: role, the relation and condition functions (one line each), examples."""
    relations: list[str] = []
    conditions: list[str] = []
    for name, func in functions.items():
        line = f"- {name}({_settings(func)}): {_summary(func)}"
        (relations if "related_candidates" in inspect.signature(func).parameters else conditions).append(line)
    examples = "\n\n".join(
        f"Description: {text}\nPlan: {json.dumps(plan, separators=(',', ':'))}" for text, plan in _EXAMPLES
    )
    return (
        f"{_ROLE}\n\nRelation functions:\n" + "\n".join(relations) + "\n\nCondition functions:\n"
        + "\n".join(conditions) + f"\n\nExamples:\n\n{examples}"
    )  # fmt: skip


def plan_user_prompt(description: str) -> str:
    """The user message: the description to read."""
    return f"Description: {description.strip()}"


# -- the rewording step (:mod:`scenariominer.mine.plan_reword`) ------------------------------------

#: Version of the rewording prompt below (the response cache keys on the whole request anyway).
REWORD_PROMPT_VERSION = "mining-reword/1"

_REWORD_ROLE = """You rewrite search requests for recorded driving logs in plain, simple English: \
the road users searched for, what they are doing, where, and near which other road users. Keep \
every number with its unit, every direction (left, right, ahead, behind) and every negation. Drop \
ticket numbers, ratings and other words that do not describe the scene. Answer with the rewritten \
request only, on one line."""

#: Worked examples: odd wordings written by hand for this prompt (none from an evaluation split),
#: each rewritten into words the phrase rules read in full (a test checks that they do).
REWORD_EXAMPLES: tuple[tuple[str, str], ...] = (
    ("Flag any instance where a bike occupies the lane reserved for buses",
     "bicycles in a bus lane"),
    ("ego.decel > 3 m/s^2 while lead_vehicle.dist < 10 m",
     "the ego vehicle braking at more than 3 m/s^2 with a vehicle ahead within 10 m"),
    ("Scenario: person on foot traverses the road in front of our car",
     "pedestrians crossing in front of the ego vehicle"),
    ("trucks sitting idle by the kerb", "parked trucks"),
    ("BUG-1123: planner jittered when a cyclist went past us on the right",
     "bicyclists passing the ego vehicle on the right"),
)  # fmt: skip


def reword_system_prompt() -> str:
    """The system message of the rewording step."""
    return _REWORD_ROLE
