"""Terse notes put in the plain wording the phrase rules read.

Claims handlers, test drivers and triage engineers write fragments: "vehicle turning right w/ ped
crossing its front", "peds facing ego, 20 m or less", "car pointed at a ped within 10 m; car
moving", "cones/barrels on the road", "car w/ 3+ peds close by". :func:`plain_notes` rewrites
them before the rest of the normalisation (:mod:`scenariominer.mine.plan_wording`):
abbreviations are spelt out, a slash between road users is "or", "N+" is "at least N", and the
parts of a note joined by commas or semicolons become one sentence: a bare distance limits the
relation before it, a part that names the subject again adds to it ("and moving"), and a part that
names another road user is a "with" clause.
"""

from __future__ import annotations

import re
from collections.abc import Callable

from scenariominer.mine.plan_nouns import CATEGORY_RE, NP, SUBJECT

__all__ = ["plain_notes"]

#: Shorthand and fragments, each with its plain wording, applied in order.
_SHORTHAND: tuple[tuple[re.Pattern[str], str | Callable[[re.Match[str]], str]], ...] = (
    # a chat message's abbreviations: "peds xing nr ego", "veh LC L", "LT at int", "ego hard decel"
    (re.compile(r"^(?:gimme|grab(?: me)?|got any|any(?:one|body) got|hunting for|hunt for)\s+"), ""),
    (re.compile(r",? ?\b(?:pls|plz|thx|thanks|asap|fyi|tia)\b[.!]*"), ""),
    (re.compile(r"\bx-?ing\b"), "crossing"),
    (re.compile(r"\bx-?walk(s?)\b"), r"crosswalk\1"),
    (re.compile(r"\bnr\b"), "near"),
    (re.compile(r"\b(?:intx|isect|int)\b(?![-'])"), "intersection"),
    (re.compile(r"\bppl\b"), "people"),
    (re.compile(r"\bvehs\b"), "vehicles"),
    (re.compile(r"\bego veh\b"), "ego vehicle"),
    (re.compile(r"\bln(s?)\b"), r"lane\1"),
    (re.compile(r"\bfwd\b"), "forward"),
    (re.compile(r"\bopp\b\.?"), "opposite"),
    (re.compile(r"\badj\b\.?"), "adjacent"),
    (re.compile(r"\bspd\b"), "speed"),
    (re.compile(r"\brds?\b"), lambda m: "roads" if m[0].endswith("s") else "road"),
    (re.compile(r"\blat\.?(?= acc)"), "lateral"),
    (re.compile(r"\b(are|is|were|was|do|does)nt\b"), r"\1 not"),
    (re.compile(r"\bnon-?ego (vehs?|vehicles?|cars?|objects?)\b"), r"\1 other than the ego vehicle"),
    (re.compile(r"\bon (?:the )?ego(?: vehicle)?(?:'s)? (left|right)(?:[- ]hand)?(?: side)?\b"),
     r"to the \1 of the ego vehicle"),
    (re.compile(r"\bon other side of (?:the )?(road|street)\b"), r"on the other side of the \1"),
    (re.compile(r"\b(?:doing|making|performing) (?:an? )?lane changes?\b"), "changing lanes"),
    # "nothing ahead in its lane for 30m": within 30 m, directly ahead when in its lane
    (re.compile(r"\b(ahead|in front(?: of (?:it|them))?)( in (?:its|their) lane)? (?:for|up to)"
                r" (\d+(?:\.\d+)?) ?(?:m|metres?|meters?)\b"),
     lambda m: f"{'directly ' if m[2] else ''}{m[1]} within {m[3]} m"),
    (re.compile(r"(?<![\w/])(?:b/c|bc|cuz|coz|bcuz)\b"), "because"),
    (re.compile(r"(?:\b(?:approx\.?|abt|roughly)\s*|~\s*)(?=\d)"), ""),
    (re.compile(r"\s*@\s*"), " at "),
    (re.compile(r"\blc(s?) (?:to (?:the )?)?(l|r|left|right)\b"),
     lambda m: "changing lanes to the " + {"l": "left", "r": "right"}.get(m[2], m[2])),
    (re.compile(r"\blc(s?)\b"), r"lane change\1"),
    (re.compile(r"\b(turn|turns|turning|turned) (l|r)\b(?![-'])"),
     lambda m: f"{m[1]} {'left' if m[2] == 'l' else 'right'}"),
    (re.compile(r"\b(?:(l)|r)(?:-| )?turn(s?)\b"), lambda m: f"{'left' if m[1] else 'right'} turn{m[2]}"),
    (re.compile(r"\b(?:(lt)|rt)\b(?![-'])"), lambda m: "left turn" if m[1] else "right turn"),
    (re.compile(r"\b(?:hard decel(?:eration|erating)?|decel(?:eration|erating)? hard)\b"), "braking hard"),
    (re.compile(r"\bw/in\b"), "within"),
    (re.compile(r"\bw/o\b"), "without"),
    (re.compile(r"\bw/(?=\s|[a-z])\s*"), "with "),
    (re.compile(r"\bwith nothing\b"), "with no objects"),
    (re.compile(r"\b(?:excl\.?|excl(?:uding)?\.)(?=\s)"), "excluding"),
    (re.compile(r"(?<![\w.])(\d+)\+(?=\s)"), r"at least \1"),
    (re.compile(rf"(?<![\w/])({CATEGORY_RE}) ?/ ?(?=(?:{CATEGORY_RE})(?![\w/]))"), r"\1 or "),
    (re.compile(r"\bthird[- ]party ((?:\w+ )?)(vehicles?|cars?|traffic)\b"),
     r"\1\2 other than the ego vehicle"),
    # places off the road given as examples: "(car park / driveway)"
    (re.compile(r" ?\((?:(?:car parks?|parking(?: lots?)?|lots?|driveways?|forecourts?|garages?)"
                r"\s*(?:/|,|or)?\s*)+\)"), ""),
    # "(drivable area but not a road)" after a parking lot: what a parking lot is
    (re.compile(r" ?\((?:in |on )?(?:the |a )?drivable (?:area|surface),? (?:but )?not (?:on )?"
                r"(?:a |the )?road\)"),
     ""),
    # "crossing its front": in front of it; "its rear": behind it
    (re.compile(r"\b(crossing|cutting across|passing|walking across) (?:its|their) (?:front|nose)\b"),
     r"\1 in front of it"),
    (re.compile(r"\b(crossing|cutting across|passing|walking across) (?:its|their) (?:rear|back|tail)\b"),
     r"\1 behind it"),
    (re.compile(r"\bcrossing (ahead of|just ahead of)\b"), "crossing in front of"),
    (re.compile(r"\bclosing on\b"), "closing in on"),
    (re.compile(r"\boff[- ]road\b"), "not on the road"),
    # "crossed left-to-right by a pedestrian": being crossed from its left to its right
    (re.compile(r"\b(?:being )?crossed (?:from )?(left|right)[- ]to[- ](left|right) by\b"),
     r"being crossed from \1 to \2 by"),
    # "moving across to right-hand lane": a lane change to that side
    (re.compile(r"\b(?:moving|pulling|shifting|switching|drifting) (?:across |over )?(?:in)?to (?:the )?"
                r"(left|right)(?:-hand| hand)? lane\b"), r"changing lanes to the \1"),
    (re.compile(r"\bstopped (?:momentarily|briefly)\b"), "coming to a momentary stop"),
    (re.compile(r"\bgoing straight \((?:no turns?|not turning)\)"), "going straight"),
    # search-box queries: "ego left turn", "trucks left of ego", "non vehicles on road", "changing
    # lanes right"
    (re.compile(rf"(?<![\w-])({CATEGORY_RE}) (left|right)[- ]turns?\b"), r"\1 turning \2"),
    (re.compile(rf"(?<![\w-])({CATEGORY_RE}) or an? (?=(?:{CATEGORY_RE})(?![\w-]))"), r"\1 or "),
    (re.compile(rf"(?<![\w-])({CATEGORY_RE}) (left|right) of\b"), r"\1 to the \2 of"),
    (re.compile(rf"^non[- ]({CATEGORY_RE})(?![\w-])(?! (?:{CATEGORY_RE})(?![\w-]))"),
     r"objects other than \1"),
    (re.compile(r"\bchanging lanes? (left|right)\b"), r"changing lanes to the \1"),
    # a tracking engineer's words: category names as the annotations spell them ("TRUCK_CAB"),
    # "pedestrian tracks", "off its left flank", "the ego's box", "in a one-lane corridor"
    (re.compile(r"\b([a-z]+)_([a-z]+)(?:_([a-z]+))?\b"), lambda m: " ".join(g for g in m.groups() if g)),
    (re.compile(rf"(?<![\w-])({CATEGORY_RE}) (?:tracks|agents|detections|instances|objects)\b"), r"\1"),
    (re.compile(r"\bannotated (?=objects?\b|tracks?\b|agents?\b)"), ""),
    (re.compile(r"\b(?:semi[- ])?tractor units?\b(?= ?\))"), "truck cabs"),
    (re.compile(r" in the (?:scene|log|recording|sequence|scenario)$"), ""),
    (
        re.compile(
            r"\b(?:which|that) (?:are|is|remain|remains|stay|stays) (?:stationary|parked|at rest|put|still)"
            r" (?:for|during|throughout) the (?:entire|whole) (?:recording|log|sequence|scenario|scene)\b"
        ),
        "which are parked",
    ),
    (re.compile(r"\b(?:momentarily |briefly )?held at (?=under|below|less than)"), ""),
    (re.compile(r"\b(?:executing|performing|making|doing|undertaking) a lane change (?:in)?to"
                r" (?:the )?(left|right)"
                r"(?:-hand| hand)?(?: lane)?\b"), r"changing lanes to the \1"),
    (re.compile(r"\boff (its|their) (left|right) side (within \d+(?:\.\d+)? ?m) and (?:at most"
                r"|within) (?:1|one) m"
                r"(?:etres?|eters?)? ahead of or behind (?:its|their) box\b"), r"directly on \1 \2 \3"),
    (re.compile(r"\b(?:off|along|down) (its|their|the) (left|right) (?:flank|side)\b"), r"on \1 \2"),
    # "on its right (within 4 m, lateral 1 m)": directly beside it, a lateral limit of 1 m
    (re.compile(r"\b(?:alongside |beside it |next to it )?on (its|their) (left|right)(?: side)?"
                r" \(?(within \d+(?:\.\d+)? ?m),? (?:and )?lateral"
                r"(?: offset| threshold| distance| gap)?(?: of)? (?:at most |within |under |<=? ?)?1 ?m\)?"),
     r"directly on \1 \2 \3"),
    (re.compile(r",? passing (?:from )?(?:back|rear) to front\b"), ""),
    (re.compile(r"\b(the ego(?: vehicle)?)'s(?=$|,)"), r"\1"),
    (re.compile(r"\b(the ego(?: vehicle)?)'s (?:bounding )?box\b"), r"\1"),
    (re.compile(r"\boriented (?=toward|towards|at\b)"), "facing "),
    (re.compile(r"\b(within \d+ degrees) of (?:their|its) heading\b"), r"\1"),
    (re.compile(r"\b(?:tracking|trailing|driving|travell?ing) behind (?:an? |the )?lead (\w+)"
                r"(?: in (?:its|their) (?:own )?lane| in the same lane)?"), r"following a \1"),
    (re.compile(r"\bsharing (?:the )?ego(?: vehicle)?'s lane\b"), "in the same lane as the ego vehicle"),
    (re.compile(r"\bon (?:an? |the |any )?(?:mapped (?:road )?|road )lanes?\b"), "on the road"),
    (re.compile(r"\b(within \d+(?:\.\d+)? ?m) (ahead|in front)(?: of (?:it|them))? in an? (?:one|1"
                r"|single)[- ]lane"
                r"(?:[- ]wide)? corridor\b"), r"directly \2 \1"),
    # a dispatcher's texts: "how many parked cars we got on this one", "when's the ego ...", "is the
    # ego ever stopped?", "slamming the brakes", "jaywalkers basically", "sketchy ones", "thru"
    (re.compile(r"^how many "), ""),
    (re.compile(r" (?:do |did )?we (?:got|get|have|had|see|saw)(?: on| in)? (?:this|the) (?:one|log"
                r"|drive|run|clip)$"), ""),
    (re.compile(r"^(?:when's|when is|when does|when do|where's|where is) "), ""),
    (re.compile(r"^(?:is|are|was|were|does|do|did) (the ego(?: vehicle)?|ego|any \w+|\w+s) ever "), r"\1 "),
    (re.compile(r"\b(?:stuck|just) (?=following|behind|sitting)"), ""),
    (re.compile(r"\bslamm(?:ing|ed|s)? (?:on )?the brakes?,? (?:decel(?:eration)?|braking) (?:worse"
                r"|harder|stronger|more)"
                r" than\b"), "braking at more than"),
    (re.compile(r"\.? (?:\w+ )?basically$"), ""),
    (re.compile(r",? (?:the )?(?:sketchy|risky|scary|interesting|weird|dangerous|fun) ones$"), ""),
    (re.compile(r"\boff to (its|their|the) (left|right)\b"), r"on \1 \2"),
    (re.compile(r"\bacross the (?:street|road) from (the ego(?: vehicle)?|ego|us)\b,?(?: on the"
                r" other side of the road)?"),
     r"on the other side of the road from \1"),
    (re.compile(r",? lat(?:eral)?\.? ?acc(?:el(?:eration)?)?\.? (\d+(?:\.\d+)? ?m/s(?:²|\^?2)) or"
                r" (?:more|higher|above)\b"),
     r" with a lateral acceleration of at least \1"),
    (re.compile(r"\bthru\b"), "through"),
    (re.compile(r"\b(?:through|during|in) an? (left|right) turn\b"), r"while turning \1"),
    (re.compile(r"\bhanging around (?=near|by|next to|at)"), ""),
    (re.compile(r"\b(?:sitting still,? )?parked or (?:just |momentarily |briefly )?stopped\b"), "stopped"),
    (re.compile(r"\b(?:that|which) (?:get|gets|got|have|has) (an? \w+) (?:walking|running) across"
                r" in front of (them|it)\b"),
     r"with \1 crossing in front of \2"),
    (re.compile(r"\b(anything|anyone|anybody) at all\b"), r"\1"),
    (re.compile(r"\boff the actual road\b"), "not on the road"),
    (re.compile(r" - (?:parking lots?|driveways?|lots?)(?:,? (?:or |and )?(?:parking lots?"
                r"|driveways?|lots?))*$"), ""),
    (re.compile(r"\b(?:got|has|have) (?:anyone|anybody|someone|somebody) on (?:its|their) tail\??"
                r" (?:an? )?vehicles?"
                r" behind (within \d+(?:\.\d+)? ?m)\b"), r"with a vehicle behind it \1"),
    (re.compile(r"\banything motori[sz]ed\b"), "vehicles"),
    (re.compile(r"\b(going straight),? \(?no turns?\)?"), r"\1"),
    (re.compile(r"\b(?:hustling|hurrying|rushing)\b"), "moving"),
    (re.compile(r",? (?:sidewalk|pavement) riders$"), ""),
    (re.compile(r"\bon the move\b"), "moving"),
    # "groups of pedestrians, at least 2 other pedestrians within 3 m": those with that many nearby
    (re.compile(rf"^(?:groups?|clusters?|crowds?|bunches?) of ({CATEGORY_RE})(?:,| with| having)? "
                r"(?=at least \d|\d+ or more|more than \d)"), r"\1 with "),
    # "with less than 10 m to the one ahead": closer than that to the road user named before
    (re.compile(r"\bwith (?:less than|under|below) (\d+(?:\.\d+)? ?(?:m|metres?|meters?)) (?:to|from|behind)"
                r" the (?:one|vehicle|car) (?:ahead|in front)(?: of (?:it|them))?\b"), r"closer than \1"),
    # "|lateral accel| > 3 m/s^2": the size of a sideways acceleration, either way
    (re.compile(r"\|\s*lat(?:eral|\.)? ?acc(?:el(?:eration)?)?\.?\s*\|\s*(?:>=?|≥|over|above|more than)\s*"
                r"(?=\d)"), "with a lateral acceleration above "),
    # "with another car following": followed by it
    (re.compile(rf"\bwith ((?:another|an?|other) {NP}) following(?: (?:it|them|behind))?(?=$|[,;])"),
     r"being followed by \1"),
)  # fmt: skip

