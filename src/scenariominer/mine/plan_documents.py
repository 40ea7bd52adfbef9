"""Requests written as parts of other documents, put in the form the phrase rules read.

* an issue tracker's ticket title: the ticket key and the bracketed tags before the title are
  dropped ("[LBL-12] [ped][crossing] Tag pedestrians crossing ..." -> "tag pedestrians crossing ...");
* a clause of a tender or contract: its number, "the supplier shall identify", "every instance of",
  "all occurrences wherein" are dropped, "ensure that all trucks turning right are identified" is
  read as "trucks turning right", and contract wording of places, distances and directions is put
  plainly ("whose footprint overlaps a marked pedestrian crossing" -> "on a marked pedestrian
  crossing", "from no further than 25 metres away" -> "within 25 metres", "braking firmly, that is,
  decelerating at 2 m/s² or more" -> the definition);
* a requirement in EARS form: "When a pedestrian is within 5 m of the ego vehicle, the system shall
  return the pedestrian" -> "a pedestrian within 5 m of the ego vehicle";
* a tag path: "vehicle/lane_change/left" -> "vehicle changing lanes to the left";
* OpenSCENARIO's names: "Entity vehicle, SpeedCondition greaterThan 10 m/s" -> "vehicle faster
  than 10 m/s", "performs LaneChangeAction to the left" -> "changing lanes to the left".

:func:`document_wording` reads the joined lower-case text; :func:`request_text` gives the
description as written without the ticket or clause wording (what the language model is shown).
A parameter block in YAML style is read by :mod:`scenariominer.mine.plan_yaml`.
"""

from __future__ import annotations

import re
from collections.abc import Callable

from scenariominer.mine.plan_nouns import NP, SUBJECT, singular

__all__ = ["camel_words", "document_wording", "request_text"]

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


#: OpenSCENARIO's CamelCase names and rule words: "LaneChangeAction", "greaterThan".
_CAMEL = re.compile(
    r"\b(?:[A-Z][a-z]+){1,4}(?:Condition|Action|Position|Participant|Ref|Trigger|Event|Maneuver|Entity)\b"
    r"|\b(?:greaterThan|lessThan|equalTo|greaterOrEqual|lessOrEqual|notEqualTo)\b"
)


def camel_words(description: str) -> str:
    """``description`` with OpenSCENARIO's CamelCase names split ("SpeedCondition" -> "Speed Condition")."""
    return _CAMEL.sub(lambda m: re.sub(r"(?<=[a-z])(?=[A-Z])", " ", m[0]), description)


def request_text(description: str) -> str:
    """``description`` as written, without the ticket or clause wording before the request.

    What the language model is shown: a ticket's key and tags, a clause's number and "the supplier
    shall deliver" dropped (a clause number such as "1.38" is no number of the scenario).
    """
    text = " ".join(description.split())
    for pattern, replacement in _WRAPPER:
        text = pattern.sub(replacement, text)
    return text or description


