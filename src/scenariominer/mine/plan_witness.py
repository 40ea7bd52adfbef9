"""A witness's account of what they saw from the car, put in the words the phrase rules read.

A witness statement sets the scene from the car the witness was in (the ego vehicle) before the
event it reports: "*I was stopped at the lights when* a man walked out in front of us", "*As we
approached the junction,* a truck turned left across our path", "a cyclist came up on our left
*while we were turning right*". :func:`witness_wording` keeps the event (the road user it is
about and what it did): the scene before "when", a leading or trailing clause of what "we" were
doing, and the witness's "I saw" are dropped; "our path" is the ego vehicle's path and "our left
side" its left. A witness alone says "in front of me", "my lane": without any "we", "us" or "our"
in the text, "me" after a preposition or a verb of passing, and "my" before the car's parts or
lane, are read as "us" and "our" ("show me ..." stays a request). The past tense is put in the
present by :func:`scenariominer.mine.plan_narrative.present_tense` later.
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
#: The witness alone ("in front of me", "my lane") as the car they were in, "us" and "our".
_SINGULAR: tuple[tuple[re.Pattern[str], str], ...] = (
    (
        re.compile(
            r"\b(of|to|behind|past|at|toward|towards|from|beside|by|near|than|as|around|alongside|overtook"
            r"|overtaking|passed|passing|followed|following|approached|approaching|tailing|tailgating|facing"
            r"|faced) (?:me|myself)\b"
        ),
        r"\1 us",
    ),
    (re.compile(r"\bnext to mine\b"), "next to ours"),
    (
        re.compile(r"\bmy (?=(?:own )?(?:car|vehicle|lane|left|right|side|path|way|front|rear|bumper)\b)"),
        "our ",
    ),
)
_REWRITES: tuple[tuple[re.Pattern[str], str], ...] = (
    (re.compile(r"^(?:for a while|at one point|at some point|earlier (?:today|on)|today|yesterday),? "), ""),
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
    (re.compile(r"\b(?:went|go(?:es|ing)?|came|com(?:es|ing)) (?:right )?(?:past|by(?= us\b))"), "passed"),
    (re.compile(r"\bin the middle of the (?:road|street|carriageway)\b"), "on the road"),
    (re.compile(r"\bacross our path\b|\bacross (?:the )?front of us\b"), "in front of us"),
    (re.compile(r"\bon our (left|right)(?:[- ]hand)? side\b"), r"on our \1"),
    # "a car coming the other way": oncoming
    (re.compile(r"\b(?:coming|going|driving|heading) the other way"
                r"(?: (?:from|to) (?:us|our (?:car|vehicle)))?\b"),
     "travelling in the opposite direction to us"),
    # what the witness's car did, with no event after it ("I was driving along behind a bus")
    (re.compile(r"^(?:i|we) (?:was|were) (?=\w+ing\b)"), "the ego vehicle "),
    (re.compile(r"\b(?:had |has |have )?(?:come|came|comes|coming) to an? (?:complete |full |dead )?"
                r"(?:stop|halt|standstill)\b"), "stopped"),
    (re.compile(r"\b(driving|following|walking|travell?ing|going|cycling|moving) along\b"), r"\1"),
    (re.compile(r"\bturn(?:ed|ing|s)? (?:off )?(?:to|on)(?:to)? (?:its|their|the) (left|right)\b"),
     r"turning \1"),
)  # fmt: skip


def witness_wording(text: str) -> str:
    """``text`` (lower case) as the event a witness reports, without the scene around it."""
    if not re.search(rf"\b(?:{_WE}|us|our|me|my|mine)\b", text):
        return text
    if not re.search(r"\b(?:we|us|our)\b", text):
        # a witness alone: "me", "my" are the car they were in
        for pattern, replacement in _SINGULAR:
            text = pattern.sub(replacement, text)
    for pattern, replacement in _REWRITES:
        text = pattern.sub(replacement, text)
    return text