#: A count first: "at least 2 vehicles ahead of ego": a condition on the road user named second.
_COUNT_FIRST = re.compile(
    rf"^(?P<count>at least \d+|\d+ or more) (?P<many>{NP}) (?P<where>ahead of|in front of|behind"
    rf"|to the left of|to the right of|near|around|next to|close to) (?P<one>{NP})(?![\w-])(?P<rest>.*)$"
)
#: How the place reads after "with N X": "ahead of Y" -> "ahead of it".
_COUNTED_PLACE = dict.fromkeys(("near", "around", "next to", "close to"), "nearby")
#: A part of a note that is only a distance: "20 m or less", "under 15 m", "within 5 m".
_DISTANCE_PART = re.compile(
    r"^(?:under|less than|below|within|at most|up to|max|<=?|≤)? ?(?P<d>\d+(?:\.\d+)?) ?(?:m|metres?|meters?)"
    r"(?: or (?:less|closer|under)| max(?:imum)?| away| ahead| in front)?$"
)
#: A part of a note that adds nothing to a path ahead: "one-lane corridor" (the path is a lane wide).
_LANE_CORRIDOR = re.compile(r"^(?:an? )?(?:one|1|single)[- ]lane(?:[- ]wide)? (?:corridor|width)$")


#: "# of peds near ego > 3": a count of road users around another, as "ego with at least 4 peds nearby".
_NUMBER_OF = re.compile(
    rf"^(?:#|number|no\.|count) of (?P<many>{NP}) (?P<where>near|around|close to|next to) (?P<one>{NP})"
    r" ?(?P<op>>=|≥|>|more than|over|above|at least) ?(?P<n>\d+)(?P<rest>.*)$"
)