#: "the system shall return": the requirement's response (EARS), the system being the search.
_SHALL = (
    r"the (?:system|scenario search|search|search engine|tool|miner|software|function|application|query"
    r"|scenario miner|mining tool) shall (?:return|select|report|output|flag|identify|list|retrieve|provide"
    r"|detect|mark|tag|label|find|include|highlight|extract|deliver)(?: as (?:a )?(?:match(?:es)?|results?))?"
)
#: A requirement in EARS form: "When/While/If/Where <condition>, the system shall return <objects>".
_EARS = re.compile(
    rf"^(?P<kind>when|while|if|where|whenever|in case) (?P<cond>.+?),? (?:then )?{_SHALL} (?P<target>.+?)\.?$"
)
_EARS_PLAIN = re.compile(rf"^{_SHALL} (?P<target>.+?)\.?$")
#: The response names the condition's subject again: "it", "them", "that object".
_PRONOUN = re.compile(r"^(?:it|them|they|that object|those objects|the object|the objects)$")
#: What the response adds about time or the relation: "while it brakes", "during the turn", "that
#: has the neighbour", "being crossed".
_RESPONSE_TAIL = re.compile(
    r" (?:(?:while|when|as|during|at|in|for) (?:it|they|the|that|those|these|its|their)\b|(?:that|which|who)"
    r" (?:has|have|is|are)\b|being\b).*$"
)
_DEMONSTRATIVE = re.compile(
    r"^(?:the|that|this|those|these|such|each such|every such|all such|the same|said) "
)
#: The condition's subject and its verb: "a pedestrian is ...", "a vehicle has another ...".
_CONDITION_VERB: tuple[tuple[re.Pattern[str], str], ...] = (
    (
        re.compile(
            r"^((?:an?|the|any|some|at least \w+) )?((?:(?!\b(?:that|which|who)\b)[a-z' -])+?)"
            r" (?:is|are) (?!(?:a|an)\b)"
        ),
        r"\1\2 ",
    ),
    (
        re.compile(r"\bwithin an? (\d+(?:\.\d+)?)[- ]degrees? (?:half[- ]angle|cone|angle|sector)\b"),
        r"within \1 degrees",
    ),
    (re.compile(r"\boccup(?:y|ies) (?=(?:an?|the) (?:[a-z-]+ )?lane\b)"), "in "),
    (
        re.compile(
            r"^((?:an?|the|any|some) )?([a-z -]+?) (?:has|have) (?=(?:an?|another|no|some|\d+|at least)\b)"
        ),
        r"\1\2 with ",
    ),
    (
        re.compile(r"\bcomes? to a (?:momentary |brief |short )?(?:standstill|stop|halt)\b"),
        "momentarily halted",
    ),
    (
        re.compile(r"\b(?:walks?|runs?|steps?) across the path (?:directly )?in front of\b"),
        "crossing in front of",
    ),
    (re.compile(r"'s (?:footprint|bounding box|box|body) (?:overlaps|intersects|touches) "), " on "),
    (re.compile(r"\baccelerates? forward\b"), "accelerating"),
)


def _head(phrase: str) -> str:
    """The last word of a noun phrase, in the singular ("motor vehicles" -> "vehicle")."""
    return singular(phrase.split()[-1]) if phrase.split() else ""


def requirement_wording(text: str) -> str:
    """A requirement in EARS form as the request it states.

    "when a pedestrian is within 5 m of the ego vehicle, the system shall return the pedestrian" ->
    "a pedestrian within 5 m of the ego vehicle"; "while at least 3 pedestrians are within 15 m of
    a vehicle, the system shall return that vehicle" -> "vehicle with at least 3 pedestrians within
    15 m"; "while the ego vehicle is turning left, the system shall return pedestrians in front of
    it" -> "pedestrians in front of it while the ego vehicle is turning left"; "the system shall
    return all vehicles that ..." -> "all vehicles that ...".
    """
    if (plain := _EARS_PLAIN.match(text)) is not None:
        return plain["target"]
    found = _EARS.match(text)
    if found is None:
        return text
    cond = re.sub(r"^the object is (?:an? |the )?", "", found["cond"])
    cond = re.sub(r",? (?:and )?when (?:it|they) (?:is|are) ", " ", cond)
    clause = cond  # the condition as a clause, for a response about something else
    for pattern, replacement in _CONDITION_VERB:
        cond = pattern.sub(replacement, cond, count=1)
    target = found["target"]
    named = _DEMONSTRATIVE.sub("", _RESPONSE_TAIL.sub("", target))
    subject = SUBJECT.match(cond)
    demonstrative = _DEMONSTRATIVE.match(target) is not None
    if _PRONOUN.match(named) or (
        demonstrative and subject is not None and _head(named) == _head(subject["noun"])
    ):
        return cond  # the condition is about the objects returned
    # the objects returned are the other road user of the condition: "... within 15 m of a vehicle"
    other = re.match(
        rf"^(?P<rest>.+?) (?P<rel>in front of|behind|ahead of|next to|of|near|close to) (?:an?|the)"
        rf" (?:\w+ )?{re.escape(_head(named))}(?:e?s)?$",
        cond,
    )
    if other is not None and demonstrative:
        rel = "" if other["rel"] in ("of", "near", "close to") else f" {other['rel']} them"
        return f"{named} with {other['rest']}{rel}"
    return f"{target} while {clause}"


