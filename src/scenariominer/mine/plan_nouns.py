"""The road-user patterns the phrase rules match with: a category word, its modifiers, a noun phrase.

Built from the tables of :mod:`scenariominer.mine.plan_phrases` (:data:`CATEGORY_PHRASES`,
:data:`MODIFIERS`); :mod:`scenariominer.mine.plan_wording`, :mod:`scenariominer.mine.plan_notes`
and :mod:`scenariominer.mine.plan_reader` all match with these.
"""

from __future__ import annotations

import re
from typing import Any

from scenariominer.mine.plan_phrases import CATEGORY_PHRASES, MODIFIERS

__all__ = ["CATEGORY_RE", "DETERMINER", "MODIFIER_RE", "NOUN", "NOUN_PHRASE", "NP", "SUBJECT", "singular"]


def _alternation(patterns: Any) -> str:
    return "|".join(f"(?:{p})" for p in patterns)


CATEGORY_RE = _alternation(p for p, _ in CATEGORY_PHRASES)
MODIFIER_RE = _alternation(p for p, _, _ in MODIFIERS)
#: Words before another road user that carry no condition ("a *lead* vehicle": the relation says it).
DETERMINER = r"(?:(?:a|an|the|any|another|other|some|all|its|their|lead|leading|preceding)\s+)"
NOUN = rf"(?:{CATEGORY_RE})(?:\s+(?:or|and)\s+(?:other\s+)?(?:{CATEGORY_RE})){{0,4}}"
NOUN_PHRASE = re.compile(rf"{DETERMINER}*(?P<mods>(?:(?:{MODIFIER_RE})\s+)*)(?P<noun>{NOUN})")
NP = rf"(?:(?:{DETERMINER}*)(?:(?:{MODIFIER_RE})\s+)*(?:{NOUN}))"


SUBJECT = re.compile(
    rf"^\s*(?:(?:all|the|a|an|any|some|every)\s+)*(?P<mods>(?:(?:{MODIFIER_RE})\s+)*)(?P<noun>{NOUN})(?![\w-])"
)


def singular(word: str) -> str:
    """``word`` in the singular ("buses" -> "bus", "vehicles" -> "vehicle"; "bus" stays "bus")."""
    if word.endswith(("sses", "xes", "ches", "shes", "uses")):
        return word[:-2]
    if word.endswith("s") and not word.endswith(("ss", "us", "is")) and len(word) > 3:
        return word[:-1]
    return word