def plain_notes(text: str) -> str:
    """``text`` (lower case, single spaces) with a note's shorthand and fragments spelt out.

    "peds facing ego, 20 m or less" -> "peds facing ego within 20 m"; "ego at a standstill,
    vehicle in front within 10 m" -> "ego at a standstill with a vehicle in front within 10 m";
    "car pointed at a ped within 10 m; car moving" -> "car pointed at a ped within 10 m and
    moving". A text with ``key: value`` parts (a specification) or brackets keeps its commas.
    """
    for pattern, replacement in _SHORTHAND:
        text = pattern.sub(replacement, text)
    text = _restated(text)
    number_of = _NUMBER_OF.match(text)
    if number_of is not None:
        least = int(number_of["n"]) + (0 if number_of["op"] in (">=", "≥", "at least") else 1)
        text = (
            f"at least {least} {number_of['many']} {number_of['where']} {number_of['one']}{number_of['rest']}"
        )
    counted = _COUNT_FIRST.match(text)
    if counted is not None:
        where, rest = _COUNTED_PLACE.get(counted["where"], counted["where"] + " it"), counted["rest"]
        within = re.match(r" within (\d+(?:\.\d+)? ?m)\b(.*)$", rest)
        if where == "nearby" and within is not None:  # "near the ego within 20 m": within 20 m of it
            where, rest = f"within {within[1]}", within[2]
        count = re.sub(r"^(\d+) or more$", r"at least \1", counted["count"])
        text = f"{counted['one']} with {count} {counted['many']} {where}{rest}"
    if ":" in text or "(" in text:
        return text
    parts = re.split(r"\s*[,;]\s*", text)
    subject = SUBJECT.match(parts[0])
    # a list of road users ("cars, trucks and buses ...") starts with a bare noun phrase
    if len(parts) < 2 or subject is None or not parts[0][subject.end() :].strip():
        return text
    joined = parts[0]
    for part in parts[1:]:
        joined += _joined_part(part, subject["noun"])
    return joined


