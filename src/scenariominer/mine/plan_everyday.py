"""Everyday words for what the phrase tables name technically, put in the tables' form.

People who do not work with driving data describe a scene the way they see it in a video: "the car
we are in" (the ego vehicle), "3 meters or closer" (within 3 m), "5 meters every second" (5 m/s),
"hitting the brakes" (braking), "the white stripes where people cross the street" (a crosswalk),
"looking right at our car" (facing it), "scooting over to the lane on their left" (a lane change
to the left). :func:`everyday_wording` rewrites such phrases after number words have become digits
(:func:`scenariominer.mine.plan_wording.normalised_text`), and drops words that only restate or
place the request ("in the videos", "the whole time" after "never", "just going straight" after
"not turning"). Each rewrite keeps the meaning; a phrase it does not know is left as written.
"""

from __future__ import annotations

import re

from scenariominer.mine.plan_nouns import CATEGORY_RE, NP

__all__ = ["everyday_wording", "figure_marks"]

_N = r"\d+(?:\.\d+)?"
_METRES = r"(?:m|metres?|meters?)"
_VERY = r"(?:really |very |super )?"
#: What a dashboard panel does with the objects found (a count, a rate, a map).
_CHART = (
    r"(?:(?:speed |time |density )?heat ?maps?|(?:hourly |daily |weekly )?counts?"
    r"(?: (?:per|by|over) (?:minute|hour|day|week|log|time))?"
    r"|(?:events?|violations?|minutes|seconds|occurrences|incidents|frames)"
    r" (?:per|by) (?:minute|hour|day|week|log)"
    r"|timeline|trend|histogram|distribution|share(?: in %| %)?|percent(?:age)?|over time)"
)
#: A defined term and the words before what it means ("'Crowded Vehicle' means any").
_DEFINED = r"'[^']+'\s+(?:means|shall mean|refers to|denotes|is defined as)\s+(?:any|each|every|all|an?)"
_SPEED_UNIT = r"(?:m/s|km/h|mph|metres? per second|meters? per second)"
#: The colours and marks of a figure ("red boxes", "blue trajectories").
_COLOUR = r"(?:(?:light|dark|bright) )?(?:red|blue|green|orange|purple|yellow|gr[ae]y|black|white|cyan|pink)"
_MARKS = (
    r"(?:boxes|box|trajectories|trajectory|dots|points|lines|tracks|outlines|markers|arrows|circles|polygons)"
)
#: A state a road user is found in ("parked", "stopped").
_STATE = r"(?:stopped|parked|stationary|moving|stopping|turning)"

