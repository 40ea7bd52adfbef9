"""A witness's account of what they saw from the car, put in the words the phrase rules read.

A witness statement sets the scene from the car the witness was in (the ego vehicle) before the
event it reports: "*I was stopped at the lights when* a man walked out in front of us", "*As we
approached the junction,* a truck turned left across our path", "a cyclist came up on our left
*while we were turning right*". :func:`witness_wording` keeps the event (the road user it is
about and what it did): the scene before "when", a leading or trailing clause of what "we" were
doing, and the witness's "I saw" are dropped; "our path" is the ego vehicle's path and "our left
side" its left. The past
tense is put in the present by :func:`scenariominer.mine.plan_narrative.present_tense` later.
"""

from __future__ import annotations

import re

__all__ = ["witness_wording"]

#: What the witness's car was doing while it happened (a verb after "I was" / "we were").
_OWN_STATE = (
    r"(?:stopped|waiting|sitting|queu(?:e)?ing|parked|stationary|stood|standing|driving|travell?ing|going|heading"
    r"|moving|pulling|turning|coming|approaching|slowing|cruising|doing|following|crawling|idling|reversing"
    r"|merging|changing|leaving|entering|just|still|already|about)"
)
_WE = r"(?:i|we|my (?:car|vehicle)|our (?:car|vehicle))"
_REWRITES: tuple[tuple[re.Pattern[str], str], ...] = (
    # "I was stopped at the lights when X": X
    (re.compile(rf"^(?:so |well,? )?{_WE} (?:(?:was|were|had been) {_OWN_STATE}"
                r"|had (?:just |only just )?\w+ed)\b[^,;]*?,?"
                r" (?:when|as|and(?: then)?(?: (?:i |we )?(?:saw|noticed|spotted|watched))?)"
                rf" (?=(?:a|an|the|this|that|some|another|two|three|several|one|suddenly|then)\b)"), ""),
    # "as we approached the junction, X" / "while I was waiting, X": X
    (re.compile(rf"^(?:as|while|when|just as|right as) {_WE} (?:was |were )?[^,;]+, (?=\S)"), ""),
    # "X as we went past" / "X while we were turning right": X
    (re.compile(rf",? (?:just |right )?(?:as|while|when) {_WE}(?: (?:was|were))? (?:\w+ing|went|passed|slowed"
                rf"|turned|pulled|drove|came|approached|stopped|waited|sat)\b.*$"), ""),
    # the witness saw it
    (re.compile(r"^(?:i|we) (?:(?:definitely|clearly|then|also|just) )?(?:saw|noticed|spotted|watched"
                r"|remember(?:ed)?|recall(?:ed)?|observed|could see|can remember|caught sight of)"
                r"(?: that| how)? (?=\S)"), ""),
    (re.compile(r"\b(?:went|go(?:es|ing)?|came|com(?:es|ing)) (?:right )?past\b"), "passed"),
    (re.compile(r"\bin the middle of the (?:road|street|carriageway)\b"), "on the road"),
    (re.compile(r"\bacross our path\b|\bacross (?:the )?front of us\b"), "in front of us"),
    (re.compile(r"\bon our (left|right)(?:[- ]hand)? side\b"), r"on our \1"),
)  # fmt: skip


def witness_wording(text: str) -> str:
    """``text`` (lower case) as the event a witness reports, without the scene around it."""
    if not re.search(rf"\b(?:{_WE}|us|our)\b", text):
        return text
    for pattern, replacement in _REWRITES:
        text = pattern.sub(replacement, text)
    return text