def _restated(text: str) -> str:
    """A question or a label followed by its plain restatement: the restatement.

    "anybody merging over to the right lane? vehicles changing lanes right" -> "vehicles changing
    lanes right"; "oncoming traffic for the ego - vehicles going the opposite way" -> "vehicles going
    the opposite way". Only when the part after names a road user first.
    """
    if "(" in text:
        return text
    for mark in ("? ", " - "):
        before, found, after = text.rpartition(mark)
        head = SUBJECT.match(after)
        if found and before and head is not None and after[head.end() :].strip():
            return after
    return text


def _joined_part(part: str, subject_noun: str) -> str:
    """How one later part of a note joins the text before it (with its leading space)."""
    if _LANE_CORRIDOR.match(part):
        return ""
    distance = _DISTANCE_PART.match(part)
    if distance is not None:
        return f" within {distance['d']} m"
    other = SUBJECT.match(part)
    if other is None or not part[other.end() :].strip():
        return f", {part}"  # no road user first, or only one: left as it was
    rest = part[other.end() :].strip()
    if _singular(other["noun"]) == _singular(subject_noun):
        return f" and {rest}"
    if re.match(r"(?:an?|the|another|some|any|at least \d+|\d+|no) ", part):
        return f" with {part}"
    return f" with {part}" if other["noun"].endswith("s") else f" with a {part}"


def _singular(noun: str) -> str:
    return noun[:-1] if noun.endswith("s") else noun
