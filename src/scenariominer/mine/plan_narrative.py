"""A description told as a story put in the present-tense form the phrase rules read.

Road-safety analysts and incident reports describe what happened: "a car that *overtook us* on
the left", "*we were tailing* another car", "a bus that *had come to a stop*", "a car that *hung
a right*". :func:`present_tense` rewrites such wording before the other normalisation
(:mod:`scenariominer.mine.plan_wording`): the first person is the ego vehicle, a past-tense verb
of a road user (after "that", "who", "which" or "we") takes the -ing form the tables read, a
finished stop is being stopped, and a few drivers' idioms say what they mean.
"""

from __future__ import annotations

import re

__all__ = ["present_tense"]

#: Past-tense verbs as the -ing form the tables read. "stopped" and "parked" are left out: they
#: are states the tables read as adjectives; "left" too (a direction).
PAST_FORMS: dict[str, str] = {
    "accelerated": "accelerating",
    "approached": "approaching",
    "braked": "braking",
    "came": "coming",
    "changed": "changing",
    "crossed": "crossing",
    "crept": "creeping",
    "cut": "cutting",
    "darted": "darting",
    "cycled": "cycling",
    "decelerated": "decelerating",
    "drove": "driving",
    "faced": "facing",
    "followed": "following",
    "headed": "heading",
    "kept": "keeping",
    "made": "making",
    "merged": "merging",
    "moved": "moving",
    "overtook": "overtaking",
    "passed": "passing",
    "pulled": "pulling",
    "ran": "running",
    "rode": "riding",
    "sat": "sitting",
    "slowed": "slowing",
    "sped": "speeding",
    "stayed": "staying",
    "stepped": "stepping",
    "stood": "standing",
    "strolled": "walking",
    "swerved": "swerving",
    "switched": "switching",
    "tailed": "tailing",
    "tailgated": "tailgating",
    "took": "taking",
    "travelled": "travelling",
    "traveled": "travelling",
    "turned": "turning",
    "waited": "waiting",
    "walked": "walking",
    "went": "going",
}
_PAST = "|".join(sorted(PAST_FORMS, key=len, reverse=True))
#: Where a past-tense verb is a road user's action: after a relative pronoun or the ego's name,
#: with adverbs between ("that suddenly swerved").
_ACTION = re.compile(
    rf"\b(?P<lead>(?:that|who|which)|(?:the )?ego(?: vehicle| car)?)(?P<adverbs>(?: \w+ly)*)"
    rf" (?:(?:was|were|had been) )?(?P<verb>{_PAST})\b(?! by\b)"
)
#: A past-tense verb that is no passive ("is crossed", "being passed by", "got overtaken").
_ANY_PAST = re.compile(
    rf"(?<!\bbeing )(?<!\bbe )(?<!\bis )(?<!\bare )(?<!\bget )(?<!\bgot )(?<!\bgets )(?<!\bgetting )"
    rf"(?<!\bnever )(?<!\bnot )(?<!n't )(?<!\bhas )(?<!\bhave )(?<!\bhad )"
    rf"\b(?P<verb>{_PAST})\b(?!(?: on (?:its|their|the) (?:left|right)(?: side)?| from behind)? by\b)"
)
#: "was" / "were" before a place, a state or a verb's -ing form: a road user's state ("a car was
#: stopped", "cars were behind us", "a pedestrian was walking").
_PROGRESSIVE = re.compile(
    r"\b(?:was|were) (?=(?:behind|ahead|in front|near|next to|beside|alongside|on|in|at|within|parked|stopped"
    r"|pointed|\w+ing)\b)"
)
#: Rewordings applied in order: (pattern, replacement).
_REWRITES: tuple[tuple[re.Pattern[str], str], ...] = (
    # an end-of-shift report: "I saw ...", "there were ...", "at one point ...", "for a while"
    (re.compile(r"^(?:i|we) (?:saw|see|noticed|spotted|watched|remember(?:ed)?|observed|recall(?:ed)?|caught)"
                r" "), ""),
    (re.compile(r"^at (?:one|1|some) point,? "), ""),
    (re.compile(r",? at (?:one|1|some) point$"), ""),
    (re.compile(r"^there (?:was|were|are|is) (?:a (?:moment|time|point|stretch) (?:when|where) )?"), ""),
    (re.compile(r"^(?:lots of|plenty of|a few|a (?:bunch|couple|handful|lot) of|several|many|some) "), ""),
    (re.compile(r"\ba (?:bunch|couple|handful|lot) of\b ?"), ""),
    (re.compile(r",? (?:today|yesterday|this morning|this afternoon|tonight|earlier)$"), ""),
    (re.compile(r",? for (?:a (?:bit|while|moment|second|few seconds)|some time)\b"), ""),
    (re.compile(r",? (?:altogether|the whole time|all the time)\b"), ""),
    (re.compile(r" ?\([^()]*\b(?:that kind of thing|and so on|and the like|or so)\b[^()]*\)"), ""),
    (re.compile(r"\b(?:pretty|really|quite|fairly|rather|super) (?=hard|fast|close|slow|sharply)"), ""),
    (re.compile(r"\bhad to (brake|stop|slow down|swerve|yield)\b"), r"\1ing"),
    (re.compile(r"\bbrakeing\b"), "braking"),
    (re.compile(r"\bstoping\b"), "stopping"),
    (re.compile(r"\bslow downing\b"), "slowing down"),
    (re.compile(r"\bswerveing\b"), "swerving"),
    (re.compile(r"\b(?:hop(?:ped|s|ping)?|jump(?:ed|s|ing)?|slid(?:e|es|ing)?|drift(?:ed|s|ing)?"
                r"|duck(?:ed|s|ing)?)"
                r" (?:over )?(?:in)?to the (?:lane|one) (?:on|to) (?:its|their|the) (left|right)\b"),
     r"changing lanes to the \1"),
    (re.compile(r"\bjerk(?:ed|s|ing)? sideways(?: to(?:wards?)? (?:its|their|the) (left"
                r"|right))?"), r"swerving \1"),
    (re.compile(r"\b(?:squeez(?:ed|ing|es?)|nudg(?:ed|ing|es?)) (?:by|past|through)\b"), "passing"),
    (re.compile(r"\b(stopped|parked|standing|sitting|waiting) right (?=on |in |at )"), r"\1 "),
    (re.compile(r"\bright through\b"), "through"),
    (re.compile(r"(?<!pass )(?<!passing )(?<!passes )\bthrough the middle of (an?|the)"
                r" (intersection|junction)\b"),
     r"on \1 \2"),
    (re.compile(r"\bup ahead\b"), "ahead"),
    (re.compile(r"\bout (?=in front of|ahead|in the)"), ""),
    (re.compile(r"\bover (?=on the)"), ""),
    (re.compile(r"\b(?:hanging|standing|milling|gathered|loitering) (?:around|about|near) (?:it"
                r"|them)\b"), "nearby"),
    (re.compile(r",? instead of (?:on )?(?:the |a )?(?:sidewalk|pavement|footpath)s?\b"), ""),
    (re.compile(r"\b(road|street|lane) itself\b"), r"\1"),
    (re.compile(r"\b(?:and )?left standing\b"), ""),
    (re.compile(r"\bwithin (?:about|roughly|approximately|around) (?=\d)"), "within "),
    (re.compile(r"\b(?:got|gets|getting|came|comes|coming) (?=within \d)"), ""),
    (re.compile(r"\bdoing over\b"), "doing more than"),
    (re.compile(r"^other (?=\w)"), ""),
    (re.compile(r"\b(?:rolled|rolling|rolls) (?=alongside|beside|past|by\b)"), "driving "),
    (re.compile(r"\bfollowing behind\b"), "following"),
    (re.compile(r"\bpassing (?=within \d)"), ""),
    (re.compile(r"\bbut not on (?:an actual|a real|any|an?) (?:mapped )?(?:road"
                r" )?lane\b"), "and not on the road"),
    (re.compile(r",? (?:like|such as) (?:[\w-]+s(?:,| and| or)? ?)+$"), ""),
    (re.compile(r"\bwhile (an?|another) (\w+) (?:was|were|is|are) (?:on|at) (?:the|a) crosswalk nearby\b"),
     r"near \1 \2 who is at a crosswalk"),
    (re.compile(r"\b(?:coming|driving|heading) (?:at|toward|towards) (?:us|the ego vehicle) the"
                r" other way\b"), ""),
    (re.compile(r"\bin the same direction (?:that |as )?(?:we|you) (?:were|are) (?:driving|going"
                r"|travell?ing|moving|heading)\b"),
     "in the same direction as the ego vehicle"),
    (re.compile(r"\b(that|which|who) (?:were|was) not\b"), r"\1 are not"),
    (re.compile(r"\b(that|which|who) (?:weren't|wasn't)\b"), r"\1 are not"),
    (re.compile(r"^we had (?=(?:at least|an?|some|\d))"), "the ego vehicle with "),
    (re.compile(r"\bwhen we had (?=(?:at least|an?|some|\d))"), "the ego vehicle with "),
    # the second person of a lesson: "you" are the ego vehicle ("you are making a left turn",
    # "vehicles on your right", "a vehicle overtaking you")
    (re.compile(r"\byou're\b"), "you are"),
    (re.compile(r"\b(?:driving|going|passing) past ((?:[\w-]+ )?[\w-]+s) (?:less than|under|within)"
                r" (\d+(?:\.\d+)?"
                r" ?(?:m|metres?|meters?)) to (?:your|its|their|the) (left"
                r"|right)\b"), r"moving with \1 on its \3 within \2"),
    (re.compile(r"\b(turning|changing lanes to the) (left|right) somewhere (ahead|in front"
                r"|behind)"), r"\1 \2 and \3"),
    (re.compile(r"\bdriving behind (another|an?) (\w+) that leads (?:you|us|it)(?: in (?:your|our"
                r"|its|the same) lane)?"),
     r"following \1 \2"),
    (re.compile(r"\bin a lane that (another|an?) ([\w ]+?) also occupies\b"), r"in the same lane as \1 \2"),
    (re.compile(r"^you share (?:your|a|the same) lane with\b"), "the ego vehicle in the same lane as"),
    (re.compile(r"^you (?:have|had) (?=(?:at least|an?|some|\d|one|two|three))"), "the ego vehicle with "),
    (re.compile(r"^you (?:have|had) (?:come|came) to an? (?:stop|halt"
                r"|standstill)\b"), "the ego vehicle stopped"),
    (re.compile(r"^you (?:are |were |have been )?"), "the ego vehicle "),
    (re.compile(r",? as you approach(?:ed)? (an?|the) (intersection|junction"
                r"|crosswalk)"), r" approaching \1 \2"),
    (re.compile(r",? before (?:entering|reaching) it$"), " but not on it"),
    (re.compile(r"\b(?:while|when|as) you (?:are|were) "), "while the ego vehicle is "),
    (re.compile(r"\b(?:in|within) your (?:own )?lane\b"), "in the same lane as the ego vehicle"),
    (re.compile(r"\byou on your (left|right)\b"), r"the ego vehicle on its \1"),
    (re.compile(r"\b(on|to) your (left|right)\b"), r"\1 the \2 of the ego vehicle"),
    (re.compile(r"\bgoing your way\b"), "travelling in the same direction as the ego vehicle"),
    (re.compile(r"\byour side of the road\b"), "the same side of the road as the ego vehicle"),
    (re.compile(r"\byour (direction of travel|path|heading)\b"), r"the ego vehicle's \1"),
    (re.compile(r"\byour\b"), "the ego vehicle's"),
    (re.compile(r"(?<!could )(?<!can )(?<!would )(?<!will )\byou\b"), "the ego vehicle"),
    (re.compile(r"\b(\w+s) left (?=off |outside |not on )"), r"\1 "),
    # the first person: "we", "our car", "our lane", "on our left"
    (re.compile(r"^we (?:were |are |was )?"), "the ego vehicle "),
    (re.compile(r"\bour (?:own )?(?:car|vehicle|av)\b"), "the ego vehicle"),
    (re.compile(r"\b(?:in|within) our (?:own )?lane\b"), "in the same lane as the ego vehicle"),
    (re.compile(r"\b(on|to) our (left|right)\b"), r"\1 the \2 of the ego vehicle"),
    (re.compile(r"\bour (direction of travel|path|heading)\b"), r"the ego vehicle's \1"),
    (re.compile(r"\b(?:stay(?:ed|ing|s)?|sat|sitting|sits) on our tail\b"), "following the ego vehicle"),
    (re.compile(r"\bon our tail\b"), "following the ego vehicle"),
    # a finished stop: "had come to a stop", "had stopped" -> stopped
    (
        re.compile(
            r"\b(?:(?:that|who|which) )?(?:had|has|have) (?:come|came) to an? (?:stop|halt|standstill)\b"
        ),
        "that is stopped",
    ),
    (re.compile(r"\b(?:that|who|which) (?:had|has|have) (stopped|parked)\b"), r"that is \1"),
    (re.compile(r"\b(?:came|come|coming) to an? (?:halt|standstill)\b"), "coming to a stop"),
    # auxiliaries of a story: "who was looking" -> "who is looking"
    (re.compile(r"\b(?:that|who|which) was\b"), "that is"),
    (re.compile(r"\b(?:that|who|which) were\b"), "that are"),
    # drivers' idioms
    (re.compile(r"\b(?:hung|hang|hangs|hanging) a (left|right)\b"), r"turning \1"),
    (
        re.compile(r"\b(?:took|take|takes|taking|made|make|makes|making) a (left|right)\b(?! turn)"),
        r"turning \1",
    ),
    (
        re.compile(
            r"\b(?:moved|moves|move|moving) over (?:into|to) the (?:lane|one) (?:on|to) (?:its|their|the)"
            r" (left|right)\b"
        ),
        r"changing lanes to the \1",
    ),
    (
        re.compile(r"\b(?:moved|moves|move|moving) over to the (left|right)(?: lane)?\b"),
        r"changing lanes to the \1",
    ),
    (re.compile(r"\b(walking|strolling|wandering) by (?=on |to |$)"), r"\1 "),
    (re.compile(r"\b(?:walked|walking|walks|walk) up (?=towards?\b|to\b)"), "walking "),
    (re.compile(r"\bat right angles to\b"), "perpendicular to"),
    (
        re.compile(r"\b(?:cut|cutting|cuts|crossed|crossing|crosses) across (the ego vehicle)(?:'s)?"
                   r"(?: direction of travel| path| heading)? at right angles\b"),
        r"moving perpendicular to \1",
    ),
    (re.compile(r"\b(?:strolling|wandering|ambling)\b"), "walking"),
    # "walking past a parked car": walking near it
    (re.compile(r"\b(walking|running|jogging|cycling|riding) (?:right )?past\b"), r"\1 near"),
    (
        re.compile(r"\b(walking|running|cycling|riding) over (?=(?:the|an?) (?:zebra|crosswalk|road))"),
        r"\1 across ",
    ),
    (re.compile(r"\bzebra crossings?\b"), "crosswalk"),
    # British words: "queuing at the junction", "indicating and changing lanes"
    (re.compile(r"\bqueue?ing\b"), "waiting"),
    (re.compile(r"\bindicating (?:and |before |to )?(?=changing|turning|pulling|merging)"), ""),
    (re.compile(r"\bintersection area\b"), "intersection"),
    (re.compile(r"\b(?:as|while|when) (?:it|they) (?:left|leaves?|was leaving|were leaving|exit(?:s|ed)?)"
                r" (?:the|an) intersection\b"), "near an intersection"),
    (re.compile(r"\bout (on|in) the (road|street)\b"), r"\1 the \2"),
    (re.compile(r" (?:down|along|up) the (?:road|street)$"), ""),
    # "the ego vehicle with at least 3 pedestrians in front of the ego vehicle": in front of it
    (re.compile(r"^(the ego vehicle\b(?: [\w ]+?)?) with (.+?) (in front of|ahead of|behind)"
                r" (?:us|the ego vehicle)\b"),
     r"\1 with \2 \3 it"),
)  # fmt: skip


def present_tense(text: str) -> str:
    """``text`` (lower case) with a story's wording put in the present tense the tables read.

    "a car that overtook us on the left" -> "a car that overtaking the ego vehicle on the left";
    "we took a left turn through the intersection" -> "the ego vehicle taking a left turn through
    the intersection"; "buses that had come to a stop" -> "buses that are stopped".
    """
    for pattern, replacement in _REWRITES:
        text = pattern.sub(replacement, text)
    text = _ACTION.sub(lambda m: f"{m['lead']}{m['adverbs']} {PAST_FORMS[m['verb']]}", text)
    # a road user's past-tense verb anywhere else ("cars turned left", "a car was tailing us"):
    # its -ing form, unless it is a passive ("being passed by", "is crossed")
    text = _PROGRESSIVE.sub("", text)
    return _ANY_PAST.sub(lambda m: PAST_FORMS[m["verb"]], text)