_REWRITES: tuple[tuple[re.Pattern[str], str], ...] = (
    # a defined term ("'crowded vehicle' means any motor vehicle ..."): what it means
    (re.compile(rf"^{_DEFINED}\s+(?:instance|occasion|event|case|situation|moment|time)s?"
                r"\s+(?:in which|where|when|at which)\s+(?:an?|the|any)\s+"), ""),
    (re.compile(rf"^{_DEFINED}\s+"), ""),
    (re.compile(r"\bmotor vehicles?\b"), "vehicle"),
    (re.compile(r"\bnot (?:exceeding|more than|greater than|in excess of)\b"), "at most"),
    (re.compile(r"\bnot (?:less|fewer) than\b"), "at least"),
    (re.compile(r"\bat a (?:rate|speed|magnitude) (?:exceeding|of more than)\b"), "more than"),
    (re.compile(r"\bat a (?:rate|speed|magnitude) of (?=at least|at most|more than|less than)"), ""),
    # the ego vehicle as seen from inside it
    (re.compile(r"\bthe (?:car|vehicle) (?:that )?(?:we(?:'re| are)|i(?:'m| am))"
                r" (?:in|riding in|sitting in|driving)\b"), "the ego vehicle"),
    # where the scene was seen
    (re.compile(r"\b(?:in|on|from) (?:the |these |those |our |all the )?"
                r"(?:videos?|movies?|clips?|films?|cameras?)\b"), " "),
    # "5 meters every second": 5 m/s
    (re.compile(rf"\b({_N}) ?{_METRES} (?:every|each) second(?: (?:every|each) second)?\b"), r"\1 m/s"),
    # "3 meters or closer", "50 meters away or closer", "3 m or less": within that distance
    (re.compile(rf"(?<!\bof)(?<!\bat),? ({_N}) ?{_METRES}(?: away)? or (?:closer|nearer|less|under)\b"),
     r" within \1 m"),
    (re.compile(rf"\b{_VERY}(?:close|near) (?:to )?(?:them|it|him|her)(?= within {_N} m\b)"), ""),
    (re.compile(rf"\b{_VERY}close to ({NP}) within ({_N} m)\b"), r"within \2 of \1"),
    # braking in a driver's words
    (re.compile(r"\b(?:are |is )?(?:hitting|stepping on|pressing) the brakes? hard\b"), "braking hard"),
    (re.compile(r"\b(?:are |is )?(?:hitting|stepping on|pressing) the brakes?(?: to slow down)?\b"),
     "braking"),
    # "never ever move (the whole time)": never move
    (re.compile(r"\bnever ever\b"), "never"),
    (re.compile(r"\b(never (?:move|moving|moves))(?: (?:at all|the whole time|all the time))?\b"), r"\1"),
    # "stopped and not moving": stopped
    (re.compile(r"\b(stopped|parked|standing still),? and not moving\b"), r"\1"),
    # a lane change in plain words
    (re.compile(r"\b(?:scooting|moving|sliding|switching|going|shifting) over (?:in)?to the lane on"
                r" (?:their|its|his|her|the) (left|right)(?: side| hand side)?\b"),
     r"changing lanes to the \1"),
    # "looking right at our car (with their face pointing at it)": facing it
    (re.compile(r"\b(?:looking|staring|gazing) (?:right|straight|directly) (?:at|toward|towards)\b"),
     "facing"),
    (re.compile(r",? with (?:their|its|his|her) (?:face|front|nose) pointing (?:at|toward|towards)"
                r" (?:it|them)\b"), ""),
    # the crosswalk and the intersection as they look
    (re.compile(r"\b(?:the )?(?:white |zebra )?stripes (?:where|that) (?:you|people|we|they|the ego vehicle)"
                r" (?:cross|crossing|walk across) the (?:street|road)\b"), "a crosswalk"),
    (re.compile(r"\b(?:an intersection|a crossroads) where the (?:streets|roads) (?:meet|cross)\b"),
     "an intersection"),
    (re.compile(r"\b(intersection|crossroads) where the (?:streets|roads) (?:meet|cross)\b"), r"\1"),
    # the drivable area in plain words
    (re.compile(r"\b(?:in )?the places? (?:where )?cars (?:are allowed to|can|may) (?:drive|go)\b"),
     "in the drivable area"),
    (re.compile(r"\b(drivable area),? like [\w ]+$"), r"\1"),
    # restatements
    (re.compile(r"\b(not turning),? (?:just |only )?(?:going|driving|moving) straight(?: ahead| on)?\b"),
     r"\1"),
    (re.compile(r"\b(opposite direction to [\w ]+?),? (?:coming|going|driving) (?:in )?the"
                r" (?:opposite|other) way\b"), r"\1"),
    (re.compile(r"^(.* and .*?)(?<!close)(?<!walking)(?<!riding) (?:all )?together$"), r"\1"),
    (re.compile(r"\band all the\b"), "and"),
    # "going really fast, faster than 15 m/s": the bound says how fast
    (re.compile(r"\b(?:going |moving |driving )?(?:really |very |super )*fast,? (?=(?:faster|more) than \d)"),
     ""),
    # "speeding up", "moving at 5 m/s or more": the tables' words
    (re.compile(r"\b(?:that )?(?:speeds|speeding|speed) up\b|\bpicking up speed\b"), "accelerating"),
    (re.compile(rf"\baccelerating (?:quickly|hard|fast|rapidly),? "
                rf"(?=(?:more than|at least|over) {_N} ?m/s\^2)"),
     "accelerating "),
    (re.compile(rf"\b((?:more than|at least|over) {_N} ?m/s\^2) of acceleration\b"), r"\1"),
    # "swerving, more than 2 m/s^2 sideways": a lateral acceleration
    (re.compile(rf",? ((?:more than|at least|over) {_N} ?m/s\^2) "
                r"(?:sideways|laterally|lateral|side to side)\b"),
     r" with a lateral acceleration of \1"),
    (re.compile(r"\b(changing lanes?|lane change) to (?:their|its|his|her) (left|right)\b"), r"\1 to the \2"),
    (re.compile(rf"\bat ({_N} ?m/s\^2) or (?:more|above|higher|greater)\b"), r"at more than \1"),
    (re.compile(rf"\b(?:that )?(?:moving|going|driving|travell?ing|move|moves|go|goes)"
                rf" at ({_N} ?{_SPEED_UNIT}) or (?:more|faster|above|higher)\b"), r"faster than \1"),
    # "creeping through an intersection at under 3 m/s": the moving one is slower than that
    (re.compile(rf"\b(\w+ing (?:through|across|into|along|past|around|on|in) (?:an?|the) [\w ]+?)"
                rf" at (?:under|less than|below) (?=({_N}) ?{_SPEED_UNIT}\b)"), r"\1 slower than "),
    # "stopped or parked trucks", "stopped trucks or parked trucks": trucks in either state
    (re.compile(rf"\b({_STATE}) ({CATEGORY_RE}) or ({_STATE}) \2\b"), r"\2 that are \1 or \3"),
    (re.compile(rf"\b({_STATE}) or ({_STATE}) ({CATEGORY_RE})\b"), r"\3 that are \1 or \2"),
    # "..., parked ones excluded", "but not the parked ones": the state they are not in
    (re.compile(rf",? (?:with )?(?:the )?({_STATE}) ones (?:excluded|not included|left out|removed)\b"),
     r" that are not \1"),
    (re.compile(rf",? (?:but not|except|excluding|without) (?:the )?({_STATE}) ones\b"), r" that are not \1"),
    (re.compile(rf"\s*[;,.]? (?:the |any )?({_STATE}) (?:{CATEGORY_RE}|ones) (?:are|is|were|being) "
                r"(?:excluded|not included"
                r"|left out|removed|ignored)\b"), r" that are not \1"),
    (re.compile(r"\bbeing crossed by (an?|the) ([\w ]+?) (?:passing|walking|moving|crossing|going) in front"
                r" of (them|it)\b"), r"with \1 \2 crossing in front of \3"),
    # "that remain in place for the entire sequence": stationary
    (re.compile(r"\b(?:that |which )?(?:remains?|stays?|stayed|remained) (?:in place|put|still|stationary)"
                r"(?: for| during| over| throughout)? (?:the )?(?:entire|whole|full)"
                r" (?:sequence|log|recording|clip|scene|drive)\b"), "that are stationary"),
    # "pedestrians in a tight group, each with at least 2 others within 2 m": the count says the group
    (re.compile(r"\bin an? (?:tight |close |small |large )?(?:group|cluster|crowd),? each with\b"), "with"),
    (re.compile(r"\b(?:in )?either direction\s*$"), ""),
    # a chart's note on what it plots ("- events per day", "[count per log]", "heat map")
    (re.compile(rf"(?:\s*[-–—:,]?\s*\[?{_CHART}\]?)+\s*$"), ""),
    # "(20 m radius)": within 20 m
    (re.compile(rf"\b({_N} ?m) radius\b"), r"within \1"),
    # "when is there a bus ...": the bus
    (re.compile(r"^there (?:is |are )?(?=an? |\d)"), ""),
)  # fmt: skip


