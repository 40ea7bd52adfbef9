"""The formal register of standards and regulations, put in the form the phrase rules read.

A scenario taxonomy for an operational design domain names the subject, defines it, and states the
conditions in passive voice and long noun phrases: "Motor vehicles, the ego vehicle excepted,
occupying the same lane as the ego vehicle"; "Pedestrians whose bounding box is situated at a
distance of no more than 5 metres from that of the ego vehicle"; "The ego vehicle, for the duration
of any manoeuvre in which a turn to the left is being executed". :func:`formal_wording` rewrites
such wording before the rest of the normalisation (:mod:`scenariominer.mine.plan_wording`):
definitions between commas dropped, bounds spelt out ("not exceeding" → "within", "no fewer than" →
"at least"), the nouns of manoeuvres made verbs ("a turn to the left is being executed" →
"turning left"), and the circumlocutions of place and time made plain ("whilst positioned upon an
intersection" → "on an intersection"; "at those instants at which" → "with"). Each rewrite keeps
the meaning; none guesses at one.
"""

from __future__ import annotations

import re

__all__ = ["formal_wording"]

_D = r"\d+(?:\.\d+)? ?(?:m|metres?|meters?)(?![\w/])"
#: Bounds in words: "not exceeding", "no more than", "no greater than", "a maximum of".
_AT_MOST = r"(?:not exceeding|no (?:more|greater) than|not (?:more|greater) than|a maximum of|at most|up to)"
_AT_LEAST = r"(?:no fewer than|not fewer than|no less than|not less than|a minimum of|at least)"
#: "within D" once the bound has been put in plain words.
_WITHIN_D = rf"within {_D}"
_SIDE = r"(left|right)(?:[- ]hand)?(?: side)?"
_TURN = r"(?:a turning maneuver|a turn|a (?:left|right) turn)"

