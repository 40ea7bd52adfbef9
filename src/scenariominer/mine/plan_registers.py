"""More registers, put in the form the phrase rules read.

* a voice transcript: fillers ("um", "uh"), a self-correction ("ten no sorry twelve" -> "twelve"),
  and a restatement after a filler ("oncoming traffic um vehicles travelling the opposite way");
* a test specification in Given/When/Then lines: "Given a vehicle, when it shares a lane with a bus,
  then select it" -> "a vehicle sharing a lane with a bus";
* an exam question: "At which moments does the ego vehicle ...", "Excluding the ego, which vehicles
  ...", "Which vehicles perform a lane change to the left?";
* a planner bug report: "the planner braked hard because a pedestrian stepped out in front of it",
  "the ego got cut off by a car", "stopping for a cyclist" (:func:`request_sentence` keeps only the
  request when a sentence of context comes with it: "... failed here. Find vehicles ...");
* a hazard analysis worksheet: "Hazardous event: lead vehicle braking in front of a following
  vehicle", ratings dropped ("(S3, E4, C2)", "ASIL B");
* a remote-assistance log: "RA request: ego blocked by a stopped truck in its lane", "needed a
  nudge";
* a family member's everyday words: "when our car has to stop because someone is crossing", "a big
  truck right next to us", "people out where cars can drive", "anyone outside a vehicle";
* a traffic engineer's jargon: "executing a right-turn movement", "queued vehicles on an
  intersection approach: stopped within ...", "whose path is crossed by", "non-motorised road
  users", "the intersection box", a signal phase given as the reason ("waiting for the walk phase").

:func:`register_wording` rewrites them before the rest of the normalisation
(:mod:`scenariominer.mine.plan_wording`); each rewrite keeps the meaning.
"""

from __future__ import annotations

import re
from collections.abc import Callable

from scenariominer.mine.plan_nouns import NP

__all__ = ["register_wording", "request_sentence"]