def everyday_wording(text: str) -> str:
    """``text`` (normalised, number words as digits) with everyday phrases in the tables' form.

    "the car we are in going fast, more than 5 meters every second" -> "the ego vehicle going
    fast, more than 5 m/s"; "cars that have 3 or more people close to them, 5 meters or closer"
    -> "cars that have 3 or more people within 5 m".
    """
    for pattern, replacement in _REWRITES:
        text = pattern.sub(replacement, text)
    return " ".join(text.split())


#: A figure's marks: "(highlighted in orange)", "(blue boxes)", ", drawn as gray boxes", "(jaywalking
#: examples)": how the figure shows the road users, not which ones.
_FIGURE_MARKS = (
    re.compile(
        rf",?\s*\(?\b(?:highlighted|shown|drawn|marked|outlined|rendered|plotted|depicted|colou?red)"
        rf" (?:in|as|with) {_COLOUR}(?: {_MARKS})?\b\)?"
    ),
    re.compile(rf"\s*\(\s*{_COLOUR} {_MARKS}\s*\)|\s*\b{_COLOUR} {_MARKS}\b"),
    re.compile(r"\s*\((?:[\w -]+ )?examples?\)"),
)


def figure_marks(text: str) -> str:
    """``text`` without the words that say how a figure shows the road users.

    "regular vehicles executing a right turn (highlighted in orange)" -> "regular vehicles
    executing a right turn"; "parked bicycles (green boxes)" -> "parked bicycles".
    """
    for pattern in _FIGURE_MARKS:
        text = pattern.sub("", text)
    return text