#: A scenario named as a tag path: "vehicle/lane_change/left", "ped.crossing.in_front_of_ego".
_TAG_PATH = re.compile(r"^[a-z][a-z0-9_-]*(?:[./][a-z0-9_-]+)+$")
_TAG_WORDS: tuple[tuple[re.Pattern[str], str | Callable[[re.Match[str]], str]], ...] = (
    (re.compile(r"\blane ?changes?(?: ?(left|right))?\b"), r"changing lanes to the \1"),
    (re.compile(r"changing lanes to the (?= |$)"), "changing lanes "),
    (re.compile(r"\b(left|right) ?turns?\b"), r"turning \1"),
    (re.compile(r"\bturns? (left|right)\b"), r"turning \1"),
    (
        re.compile(
            r"\b(?:speed|velocity) (?:above|over|gt|min|greater than|faster than)"
            r" (\d+(?:\.\d+)?) ?(mps|ms|m/s)?\b"
        ),
        r"faster than \1 m/s",
    ),
    (
        re.compile(
            r"\b(?:speed|velocity) (?:below|under|lt|max|less than|slower than)"
            r" (\d+(?:\.\d+)?) ?(mps|ms|m/s)?\b"
        ),
        r"slower than \1 m/s",
    ),
    (re.compile(r"\b(above|over|below|under) (\d+(?:\.\d+)?) ?(?:mps|ms)\b"), r"\1 \2 m/s"),
    # units run into their numbers, a bare distance as the last level: "2mps2", "10m"
    (re.compile(r"\b(\d+(?:\.\d+)?) ?mps2\b"), r"\1 m/s²"),
    (re.compile(r"\bminus (\d+(?:\.\d+)?) m/s²"), r"-\1 m/s²"),
    (
        re.compile(r"^ego (vehicle|pedestrian|car|truck|bus|cyclist|object)s? (ahead|in front|behind)\b"),
        lambda m: f"{m[1]} {'behind' if m[2] == 'behind' else 'in front of'} the ego vehicle",
    ),
    (
        re.compile(r"\bbraking (?:hard )?(?:below|under) -(\d+(?:\.\d+)?) m/s²"),
        r"braking harder than \1 m/s²",
    ),
    (re.compile(r"\b(within|under|lt|max) (\d+(?:\.\d+)?) ?m\b"), r"within \2 m"),
    (re.compile(r"(?<!within )(?<!\d)\b(\d+(?:\.\d+)?) ?m$"), r"within \1 m"),
    (
        re.compile(r"\blateral acc(?:el|eleration)? (left|right) (?:over|above|gt|min) (\d+(?:\.\d+)?) m/s²"),
        r"with a lateral acceleration to the \1 of more than \2 m/s²",
    ),
    (re.compile(r"\bnear (other )?([a-z]+) min (\d+)\b"), r"near at least \3 \1\2"),
    (
        re.compile(r"\b(left|right) side (?:an? )?([a-z ]+?) within (\d+(?:\.\d+)?) m\b"),
        r"with a \2 on its \1 within \3 m",
    ),
    (re.compile(r"\bahead (at least \d+ [a-z]+s) within (\d+(?:\.\d+)?) m\b"), r"with \1 ahead within \2 m"),
    (re.compile(r"(?<!the )\bsame lane as (ego|an? [a-z]+)\b"), r"in the same lane as \1"),
    (re.compile(r"\boff (?:the )?(?:crosswalk|pedestrian crossing|xwalk)\b"), "not at a pedestrian crossing"),
    (re.compile(r"(?<!in the )\bdrivable area\b"), "in the drivable area"),
    (re.compile(r"^vehicle non regular\b"), "vehicles other than regular vehicles"),
    (re.compile(r"^vehicle incl(?:uding)? (bicycle|bike)s?\b"), "vehicles or bicycles"),
    (
        re.compile(r"\bnear ((?:other |moving )?(?:ego|[a-z]+(?: [a-z]+)?)) within (\d+(?:\.\d+)?) m\b"),
        r"within \2 m of \1",
    ),
    (
        re.compile(
            r"\b(following|facing|approaching|near|behind|overtaking|passing)"
            r" (?=(?:regular vehicle|vehicle|pedestrian|truck|bus|bicycle|car|box truck)\b)"
        ),
        r"\1 a ",
    ),
    (
        re.compile(r"\b(following|facing|approaching|near|behind|overtaking|passing|front of|of) ego\b"),
        r"\1 the ego vehicle",
    ),
)