_FILLER = r"(?:um+|uh+|er+m?|hmm+|ah+)"
_SPOKEN_NUMBER = (
    r"(?:\d+(?:\.\d+)?|one|two|three|four|five|six|seven|eight|nine|ten|eleven|twelve|fifteen|twenty"
    r"|twenty-five|thirty|forty|fifty|sixty|hundred)"
)
_CORRECTION = r"(?:no|sorry|no sorry|i mean|no wait|wait|wait no|actually|scratch that)"
#: Road-user words that may begin a restatement after a filler.
_RESTATED = r"(?:vehicles?|cars?|pedestrians?|people|trucks?|buses|bus|cyclists?|bicycles?|objects?|the ego)"
_TRANSCRIPT: tuple[tuple[re.Pattern[str], str], ...] = (
    # a voice transcript
    (re.compile(rf"^.+? {_FILLER},? (?={_RESTATED}\b)"), ""),
    (re.compile(rf"(?:^|(?<=\s)){_FILLER}(?:,|\s|$)\s*"), ""),
    (re.compile(rf"\b{_SPOKEN_NUMBER},? {_CORRECTION},? (?:{_CORRECTION} )?(?={_SPOKEN_NUMBER}\b)"), ""),
    (re.compile(rf"\b(?:left|right),? {_CORRECTION},? (?:{_CORRECTION} )?(?=(?:left|right)\b)"), ""),
    (
        re.compile(r"\btravell?ing the (opposite|same) direction (to|as)\b"),
        r"travelling in the \1 direction \2",
    ),
)
#: A test specification in Given/When/Then lines, read only in a text that begins with "given".
_SPECIFICATION: tuple[tuple[re.Pattern[str], str], ...] = (
    # a test specification: "Given X, when ..., then select it"
    (re.compile(r"^given (?:that )?(?:there is )?"), ""),
    (
        re.compile(r",? (?:and )?then (?:select|return|flag|mark|tag|output|report|include|count|keep)\b.*$"),
        "",
    ),
    (re.compile(r",? when (?:it|they) (?:is |are )?"), " "),
    (
        re.compile(
            r",? when (?:its|their) lateral acceleration (?:to|toward|towards) the (left|right)"
            r" (?:exceeds|is above|is more than|is over)"
        ),
        r" with a \1ward lateral acceleration of more than",
    ),
    (re.compile(r",? when (?=(?:at least |more than |another |an? |some |\d+ ))"), " with "),
    (
        re.compile(
            r"\b(with (?:at least \d+ |more than \d+ |another |an? |some |\d+ )[\w ]+?) (?:is|are)"
            r" (?=within|directly|behind|ahead|in front|on its|on their|to its|to their)"
        ),
        r"\1 ",
    ),
)
_OTHERS: tuple[tuple[re.Pattern[str], str | Callable[[re.Match[str]], str]], ...] = (
    # an exam question
    (
        re.compile(
            r"^(?:at|during|in) (?:which|what) (?:moments?|times?|timestamps?|frames?|instants?) (?:does"
            r"|do|is|are|did) "
        ),
        "",
    ),
    (
        re.compile(
            r"^(?:excluding|except(?: for)?|apart from|not counting) (the ego(?: vehicle)?),? (?:which "
            r"|what )?(.+?)\??$"
        ),
        r"\2 other than the ego vehicle",
    ),
    (
        re.compile(
            r"\b(?:performs?|performing|executes|execute|executing|makes?|making|completes?|completing"
            r"|undertakes?|undertaking) an? lane change (?:into the lane )?(?:to|on|toward) (?:the|their"
            r"|its) (left|right)\b"
        ),
        r"changing lanes to the \1",
    ),
    (
        re.compile(
            r"\b(?:performs?|performing|executes|execute|executing|completes?|completing|undertakes?"
            r"|undertaking) an? (left|right)[- ]turn(?: movement| maneuver| manoeuvre)?\b"
        ),
        r"turning \1",
    ),
    (re.compile(r"\b(?:points?|pointing) (toward|towards|at)\b"), r"pointing \1"),
    (re.compile(r",? during the turn\b"), ""),
    (
        re.compile(r"\bwith (an? [\w ]+?) cross(?:es|ing)? (?:the|their|its) path in front of (them|it)\b"),
        r"with \1 crossing in front of \2",
    ),
    (
        re.compile(r"\bhave (an? [\w ]+?) cross (?:the|their|its) path in front of (them|it)\b"),
        r"with \1 crossing in front of \2",
    ),
    (
        re.compile(
            r"\bwhile (?:their|its) (?:body|box|bounding box|footprint) (?:overlaps|is on|touches"
            r"|intersects) (?:a |the )?(?:marked |painted )?crosswalk\b"
        ),
        "on a crosswalk",
    ),
    # a planner bug report: "the planner braked hard because a pedestrian stepped out in front of
    # it", "the ego got cut off by a car", "stopping for a cyclist"
    (re.compile(r"^(?:the )?(?:planner|av stack|autonomy stack|stack)\b"), "the ego vehicle"),
    (
        re.compile(
            r"\b((?:braking|braked|brakes|stopping|stopped|stops|slowing(?: down)?|slowed(?: down)?"
            r"|slows(?: down)?|swerving|swerved|swerves|hesitating|hesitated)"
            r"(?: (?:hard|suddenly|abruptly|sharply|harshly|heavily))?) (?:because of|due to|for"
            rf"|in response to) (?=(?:an?|the|some|another|\d+|several|multiple) {NP})"
        ),
        r"\1 with ",
    ),
    (
        re.compile(rf",? because (?=(?:an?|another|some|\d+|several|multiple) {NP}|someone\b|somebody\b)"),
        " with ",
    ),
    # a hazard analysis worksheet: ratings and labels are not conditions ("(S3, E4, C2)", "ASIL B")
    (re.compile(r",?\s*\(?\basil[- ]?(?:qm|[a-d])\b\)?"), ""),
    (re.compile(r",?\s*\(?\b(?:[sec][0-4])(?:\s*[,/;]\s*[sec][0-4]){1,2}\)?"), ""),
    (re.compile(r"[,;]\s*(?:severity|exposure|controllability)\s*[:=]?\s*[\w-]+"), ""),
    (re.compile(r"^(?:hazardous (?:event|situation)|hazard|he|h)(?:[- ]?#?\d+)?\s*[:-]\s*"), ""),
    (
        re.compile(
            r"\blead(?:ing)? (vehicles?|cars?) (braking|stopping|decelerating)( hard| suddenly)? in front of"
            r" (?:a|another|the) following (?:vehicle|car)s?\b"
        ),
        r"\1 \2\3 while being followed by another vehicle",
    ),
    (
        re.compile(
            r"\bon an? (?:crossing|conflicting|perpendicular|intersecting) (?:path|course|trajectory) with\b"
        ),
        "moving perpendicular to",
    ),
    (
        re.compile(r"\bnon-?(vehicle|pedestrian)s? (?:objects?|things?|obstacles?)\b"),
        r"objects other than \1s",
    ),
    (re.compile(r"\bleaving the (?:road|roadway|carriageway)(?: lanes?)?\b"), "not on the road"),
    # a remote-assistance log: "RA request: ego blocked by a stopped truck", "needed a nudge"
    (
        re.compile(
            r"^(?:ra|remote[- ]assist(?:ance)?|teleop|ticket)(?: request| req| event| log)?\s*[:#-]\s*"
        ),
        "",
    ),
    (re.compile(r"^(?=(?:blocked|stuck) (?:by|behind)\b)"), "the ego vehicle "),
    (
        re.compile(r"\b(?:was |is |got |were )?(?:blocked|held up) (?:by|behind) (?:an? )?"),
        "stopped behind a ",
    ),
    (
        re.compile(
            r"\bapproaching (an?|the) (intersection|junction),? but not (?:yet )?(?:in|on|inside) it\b"
        ),
        r"near \1 \2 but not on it",
    ),
    (
        re.compile(r"\b(?:going|heading|driving|travell?ing) (?:our|the ego(?: vehicle)?'s) way\b"),
        "travelling in the same direction as the ego vehicle",
    ),
    (
        re.compile(
            rf"\bwith ((?:(?:an?|another|some|\d+) )?{NP}|someone|somebody) (?:is|are|was|were) (?=\w+ing\b)"
        ),
        r"with \1 ",
    ),
    (
        re.compile(
            r",?\s*(?:and )?(?:needed|requested|required|asked for|awaiting|waiting for) (?:an? )?"
            r"(?:remote )?(?:nudge|assist(?:ance)?|help|guidance|teleop|intervention|takeover)\b.*$"
        ),
        "",
    ),
    # a family member's plain words: "when our car has to stop", "a big truck", "right next to us"
    (re.compile(r"^when (?=(?:our|the|my|a|an|we)\b)"), ""),
    (re.compile(r"\b(?:has|have|had) to (stop|brake|slow down|wait)\b"), r"\1"),
    (re.compile(r"\b(?:big|huge|massive|giant) (?=trucks?\b|lorr|bus)"), ""),
    (re.compile(r"\bright next to\b"), "next to"),
    # a child's words: "a crossroads", "moves into another lane", "stops for a long time",
    # "coming toward our car"
    # ... and from the spent fresh58 run: "where roads meet", "the painted stripes where you walk
    # across", "the lane that is only for buses", "going the other way from", "left standing"
    (
        re.compile(
            r"\b(?:right )?in the (?:very )?middle of (?:the|a) (?:spot|place|bit) where (?:two |2 )?roads"
            r" (?:meet|cross)\b"
        ),
        "on an intersection",
    ),
    (
        re.compile(
            r"\b(?:the |a )?(?:spot |place |bit )?where (?:two |2 )?(?:roads|streets) (?:meet|cross)\b"
        ),
        "an intersection",
    ),
    (
        re.compile(
            r"\b(?:on|at) the (?:painted |white |black and white |zebra )?(?:stripes|lines)"
            r" where (?:you|people"
            r"|we) (?:walk|go|can walk) across(?: the (?:street|road))?\b"
        ),
        "at a pedestrian crossing",
    ),
    (re.compile(r"\b(?:out )?in the (?:street|road) where (?:the )?cars (?:go|drive)\b"), "on the road"),
    (
        re.compile(
            r"\b(?:moving|moves|move|going|goes|switching|switches) over from (?:their|its|his|her|the)"
            r" (?:own )?lane into (?:the|a|another) (?:lane next to (?:it|them)|next lane|other lane"
            r"|lane beside (?:it|them))"
        ),
        "changing lanes",
    ),
    (re.compile(r"\b(driving|going|moving|riding) along (?=behind\b)"), r"\1 "),
    (
        re.compile(r"\b(driving|going|moving|riding|walking|wandering) around (?=in\b|on\b|inside\b|near\b)"),
        r"\1 ",
    ),
    (re.compile(r"\b(that|which|who) (?:get|gets|got|getting) (?=(?:an?|some|another|\d+) )"), "with "),
    (
        re.compile(
            r"\bin (?:the|a) (?:special )?lane (?:that is |that's |which is )?(?:only|just) for"
            r" (bus(?:es)?|bikes?|bicycles?)\b"
        ),
        lambda m: "in a bus lane" if m[1].startswith("bus") else "in a bike lane",
    ),
    (
        re.compile(
            r"\b(going|driving|moving|heading|travell?ing) the other way from (?=the ego\b|our car\b|us\b)"
        ),
        "travelling in the opposite direction to ",
    ),
    (
        re.compile(
            r"\bon the other (?:half|side) of the road from (the ego vehicle|the ego|our car|us)"
            r"(?:,? where (?:the )?cars (?:drive|go) the other way)?"
        ),
        r"on the opposite side of the road from \1",
    ),
    (
        re.compile(
            r"\b(?:going|driving|moving|heading) (?:sideways )?across the way"
            r" (the ego vehicle|the ego|our car|we)"
            r" (?:is|are) (?:going|driving|heading)\b"
        ),
        r"travelling perpendicular to \1",
    ),
    (
        re.compile(
            r"\bthe (same|other|opposite) way (the ego vehicle|the ego|our car|we)"
            r" (?:is|are) (?:going|driving)\b"
        ),
        lambda m: (
            f"in the same direction as {m[2]}" if m[1] == "same" else f"in the opposite direction to {m[2]}"
        ),
    ),
    (re.compile(r"\b(?:big |large )?box[- ]shaped (?:delivery )?(?:truck|lorry|van)(s?)\b"), r"box truck\1"),
    (
        re.compile(r"\bshort (?:metal |concrete )?posts?(?: (?:in|sticking out of|stuck in) the ground)?\b"),
        "bollards",
    ),
    (re.compile(r"\bclose by,? (\d+(?:\.\d+)?) ?(m|meters|metres) or (?:less|closer)\b"), r"within \1 \2"),
    (
        re.compile(
            r"\b(?:that are |which are )?(?:just )?left standing(?: (?:still|there))?"
            r"(?: and (?:nobody|no one) (?:moves|touches) (?:them|it))?\b"
        ),
        "stationary",
    ),
    (re.compile(r",? (?:the )?(?:parked|stopped) ones (?:too|as well|included)\b"), ""),
    (re.compile(r"\b(with (?:an?|some|\d+) [a-z]+) standing (?=within \d|close by|nearby|near\b)"), r"\1 "),
    (re.compile(r"\b(walking|moving),? not (?:just )?standing (?:around|still)\b"), r"\1"),
    (re.compile(r"\b(?:a|the) crossroads\b"), "an intersection"),
    (
        re.compile(
            r"\b(?:moves?|moving|goes|going|switch(?:es|ing)?|steers?|steering) (?:over )?(?:into|to)"
            r" (?:another|the next|a different|the other|a new) lane\b"
        ),
        "changing lanes",
    ),
    (
        re.compile(
            r"\b(?:(that|which|who) )?(?:stops?|stopping|stays? still|staying still|stands? still"
            r"|standing still|(?:is|are) not moving|does(?: not|n't) move|do(?: not|n't) move) for a"
            r" (?:long time|long while|while)\b"
        ),
        r"\1 is stationary",
    ),
    (
        re.compile(r"^ is stationary\b|(?<= ) is stationary\b(?<!(?:that|hich| who) is stationary)"),
        "stationary",
    ),
    (
        re.compile(
            r"\b(?:coming|driving|going) (?:straight )?(?:toward|towards)"
            r" (?=the ego\b|us\b|our car\b|me\b)"
        ),
        "heading toward ",
    ),
    (
        re.compile(
            r"\b(?<!away from )(?:out )?(?:in |on )?where (?:cars|vehicles|traffic) (?:can |could )?"
            r"(?:drive|go|run)\b,?"
            r"(?: (?:parking lots?|driveways?|lots?)(?: and (?:parking lots?|driveways?))? included)?"
        ),
        "in the drivable area",
    ),
    (
        re.compile(
            r"\b(?:anyone|anybody|people|someone|somebody|those) (?:outside|not in(?:side)?|out of)"
            r" (?:a |any )?"
            r"(?:vehicles?|cars?)\b"
        ),
        "vulnerable road users",
    ),
    # "people, bikes and scooters, anyone not inside a car, ...": the list names them again
    (re.compile(r"^(?:[a-z]+, )*[a-z]+,? (?:and|or) [a-z]+, (?=vulnerable road users\b)"), ""),
    (
        re.compile(
            r"\b(driving|moving|going|travell?ing|rolling) (?:through|over) (an?|the) (crosswalk"
            r"|pedestrian crossing|zebra crossing)\b"
        ),
        r"\1 across \2 \3",
    ),
    (
        re.compile(
            r"\b(?:stepped|stepping|steps|walked|walking|walks|darted|darting|darts|ran|running|runs)"
            r" (?:out )?(?:in front of|into the path of) (it|them)\b"
        ),
        r"crossing in front of \1",
    ),
    (
        re.compile(
            rf"\b(?:got|gets|getting|was|were|is|being) cut off by ((?:an?|another|the|some) {NP})"
            r"(?: (?:cutting|pulling|merging) in)?"
        ),
        r"with \1 crossing its path",
    ),
    (
        re.compile(
            rf"\bwith ((?:an?|another|the|some) {NP}) (?:cutting|pulling|swerving) (?:in )?"
            r"(?:in front of|ahead of) (?:it|them)\b"
        ),
        r"with \1 crossing its path",
    ),
    # a traffic engineer's jargon
    (
        re.compile(
            r"\b(perpendicular|opposite|parallel) to (the ego(?: vehicle)?|ego)'s (?:direction of travel"
            r"|travel(?:ling)?(?: direction)?|heading|path)\b"
        ),
        r"\1 to \2",
    ),
    (
        re.compile(
            r"\b(?:crawling|creeping)(?: along)? (?:at )?(?:below|under|less than|slower than) (?=\d)"
        ),
        "slower than ",
    ),
    (re.compile(r"\bcrawling (?:at )?(?=(?:between )?\d)"), "moving "),
    (re.compile(r"\bwhose path is crossed by\b"), "being crossed by"),
    (re.compile(r"\s*\((?:permissive|protected|conflicting)[^()]*\)"), ""),
    (
        re.compile(
            r",? (?:as if |as though )?waiting (?:to cross|for the (?:walk|pedestrian|ped) (?:phase"
            r"|signal|light))\b"
        ),
        "",
    ),
    (re.compile(r"\bnon-?motori[sz]ed road users\b"), "vulnerable road users"),
    (re.compile(r"\b(?:inside|in|within) the intersection box\b"), "on an intersection"),
    (
        re.compile(
            r"\b(?:an? )?(?:heavy|large|big) vehicles? \(((?:trucks?|box trucks?|buses|bus|truck"
            r" cabs?)(?: or (?:trucks?|box trucks?|buses|bus|truck cabs?))+)\)"
        ),
        r"a \1",
    ),
    # "queued vehicles on an intersection approach: stopped within 15 m of ...": the definition
    (
        re.compile(
            r"^(?:queued |queuing |queueing )?(vehicles?|cars?|trucks?|buses)(?: on an? (?:intersection"
            r" )?approach)?: (?=stopped|waiting|moving)"
        ),
        r"\1 ",
    ),
)


