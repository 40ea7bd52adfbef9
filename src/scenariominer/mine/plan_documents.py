"""Requests written as parts of other documents, put in the form the phrase rules read.

* an issue tracker's ticket title: the ticket key and the bracketed tags before the title are
  dropped ("[LBL-12] [ped][crossing] Tag pedestrians crossing ..." -> "tag pedestrians crossing ...");
* a clause of a tender or contract: its number, "the supplier shall identify", "every instance of",
  "all occurrences wherein" are dropped, "ensure that all trucks turning right are identified" is
  read as "trucks turning right", and contract wording of places, distances and directions is put
  plainly ("whose footprint overlaps a marked pedestrian crossing" -> "on a marked pedestrian
  crossing", "from no further than 25 metres away" -> "within 25 metres", "braking firmly, that is,
  decelerating at 2 m/s² or more" -> the definition).

:func:`document_wording` reads the joined lower-case text; :func:`request_text` gives the
description as written without the ticket or clause wording (what the language model is shown).
A parameter block in YAML style is read by :mod:`scenariominer.mine.plan_yaml`.
"""

from __future__ import annotations

import re

from scenariominer.mine.plan_nouns import NP

__all__ = ["document_wording", "request_text"]

#: The wording around the request in a ticket title or a contract clause: its key and tags, its
#: number, "the supplier shall deliver" (matched in any case: :func:`request_text` reads the
#: description as written).
_WRAPPER: tuple[tuple[re.Pattern[str], str], ...] = (
    # a ticket title: "[LBL-1021] [ped] [crossing] Tag ..." / "MINE-301 [bus] Label ..." / "QA-7: Find ..."
    (re.compile(r"^\[?[a-z][a-z0-9]*-\d+\]?(?::\s*|\s+)(?=\[|[a-z])", re.I), ""),
    (re.compile(r"^(?:\[[\w ./:&+-]{1,30}\]\s*)+(?::\s*|-\s+)?", re.I), ""),
    # a contract clause: its number ("3.1", "4.2.1.", "R-12", "(a)")
    (
        re.compile(
            r"^(?:(?:clause|section|req(?:uirement)?|item)\s+)?(?:[a-z]{1,4}-\d+[.):]?|\d+(?:\.\d+)+[.)]?|\d+[.)])"
            r"\s+(?=\D)",
            re.I,
        ),
        "",
    ),
    (re.compile(r"^\([a-z0-9]{1,3}\)\s+", re.I), ""),
    (
        re.compile(
            r"^the (?:supplier|contractor|vendor|provider|service provider|bidder|tenderer|consultant)"
            r" (?:shall|must|will|is required to|agrees to)(?: be required to)?"
            r"(?: (?:identify|deliver|provide|extract|supply|detect|annotate|report|list|tag|label|mine"
            r"|furnish|produce|return|submit|flag|locate|retrieve|mark)"
            r"(?: and (?:identify|deliver|provide|extract|supply|report|list|tag|label"
            r"|mark|flag))?)?(?: to the (?:client|authority|purchaser|buyer|contracting authority))?,?\s+",
            re.I,
        ),
        "",
    ),
)
#: Wording of a ticket title and of a contract clause, dropped or put plainly.
_DOCUMENT: tuple[tuple[re.Pattern[str], str], ...] = (
    *_WRAPPER,
    (re.compile(r"^(?:each|every) (?=\S)"), ""),
    # "ensure that all trucks turning right are identified" -> "all trucks turning right"
    (
        re.compile(
            r"^ensure that (.+?) (?:is|are) (?:identified|extracted|delivered|reported|detected|labelled"
            r"|labeled|tagged|flagged|provided)(?: in full)?\.?$"
        ),
        r"\1",
    ),
    (
        re.compile(
            r"^(?:all |every |each |any )?(?:(?:relevant|such) )?(?:instances?|occurrences?|cases?|examples?"
            r"|events?|situations?|scenarios?|episodes?|time (?:intervals?|periods?|spans?))"
            r" (?:of|wherein|where|in which|whereby|during which|when)\s+"
        ),
        "",
    ),
    # what the supplier delivers it with: "..., together with the timestamps", "in the agreed format"
    (
        re.compile(
            r"(?:^|,? )together with (?:the |their |its )?(?:timestamps?|track ids?|frame ids?)"
            r"(?: and (?:the |their |its )?(?:timestamps?|track ids?|frame ids?))?,?(?= |$)"
        ),
        "",
    ),
    (re.compile(r"^(?:and |, ?)"), ""),
    (re.compile(r",? (?:in|using) the (?:agreed|specified|prescribed) (?:format|schema|manner)\b.*$"), ""),
    (re.compile(r",? (?:as|which shall be|to be) delivered (?:to|in)\b.*$"), ""),
    # a definition given after the term: "all vehicles braking firmly, that is, decelerating at 2
    # m/s² or more" -> the definition; "parked vehicles, meaning vehicles that ..." -> "... i.e. ..."
    (
        re.compile(
            r"^(?P<head>.+?) \w+ing(?: \w+ly)?, (?:that is|i\.e\.|meaning|namely|in other words),?"
            r" (?P<definition>\w+ing\b[^,]*\d[^,]*)$"
        ),
        r"\g<head> \g<definition>",
    ),
    (re.compile(rf", (?:that is|meaning|namely|in other words),? (?={NP}(?![\w-]))"), " i.e. "),
    # contract wording of a place, a lane, a distance, a direction
    (
        re.compile(
            r"\bwhose (?:footprint|bounding box|box|body|extent|outline)"
            r" (?:overlaps|intersects|touches|lies on)"
            r" (?=(?:an? |the )?(?:marked |painted )?(?:pedestrian crossing|crosswalk|zebra crossing)s?\b)"
        ),
        "on ",
    ),
    (
        re.compile(
            r",? (?:excluding|except|other than|but not) (?:those|ones|vehicles|cars|any)"
            r"(?: that are| which are)?"
            r" parked(?: for the (?:whole|entire) (?:log|recording|sequence|scene)| throughout)?\b"
        ),
        " but not parked",
    ),
    (
        re.compile(r"\bin (?:the|a) direction opposite (?:to|from)(?: that of)? "),
        "in the opposite direction to ",
    ),
    (re.compile(r"\b(?:that|which|who) (?:comes?|came|gets?|got) (?=within \d|closer than \d)"), ""),
    (re.compile(r"\b(?:that|which|who) (?:occupy|occupies) (?=the same lane as\b)"), "in "),
    (
        re.compile(r"\bfrom no (?:further|farther|more) than (\d+(?:\.\d+)?) ?(m|metres|meters)(?: away)?\b"),
        r"within \1 \2",
    ),
    (re.compile(r"\b(\d+(?:\.\d+)?) ?(m|metres|meters) away or (?:closer|less|nearer)\b"), r"within \1 \2"),
    (
        re.compile(
            r"\b(decelerating|braking|slowing(?: down)?|accelerating) at (\d+(?:\.\d+)?) ?(m/s²|m/s2|m/s\^2)"
            r" or (?:more|above|greater|higher)\b"
        ),
        r"\1 at more than \2 \3",
    ),
    (
        re.compile(
            r"\b(swerving|veering) (left|right) at (?:over|above|more than) (\d+(?:\.\d+)?)"
            r" ?(m/s²|m/s2|m/s\^2) lateral\b"
        ),
        r"\1 \2 with a lateral acceleration of more than \3 \4",
    ),
    # "in the same lane as and ahead of the ego vehicle": each relation with its object
    (
        re.compile(
            r"\b(in the same lane as|next to|behind|ahead of|in front of),? and (in the same lane as|next to"
            r"|behind|ahead of|in front of),? (the ego vehicle|the ego|(?:the|a|an) [a-z]+)\b"
        ),
        r"\1 \3 and \2 \3",
    ),
)


def request_text(description: str) -> str:
    """``description`` as written, without the ticket or clause wording before the request.

    What the language model is shown: a ticket's key and tags, a clause's number and "the supplier
    shall deliver" dropped (a clause number such as "1.38" is no number of the scenario).
    """
    text = " ".join(description.split())
    for pattern, replacement in _WRAPPER:
        text = pattern.sub(replacement, text)
    return text or description


def document_wording(text: str) -> str:
    """``text`` (lower case, one line) without the ticket or clause wording around the request."""
    for pattern, replacement in _DOCUMENT:
        text = pattern.sub(replacement, text)
    return text
