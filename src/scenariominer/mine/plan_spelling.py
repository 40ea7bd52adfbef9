"""Typing slips in a description, put right before the phrase rules read it.

A word the phrase rules do not know and no English dictionary holds ("pedestrain", "vehciles",
"turnign", "interesction") is replaced by the nearest word one or two edits away (a letter added,
dropped, changed or two swapped), preferring a word of the rules' own vocabulary; two words run
together ("pedestriansnear") are split where both halves are words. A word that either vocabulary
knows is never changed, nor are numbers, units and words of fewer than four letters.

The English dictionary is pyspellchecker's word-frequency list (``pip install 'scenariominer[mine]'``);
without it nothing is changed.
"""

from __future__ import annotations

import importlib
import pkgutil
import re
from functools import cache, lru_cache
from typing import Any

__all__ = ["corrected_spelling"]

_WORD = re.compile(r"[a-z]{4,}")
#: Slips too short for the nearest-word search, or that spell another English word ("busses").
_SLIPS = {
    "teh": "the", "hte": "the", "adn": "and", "nad": "and", "busses": "buses", "thier": "their",
    # abbreviations the nearest-word search would take for slips ("incl" is no "inch")
    "incl": "including", "excl": "excluding", "approx": "about",
}  # fmt: skip
_SLIP = re.compile(rf"\b(?:{'|'.join(_SLIPS)})\b")


@cache
def _rules_vocabulary() -> frozenset[str]:
    """Every word in the source of the phrase-rule modules (``mine/plan_*.py``): what they can read."""
    import inspect

    import scenariominer.mine as mine

    words: set[str] = set()
    for module in pkgutil.iter_modules(mine.__path__):
        if module.name.startswith("plan_") and module.name != "plan_spelling":
            source = inspect.getsource(importlib.import_module(f"scenariominer.mine.{module.name}"))
            source = re.sub(r"\\[a-zA-Z]", " ", source).lower()  # no regex escapes: "\bx-?walk" is "xwalk"
            # a pattern's optional letters both ways: "x-?walks?" -> "xwalk", "x-walks"
            for variant in (source, re.sub(r"[a-z'-]\?", "", source), re.sub(r"(?<=[a-z'-])\?", "", source)):
                words.update(re.findall(r"[a-z]{3,}", variant))
    return frozenset(words)


@cache
def _dictionary() -> Any:
    """The English dictionary of pyspellchecker (edits up to two), or ``None`` when not installed."""
    try:
        from spellchecker import SpellChecker
    except ImportError:
        return None
    return SpellChecker(distance=2)


def _known(word: str, dictionary: Any) -> bool:
    """Whether either vocabulary holds ``word`` (a contraction may lack its apostrophe: "arent")."""
    if word.endswith("nt") and f"{word[:-2]}n't" in dictionary:
        return True
    return word in _rules_vocabulary() or word in dictionary


def _fixed(word: str, dictionary: Any) -> str:
    """``word`` or what it was meant to be."""
    if _known(word, dictionary):
        return word
    near = dictionary.known(dictionary.edit_distance_1(word))
    if near:
        return _nearest(word, near, dictionary)
    # two words run together: split where both halves are words, preferring the rules' words
    splits = [
        (word[:i], word[i:])
        for i in range(2, len(word) - 1)
        if _known(word[:i], dictionary) and _known(word[i:], dictionary)
    ]
    if splits:
        left, right = max(
            splits,
            key=lambda s: (
                (s[0] in _rules_vocabulary()) + (s[1] in _rules_vocabulary()),
                -abs(len(s[0]) - len(s[1])),
            ),
        )
        return f"{left} {right}"
    farther = dictionary.known(dictionary.edit_distance_2(word)) if len(word) >= 6 else set()
    return _nearest(word, farther, dictionary) if farther else word


def _nearest(word: str, candidates: set[str], dictionary: Any) -> str:
    """The candidate ``word`` was most likely meant to be.

    A word the rules read first, then the longest beginning shared with ``word`` (a slip is
    likelier late in a word: "crosing" is "crossing", not "closing"), then a letter dropped
    rather than one added ("parkd" is "parked", not "park"), then the most frequent.
    """

    def shared(c: str) -> int:
        return next(
            (i for i, (a, b) in enumerate(zip(word, c, strict=False)) if a != b), min(len(word), len(c))
        )

    return max(
        sorted(candidates),
        key=lambda c: (
            c in _rules_vocabulary(),
            shared(c),
            len(c) >= len(word),
            dictionary.word_usage_frequency(c),
        ),
    )


@lru_cache(maxsize=4096)  # pure; the reader normalises one description more than once
def corrected_spelling(text: str) -> str:
    """``text`` (lower case) with its typing slips put right; unchanged without a dictionary."""
    text = _SLIP.sub(lambda m: _SLIPS[m[0]], text)
    words = [w for w in _WORD.findall(text) if w not in _rules_vocabulary()]
    if not words:
        return text
    dictionary = _dictionary()
    if dictionary is None:
        return text
    return _WORD.sub(lambda m: _fixed(m[0], dictionary), text)
