"""Plain wordings the tables do not read directly, put in the form they read.

The rewording step (:mod:`scenariominer.mine.plan_reword`) asks the model for plain English, and
plain English has its own habits the phrase tables were not written for: a distance given as a
gap ("ahead of the ego vehicle with a gap of 20 m"), a speed bound named ("with a minimum speed of
5 m/s"), a manoeuvre joined by "with" ("tracks with lane changes to the right"), an acceleration's
sign ("trucks with negative acceleration"). :func:`plain_wording` rewrites them, after number words
have become digits (:func:`scenariominer.mine.plan_wording.normalised_text`). Each rewrite keeps the
meaning; a bound the tables cannot state ("a gap of at least 20 m") is left as written, so it stays
unread rather than read as its opposite.
"""

from __future__ import annotations

import re

from scenariominer.mine.plan_nouns import NOUN, NP

__all__ = ["plain_wording"]

_DISTANCE = r"(\d+(?:\.\d+)? ?(?:m|metres?|meters?))\b"
_MANOEUVRE = r"(?:accelerating|decelerating|braking|changing|turning|stopping|speeding|slowing|swerving)"

_REWRITES: tuple[tuple[re.Pattern[str], str], ...] = (
    # a contract's number twice, in words and in figures ("five (5) metres", now "5 5 metres")
    (re.compile(r"\b(\d+)(?:\.0+)? \1(?:\.0+)?(?= ?(?:m|metres?|meters?|m/s|m/s\^2|km/h|mph|seconds?|s"
                r"|degrees?|deg|pedestrians?|vehicles?|cars?|objects?)\b)"), r"\1"),
    # "inside twenty metres" (the number word became a digit after the learners' rewrite ran)
    (re.compile(r"\binside (?=\d)"), "within "),
    # "with a gap of 20 m (or less)": within 20 m; "a gap of at least 20 m" stays unread
    (re.compile(r"\bwith (?:a |an )?(?:gap|distance|separation|spacing|clearance) of "
                r"(?:at most |up to |no more than |under |less than |below )?"
                + _DISTANCE + r"(?: or less)?"),
     r"within \1"),
    # "with a minimum speed of 5 m/s", "at a maximum speed of 5 km/h": the bound it names (the
    # tables' "faster than" and "slower than" include the bound)
    (re.compile(r"\b(?:with|at) (?:a |an )?(?:minimum|min\.?|lowest) speed of (?=\d)"), "faster than "),
    (re.compile(r"\b(?:with|at) (?:a |an )?(?:maximum|max\.?|top|highest) speed of (?=\d)"), "slower than "),
    # "trucks with negative acceleration": decelerating
    (re.compile(r"\bwith (?:a )?negative (?:acceleration|longitudinal acceleration)\b"), "decelerating"),
    (re.compile(r"\bwith (?:a )?positive (?:acceleration|longitudinal acceleration)\b"), "accelerating"),
    # "vehicle with changing lanes to the right", "ego vehicle with accelerating more than ...":
    # a manoeuvre joined by "with" (after "lane changes" and "acceleration" became verbs)
    (re.compile(rf"\bwith (?={_MANOEUVRE}\b)"), ""),
    # "wheeled devices that have a pedestrian nearby": with one nearby
    (re.compile(r"\b(?:that|which|who) (?:has|have) (?=(?:an?|\d+|at least \d+|several|some|other) [\w ]+?"
                r" (?:nearby|close by|around)$)"), "with "),
    # "another vehicle within 3 m of ...": a vehicle (the first words name the subject)
    (re.compile(r"^another (?=\w)"), ""),
    (re.compile(r"\b(?:road objects?(?: of any (?:kind|type|sort))?|objects? of any (?:kind|type|sort))\b"),
     "objects"),
    (re.compile(r"\bour ego vehicle\b"), "the ego vehicle"),
    # "stopped near an intersection, not the parked ones": and not parked
    (re.compile(r",? not the (parked|moving|stopped|stationary) ones\b"), r" and not \1"),
    # "at a distance of no more than 20 m", "at a separation of 20 m": within it
    (re.compile(r"\bat (?:a |an )?(?:distance|separation|range|spacing) of (?:no more than |not more than "
                r"|at most |up to |less than |under |below )?(?=\d+(?:\.\d+)? ?(?:m|metres?|meters?)\b)"),
     "within "),
    # "crossing the path in front of a vehicle": crossing in front of it
    (re.compile(r"\bcrossing (?:the|its) path (?:in front )?of\b"), "crossing in front of"),
    # "near at least 3 pedestrians within 20 m": that many within that distance; "near a bus within
    # 20 m": within 20 m of it (else "within 20 m" is read as the distance to the ego vehicle)
    (re.compile(rf"\bnear ((?:at least |more than |over )?\d+ (?:other )?(?:{NOUN}))"
                rf" within {_DISTANCE}(?! of)"),
     r"with \1 within \2"),
    (re.compile(rf"\bnear ({NP}) within {_DISTANCE}(?! of)"), r"within \2 of \1"),
    # "orange cones": the cones
    (re.compile(r"\borange (?=(?:traffic |construction )?(?:cones?|barrels?|pylons?)\b)"), ""),
)  # fmt: skip


def plain_wording(text: str) -> str:
    """``text`` (normalised, number words as digits) with plain wordings put in the tables' form.

    "pedestrians ahead of the ego vehicle with a gap of 20 m" -> "pedestrians ahead of the ego
    vehicle within 20 m"; "trucks with negative acceleration" -> "trucks decelerating".
    """
    for pattern, replacement in _REWRITES:
        text = pattern.sub(replacement, text)
    return " ".join(text.split())