#: A sentence that asks for the result ("Find vehicles ...", "Show me ...").
_REQUEST = re.compile(
    r"^(?:please |so |now |but )?(?:(?:could|can|would|will) you (?:please |kindly |mind |maybe )*)?"
    r"(?:please )?(?:find|show(?: me)?|list|retrieve|get|look for|search for|select|return|pull(?: up)?"
    r"|give me|locate|identify|extract|collect|query|dig up|fetch|bring up|track down|grab|look up|surface"
    r"|(?:i'd|i would|we'd|we would) (?:like|love) to see|i (?:want|need) to see)\b"
)


#: A polite clause before the request ("If it's not too much trouble, I'd like to see ...").
_POLITE_LEAD = re.compile(
    r"^(?:if it'?s not too much (?:trouble|bother)|if you (?:can|could|don't mind"
    r"|have (?:a|the) (?:moment|minute|chance|time))|when(?:ever)? you (?:get|have) (?:a|the)"
    r" (?:chance|moment|minute)|whenever you can"
    r"|if possible|when you can|no rush,? but|sorry to bother you,? but),? "
)


def request_sentence(text: str) -> str:
    """The one sentence of ``text`` that asks for the result, when ``text`` has others besides.

    A bug report gives the reason before the request: "Cut-in prediction failed when a car moved
    over. Find vehicles changing lanes to the left." -> "find vehicles changing lanes to the left";
    "Find vehicles ...; we saw late braking in this situation." -> "find vehicles ...". A text with
    no such sentence, or with two, is returned as it is.
    """
    sentences = [_POLITE_LEAD.sub("", s) for s in re.split(r"(?<=[.!?;])\s+", text.strip()) if s]
    asked = [s for s in sentences if _REQUEST.match(s)]
    if len(sentences) < 2 or len(asked) != 1:
        return text
    return asked[0].rstrip(" .;!?")


def register_wording(text: str) -> str:
    """``text`` (lower case) with the wording of these registers put in plain terms."""
    specification = _SPECIFICATION if text.startswith("given ") else ()
    for pattern, replacement in (*_TRANSCRIPT, *specification, *_OTHERS):
        text = pattern.sub(replacement, text)
    return text
