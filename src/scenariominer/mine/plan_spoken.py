"""Spoken requests: a wake word before the request, a question asked instead of a request.

What is said to a voice assistant or typed into a chat window starts with the name of whom it is
asked ("Hey Miner, ...", "OK computer, ...") and is often a question: "were there any parked
trucks on these drives?", "when did the vehicle we were following hit the brakes?", "did any
vehicle change lanes to the left?", "was a bus ever driving in a bus lane?", "when were we
stopped?". :func:`spoken_request` drops the wake word and turns the question into the request
the phrase tables read ("find any parked trucks", "find the vehicle being followed by the ego
vehicle hit the brakes", "we stopped"), before anything else reads the text
(:func:`scenariominer.mine.plan_wording.normalised_text`). The words that only say where to look
("on these drives", "in the logs") are dropped too. A text that is neither is returned as it is.
"""

from __future__ import annotations

import re

from scenariominer.mine.plan_nouns import CATEGORY_RE

__all__ = ["spoken_request"]

_N = r"\d+(?:\.\d+)?"
#: Words that begin the request after a wake word said without a comma ("hey miner find ...").
_REQUEST_START = (
    r"(?:find|show|list|get|give|search|look|pull|fetch|display|were|was|are|is|did|do|does|when"
    r"|where|how|any|can|could|would|will|please|i|we)\b"
)
_WAKE_WORD = re.compile(
    r"^(?:(?:hey|hi|hello|ok(?:ay)?|yo|alright)(?: there)?(?: [\w'-]+){0,2}?\s*[,!:;]+"
    r"|(?:computer|assistant|miner|system)\s*[,!:;]+"
    rf"|(?:hey|hi|hello|ok(?:ay)?)(?: [\w'-]+){{1,2}}? (?={_REQUEST_START}))\s*"
)
#: "when were ...", "at what times did ...", "how often was ...": a question for the moments.
_WHEN = (
    r"(?:when|at what (?:times?|moments?|points?(?: in time)?)|at which (?:times?|moments?|points?)"
    r"|how often|how many times|in which (?:frames|moments))"
    r" (?:was|were|is|are|did|does|do|has|have|had)(?: there(?: been)?)?"
)
_QUESTIONS: tuple[tuple[re.Pattern[str], str], ...] = (
    # "when were we stopped", "did we make any left turns": the ego vehicle, in the first person
    (re.compile(rf"^{_WHEN} (?=we\b)"), ""),
    (re.compile(r"^(?:did|do|have|had) we (?:ever )?"), "we "),
    (re.compile(r"^(?:were|are|was) we (?:ever )?"), "we were "),
    (re.compile(rf"^{_WHEN} "), "find "),
    # "were there any", "has there ever been a"
    (re.compile(r"^(?:were|was|have|has|had) there (?:ever )?(?:been )?(?:ever )?"), "find "),
    # "did any vehicle change lanes", "was a bus ever driving", "were any cars driving"
    (re.compile(r"^(?:did|do|does|have|has|had|were|was|are|is) (?=(?:any|an?|the|some|\d+)\b)"), "find "),
)
#: Words that only say where to look: "on these drives", "in the logs", "across all recordings".
_SCOPE = re.compile(
    r"\s*\b(?:in|on|from|across|during|over|throughout) (?:all )?(?:of )?"
    r"(?:the |these |those |our |this |that |my )?"
    r"(?:drives?|logs?|recordings?|sequences?|data ?sets?|trips?|runs?|sessions?|test drives?)\b"
    r"(?= *(?:[?.!,]|$))"
)
_REWRITES: tuple[tuple[re.Pattern[str], str], ...] = (
    # "the vehicle we were following", "the car you are following": the one the ego vehicle follows
    (
        re.compile(
            rf"\b((?:{CATEGORY_RE})) (?:that |which )?(?:we|you) (?:were|are|was|is) (?:following|behind)\b"
        ),
        r"\1 being followed by the ego vehicle",
    ),
    # "from less than 20 meters away": within 20 m
    (
        re.compile(
            rf"\bfrom (?:less than|under|within|fewer than|closer than) ({_N}) ?(m|meters?|metres?)"
            r"(?: away)?\b"
        ),
        r"within \1 \2",
    ),
    # "a car (that) had at least three pedestrians within 10 meters": a car with ...
    (
        re.compile(
            rf"\b((?:{CATEGORY_RE})) (?:that |which |who )?(?:had|has|have) (?=(?:at least|at most"
            r"|more than|fewer than|less than|an?|some|\d+|one|two|three|four|five|six)\b)"
        ),
        r"\1 with ",
    ),
)


def spoken_request(text: str) -> str:
    """``text`` (lower case) without a wake word, a question put as a request.

    "hey miner, were there any parked trucks on these drives?" -> "find any parked trucks?";
    "ok computer, when were we stopped?" -> "we stopped?"; "did any vehicle change lanes to the
    left?" -> "find any vehicle change lanes to the left?". Other text is returned unchanged.
    """
    text = _WAKE_WORD.sub("", text.strip())
    for pattern, replacement in _QUESTIONS:
        asked = pattern.sub(replacement, text, count=1)
        if asked != text:
            # "was a bus ever driving ...": "ever" belongs to the question
            text = re.sub(r"\bever (?=\w+(?:ing|ed)\b)", "", asked, count=1)
            break
    text = _SCOPE.sub("", text)
    if text.startswith("we "):
        # "(when were) we driving behind another car in our lane": the lane is the ego vehicle's own
        text = re.sub(r"\b(?:in|within) our (?:own )?lane\b", "in the same lane", text)
    for pattern, replacement in _REWRITES:
        text = pattern.sub(replacement, text)
    return text
