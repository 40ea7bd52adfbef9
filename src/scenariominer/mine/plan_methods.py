"""The wording of a research paper's methods section, put in the words the phrase rules read.

Researchers state a selection in the passive voice, around the scenario: "*Segments were retained
in which* a pedestrian was observed within 5 m of the ego vehicle", "*We selected all* buses that
were stationary *for the duration of the segment*", "Vehicles turning left *were annotated for
further analysis*", "*The analysis was restricted to* vehicles facing the ego vehicle", "a speed
above 10 m/s *(approximately 36 km/h)*". :func:`methods_wording` drops that frame (what was done
with the data, not what to find), a restatement of a number in other units, the span of the
whole segment and a few academic words ("located", "designated", "in the vicinity of"), and
returns the scenario. A selection that *drops* something ("... were excluded") is not read as
one that keeps it: such a sentence comes back unchanged.
"""

from __future__ import annotations

import re
from collections.abc import Callable

__all__ = ["methods_wording"]

#: What researchers select: pieces of the recordings.
_UNITS = (
    r"(?:segments?|instances?|cases?|frames?|events?|samples?|scenes?|scenarios?|sequences?|clips?"
    r"|occurrences?|situations?|moments?|timestamps?|time ?steps?|episodes?|observations?|periods?"
    r"|intervals?|snippets?|excerpts?|windows?|encounters?|interactions?|records?|data ?points?)"
)
#: Verbs of keeping, finding or studying (never of dropping: "excluded", "discarded", "removed").
_KEPT = (
    r"(?:retained|identified|extracted|selected|kept|included|considered|flagged|label?led|labeled|annotated"
    r"|analy[sz]ed|collected|sampled|examined|drawn|defined|detected|retrieved|isolated|chosen|counted"
    r"|obtained|sought|used|marked|found|queried|mined|studied|investigated|recorded|logged|classified"
    r"|categori[sz]ed|coded|tagged|compiled|gathered|enumerated|assessed|evaluated|inspected|reviewed)"
)
_BE = r"(?:were|was|are|is|have been|has been|had been)"
#: "for further analysis", "in the present study", "as events of interest"
_PURPOSE = (
    r"(?: (?:for|in|into) (?:(?:the|further|subsequent|later|our|this|present|detailed|final) )*"
    r"(?:analysis|analyses|evaluation|study|data ?set|investigation|sample|corpus|inspection|review))?"
    r"(?: (?:as|for) (?:(?:positive|relevant|candidate|target|the) )*(?:positives?|cases|events|instances"
    r"|candidates|examples|set|class|of interest|relevant))?"
)
_STUDY = (
    r"(?:(?:in|for) (?:this|our|the present|the current) (?:study|work|analysis|paper|investigation),? )?"
)
_FRAMES = [
    # "segments were retained in which X", "events were defined as X", "samples were drawn of X"
    re.compile(
        rf"^{_STUDY}(?:(?:all|only|the) )*{_UNITS}(?: {_BE} {_KEPT}{_PURPOSE})?,?"
        r" (?:in which|during which|wherein|at which|on which|where|when|whenever|for which|such that|of|as"
        r"|containing|involving|featuring|showing|that (?:contain|involve|feature|show)(?:ed|s)?) (?P<x>.+)$"
    ),
    # "we selected all X", "the authors identified every X"
    re.compile(
        rf"^{_STUDY}(?:we|the authors|this study|the study|our analysis|the analysis)"
        r"(?: (?:then|subsequently|additionally|further|first|also))?"
        rf" (?:{_KEPT}|searched for|looked for|focus(?:s)?ed on|restricted (?:the|our) analysis to"
        r"|observed|noted)"
        rf"(?: (?:all|every|each|any|those|the))?(?: {_UNITS} (?:of|in which|where|involving))? (?P<x>.+)$"
    ),
    # "the analysis was restricted to X", "attention was confined to X"
    re.compile(
        r"^(?:the |our )?(?:analysis|study|evaluation|investigation|sample|data ?set|selection|attention"
        r"|focus) (?:was|is|were)"
        r" (?:restricted|limited|confined|narrowed|focus(?:s)?ed|directed|centred|centered)"
        r" (?:to|on) (?P<x>.+)$"
    ),
    # "the dataset was filtered for X"
    re.compile(
        r"^(?:the |our )?(?:data ?set|data|recordings|logs|corpus|database) (?:was|were) (?:filtered|searched"
        r"|queried|screened|mined|scanned) (?:for|to (?:keep|retain|include|find|identify)) (?P<x>.+)$"
    ),
    # "a vehicle was classified as tailgating if it followed X": the definition
    re.compile(
        r"^(?P<who>(?:an? |the )?[\w-]+(?: [\w-]+)?) (?:was|is|were|are) (?:classified|defined|considered"
        r"|label?led|labeled|counted|regarded|treated|coded|marked|flagged)"
        r" as (?:an? )?[\w-]+(?: [\w-]+){0,2},? (?:if|when|whenever|where) (?:it|they|the \w+) (?P<x>.+)$"
    ),
    # "it was observed that X"
    re.compile(r"^it (?:was|is|has been) (?:observed|noted|found|seen|recorded|determined) that (?P<x>.+)$"),
    # "X were annotated for further analysis"
    re.compile(rf"^(?:only )?(?P<x>.+?),? {_BE} (?:then |subsequently |also )?{_KEPT}{_PURPOSE}$"),
]
#: A bound in words as the tables' word for it.
_BOUND = {
    "below": "below",
    "under": "below",
    "less than": "below",
    "at most": "below",
    "above": "above",
    "over": "above",
    "exceeding": "above",
    "greater than": "above",
    "at least": "above",
}
_INNER: list[tuple[re.Pattern[str], str | Callable[[re.Match[str]], str]]] = [
    # "was observed within 5 m": the state, not the observing
    (re.compile(r"\b(?:was|were|is|are) (?:observed|detected|seen|found|recorded|present) (?=\S)"), ""),
    (
        re.compile(r"\b(?:objects?|agents?|actors?|tracks?|instances?) of (?:the )?(?:class|category|type) "),
        "",
    ),
    (re.compile(r"\b(?:located|situated|positioned) (?=within|in|on|at|inside|outside|near)\b"), ""),
    (re.compile(r"\bdesignated (?=(?:pedestrian )?crossings?|crosswalks?|lanes?|bike lanes?)"), ""),
    (re.compile(r"\bin (?:the|close) (?:immediate )?(?:vicinity|proximity) of\b"), "near"),
    (
        re.compile(
            r"\bwhose (?:speed|velocity) (?:exceeded|exceeds|was above|is above|was greater than|was over)"
        ),
        "with a speed above",
    ),
    (
        re.compile(r"\bwhose (?:speed|velocity) (?:was below|is below|was less than|was under|fell below)"),
        "with a speed below",
    ),
    # "(approximately 36 km/h)": the same number in other units
    (
        re.compile(
            r"\s*\((?:approximately|approx\.?|about|roughly|around|ca\.|circa|i\.e\.?|≈|~|=)?\s*"
            r"\d+(?:\.\d+)?\s*(?:km/h|kph|mph|m/s|ft|feet|m|metres|meters|s|seconds)\)"
        ),
        "",
    ),
    # "decelerated (longitudinal acceleration below -1 m/s²)": the definition in brackets is the test
    (
        re.compile(
            r"\b(?:accelerat|decelerat|brak)\w* \((?:i\.e\.,? |defined as |with )?(?:a )?(?:longitudinal )?"
            r"acceleration (?:of )?(below|under|less than|above|over|exceeding|greater than|at least|at most)"
            r" (-?\d+(?:\.\d+)?) ?m/s(?:²|\^2|2)\)"
        ),
        lambda m: f"with acceleration {_BOUND[m[1]]} {m[2]} m/s^2",
    ),
    # "for which no other vehicle was present ahead within 30 m": with no vehicle ahead
    (
        re.compile(
            r"\b(?:for which|for whom|where|such that|in which) no (?:other )?([\w-]+(?: [\w-]+)?)"
            r" (?:(?:was|were|is|are) )?(?:present |located |observed |detected |found )?"
            r"(?=ahead|behind|nearby|in front|to the|on (?:its|their))"
        ),
        r"with no \1 ",
    ),
    # "the ego vehicle had at least one pedestrian ahead of it", "while a pedestrian was ahead of it"
    (
        re.compile(
            r"\b(?:had|has|have) (?=(?:at least \w+|an?|no|one|\d+) [\w ]+? (?:ahead|behind|in front|nearby"
            r"|to the (?:left|right)|on (?:its|their) (?:left|right))\b)"
        ),
        "with ",
    ),
    (
        re.compile(
            r"\bwhile ((?:an?|at least \w+|\d+) [\w-]+(?: [\w-]+)?) (?:was|were|is|are)"
            r" (?:located |positioned )?"
            r"(?=(?:ahead of|behind|in front of|to the (?:left|right) of) (?:it|them)\b)"
        ),
        r"with \1 ",
    ),
    # the span of the whole recording
    (
        re.compile(
            r",? (?:for|over|during|across) the (?:entire |whole |full )?(?:duration|length|course|extent)"
            r" of the (?:segment|clip|sequence|recording|log|scene|episode|observation(?: period)?|window)"
            r"|,? throughout the (?:entire |whole )?(?:segment|clip|sequence|recording|log|scene|episode)"
        ),
        "",
    ),
]
#: Verbs that drop what they name: such a sentence is no selection of it.
_DROPPED = re.compile(r"\b(?:excluded|discarded|removed|omitted|filtered out|eliminated|rejected|ignored)\b")


def methods_wording(text: str) -> str:
    """``text`` (lower case) without a methods section's frame around the scenario."""
    if _DROPPED.search(text):
        return text
    stripped = text.rstrip(" .")
    for frame in _FRAMES:
        found = frame.match(stripped)
        if found is not None:
            stripped = " ".join(filter(None, (found.groupdict().get("who"), found.group("x"))))
            break
    else:
        return text
    # "cases in which X were selected": the frame both before and after
    if frame is not _FRAMES[-1] and (after := _FRAMES[-1].match(stripped)) is not None:
        stripped = after.group("x")
    for pattern, replacement in _INNER:
        stripped = pattern.sub(replacement, stripped)
    return " ".join(stripped.split())
