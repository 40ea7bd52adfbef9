"""Prompts of LLM scenario understanding (braking paper, section III-D.2, Fig. 4d), versioned.

The prompt has the paper's four parts: a role and instructions, the known scenario categories
with their definitions, the scenario description, and the JSON output format with the keys
``description``, ``category`` and ``explanation``. Everything that is the same for every event
(role, how to read the tags, categories, output format) is in the system message and the
description alone is the user message, so a backend that keeps its prompt cache (llama.cpp does)
evaluates the shared prefix once per run instead of once per event.

Changing any text here changes the answers: bump :data:`PROMPT_VERSION`, which is part of the
analysis fingerprint, so stored results are recomputed.
"""

from __future__ import annotations

from collections.abc import Sequence

from scenariominer.config.tags import TagConfig
from scenariominer.explain.categories import NOT_RELEVANT, UNKNOWN_BUT_RELEVANT, CategorySet
from scenariominer.llm.base import Message, system, user

__all__ = [
    "JUDGE_PROMPT_VERSION",
    "PROMPT_VERSION",
    "build_messages",
    "judge_messages",
    "judge_system_prompt",
    "system_prompt",
]

#: Version of the prompt texts below; stored with every result.
PROMPT_VERSION = "braking-understanding/2"

_ROLE = (
    "You are an expert in the safety validation of automated vehicles. You read a rule-based, "
    "tag-by-tag description of a short driving scenario between the ego vehicle and one other road "
    "user, the guest, recorded while the ego vehicle braked. Your task is to understand why the ego "
    "vehicle brakes and to classify the scenario."
)

_TAG_GUIDE = """How to read the description:
- Times are seconds from the start of the scenario; "(for X s)" is how long a new value lasts.
- longitudinal: CRUISING, STANDING_STILL, ACCELERATING, DECELERATING (braking), REVERSING.
- lateral: FACING_FORWARD; VEERING_LEFT / VEERING_RIGHT (heading change of {veer:.2f} to {turn:.2f} rad, \
e.g. a lane change); TURNING_LEFT / TURNING_RIGHT (more than {turn:.2f} rad, e.g. a turn at a junction).
- relative heading of the guest compared with the ego: SAME (same direction), LEFT or RIGHT (moving across \
the ego's direction), OPPOSITE (oncoming).
- relative position of the guest seen from the ego: FRONT, FRONT_LEFT, LEFT, BACK_LEFT, BACK, BACK_RIGHT, \
RIGHT, FRONT_RIGHT.
- distance between the two boxes: VERY_CLOSE (almost touching), CLOSE (under {close:g} m), MEDIUM \
({close:g} to {far:g} m), FAR (over {far:g} m).
- collision risk, from predicting both actors at constant speed and turn rate: HIGH (collision predicted \
within {high:g} s), LOW (within {horizon:g} s), NO.
- trajectory overlap risk, from the paths both actually drive next: HIGH (they overlap within {ohigh:g} s), \
LOW (within {olow:g} s), NO."""

#: Tag patterns of the built-in categories, given as a checklist a small model can follow step by
#: step. Only the patterns of categories present in the set are listed, so a user's own category
#: file brings only its own definitions.
_PATTERNS: tuple[tuple[str, str], ...] = (
    (
        "left_oppo",
        "the ego is TURNING_LEFT or VEERING_LEFT and the guest's relative heading is OPPOSITE",
    ),
    ("right_ped", "the ego is TURNING_RIGHT or VEERING_RIGHT and the guest is a PEDESTRIAN"),
    (
        "obj_crossing",
        "the guest's relative heading is LEFT or RIGHT while it is in FRONT, FRONT_LEFT or FRONT_RIGHT",
    ),
    (
        "cut_in",
        "the guest's relative heading is SAME and the guest itself is VEERING or TURNING (often "
        "left then right, or right then left) while ahead of the ego",
    ),
)


def _pattern_checklist(categories: CategorySet) -> str:
    present = [(name, text) for name, text in _PATTERNS if name in set(categories.names)]
    if not present:
        return ""
    items = ";\n".join(f"   {chr(ord('a') + i)}. {text}: {name}" for i, (name, text) in enumerate(present))
    return f"   Check, in this order, which pattern the tags show, and its category:\n{items}.\n"