#: (pattern, replacement), applied in order to the lower-cased text.
_REWRITES: tuple[tuple[re.Pattern[str], str], ...] = (
    (re.compile(r"\bwhilst\b"), "while"),
    # "only while they are stopped", "but only when the ego is moving": the condition itself
    (re.compile(r"(?:,\s*)?(?:\bbut )?\bonly (?=(?:while|when|whenever|if|during)\b)"), " "),
    # a researcher's requests: "I would like to observe ...", "I am interested in the moments when ..."
    (re.compile(r"^(?:i would like to|i'd like to|i want to|we want to|we would like to) (?:observe"
                r"|see|find|identify"
                r"|study|examine|look at) "), ""),
    (re.compile(r"^to (?:observe|see|find|identify|study|examine) "), ""),
    (re.compile(r"^i am interested in (?:the )?(?:moments|times|instants|cases|situations) (?:when"
                r"|where|in which) "), ""),
    (re.compile(r", that is, .*$"), ""),
    (re.compile(r"\b(chang(?:e|es|ing) lanes) towards? (?:their|its|the) (left|right)\b"), r"\1 to the \2"),
    (re.compile(r"\b(?:that|which) (?:have|has) been (?:placed |left |put |set )?(?=on |in |at |near )"), ""),
    (re.compile(r"\b(directly (?:behind|ahead of|in front of) (?:them|it)),? within a lane'?s width"
                r" of (?:their|its)"
                r" path,? (?:at a distance of )?(\S+) (?:metres|meters|m) or less\b"), r"\1 within \2 m"),
    (re.compile(r"\b(?:that|which) (?:share|shares) (?:a|the same) lane with\b"), "in the same lane as"),
    (re.compile(r"\bnot actually\b"), "not"),
    (re.compile(r"\bwhose (?:sideways|lateral) acceleration toward (?:their|its) (left|right) exceeds\b"),
     r"with a lateral acceleration toward the \1 of more than"),
    (re.compile(r"\bwith more than (\S+ ?m/s(?:²|\^2)) of (left|right)ward lateral acceleration\b"),
     r"with a \2ward lateral acceleration of more than \1"),
    (re.compile(r"\b(followed by [\w ]+?) in (?:its|their) (?:own )?lane\b"), r"\1"),
    (re.compile(r"\b(?:that|which) (the ego(?: vehicle)?) is following in (?:its|their) (?:own"
                r" )?lane\b"), r"that \1 is following"),
    (re.compile(r"\bwhile (?:remaining|staying|keeping) (?=within)"), ""),
    (re.compile(r"\b(parked|stationary) (?:for|during|throughout) (?:the )?(?:entire|whole) (?:recording"
                r"|log|sequence|scene)\b"),
     r"\1"),
    (re.compile(r"\bwhile (another|an?) ([\w ]+?) (?:is|are) (on (?:their|its|the) (?:left|right))"
                r" (within \S+"
                r" (?:m|metres|meters))\b"), r"with \1 \2 \3 \4"),
    (re.compile(r"\bthe mapped drivable area\b"), "the drivable area"),
    (re.compile(r"\bwhose (?:bounding )?box(?:es)? overlaps? (?:the area of )?(?:an? |the"
                r" )?(?:mapped |marked )?"
                r"(?:pedestrian crossing|crosswalk)s?(?: polygons?)?\b"), "on a crosswalk"),
    (re.compile(r"\b(?:moving|pulling|shifting|merging|moves|moved) (?:over )?into the"
                r" (?:neighbou?ring|adjacent|next)"
                r" lane on (?:their|its) (left|right)\b"), r"changing lanes to the \1"),
    (re.compile(r"(?:,? while (?:its|their) (?:centre|center) is|,? while)? on an? intersection"
                r" lane segments?\b"),
     " on an intersection"),
    (re.compile(r"\b(?:regular|ordinary|normal|standard) passenger (vehicles?|cars?)\b"), r"regular \1"),
    (re.compile(r"\bupon\b"), "on"),
    (re.compile(r"\bmanoeuvres?\b"), "maneuver"),
    # definitions between commas: ", defined as objects of the bus category,", ", being fixed posts
    # delimiting the roadway,", ", as a category of temporary traffic control device,"
    (
        re.compile(
            r", (?:defined as|being(?! (?:followed|overtaken|passed|crossed|approached|tailgated|cut"
            r"|blocked|tracked))"
            r"|as a category of|as a class of|i\.e\.|namely|that is) [^,]*,"
        ),
        "",
    ),
    (re.compile(r"^([^,]*?), being those (?:whose|which|that|who) "), r"\1 whose "),
    (re.compile(r",? comprising (?:[\w-]+,? )*?(?:and |or )?[\w-]+ (?:buses|vehicles|cars|trucks"
                r"|pedestrians|cyclists),"),
     ""),
    (re.compile(r" of (?:every|any|all) (?:class(?:es)?|categor(?:y|ies))\b"), ""),
    (re.compile(r"\bbut not on any (?:mapped )?(?:road )?lanes?\b"), "and not on the road"),
    (re.compile(r"\b(?:whose position is|while (?:their|its) position is) (?=outside|on|in|within|inside"
                r"|off)"), ""),
    (re.compile(r",? as defined by the (?:map|hd map|vector map)\b"), ""),
    (re.compile(r"\bsubjected to\b"), "with"),
    (re.compile(r"\btoward (?:their|its) (left|right)-hand side\b"), r"toward the \1"),
    (re.compile(r"\boccupying the same lane as\b"), "in the same lane as"),
    (re.compile(r"\b(?:on|in) a lane designated for (?:general )?(?:vehicular|motor|vehicle) traffic\b"),
     "in a vehicle lane"),
    (re.compile(r"\b(an?|the|another) ((?:[\w-]+ ){0,2}[\w-]+) in motion\b"), r"\1 moving \2"),
    (re.compile(r"\b(?:which|that) lies? (?=within|on|in|near)"), ""),
    (re.compile(r"\b(?:(?:which|that) (?:are|is) )?(?:(?:while|when) )?(?:situated|located|positioned"
                r"|lying|placed)"
                r" (?=within|on|in|near|outside|inside)"),
     ""),
    (re.compile(r"\bon (?:an? |the )?(?:mapped )?road lanes?\b"), "on the road"),
    (re.compile(r"\b(walking|moving|travell?ing|driving|riding|going) (?:at a speed of |with a speed of"
                r" )?at least"
                r" (\d+(?:\.\d+)? ?(?:m/s|km/h|mph|kph))"), r"\1 faster than \2"),
    (re.compile(r"\b(the ego(?: vehicle)?) itself\b"), r"\1"),
    # ", the ego vehicle excepted," / ", other than the ego vehicle,": not the ego
    (re.compile(r",? the ego(?: vehicle)? (?:excepted|excluded),?"), " other than the ego vehicle"),
    (re.compile(r", (other than|except(?: for)?|excluding) (the ego(?: vehicle)?),"), r" \1 \2"),
    # bounds
    (re.compile(rf"\b(?:at a distance|a separation|a distance)(?: of)? {_AT_MOST} ({_D})"), r"within \1"),
    (re.compile(rf",? the (?:separation|distance) (?:between the two|to (?:that|the) \w+)(?: being)?"
                rf" {_AT_MOST} "
                rf"({_D})"), r" within \1"),
    (re.compile(rf"\bwithin a distance of ({_D})"), r"within \1"),
    (re.compile(rf"\b{_AT_MOST} ({_D})(?: away)? from\b"), r"within \1 of"),
    (re.compile(rf"\b{_AT_MOST} ({_D})(?: away)?"), r"within \1"),
    (re.compile(rf"\b{_AT_LEAST} (?=\d|one|two|three|four|five)"), "at least "),
    (re.compile(r"\bin excess of\b"), "more than"),
    (re.compile(r"\bat a (?:ground|travel) speed (?:of )?"), "at a speed of "),
    # places: "whose bounding box is situated within 5 m from that of the ego vehicle", "whose
    # bounding box is observed to overlap the area of a marked pedestrian crossing", "whose position
    # lies within a lane reserved for buses", "while their centre lies on a mapped road lane"
    (re.compile(r"\b(?:whose|with their|their) bounding box(?:es)? (?:is |are )?(?:situated |located )?"
                rf"(within {_D}) (?:from|of) (?:that|those) of\b"), r"\1 of"),
    (re.compile(r"\b(?:whose|with their|their) bounding box(?:es)? (?:is |are )?(?:observed to )?overlaps?"
                r" (?:the area of )?(?:an? |the )?(?:marked )?(?:pedestrian crossing|crosswalk)s?\b"),
     "on a crosswalk"),
    (re.compile(r",? ?(?:while |whose |with )?(?:their |its )?(?:centre|center|position) (?:lies|is|lie)"
                r" (?:with)?in (?:a |the )?(?:lane|lanes) reserved for (?:buses|bus"
                r" traffic)\b"), " in a bus lane"),
    (re.compile(r",? ?(?:while |whose |with )?(?:their |its )?(?:centre|center|position) (?:lies|is|lie)"
                r" on (?:an? |the )?(?:mapped )?road(?: lane)?s?\b"), " on the road"),
    (re.compile(r"\b(?:which are |that are )?(?:placed|positioned|located|situated|lying) on (?:an? |the )?"
                r"(?:mapped )?road lanes?\b"), "on the road"),
    (re.compile(r"\bin a lane reserved for buses\b"), "in a bus lane"),
    (re.compile(r"\bin the vicinity of\b"), "near"),
    (re.compile(r"\bon the side of the road opposite to that on which (the ego(?: vehicle)?) is"
                r" (?:travell?ing|driving)\b"),
     r"on the other side of the road from \1"),
    # times: "during intervals in which it is", "at those instants at which", "for the duration of"
    (re.compile(r",? (?:during|at|in) (?:those |the )?(?:intervals|periods|instants|times|moments)"
                r" (?:in|at|during) which (?:it is |they are )?"), " while "),
    (re.compile(r",? (?:for the duration of|during) any maneuver in which "), " while "),
    (re.compile(r",? (?:while|when) (?:situated|located|positioned) "), " "),
    (re.compile(r"\bwhich, while (?:positioned|located|situated) (on|in|at|near) ([^,]*),"
                r" are\b"), r"\1 \2 and"),
    (re.compile(r"\b(?:which|that) (?:are|is) observed to be\b"), ""),
    (re.compile(r"\b(?:are|is) observed to be\b"), ""),
    # manoeuvres as nouns: "a turn to the left is being executed", "undertaking a turn to the
    # right", "executing a left turn", "engaged in a turning maneuver"
    (re.compile(rf"\ba turn to the {_SIDE} is being (?:executed|made|performed"
                rf"|undertaken)\b"), r"turning \1"),
    (re.compile(r"\b(?:undertaking|executing|performing|making|carrying out) (?:a turn to the (left|right)"
                r"|a (left|right) turn)\b"), r"turning \1\2"),
    (re.compile(rf"\b(are |is )?not engaged in {_TURN}(?: in either direction)?"), r"\1not turning"),
    (re.compile(rf"\bengaged in {_TURN}"), "turning"),
    (re.compile(rf"\btransferring from (?:their|its) (?:present|current) lane into the adjacent lane on"
                rf" (?:their|its)"
                rf" {_SIDE}"), r"changing lanes to the \1"),
    (re.compile(r"\bbraking is being applied at a deceleration of "), "braking at "),
    (re.compile(r"\bbraking (?:at )?(?:a deceleration of )?at least (\d+(?:\.\d+)?"
                r" ?m/s)"), r"braking at more than \1"),
    (re.compile(r"\b(?:momentarily )?brought to a halt, with a (?:ground )?speed of no more than (\S+"
                r" ?m/s),"),
     r"slower than \1"),
    (re.compile(r"\bwith a (?:ground )?speed of no more than\b"), "at most"),
    (re.compile(r"\bin a stopped condition, whether parked or only momentarily at rest,"), "stopped"),
    (re.compile(r"\bin motion\b"), "moving"),
    # relations: "being driven behind a lead motor vehicle travelling in the same lane and
    # direction", "travelling behind a bus as their lead vehicle within the same lane"
    (re.compile(r"\b(?:it is |they are )?being driven behind (?:a |the )?lead (.+?) travell?ing in the"
                r" same lane"
                r"(?: and direction)?$"), r"following a \1"),
    (re.compile(r"\b(?:which are |that are )?travell?ing behind (an? [\w ]+?) as (?:their|its) lead vehicle"
                r"(?: within| in) the same lane\b"), r"following \1"),
    (re.compile(r"\b(?:which|that) have (?:their|its) (?:forward )?path crossed by\b"), "being crossed by"),
    (re.compile(r"\bwhose (?:orientation|heading|front) is (?:directed|oriented|pointed) (?:toward"
                r"|towards|at)\b"),
     "facing"),
    (re.compile(r"\bwhose heading points at\b"), "facing"),
    (re.compile(rf",? where (?:the ego(?: vehicle)?|the \w+) is ({_WITHIN_D}) of (?:the|that) [\w"
                rf" ]+$"), r" \1"),
    (re.compile(r"\b(?:which are |that are )?moving so as to approach\b"), "heading toward"),
    (re.compile(r"\bwhose direction of travel is (perpendicular|opposite) to (?:the direction of travel"
                r" of|that of)\b"),
     r"travelling \1 to"),
    (re.compile(r"\bhaving a further\b"), "with another"),
    (re.compile(r"\baccompanied by\b"), "with"),
    (re.compile(r"\bbeing passed along (?:their|its) " + _SIDE + r", from rear to front, by\b"),
     r"being overtaken on the \1 by"),
    (re.compile(rf" {_WITHIN_D} of that side\b"), ""),
    (re.compile(rf"\bwhile (at least (?:\d+|one|two|three|four|five|six)|an?|one) (\w+) (?:is|are)"
                rf" present ({_WITHIN_D})"
                r"(?: of (?:it|them))?"), r"with \1 \2 \3"),
    (re.compile(rf"\bduring which (?:at least one|an?) (\w+) is present ahead of the vehicle ({_WITHIN_D})"),
     r"with a \1 ahead of it \2"),
    (re.compile(r"\bwith at least one other\b"), "with another"),
    (re.compile(r"\bwhich lie (within \S+ ?m) of\b"), r"\1 of"),
    (re.compile(r"\b(\w+) or an? (\w+) (within|near)\b"), r"\1 or \2 \3"),
    (re.compile(r"\b(located|situated) (ahead of|behind|in front of)\b"), r"\2"),
    (re.compile(r"\bwithin an angular tolerance of (\d+) degrees\b"), r"within \1 degrees"),
    (re.compile(rf"\b(ahead of|behind|in front of) ([\w ]+?),? (within {_D}),? (?:and )?within a lateral"
                rf" margin"
                r" of (?:1|one) met(?:re|er)s?(?: beyond the sides of (?:the ego(?: vehicle)?|it|them"
                r"|the vehicle))?"),
     r"directly \1 \2 \3"),
    (re.compile(rf"\balongside on (?:their|its) {_SIDE},? (within {_D}) and within (?:1|one) met(?:re"
                rf"|er) of the"
                r" vehicle's front or rear extent"), r"directly to the \1 of them \2"),
)  # fmt: skip


def formal_wording(text: str) -> str:
    """``text`` (lower case, single spaces) with the formal register put in plain English.

    "motor vehicles, the ego vehicle excepted, occupying the same lane as the ego vehicle" ->
    "motor vehicles other than the ego vehicle occupying the same lane as the ego vehicle";
    "pedestrians whose bounding box is situated at a distance of no more than 5 metres from that of
    the ego vehicle" -> "pedestrians within 5 metres of the ego vehicle".
    """
    text = text.rstrip(" .")
    for pattern, replacement in _REWRITES:
        text = pattern.sub(replacement, text)
    return " ".join(text.split()).strip(" ,")