def tag_path(text: str) -> str:
    """A tag path as words: "vehicle/lane_change/left" -> "vehicle changing lanes to the left"."""
    if _TAG_PATH.match(text) is None:
        return text
    text = " ".join(re.split(r"[./_-]+", text))
    for pattern, replacement in _TAG_WORDS:
        text = pattern.sub(replacement, text)
    return " ".join(text.split())


#: OpenSCENARIO's names: entities, actions and conditions ("LaneChangeAction", "SpeedCondition").
_SCENARIO_NAMES: tuple[tuple[re.Pattern[str], str | Callable[[re.Match[str]], str]], ...] = (
    (
        re.compile(r"\b(?:any|every|all) (?:entity|entities|scenario objects?|traffic participants?)\b"),
        "objects",
    ),
    (re.compile(r"\b(?:traffic participant|entity ref|entity) (?=[a-z])"), ""),
    (re.compile(r"\b(?:entity|entities) (?=at\b|on\b|in\b|with\b|that\b|which\b)"), ""),
    (re.compile(r"(?<!waiting )\bat standstill\b"), "stopped"),
    (
        re.compile(r"\b(while|when|as) the ego(?: vehicle)? (turn|chang|brak|accelerat|decelerat)(?:es|s) "),
        lambda m: f"{m[1]} the ego vehicle is {m[2]}ing ",
    ),
    (re.compile(r"\boutside (?:any|an?|the) (?:junction|intersection)s?\b"), "not on an intersection"),
    (
        re.compile(
            r"\b(?:performs|executes|does|carries out) (?:an? )?lane change action"
            r"(?: to(?:wards?)? the (left|right))?"
        ),
        r"changing lanes to the \1",
    ),
    (re.compile(r"changing lanes to the (?=[.;,]|$| )"), "changing lanes "),
    (re.compile(r"\b(?:performs|executes|does) (?:an? )?(left|right) turn\b"), r"turning \1"),
    (
        re.compile(r"\brouting action (?:turn|turning) (left|right)(?: at (?:a |the )?junction)?"),
        r"turning \1 at an intersection",
    ),
    (
        re.compile(r"[.;,]? (?:with )?(?:condition: )?speed condition (?:greater than|greater|above|gt) "),
        " faster than ",
    ),
    (
        re.compile(r"[.;,]? (?:with )?(?:condition: )?speed condition (?:less than|lower than|below|lt) "),
        " slower than ",
    ),
    (
        re.compile(
            r"[.;,]? (?:with )?(?:condition: )?speed condition (?:equal to|equals?|eq|==|=)"
            r" 0(?:\.0)?(?: m/s)?"
        ),
        " stopped",
    ),
    (
        re.compile(
            r"[.;,]? (?:condition: )?relative distance condition (?:to|from|relative to)"
            r" (ego|the ego vehicle|an? [a-z ]+?) (?:less than|lessthan|below|under|<) (\d+(?:\.\d+)?) ?m\b"
        ),
        r" within \2 m of \1",
    ),
    (re.compile(r"\btime headway condition:? "), ""),
    (
        re.compile(
            r"[.;,]? (?:relative )?lane position: same lane as (ego|the ego vehicle),?"
            r" (?:and )?(ahead|in front|behind)\b"
        ),
        r" in the same lane as \1 and \2 of \1",
    ),
    (re.compile(r"\bbehind of\b"), "behind"),
    (re.compile(r"\. (?:condition|trigger|start trigger): "), " "),
)


#: The entity a statement is about: "Entity: truck; ..." (a key of a specification line when parts
#: follow after ";"), "EntityRef vehicle, ...".
_ENTITY = re.compile(
    r"(?:^|(?<=[;,.] ))(?:entity ref|entity|scenario object|traffic participant)(?::|,)? |^actor (?=[a-z])"
)


def scenario_names(text: str) -> str:
    """OpenSCENARIO's names in plain words (text in lower case, CamelCase already split)."""
    text = _ENTITY.sub(lambda m: "actor: " if m.start() == 0 and ";" in text else "", text)
    for pattern, replacement in _SCENARIO_NAMES:
        text = pattern.sub(replacement, text)
    return " ".join(text.split())


def document_wording(text: str) -> str:
    """``text`` (lower case, one line) without the ticket or clause wording around the request."""
    text = scenario_names(tag_path(requirement_wording(text)))
    for pattern, replacement in _DOCUMENT:
        text = pattern.sub(replacement, text)
    return text