_INSTRUCTIONS = """Instructions:
1. Find when the ego starts DECELERATING and look at the guest just before and during that time.
2. Choose the one category whose definition best explains the braking.
{patterns}   If the guest makes the ego brake but no definition fits, choose {unknown}. If the guest \
is not the reason for the braking, choose {not_relevant}.
3. Answer with one JSON object with exactly these keys, and keep it short:
   "description": one sentence (at most 20 words) rephrasing the event that makes the ego brake;
   "category": the name of the chosen category, exactly as written in the list;
   "explanation": one sentence (at most 20 words) naming the tags that support this category."""


def system_prompt(categories: CategorySet, tag_cfg: TagConfig | None = None) -> str:
    """The system message: role, how to read the tags, the categories, instructions and output format.

    Args:
        categories: the categories to choose from, in the order listed.
        tag_cfg: the tag thresholds quoted in the reading guide (defaults to the paper's values).
    """
    cfg = tag_cfg or TagConfig()
    guide = _TAG_GUIDE.format(
        veer=cfg.veer_angle_rad,
        turn=cfg.turn_angle_rad,
        close=cfg.distance_close_m,
        far=cfg.distance_far_m,
        high=cfg.ttc_high_s,
        horizon=cfg.ttc_horizon_s,
        ohigh=cfg.overlap_high_s,
        olow=cfg.overlap_low_s,
    )
    listed = "\n".join(f"- {c.name}: {c.definition}" for c in categories.categories)
    patterns = _pattern_checklist(categories)
    instructions = _INSTRUCTIONS.format(
        patterns=patterns, unknown=UNKNOWN_BUT_RELEVANT, not_relevant=NOT_RELEVANT
    )
    return f"{_ROLE}\n\n{guide}\n\nScenario categories:\n{listed}\n\n{instructions}"


def build_messages(
    description: str, categories: CategorySet, tag_cfg: TagConfig | None = None
) -> list[Message]:
    """The conversation for one event: the shared system message, then the event's description.

    Args:
        description: the structured scenario description (:mod:`scenariominer.events.describe`).
        categories: the categories to choose from.
        tag_cfg: the tag thresholds quoted in the reading guide.
    """
    return [
        system(system_prompt(categories, tag_cfg)),
        user(f"Scenario description:\n{description.strip()}"),
    ]


# ---------------------------------------------------------------- judgement from facts (v3)

#: Version of the judgement prompt below (hybrid and LLM-alone judges); stored with every result.
JUDGE_PROMPT_VERSION = "braking-judge/5"  # 5: explanations checked against the facts

_JUDGE_ROLE = (
    "You explain why an automated vehicle (the ego) braked, from facts measured in its driving log "
    "about the road user involved (the guest)."
)

_JUDGE_TASK = """Answer with one JSON object:
- "category": one of the allowed category names given with the facts (omit it when the category is given);
- "description": at most 15 words, in your own words: what the guest did that made the ego brake;
- "explanation": at most 25 words: the facts that show it (where the guest was, speeds, gap, time to \
collision). Do not repeat the description.
Use only numbers given in the facts.

Example answer for a car that moved in from the next lane:
{"category": "cut_in", "description": "A car from the left lane moves in just ahead of the ego.", \
"explanation": "The car veers right from front-left to front, 6.2 m ahead at 41 km/h; time to collision \
1.9 s, so the ego brakes at 3.1 m/s²."}"""


def judge_system_prompt(categories: CategorySet) -> str:
    """The system message of the judgement: role, every category with its definition, answer format.

    It is the same for every event of a category set (the per-event part is the user message),
    so its evaluated state is reused across calls and processes.
    """
    listed = "\n".join(f"- {c.name}: {c.definition}" for c in categories.categories)
    return f"{_JUDGE_ROLE}\n\nScenario categories:\n{listed}\n\n{_JUDGE_TASK}"


def judge_messages(facts_text: str, allowed: Sequence[str], categories: CategorySet) -> list[Message]:
    """The conversation judging one event: the shared system message, then its facts.

    Args:
        facts_text: the event's facts (:meth:`~scenariominer.explain.facts.EventFacts.text`).
        allowed: the category names the answer may use (one when the rules already decided).
        categories: the category set.
    """
    if len(allowed) == 1:
        choice = f"The category is {allowed[0]}; describe and explain it."
    else:
        choice = "Allowed categories: " + ", ".join(allowed) + "."
    return [
        system(judge_system_prompt(categories)),
        user(f"Facts:\n{facts_text.strip()}\n\n{choice}"),
    ]
