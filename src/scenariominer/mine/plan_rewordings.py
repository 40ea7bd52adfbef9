"""The rewordings of the description reader: other wordings put in the one form the tables read.

Applied in order by :func:`scenariominer.mine.plan_wording.normalised_text` after the registers of
:mod:`~scenariominer.mine.plan_formal`, :mod:`~scenariominer.mine.plan_notes`,
:mod:`~scenariominer.mine.plan_learners` and :mod:`~scenariominer.mine.plan_narrative` have been put
in plain English: (pattern, replacement) pairs, each keeping the meaning.
"""

from __future__ import annotations

import re
from collections.abc import Callable

from scenariominer.mine.plan_nouns import MODIFIER_RE, NOUN, NP
from scenariominer.mine.plan_phrases import TO_MPS

#: "a clear road ahead" (read as no vehicle ahead).
_CLEAR_ROAD = (
    r"(?:an? )?(?:clear|empty|free|open) (?:road|lane|path|way|space)"
    r"(?: (?:ahead|in front)(?: of (?:it|them))?)?"
)

#: A relation verb that two of may share one object: "approaching and facing X".
_RELATION_VERB = (
    r"(?:approaching|facing|following|overtaking|passing|tailgating|closing in on|near|next to|behind"
    r"|ahead of|in front of|(?:heading|moving|driving) towards?)"
)
_SHARED_VERB = re.compile(
    rf"(?<![\w-])(?P<v1>{_RELATION_VERB}) and (?P<v2>{_RELATION_VERB}) (?P<obj>{NP})(?![\w-])"
)
#: The ego vehicle's names in a normalised text.
_EGO = r"(?:the )?ego(?: vehicle| car)?"
#: Any road-user word.
_ROAD_USER = re.compile(rf"(?<![\w-])(?:{NOUN})(?![\w-])")
_SPEED_UNITS = "|".join(map(re.escape, TO_MPS))
#: Other wordings put in the one form the tables read: (pattern, replacement).
_REWORDINGS: tuple[tuple[re.Pattern[str], str | Callable[[re.Match[str]], str]], ...] = (
    # "someone hanging back behind a bus": a driver (the pedestrian reading of "someone" otherwise)
    (
        re.compile(
            r"\b(?:someone|somebody)(?= (?:who (?:is|was) )?(?:hanging back|lagging|following|tailgating"
            r"|tailing|trailing|driving|overtaking|cutting in|changing lanes|speeding|parked|double-parked))"
        ),
        "a vehicle",
    ),
    # "cars that a pedestrian walked across the back of": the subject is the one crossed
    (
        re.compile(
            rf"\b(?:that|which) (?P<np>{NP}) (?:is |was )?(?:crossed|crossing|walked across|walking across"
            r"|ran across|running across|cut across|cutting across|passed|passing|walked|walking|stepped"
            r"|stepping)"
            r" (?P<side>in front of|the front of|behind|the back of|the rear of)"
            r"(?= (?:and|with|while|at|on|in)\b|$)"
        ),
        lambda m: "being crossed " + ("by " if "front" in m["side"] else "from behind by ") + m["np"],
    ),
    # "pedestrians that the ego vehicle is driving toward": the other road user heads at the subject
    (
        re.compile(
            rf"(?:\b(?:that|which|who|whom) )?(?<![\w-])(?P<np>{NP}) (?:is|are|was|were) "
            r"(?:heading|driving|moving|going|travell?ing|coming|riding) (?:straight |directly )?"
            r"(?:towards?|at)(?= within\b|$)"
        ),
        r"with \g<np> heading toward them",
    ),
    # "with a clear lane ahead, meaning no vehicle in front within 30 m": the definition
    (re.compile(rf"\bwith {_CLEAR_ROAD},? (?:meaning|i\.e\.?|that is|so) (?=no )"), "with "),
    # "... within 30 m inside about one lane's width", "ahead in its lane corridor": directly ahead
    (
        re.compile(
            r"\b(in front of|ahead of) (them|it) (within \d+(?:\.\d+)? ?(?:m|metres?|meters?))"
            r" (?:inside|within|in) (?:about |roughly |approximately )?(?:one|1|a|a single) lane'?s? width\b"
        ),
        r"directly \1 \2 \3",
    ),
    (
        re.compile(r"\b(ahead|in front) in (?:its|their|the same|our) (?:own )?lane(?: corridor)?\b"),
        r"directly \1",
    ),
    # "a lead vehicle in its lane less than 10 m ahead": directly ahead within 10 m
    (
        re.compile(
            r"\bin (?:its|their|our|the same) (?:own )?lane (?:less than|under|within|closer than) "
            r"(\d+(?:\.\d+)? ?(?:m|metres?|meters?)) (?:ahead|in front)\b"
        ),
        r"directly ahead within \1",
    ),
    # "with 3 or more pedestrians nearby within 5 m": within that distance
    (re.compile(rf"(?<![\w-])({NP}) (?:nearby|close by|around) (?=within \d)"), r"\1 "),
    # "vehicles the ego overtakes": the subject is the one overtaken
    (
        re.compile(
            rf"^((?:all |the |any )?(?:{NOUN})) (?:that |which |whom )?(?P<np>{NP}) (?:is |are )?(?:overtakes"
            r"|overtook|overtaking|passes|passed|passing)(?= on\b|$)"
        ),
        r"\1 being overtaken by \g<np>",
    ),
    (
        re.compile(
            rf"\b(being (?:overtaken|passed)) by (?P<np>{NP}) (?P<side>on (?:its|their|the) (?:left|right)"
            r"(?:[- ]hand)?(?: side)?)(?=$|,| and| with| while)"
        ),
        r"\1 \g<side> by \g<np>",
    ),
    # "regular vehicles the ego's heading points at": with the ego facing them
    (
        re.compile(
            rf"^((?:all |the |any )?(?:{NOUN})) (?:that |which )?(?P<np>{NP})(?:'s)? "
            r"(?:heading |front |nose )?"
            r"(?:points?|is pointing|pointing|points|faces|is facing|facing|aims|aiming) (?:at|towards?)"
            r"(?=$| within)"
        ),
        r"\1 with \g<np> facing toward them",
    ),
    # "near a vehicle that is moving toward it": near one heading toward the subject
    (
        re.compile(
            rf"\bnear (?P<np>{NP}) (?:that|which|who) (?:is|are) (?:moving|heading|driving|coming|going)"
            r" (?:towards?|at) (?:it|them)\b"
        ),
        r"near \g<np> with \g<np> heading toward them",
    ),
    # "within 10 m of its bumper": of it
    (
        re.compile(r"\b(within \d+(?:\.\d+)? ?(?:m|metres?|meters?)) of (?:its|their) (?:front )?bumper\b"),
        r"\1",
    ),
    # "bollards that a moving vehicle passes within 2 m of": with one that near
    (
        re.compile(
            rf"\b(?:that|which) (?P<np>{NP}) (?:is |are )?(?:passes|passed|passing|drives|drove|driving|goes"
            r"|went|going|comes|came|coming) (?:by |past )?(?P<d>within \d+(?:\.\d+)? ?(?:m|metres?|meters?))"
            r" of$"
        ),
        r"with \g<np> \g<d>",
    ),
    # the register of road rules: what an offence looks like in the logs
    (
        re.compile(
            r"\b(?:blocking|obstructing)(?= (?:the |an? )?(?:intersection|junction|crosswalk|crossing"
            r"|bike lane|bus lane|lane)\b)"
        ),
        "stopped on",
    ),
    (
        re.compile(
            r"\b(?:(?:failing|failed|refusing|not stopping) to (?:yield|give way)|(?:not|never) (?:yielding"
            r"|giving way)|(?:does|do|did) not (?:yield|give way)) to (?P<np>.+?)"
            r"(?= (?:at|on|in|near|while|and)\b|$)"
        ),
        r"moving with \g<np> crossing in front of them",
    ),
    (re.compile(r"\bencroaching (?:in)?(?:to|onto|on) "), "in "),
    (
        re.compile(
            r"\bwith (?:a )?(?:less than|under|below) (\d+(?:\.\d+)? ?m) (?:of )?"
            r"(?:gap|headway|clearance|spacing)\b"
        ),
        r"within \1",
    ),
    # a question about behaviour: "how do cyclists behave when they ride through ...": the behaviour
    (
        re.compile(
            r"^(?:how|in what way) (?:do|does|did) (?P<who>.+?) (?:behave|act|react|move|drive)"
            r"(?: when| while| as| if)? (?:they|it|he|she) "
        ),
        r"\g<who> ",
    ),
    (re.compile(rf"^(?:do|does|did) (?=(?:the |any |all )?{NP} )"), ""),
    # "slowing down as they approach pedestrians": while approaching them
    (
        re.compile(
            r"\b(?:as|while|when) (?:they|it) (?=approach|near|pass|enter|leave|cross|turn|drive|ride)"
        ),
        "",
    ),
    # off the road: "off the mapped road lanes", "outside of the road", "(not on any mapped lane)"
    (re.compile(r"\bnot on any mapped lanes?\b"), ""),
    (
        re.compile(
            r"\b(?:off|outside(?: of)?) (?:the |any |every )?(?:mapped )?(?:road(?:way)?|street)?"
            r"(?: ?lanes?)?(?<=road|reet|lane|anes|dway)\b"
        ),
        "not on the road",
    ),
    (re.compile(r",? rather than (?:on|in) (?:a|the) (?:street|road|carriageway)\b"), " and not on the road"),
    (re.compile(r"\boff the (?:road|carriageway|roadway|street)\b"), "not on the road"),
    (re.compile(r"\b(?:close |right |tight )?up behind\b"), "behind"),
    # "with a vehicle passing on its left": being passed on that side by it
    (
        re.compile(
            rf"\bwith (an?|another) ({NP}) (?:passing|overtaking) (?:it |them )?(?:along |on )(its|their)"
            r" (left|right)(?: side)?\b"
        ),
        r"being passed on \3 \4 by \1 \2",
    ),
    # "with a vehicle on its left and another on its right, each within 4 m": each with that limit
    (
        re.compile(
            rf"\bwith (an?) ({NP}) on (its|their) (left|right) and another(?: one)? on (?:its|their)"
            r" (left|right),? each within (\d+(?:\.\d+)? ?m)\b"
        ),
        r"with \1 \2 on \3 \4 within \6 and with another \2 on \3 \5 within \6",
    ),
    (re.compile(r"\bcar parks?\b"), "parking lot"),
    (
        re.compile(r"\bswing(?:s|ing)? (?:out )?(?:to(?:wards?)? )?(?:the |its |their )?(left|right)\b"),
        r"swerving \1",
    ),
    (
        re.compile(
            r"\bother side of (?:the )?road (?:compared (?:with|to)|relative to|with respect to|than) "
        ),
        "other side of the road from ",
    ),
    # "veh lane change to the right": a lane change named by its noun
    (
        re.compile(r"(?<!\ba )(?<!\bthe )(?<!\bany )\blane[- ]changes? (?:in)?to the (left|right)\b"),
        r"changing lanes to the \1",
    ),
    (re.compile(r"\b(?:doing|making|taking|performing) an? turn to the (left|right)\b"), r"turning \1"),
    # a commentary after the description: ", which is where weaving is most risky", ", blocking it"
    (
        re.compile(r",? which (?:is|are) (?:where|when|why|how|often|usually|especially|particularly)\b.*$"),
        "",
    ),
    (re.compile(r",? (?:blocking|obstructing) (?:it|them)$"), ""),
    (re.compile(r",? instead of (?:staying|being|keeping|remaining) .*$"), ""),
    (re.compile(r"\bon top of\b"), "on"),
    (re.compile(r",? (?:say|like|for instance) (?:in|on|at|through) .*$"), ""),
    (re.compile(r"\bmaking any (left|right) turns?\b"), r"making a \1 turn"),
    (re.compile(r"\bget (overtaken|passed|cut off|followed|crossed)\b"), r"getting \1"),
    (re.compile(r"\bpassing through (?:the middle of )?(an?|the) (intersection|junction)\b"), r"on \1 \2"),
    (re.compile(r"\bthrough (an?|the) (parking lot|driveway)\b"), r"in \1 \2"),
    # "while an oncoming vehicle is within 30 m": with one there
    (
        re.compile(r"\bwhile (an?|another|the) (.+?) (?:is|are) (?=within|nearby|near|ahead|behind|close)"),
        r"with \1 \2 ",
    ),
    (re.compile(r"\bsharing (?:its|their|our|his|her) lane with\b"), "sharing a lane with"),
    (re.compile(r"\balongside (?=on (?:its|their|the) (?:left|right))"), ""),
    (re.compile(r"\bwithout turning\b"), "not turning"),
    # "the ego vehicle's lane / path"
    (re.compile(r"\b(?:the )?ego(?: vehicle| car)?(?:'s?)? lane\b"), "the same lane as the ego vehicle"),
    (re.compile(r"\b(?:the )?ego(?: vehicle| car)?'s? path\b"), "the path of the ego vehicle"),
    # "in the same lane as the ego vehicle and in front of it": in front of the ego vehicle
    (
        re.compile(
            rf"(?<![\w-])(?P<np>{NP}) and (?P<d>within \d+(?:\.\d+)? ?m )?(?P<rel>in front of|ahead"
            rf" of|behind)"
            r" (?:it|them)(?![\w-])"
        ),
        lambda m: f"{m['np']} and {m['rel']} {m['np']}" + (f" {m['d'].strip()}" if m["d"] else ""),
    ),
    # "a stopped lead vehicle": the relation says it leads
    (re.compile(rf"(?<![\w-])({MODIFIER_RE}) (?:lead|leading|preceding) (?=(?:{NOUN})(?![\w-]))"), r"\1 "),
    # a subject's adjective that is a motion or a relation: "left-turning cars", "oncoming trucks"
    (re.compile(rf"^((?:an? |the |all )?)(left|right)[- ]turning ({NOUN})(?![\w-])"), r"\1\3 turning \2"),
    (re.compile(rf"^((?:an? |the |all )?)lane[- ]changing ({NOUN})(?![\w-])"), r"\1\2 changing lanes"),
    (re.compile(rf"^((?:an? |the |all )?)(swerving|veering|weaving) ({NOUN})(?![\w-])"), r"\1\3 \2"),
    # "non-ego vehicles", "non-bus vehicles": other than those
    (re.compile(rf"^((?:an? |the |all |any )?)non-?(ego|{NOUN}) ({NOUN})(?![\w-])"), r"\1\3 other than \2"),
    # "a car within 5 m of them": within 5 m (of the road user named last)
    (re.compile(r"\b(within \d+(?:\.\d+)? ?(?:m|meters?|metres?)) of (?:them|it|him|her)\b"), r"\1"),
    # "max 5 meter away": within 5 m
    (
        re.compile(
            r"\b(?:max(?:imum|imal|imally)?|at most|up to) (\d+(?:\.\d+)?) ?(m|meters?|metres?)(?![\w/])"
            r"(?: away)?"
        ),
        r"within \1 \2",
    ),
    # articles left out: "on left of ego", "inside drivable area", "same lane with a bus"
    (re.compile(r"\b(on|to) (left|right) (?:side )?of\b"), r"\1 the \2 of"),
    (re.compile(r"\b(in|inside|within|on|outside|off|out of) drivable area\b"), r"\1 the drivable area"),
    (re.compile(r"\bsame lane with\b"), "same lane as"),
    # "following X with a gap under 10 m": closer than that
    (
        re.compile(
            r"\b(?:with |at )?(?:an? |the )?(?:gap|headway|spacing|distance)(?: of)?"
            r" (?:under|less than|below|smaller than|shorter than) (?=\d)"
        ),
        "closer than ",
    ),
    # "following the ego vehicle in the same lane as the ego vehicle": in the same lane
    # (not after "other than": "vehicles other than a bus in the same lane as a bus")
    (
        re.compile(
            rf"(?<!than )(?<!except )(?<!excluding )\b(?P<np>{NP}) in (?:the )?same lane as (?P=np)(?![\w-])"
        ),
        r"\g<np> in the same lane",
    ),
    # "within 2 m of a pedestrian crossing": the crosswalk, not a pedestrian crossing the road
    (
        re.compile(r"\b(of|at|near|on|to|by|in|from|approach(?:es|ing)?) (an?|the) pedestrian crossings?\b"),
        r"\1 \2 crosswalk",
    ),
    # "closing the gap at 1 m/s or more": the closing speed
    (
        re.compile(r",? (?:closing (?:the gap|in|the distance)) at (\d+(?:\.\d+)? ?m/s) or more\b"),
        r" with a closing speed of at least \1",
    ),
    # "ahead of them in roughly their own lane": directly ahead
    (
        re.compile(
            r"\b(ahead of|in front of|behind) (them|it) in (?:roughly |about |approximately )?"
            r"(?:their|its) (?:own )?lane\b"
        ),
        r"directly \1 \2",
    ),
    (
        re.compile(
            r"\b(ahead of|in front of|behind) (them|it) (within \d+(?:\.\d+)? ?(?:m|metres?|meters?|feet|ft))"
            r",? in (?:roughly |about |approximately )?(?:the same|their|its) (?:own )?lane(?: width)?\b"
        ),
        r"directly \1 \2 \3",
    ),
    # "somewhere other than on an intersection": not there
    (re.compile(r"\b(?:somewhere|anywhere) (?:other than|but|except) "), "not "),
    # "surrounded by at least 5 vehicles within 10 m": with that many nearby
    (
        re.compile(r"\bsurrounded by (?:at least )?(\d+) (?:or more )?(?!.* on all)"),
        r"with at least \1 ",
    ),
    # "with a clear road ahead": no vehicle ahead
    (
        re.compile(rf"\bwith {_CLEAR_ROAD}(?![\w-])"),
        "with no vehicle ahead",
    ),
    (re.compile(r"\b(?:a |the )?lane of (?:the )?type (\w+)\b"), r"a \1 lane"),
    # "turns, any direction": turning (either way)
    (re.compile(r"\b(turning|turns?) (?:in )?(?:any|either) direction\b"), r"\1"),
    # "..., and there is a vehicle behind it": with one there
    (
        re.compile(
            r"\b(?:and |whenever |when |while |as long as )?there (?:is|are)"
            r" (?=an? |some |\d|multiple |several |many |at least )"
        ),
        "with ",
    ),
    # "ped walking (> 1 m/s)": faster than that ("doing more than 10 mph" has its own phrase)
    (
        re.compile(rf"(?<!doing )(?<!at )\bmore than (\d+(?:\.\d+)? ?(?:{_SPEED_UNITS}))(?![\w^²/])"),
        r"faster than \1",
    ),
    # "close behind X within 10 m": the distance says how close
    (re.compile(r"\bclose (behind|ahead of|in front of)\b(?=.* within \d)"), r"\1"),
    # "the ego have a vehicle ... ahead" (after "when does"): the ego with one
    (
        re.compile(
            rf"^((?:the |a |an |all )?{NOUN}) (?:have|has)"
            r" (?=an? |some |\d|multiple |several |many |at least )"
        ),
        r"\1 with ",
    ),
    (re.compile(r",? ?within (?:about |roughly )?(?:a|one) lane(?: width)?$"), ""),
    (re.compile(r"\bfrom within\b"), "within"),
    (re.compile(r"\b(?:quicker|speedier) than\b"), "faster than"),
    # "looking at / facing X": facing it
    (re.compile(r"\b(?:looking|staring) at ?/ ?(?=facing)"), ""),
    # "going the same way" (as the ego)
    (re.compile(r"\b(?:in )?the (same|opposite) way\b(?! (?:as|to|like)\b)"), r"in the \1 direction"),
    # "passing X on its left, from behind to ahead": what passing says already
    (re.compile(r" from behind to (?:ahead|the front)\b"), ""),
    # "with pedestrians close to it, within 5 m": the distance says how close
    (re.compile(r"\b(?:close to|near|next to|around) (?:it|them)(?= within \d)"), ""),
    # "following X and the lead vehicle brakes": X is the one braking
    (
        re.compile(
            rf"\bfollowing ({NP}) and (?:the (?:lead|leading|front) (?:vehicle|car)|it|that (?:vehicle|car)) "
        ),
        r"following \1 that ",
    ),
    # "brakes (below -1 m/s2)", "accelerating below -2 m/s²": braking harder than that
    (
        re.compile(
            r"\b(?:braking|decelerating|slowing(?: down)?|accelerating|an acceleration) \(?(?:at )?"
            r"(?:below|under|less than|lower than) -(\d+(?:\.\d+)?) ?(m/s2|m/s²|m/s\^2)\)?"
        ),
        r"braking more than \1 \2",
    ),
    # shorthand and manner words: "accel", "decel", "suddenly speeding up", "getting passed"
    (re.compile(r"\baccel\b"), "acceleration"),
    (re.compile(r"\bdecel\b"), "deceleration"),
    (re.compile(r"\b(?:suddenly|abruptly) (?=\w+ing\b)"), ""),
    (re.compile(r"\bgetting (passed|overtaken|followed|tailgated)\b"), r"being \1"),
    (
        re.compile(r"\b(?:got|gets|was|were)(?: being)? (passed|overtaken|followed|tailgated)(?= by\b)"),
        r"being \1",
    ),
    (
        re.compile(
            r"\b(?:speeding up|accelerating) (?:with )?(?:an? )?acceleration (?:of )?"
            r"(more than|over|above|at least) "
        ),
        r"accelerating \1 ",
    ),
    (
        re.compile(
            r"\b(?:slowing down|braking|decelerating) (?:with )?(?:an? )?deceleration (?:of )?"
            r"(more than|over|above|at least) "
        ),
        r"decelerating \1 ",
    ),
    # "driving straight at the ego, closing in": toward it
    (
        re.compile(
            rf"\b(driving|heading|moving|going|coming|riding) (?:straight |directly |right )at ({NP})"
        ),
        r"\1 toward \2",
    ),
    (re.compile(rf"\b(towards?|at) ({NP}) closing in\b"), r"\1 \2"),
    # "while a car is ahead of it": with one there
    (re.compile(rf"\b(?:while|when|whenever) (an? |some |\d+ )({NOUN}) (?:is|are) "), r"with \1\2 "),
    # "the ego speed is above 20 mph": the ego going above it
    (re.compile(rf"^({_EGO}|(?:the |a )?{NOUN})(?:'s?)? speed is\b"), r"\1 going"),
    # "..., please": politeness
    (re.compile(r"(?: please)+$"), ""),
    # "following X in their lane": following is in X's lane already
    (
        re.compile(rf"\b(following|tailgating|trailing) ({NP}) in (?:their|its|the same|his|her) lane\b"),
        r"\1 \2",
    ),
    # "stopped behind a truck in its lane": behind it in the same lane
    (
        re.compile(
            rf"\b((?:stopped|waiting|sitting|queued|queuing|stuck|standing) behind) ({NP})"
            r" in (?:its|their|his|her) (?:own )?lane\b"
        ),
        r"\1 \2 in the same lane",
    ),
    # "whenever there is a pedestrian on its right": with one there
    (re.compile(r"\b(?:whenever|when|while|as long as) there (?:is|are) "), "with "),
    # "trucks while they are moving", "the ego vehicle while it is following X": the subject's own
    (re.compile(r"\b(?:while|when|whenever) (?:they|it) (?:is|are) "), ""),
    # "moving vehicles that are not regular vehicles": other than those
    (re.compile(rf"\b(?:that|which|who) (?:are|is) not (?:an? )?({NOUN})(?![\w-])"), r"other than \1"),
    # "closing in on X from behind": toward X, behind it
    (
        re.compile(rf"\b(approaching|closing in on) ({NP}) from (?:behind|the rear)\b"),
        r"\1 \2 behind \2",
    ),
    # "somewhere ahead of it": ahead of it (any distance, the predicate's default)
    (re.compile(r"\bsomewhere (?=ahead|in front|behind|to (?:the|its|their) (?:left|right))"), ""),
    (
        re.compile(rf"^((?:an? |the |all )?)oncoming ({NOUN}) (?:relative to|with respect to|compared to) "),
        r"\1\2 travelling in the opposite direction to ",
    ),
    (
        re.compile(rf"^((?:an? |the |all )?)oncoming ({NOUN})(?![\w-])"),
        r"\1\2 travelling in the opposite direction to the ego vehicle",
    ),
    (re.compile(r"\bgetting closer to\b"), "closing in on"),
    # "merging into the ego's lane": a lane change, then in that lane
    (
        re.compile(r"\b(?:merging|cutting|changing lanes?|moving over|pulling) into the same lane as\b"),
        "changing lanes in the same lane as",
    ),
    # "on the ego's left side": to the left of it
    (
        re.compile(r"\bon (?:the )?ego(?: vehicle| car)?'s? (left|right)(?:[- ]hand)?(?: side)?"),
        r"on the \1 side of the ego vehicle",
    ),
    (
        re.compile(r"\bto (?:the )?ego(?: vehicle| car)?'s? (left|right)(?:[- ]hand)?(?: side)?"),
        r"to the \1 of the ego vehicle",
    ),
    # "of any kind": every category (the subject's own word says it)
    (
        re.compile(
            r"(?<!truck)(?<!trucks) (?:of (?:any|every) (?:kind|type|sort|category)|of all (?:kinds|types))\b"
        ),
        "",
    ),
    # "a car to the left of it": on its left
    (re.compile(r"\b(?:to|on) the (left|right)(?: side| hand side)? of (?:it|them|him|her)\b"), r"on its \1"),
    # "whose direction of travel is perpendicular to that of X"
    (
        re.compile(
            r"\b(?:whose |with (?:a |their |its )?)(?:direction of travel|travel direction|heading|direction)"
            r" is (?:at right angles|perpendicular) to (?:that of )?"
        ),
        "moving perpendicular to ",
    ),
    (
        re.compile(
            r"\b(?:whose |with (?:a |their |its )?)(?:direction of travel|travel direction|heading|direction)"
            r" is (?P<dir>opposite|the same as) (?:to )?(?:that of )?"
        ),
        lambda m: (
            "moving in the " + ("opposite direction to " if m["dir"] == "opposite" else "same direction as ")
        ),
    ),
    # "at 1 to 3 m/s": between them
    (
        re.compile(rf"\b(?:at |from )?(\d+(?:\.\d+)?) ?(?:-|to) ?(\d+(?:\.\d+)?) ?({_SPEED_UNITS})"),
        r"between \1 and \2 \3",
    ),
    # "neither X nor Y": not X, not Y
    (re.compile(r"\bneither (.+?) nor\b"), r"not \1 not"),
    (re.compile(r"^jaywalkers\b"), "jaywalking pedestrians"),
    # "the lead vehicle (that the ego vehicle is following)", nothing else: followed by the ego
    (
        re.compile(
            r"^(?:the |a )?(?:lead|leading) (vehicle|car)s?(?: (?:that|which) (?:the )?ego(?: vehicle| car)?"
            r" is following)?$"
        ),
        r"\1s being followed by the ego vehicle",
    ),
    (
        re.compile(
            rf"^((?:the |a |all )?{NOUN}) (?:that|which) (?:the )?ego(?: vehicle| car)? is following\b"
        ),
        r"\1 being followed by the ego vehicle",
    ),
    # simple English: "more fast than" -> "faster than", "same direction like" -> "... as"
    (re.compile(r"\bmore (fast|slow)(?:ly)? than\b"), r"\1er than"),
    (re.compile(r"\b(?:in )?(?:the )?same (?:direction|way) (?:like|as)\b"), "in the same direction as"),
    (re.compile(r"\b(?:sideways|side|lateral) accel(?:eration)?\b"), "lateral acceleration"),
    (re.compile(r"\bin (?:its|their|his|her) own lane\b"), "in the same lane"),
    # "leaving out X", "not counting X": other than X
    (re.compile(r"\b(?:leaving out|not counting|without counting|ignoring|excluding)\b"), "other than"),
    # "vehicle that a person walks across in front of it": a clause of another road user about
    # the subject ("it", "them") is the subject's "with"
    (
        re.compile(
            rf"^((?:an? |the |all )?{NOUN}) (?:that|which|where)"
            rf" ((?:an? |the |some )?{NOUN}) (?:is |are )?(.* (?:it|them))$"
        ),
        r"\1 with \2 \3",
    ),
    # "a car that is stopped while a pedestrian crosses in front of it": the same, after "while"
    (
        re.compile(rf" (?:while|as|when|whilst) ((?:an? |the |some )?{NOUN}) (?:is |are )?(.* (?:it|them))$"),
        r" with \1 \2",
    ),
    # "the opposite way to X", "across the front of X", "X's direction of travel"
    (re.compile(r"\b(?:in )?the (opposite|same) way (to|as)\b"), r"in the \1 direction \2"),
    (re.compile(r"\b(?:across|in) the front of\b"), "in front of"),
    (
        re.compile(
            r"\b((?:the )?ego(?: vehicle| car)?)'s? (?:direction of travel|travel direction|heading"
            r"|direction)\b"
        ),
        r"\1",
    ),
    # "X where a vehicle is following it", "... and no other vehicle is ahead": with one doing so
    (
        re.compile(
            rf"\b(?:where|whenever|in which|and) (?P<np>(?:an?|another|some|no|no other|other) {NP})"
            r" (?:is|are) "
        ),
        r"with \g<np> ",
    ),
    # "X where they are ...", "X where it turns": a clause about the subject
    (re.compile(r"^(.*?) where (?:they|it) (?:are|is) "), r"\1 that are "),
    (re.compile(r"^(.*?) where (?:they|it) "), r"\1 that "),
    # "where speed is above 8 m/s", "where acceleration exceeds 1.5 m/s²": with that
    (
        re.compile(
            r"\b(?:where|whenever|when) (?:its |their |the )?(speed|velocity|acceleration|deceleration)"
            r" (?:is )?"
        ),
        r"with \1 ",
    ),
    (
        re.compile(
            r"\b(speed|velocity|acceleration|deceleration) (?:is )?(?:exceeds?|exceeding|greater than"
            r"|higher than)(?= \d)"
        ),
        r"\1 above",
    ),
    # contractions: "aren't parked" -> "are not parked"
    (re.compile(r"\b(are|is|was|were|do|does|did|has|have)n't\b"), r"\1 not"),
    # "a pedestrian who is less than 20 m away": the distance read as the pedestrian's
    (
        re.compile(
            r"\b(?:who|which|that) (?:is|are) (?=(?:within|less than|under|no more than|closer than) \d)"
        ),
        "",
    ),
    # "with more than 2 m/s² of lateral acceleration": the usual order
    (
        re.compile(
            r"\b(more than|over|above|at least) (\d+(?:\.\d+)?) ?(m/s2|m/s²|m/s\^2) of lateral acceleration"
        ),
        r"a lateral acceleration of \1 \2 \3",
    ),
    # "us", "we": the ego vehicle ("vehicles in front of us")
    (re.compile(r"(?<= )us\b"), "the ego vehicle"),
    # a manoeuvre with no road user named is a vehicle's ("hard braking events")
    (
        re.compile(
            r"^(?:hard|heavy|emergency|sudden|harsh) braking(?: events?| manoeuvres?| maneuvers?)?\b"
            rf"(?! (?:{NOUN}))"
        ),
        "vehicles braking hard",
    ),
    (
        re.compile(
            r"^(?:all |any )?(?:changing lanes|lane changes?(?: events?| manoeuvres?| maneuvers?)?)"
            r"(?=$| to the (?:left|right)\b| (?:at|near|on|in|with|while|by)\b)"
        ),
        "vehicles changing lanes",
    ),
    (
        re.compile(
            r"^(?:all |any )?(left|right)[- ]turns?(?: events?| manoeuvres?| maneuvers?)?"
            r"(?=$| (?:at|near|on|in|with|while|by)\b)"
        ),
        r"vehicles turning \1",
    ),
    (
        re.compile(r"^(?:all |any )?u-?turns?(?: events?| manoeuvres?| maneuvers?)?(?=$| )"),
        "vehicles making a u-turn",
    ),
    # "turning left with an oncoming vehicle", "vehicles with a parked car": another road user with
    # its own condition and no relation word is one close by (the bare "with X nearby"), the
    # condition its own, not the subject's
    (
        re.compile(
            rf"(?<!lane )(?<!road )\bwith (?P<np>(?:an? |some |other |another |\d+ )?(?:(?:{MODIFIER_RE}) )+"
            rf"(?:{NOUN}))(?=$| and | while | when | whenever )"
        ),
        r"with \g<np> nearby",
    ),
    # a catalogue's "Cut-in from the left": a vehicle moving into the lane ahead of the ego vehicle,
    # from the left lane (a lane change to the right)
    (re.compile(r"\bcutting-in\b"), "cutting in"),
    (re.compile(r"^(?:an? |the )?cutting in\b"), "vehicles cutting in"),
    (
        re.compile(r"\bcutting in from (?:the |its |their )?(left|right)(?:[- ]hand)?(?: side| lane)?\b"),
        lambda m: f"changing lanes to the {'right' if m[1] == 'left' else 'left'} and cutting in",
    ),
    (
        re.compile(r"\bcutting in\b(?! (?:in front of|front of|ahead of|between|line)\b)"),
        "cutting in ahead of the ego vehicle",
    ),
    # "lead vehicle ahead of the ego in its lane": the relation says which one it is
    (re.compile(rf"^(?:the |a )?lead(?:ing)? (?=(?:{NOUN})(?![\w-])(?! (?:of|for)\b).*\bego\b)"), ""),
    # "lead vehicle braking" (a catalogue title): the vehicle the ego vehicle follows
    (
        re.compile(rf"^(?:the |a )?lead(?:ing)? (?P<noun>{NOUN})(?![\w-])(?! (?:of|for)\b)(?!.*\bego\b)"),
        r"\g<noun> being followed by the ego vehicle",
    ),
    # an annotator's exclusions: "..., excluding those standing still", "do not tag parked ones",
    # "but skip the parked ones": the condition negated
    (
        re.compile(
            r"\s*[,;]?\s*(?:but )?(?:excluding|except(?: for)?|not counting|apart from|leaving out|other than"
            r"|(?:do not|don't) (?:tag|label|include|count|annotate|mark|select)|skip|ignore|omit)"
            r" (?:the |any |all )?(?:ones |those )?(?:that are |which are |who are |that |which |who )?"
            r"(?P<condition>parked|stopped|stationary|standing still|moving|turning(?: left| right)?)"
            r"(?: ones)?(?=$|[,;.]| and )"
        ),
        lambda m: " that are not " + ("stationary" if m["condition"] == "standing still" else m["condition"]),
    ),
    (
        re.compile(
            r"\s*[,;]?\s*(?:but )?(?:excluding|except(?: for)?|not counting|apart from|leaving out"
            r"|(?:do not|don't) (?:tag|label|include|count|annotate|mark|select)|exclude|skip|ignore|omit)"
            r" (?:the )?ego(?: vehicle| car)?(?: itself)?(?=$|[,;.]| and )"
        ),
        " other than the ego vehicle",
    ),
    # a news story's motion: "cars zipping past the robotaxi", "a car inching forward", "cruising"
    (
        re.compile(
            r"\b(?:zipping|racing|speeding|whizzing|flying|tearing|darting|dashing|cruising|rolling|edging"
            r"|inching|sliding|creeping|crawling) (?:past|by)\b(?= \w)"
        ),
        "passing",
    ),
    (re.compile(r"\b(?:inching|edging)(?: (?:forward|along|ahead))?\b"), "creeping"),
    (re.compile(r"\bcruising\b"), "moving"),
    # "a pedestrian stepping off the curb into the road": on the road
    (
        re.compile(
            r"\b(?:stepping|walking|wandering|darting|dashing|running)"
            r"(?: off the (?:curb|kerb|sidewalk|pavement))? (?:out )?(?:into|onto) the (?:road|street|roadway"
            r"|carriageway|traffic)\b|\b(?:stepping|stepped|steps) off the (?:curb|kerb)\b"
        ),
        "on the road",
    ),
    # "a delivery truck parked by the curb": where a parked vehicle is
    (
        re.compile(
            r"\b(parked|stopped|stationary|sitting|waiting) (?:by|at|along|next to|against|on) the"
            r" (?:curb|kerb|curbside|kerbside|roadside|side of the (?:road|street))\b"
        ),
        r"\1",
    ),
    # "hits the brakes hard": hard braking; "waits patiently as a pedestrian crosses": while
    (re.compile(r"\b(?:hitting|slamming(?: on)?|stomping on|jamming on) the brakes hard\b"), "braking hard"),
    (re.compile(r" (?:patiently|quietly|calmly|carefully|casually|nervously|lazily|gently)\b"), ""),
    (re.compile(r"\b(\w+ing) as (?=(?:an?|the|some|\d+) )"), r"\1 while "),
    # "regular vehicles that never move during the whole sequence": parked
    (
        re.compile(
            r"\b(?:that |which |who )?(?:never (?:move|moving)|(?:do|does) not (?:ever )?(?:move|moving))"
            r"(?: at all)?(?: (?:during|throughout|for|in) the (?:whole|entire|full) \w+)?\b"
        ),
        "that are stationary",
    ),
    (re.compile(r"\bdirectly directly\b"), "directly"),
    # "cornering or swerving hard to the right": swerving; "with lateral acceleration above 2 m/s²
    # toward their right": rightward
    (re.compile(r"\b(?:cornering|turning sharply) or (swerving)\b"), r"\1"),
    (
        re.compile(
            r"\bwith (?:an? )?(?:lateral|sideways) acceleration"
            r" (?:above|over|of more than|more than|exceeding) (\S+ ?m/s(?:²|\^2|2)?)"
            r" (?:toward|towards|to) (?:their|its|the) (left|right)\b"
        ),
        r"with a \2ward lateral acceleration of more than \1",
    ),
    # a catalogue's titles: "Ego acceleration event (above 1 m/s²)", "Vehicle swerve to the right
    # (lateral acceleration below -2 m/s²)", "Pedestrian cluster - three or more other pedestrians
    # within 5 m", "Straight-through vehicle", "Left-turning vehicle with a crosswalk pedestrian"
    (
        re.compile(
            r"(?<!lateral )(?<!with an )(?<!with a )\bacceleration(?: events?)?"
            r" (?:above|over|more than|of more than|exceeding)"
            r" (\d+(?:\.\d+)?) ?m/s(?:²|\^2|2)"
        ),
        r"accelerating more than \1 m/s^2",
    ),
    (
        re.compile(
            r"\b(?:with )?(?:an? )?lateral acceleration (?:below|under|less than)"
            r" -(\d+(?:\.\d+)?) ?m/s(?:²|\^2|2)?"
        ),
        r"with a rightward lateral acceleration of more than \1 m/s^2",
    ),
    (
        re.compile(
            rf"^(?P<np>{NP})(?: (?:cluster|group|crowd|event|case|scenario))? - "
            r"(?=(?:\d+|at least|more than|an?|some) )"
        ),
        r"\g<np> with ",
    ),
    (re.compile(rf"^straight[- ]through (?P<noun>{NOUN})\b"), r"\g<noun> going straight"),
    (re.compile(r"\bno turns?\b"), "not turning"),
    (
        re.compile(r"\bwith (?:an? )?(?:crosswalk|crossing) (pedestrian|ped)s? within (\d+(?:\.\d+)? ?m)\b"),
        r"within \2 of a pedestrian who is at a crosswalk",
    ),
    (re.compile(r"\bon the (left|right)(?:[- ]hand)? side of\b"), r"to the \1 of"),
    # "at most 2 m/s": a top speed, as "slower than"
    (
        re.compile(
            rf"\b(?:moving |going |driving |travell?ing )?at most (\d+(?:\.\d+)?) ?({_SPEED_UNITS})(?![\w/])"
        ),
        r"moving slower than \1 \2",
    ),
    # "more than 20 m from the ego vehicle", "at least 20 m away from X": not within that distance
    (
        re.compile(
            r"\b(?:more than|at least|over|farther than|further than|beyond) (\d+(?:\.\d+)?) ?"
            r"(?:m|meters?|metres?) (?:away )?from\b(?! (?:any |an |the )?intersections?\b)"
        ),
        r"not within \1 m of",
    ),
    # "acceleration less than -3 m/s^2": braking harder than 3 m/s^2
    (
        re.compile(
            r"(?<!lateral )\b(?:with (?:an? )?)?(?:longitudinal )?acceleration"
            r" (?:less than|below|under|at most)"
            r" -(\d+(?:\.\d+)?) ?(m/s(?:\^2|²|2)?)"
        ),
        r"braking harder than \1 m/s^2",
    ),
    # "less than 10 m ahead": within 10 m (not "less than 10 m/s")
    (
        re.compile(
            r"\b(?:less than|under|no more than|at most|closer than) (\d+(?:\.\d+)?) ?"
            r"(m|meters?|metres?)(?![\w/])"
        ),
        r"within \1 \2",
    ),
    # "a vehicle within 10 m directly ahead of it": the distance after the direction (after
    # "less than 10 m" became "within 10 m")
    (
        re.compile(
            r"\b(within \d+(?:\.\d+)? ?(?:m|meters?|metres?)) ((?:directly |right |just |straight )?"
            r"(?:ahead|in front|behind) of (?:it|them))"
        ),
        r"\2 \1",
    ),
    # last, after "oncoming X" has named the ego: "vehicles close behind the AV while it brakes",
    # "oncoming vehicles while the AV is turning left": the ego's own (no road user between)
    (
        re.compile(rf"\b({_EGO})(.*?) (?:while|when|whenever) (?:{_EGO} is|it is|it) (.+)$"),
        lambda m: m[0] if _ROAD_USER.search(m[2]) else f"{m[1]} that is {m[3]}{m[2]}",
    ),
)
