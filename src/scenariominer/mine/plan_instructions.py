"""An annotator's instructions, put in the form the phrase rules read.

A labelling guide tells annotators which objects to tag and in which frames: "Tag every pedestrian
for the frames in which they are inside the drivable area; pedestrians on the sidewalk do not get
this tag", "Mark every vehicle for the duration of a left turn", "Tag pedestrians at the moments
they cross in front of any vehicle; tag the pedestrian, not the vehicle". :func:`instruction_wording`
keeps what describes the scenario: notes about the tag itself (who gets it, what stays untagged,
"for this task") are dropped, the frames a tag covers become the condition they state ("for the
frames in which they are inside X" -> "inside X"), and a manoeuvre's duration becomes its verb ("for
the duration of a left turn" -> "turning left"). The request verb itself ("tag", "label") is read
with the other request words (:mod:`scenariominer.mine.plan_wording`).
"""

from __future__ import annotations

import re

__all__ = ["instruction_wording"]

#: A sentence or clause that speaks of the tag, not of the scene.
_TAG_NOTE = re.compile(
    r"\b(?:tags?|tagged|tagging|untagged|labels?|labell?ed|labell?ing|unlabell?ed|annotat\w*|for this task"
    r"|do(?:es)? not get|don't get|doesn't get)\b"
)
#: Words that begin a tag note inside a sentence ("..., tag the pedestrian, not the vehicle").
_CLAUSE_BREAK = re.compile(r"\s*;\s*|(?<=\w)\.\s+")
_REWRITES: tuple[tuple[re.Pattern[str], str], ...] = (
    # the request verb, first (what follows names the subject)
    (
        re.compile(
            r"^(?:please )?(?:(?:could|can|would|will) you (?:please )?)?(?:tag|label|annotate|mark|flag"
            r"|highlight)(?: (?:every|each|all|any))?"
            r"(?: (?:frames?|moments?|times?|timestamps?|instances?|cases?) (?:in which|where|when|that))? "
        ),
        "",
    ),
    # the frames a tag covers: the condition they state
    (
        re.compile(
            r"\s*,?\s*\b(?:but )?(?:only )?(?:for|in|during|at|over) (?:the |all |those |any |each )?"
            r"(?:video )?(?:frames?|moments?|timestamps?|instants?|times?|periods?|intervals?)"
            r"(?: (?:in which|where|when|that|at which|during which))? (?:they|it|he|she)(?: (?:are|is))?\s+"
        ),
        " ",
    ),
    (
        re.compile(
            r"\bfor the (?:duration|length) of (?:a|an|the|their|its|any) (left|right)(?:[- ]hand)? turn\b"
        ),
        r"turning \1",
    ),
    (
        re.compile(
            r"\s*,?\s*\bfor the (?:whole|entire|full) (?:manoeuvre|maneuver|turn|lane change|event)\b"
        ),
        "",
    ),
    (re.compile(r"\b(on|in|inside|at) the intersection itself\b"), r"\1 the intersection"),
    # "whenever they move over into ...": the verb itself
    (re.compile(r"\bwhenever (?:they|it) (?=\w+)"), ""),
    # "whenever at least two pedestrians are within 15 m of it": a with clause
    (
        re.compile(
            r"\bwhenever (?P<np>(?:at least |more than |no fewer than )?(?:\w+|an?|some) [\w ]+?) (?:are|is)"
            r" (?P<rest>within [\w.]+ ?(?:m|metres?|meters?))(?: of (?:it|them|the ego(?: vehicle)?))?\b"
        ),
        r"with \g<np> \g<rest>",
    ),
    # "whose nose points at X": facing X; "whether they are moving or parked": no condition
    (
        re.compile(
            r"\bwhose (?:nose|front|bonnet|hood) (?:points?|is pointed|is pointing) (?:at|towards?)\b"
        ),
        "facing",
    ),
    (
        re.compile(
            r"\s*,?\s*\bwhether (?:they are|it is|moving or|parked or|stopped or)[\w ]*?"
            r"(?:moving|parked|stopped|stationary|not)(?: or not)?(?=$|[,;.])"
        ),
        "",
    ),
    (re.compile(r"\b(their|its|own) lane corridor\b"), r"\1 lane"),
    # "the lead vehicle the ego vehicle is following": a relative clause without "that"
    (
        re.compile(
            r"^((?:the |a |an )?(?:lead |leading )?(?:vehicles?|cars?|trucks?|bus(?:es)?|pedestrians?"
            r"|objects?)) (?=the ego(?: vehicle)? is (?:following|overtaking|passing|approaching|facing)\b)"
        ),
        r"\1 that ",
    ),
    # "overtaking the ego vehicle on its left, passing from behind it to ahead of it along its left
    # side": the definition of an overtaking repeats it
    (
        re.compile(
            r"\b((?:overtaking|passing) [\w ]+? on (?:its|their) (left|right)),? passing from behind"
            r" (?:it|them) to ahead of (?:it|them)(?: (?:along|on) (?:its|their) \2(?: side)?)?"
        ),
        r"\1",
    ),
)


#: A later clause that says what to include ("include people who never move as well as ...") or
#: which frames to count: a note on the tag's extent, read from the first clause.
_EXTENT_NOTE = re.compile(r"^(?:include|including|this includes|also include|count|only count)\b")
#: A later clause that excludes a state ("do not tag parked ones"): kept, read as a negated condition
#: (:mod:`scenariominer.mine.plan_rewordings`).
_EXCLUSION = re.compile(
    r"^(?:but )?(?:do not|don't) (?:tag|label|include|count|annotate|mark|select) (?:the |any |all )?"
    r"(?:ones |those )?(?:that are |which are |who are )?(?:parked|stopped|stationary|standing still|moving"
    r"|turning)"
)


def _scene_parts(text: str) -> str:
    """``text`` without the sentences and ';' clauses after the first that speak of the tag."""
    parts = _CLAUSE_BREAK.split(text)
    kept = [
        parts[0],
        *(p for p in parts[1:] if _EXCLUSION.match(p) or not (_TAG_NOTE.search(p) or _EXTENT_NOTE.match(p))),
    ]
    if len(kept) == len(parts):
        return text
    return "; ".join(part.strip() for part in kept if part.strip())


def instruction_wording(text: str) -> str:
    """``text`` (lower case) with an annotator's instructions put as a description of the scene."""
    text = _scene_parts(text)
    for pattern, replacement in _REWRITES:
        text = pattern.sub(replacement, text)
    # "..., tag the pedestrian, not the vehicle": which of two road users is tagged
    return re.sub(
        r"\s*,?\s*\b(?:tag|label|mark|annotate) (?:only )?the \w+,? (?:not|rather than) the \w+\.?$", "", text
    )
