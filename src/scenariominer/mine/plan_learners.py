"""Wording of writers whose first language is not English, put in the form the phrase rules read.

Validation teams work in many languages, and their English carries the grammar of the first:
"vehicles which are turning to left", "the car which drives behind of the ego", "pedestrian goes
over the street", "the bicycle drives on the bicycle way", "the ego is overtaken from a bus",
"vehicles in a distance of less than 5 m to a pedestrian". :func:`learner_wording` rewrites such
wording before the rest of the normalisation (:mod:`scenariominer.mine.plan_wording`): articles
put back before a side, prepositions set right, literal translations of place words and of
passives made plain. Each rewrite keeps the meaning; none guesses at one.
"""

from __future__ import annotations

import re

__all__ = ["learner_wording"]

_SPEED = r"\d+(?:\.\d+)? ?(?:m/s|km/h|kph|kmh|mph)"

#: (pattern, replacement), applied in order to the lower-cased text.
_REWRITES: tuple[tuple[re.Pattern[str], str], ...] = (
    # a side without its article: "turning to left", "on right side of the ego"
    (re.compile(r"\b(to|on|from|at) (left|right)\b(?![- ]hand| angles?| of way| away| now| here| there)"),
     r"\1 the \2"),
    (re.compile(r"\bto the (left|right) side\b(?! of)"), r"to the \1"),
    # prepositions after a place word: "behind of", "in front from", "next of"
    (re.compile(r"\bbehind of\b"), "behind"),
    (re.compile(r"\bin front (?:from|to)\b"), "in front of"),
    (re.compile(r"\bnext of\b"), "next to"),
    # "goes over the street": crosses it
    (re.compile(r"\b(?:goes|go|going|went|walks?|walking|walked|runs?|running) over"
                r" (?:the |a )?(street|road)\b"), r"crossing the \1"),
    # "the car is standing at the crossing": a vehicle that stands is stopped
    (re.compile(r"\b((?:cars?|vehicles?|trucks?|buses|bus|ego(?: vehicle| car)?)"
                r"(?: (?:which|that))?(?: (?:is|are))?) standing\b(?! still)"), r"\1 stopped"),
    # "in the near", "in near of the intersection", "inside 5 meters", "at less than 10 m"
    (re.compile(r"\bin (?:the )?near of\b"), "near"),
    (re.compile(r"\bin the near\b"), "nearby"),
    (re.compile(r"\b(?:inside|at less than|in less than) (?=\d)"), "within "),
    # "looking in direction to the ego", "point to a pedestrian", "coming to them"
    (re.compile(r"\bin (?:the )?direction (?:to|of) (?=(?:the|an?|its|their) )"), "toward "),
    (re.compile(r"\b(?:which|that) (?:points?|is pointing|are pointing) (?:to|at)\b"), "facing"),
    (re.compile(r"\b(coming|moving|driving) (?:directly |straight )?(?:to|onto) (?=(?:them|it|the) )"
                r"(?!the (?:\w+ )?(?:stop|halt|standstill)\b)"),
     r"\1 toward "),
    # "slower as 5 m/s": than; "which are no bus": other than buses
    (re.compile(r"\b(slower|faster|more|less|higher|lower|closer|further|farther) as\b"), r"\1 than"),
    (re.compile(r"\b(?:which|that) (?:are|is) no (\w+)"), r"other than \1"),
    (re.compile(r"\boutside from\b"), "outside"),
    (re.compile(r"\bparking (?:place|area)s?\b"), "parking lot"),
    # "the car is parking on the road": parked (a state, not a manoeuvre)
    (re.compile(r"\b(is|are|was|were) parking\b(?! (?:lot|space|area|garage|bay))"), r"\1 parked"),
    # literal place words: "bicycle way", "cycle path"; "the crossing" as a noun
    (re.compile(r"\b(?:bicycle|bike|cycle|cycling) (?:way|path|track|road)s?\b"), "bike lane"),
    (re.compile(r"\b(at|on|near|before|in front of|across) (?:the|a) (?:pedestrian )?crossing\b"
                r"(?! (?:the|a|in|of)\b)"), r"\1 the crosswalk"),
    # "is overtaken from a bus": by it
    (re.compile(r"\b(?:is|are|was|were|gets?|getting) (overtaken|passed|followed|approached|crossed)"
                r" (?:from|through) (?!(?:the |its |their )?(?:left|right|behind|front|rear|back|side)\b)"),
     r"being \1 by "),
    # "drives with more than 10 m/s", "with a speed of 10 m/s": at that speed
    (re.compile(rf"\b(?:with|at|by) (?:a |the )?(?:speed|velocity) (?:of )?(?=(?:more|less|over|under"
                rf"|above|below|at least|at most|about|around)\b|{_SPEED})"), ""),
    (re.compile(rf"\b(driving|drives|moving|moves|going|goes|riding|rides|travell?ing|travels) with "
                rf"(?=(?:more|less|over|under|above|below|at least|at most)\b|{_SPEED})"), r"\1 "),
    # "in a distance of less than 5 m to a pedestrian": within 5 m of it
    (re.compile(r"\b(?:in|at|with) (?:a |the )?distance (?:of )?"
                r"(?:less than |under |below |within |up to |max )?(\d+(?:\.\d+)? ?m) (?:to|from|of) "),
     r"within \1 of "),
    (re.compile(r"\bin (?:less than|under) (\d+(?:\.\d+)? ?m) distance (?:to|from|of) "), r"within \1 of "),
)  # fmt: skip


def learner_wording(text: str) -> str:
    """``text`` (lower case, single spaces) with a learner's wording put in plain English.

    "vehicles which are turning to left" -> "vehicles which are turning to the left"; "pedestrian
    goes over the street" -> "pedestrian crossing the street"; "the ego is overtaken from a bus" ->
    "the ego being overtaken by a bus".
    """
    for pattern, replacement in _REWRITES:
        text = pattern.sub(replacement, text)
    return " ".join(text.split())
