"""A telegram-style request, put in the plain words the phrase rules read.

Some users write like an old telegram: all capitals, articles dropped, each sentence ended by the
word ``STOP`` ("FIND PARKED VEHICLES STOP UNMOVED ENTIRE LOG STOP"). Read naively, every ``STOP``
would ask for stopped objects. :func:`telegram_wording` recognises the form (mostly capitals and a
final ``STOP``; "STOP SIGN" stays a sign), keeps the first sentence, which carries the request, and
of the later ones only those that state a measured bound ("SPEED OVER 1 METRE PER SECOND"), put in
brackets after it as its definition; the others ("ADVISE SOONEST", "SEND TIMES", "UNMOVED ENTIRE
LOG", "REPORT PEDESTRIANS NOT EGO") are courtesies, glosses or restatements. Telegraphese without
articles is put back in the forms the rules read: "SAME LANE" is "in the same lane", "MAKING LEFT
TURN" is "making a left turn", and "IN LOG", "EITHER DIRECTION", "ANY LOCATION" say nothing.
Text in any other form comes back unchanged.
"""

from __future__ import annotations

import re

__all__ = ["telegram_wording"]

#: The word that ends a telegram's sentence (not the one of a stop sign).
_STOP = re.compile(r"\s*\bSTOP\b(?!\s+SIGNS?\b)[.!]?\s*")
_FINAL_STOP = re.compile(r"\bSTOP[.!]?\s*$")
#: A later sentence that bounds a measured value: a number and a unit.
_BOUND = re.compile(
    r"\b(?:\d+(?:\.\d+)?|half|one|two|three|four|five|six|seven|eight|nine|ten)\s+"
    r"(?:m|metres?|meters?|km/h|kph|mph|kilometres?|kilometers?|miles?|seconds?)\b",
    re.IGNORECASE,
)
#: Telegraphese put back in the forms the phrase rules read (applied to the lower-cased text).
_TELEGRAPHESE = (
    (r"\b(?:seen |present |appearing )?in (?:the )?(?:log|logs|recording|recordings|data)\b", " "),
    (r"\b(?:in )?(?:either|any|both) (?:direction|directions|way|location|locations)\b", " "),
    (r"\beither one\b|\bitself\b", " "),
    (r"(?<!\bthe )(?<!\bits )(?<!\btheir )\bsame lane\b", "in the same lane"),
    (r"\bin in the same lane\b", "in the same lane"),
    (r"\bmaking (left|right|u) turns?\b", r"making a \1 turn"),
    (r"\bhalf (?=metres?|meters?|m\b)", "0.5 "),
    (r"\bbeing crossed in front by\b", "being crossed by"),
    (r"\bswerving (left|right) \((lateral acceleration [^()]*?) toward (?:the )?\1\)", r"with \2 toward \1"),
)


def telegram_wording(description: str) -> str:
    """``description`` as plain words when it is written as a telegram, else unchanged."""
    letters = [c for c in description if c.isalpha()]
    if not letters or sum(c.isupper() for c in letters) < 0.8 * len(letters):
        return description
    if _FINAL_STOP.search(description) is None:
        return description
    sentences = [s.strip() for s in _STOP.split(description) if s.strip()]
    if not sentences:
        return description
    request = sentences[0].lower()
    bounds = [s.lower() for s in sentences[1:] if _BOUND.search(s) and not _BOUND.search(sentences[0])]
    text = request + "".join(f" ({bound})" for bound in bounds[:1])
    for pattern, replacement in _TELEGRAPHESE:
        text = re.sub(pattern, replacement, text)
    return " ".join(text.split())
