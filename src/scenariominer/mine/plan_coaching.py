"""A driving instructor's remarks: the road users a learner is told to watch.

An instructor points at what to look out for and says why: "Watch out for cars changing lanes to
their left, they often cut in without much warning", "Keep an eye on oncoming vehicles", "Mind
the bollards within 5 metres of the intersection, don't clip them when you turn", "Whenever you
are following a bus in your lane, stay well back", "See the construction cones out on the road?
Slow down ...". :func:`coaching_remark` keeps what is to be watched (the words after "watch
for", the situation after "whenever", the road users a question points at) and drops the advice
and the reason around it; "you" and "your car" are the learner's car, the ego vehicle. Text that
is not such a remark is returned as it is.
"""

from __future__ import annotations

import re

__all__ = ["coaching_remark"]

#: "watch out for", "keep an eye on", "mind", "be careful of": the words that point at a road user.
_WATCH = (
    r"(?:(?:always|please|and|just|also|now) )*"
    r"(?:watch(?: out)?(?: for)?|keep (?:an eye|a close eye|watch|a lookout) (?:on|for)|keep track of"
    r"|keep (?:scanning|looking|checking) for|look out for|be on the lookout for|look for|mind"
    r"|check(?: (?:your|the) mirrors?)?(?: for)?|notice|note|be (?:careful|wary|mindful|aware|alert)"
    r" (?:of|with|around|to)|pay attention to|be ready for|spot|clock|scan for|beware of)"
)
_WATCH_START = re.compile(rf"^{_WATCH}\s+")
#: "give every cyclist plenty of space": the road user between "give" and the room it gets ("give
#: every" may have been read as a request, "find", already).
_GIVE = re.compile(
    r"^(?:always )?(?:give|find) (?P<who>.+?) (?:plenty of|lots of|extra|more|enough)? ?"
    r"(?:space|room|clearance"
    r"|a wide berth|a (?:wide|wider) gap|a gap)\b.*$"
)
#: A question pointing at road users: "see the construction cones out on the road?".
_SEE = re.compile(r"^(?:do you |can you )?(?:see|notice|spot) (?P<what>[^?]+)\?")
#: "whenever you are following a bus in your lane, stay well back": the situation comes first.
_SITUATION = re.compile(
    r"^(?:whenever|when|every time|each time|any ?time|if|once|as soon as|before) (?P<cond>[^,]+),\s*"
    r"(?:always )?(?P<advice>.+)$"
)
#: Advice to the learner after the situation: "stay well back", "slow right down", "you need to brake".
_IMPERATIVE = (
    rf"(?:{_WATCH}\s|(?:stay|slow|give|brake|keep|hold|leave|wait|ease|be|let|make|use|don't|do not|never"
    r"|cover|expect|assume|prepare|get ready|remember|drop|back off|you (?:need|should|must|have) to)\b)"
)
#: "parked box trucks hide pedestrians, so watch every box truck that is parked": the watched ones.
_SO_WATCH = re.compile(rf"^[^,]+,? so (?={_WATCH}\s)")
#: "watch your speed every time you turn right": the situation after what is watched.
_OWN_DRIVING = re.compile(
    r"^(?:watch|check|mind) (?:your|the) (?:speed|distance|gap|mirrors?|position|lane position)"
    r" (?:every time|whenever|when|each time|as) (?P<cond>[^,]+)"
)
#: The advice or reason after what is watched: ", they often cut in", ", don't clip them".
_ADVICE = re.compile(
    r"(?:,\s*|\s+-\s+|\s+and (?=give|slow|stay|keep|let|be|brake|hold|leave|wait|ease)\b)"
    r"(?:they|it|he|she|someone|somebody|any of them|that is|that's|those are|these are|this is|there"
    r"|don't|do not|never|be|slow|stay|give|you|so|because|as|in case|whatever|all of them"
    r"|let|leave|wait|ease|brake|keep|hold|the ones|which|especially)\b.*$"
    r"|\s+(?:when|as|while|before|if|so) (?:you|we)\b.*$"
)
_REWRITES: tuple[tuple[re.Pattern[str], str], ...] = (
    (re.compile(r"\b(?:your|our) (?:own )?(?:car|vehicle)\b"), "the ego vehicle"),
    (re.compile(r"\b(?:out|up|over) (?=on the (?:road|pavement|sidewalk|street|pedestrian crossing)\b)"), ""),
    (re.compile(r"\bthe (road|street|crossing|intersection|crosswalk) itself\b"), r"the \1"),
    (re.compile(r",? (?:along|around|round|near|through|up) here\b"), ""),
    (re.compile(r"\b(?:yourself|themselves)\b"), ""),
    (re.compile(r"\bwhile they are (?=on|in|at|near)\b"), ""),
    # "doing over 54 km/h": moving faster than that
    (
        re.compile(r"(?<!turns )(?<=[a-z]s )right (?=(?:on|in|at) the\b)"),
        "",
    ),  # "pedestrians right on the crossing"
    (re.compile(r"\b(?:along|on|in|down) (?:this|that) (?:street|road|stretch)\b"), ""),
    (
        re.compile(
            r"\b(?:the )?same way (?:as )?(?:you|we) (?:are|were) (?:driving|going|heading|travell?ing)\b"
        ),
        "in the same direction as the ego vehicle",
    ),
    (re.compile(r"\bdoing (?=(?:over|more than|above|under|less than|below|at least) \d)"), "moving at "),
)


def coaching_remark(text: str) -> str:
    """``text`` (lower case) as the road users it tells a learner to watch.

    "watch out for cars changing lanes to their left, they often cut in" -> "find cars changing
    lanes to their left"; "whenever you are following a bus in your lane, stay well back" -> "you
    are following a bus in your lane"; "see the construction cones out on the road? slow down
    ..." -> "find the construction cones on the road". Other text is returned unchanged.
    """
    remark = text.strip()
    if match := _SEE.match(remark):
        remark = "find " + match["what"]
    elif match := _OWN_DRIVING.match(remark):
        remark = match["cond"]
    elif match := _GIVE.match(remark):
        remark = "find " + match["who"]
    else:
        remark = _SO_WATCH.sub("", remark, count=1)
        situation = _SITUATION.match(remark)
        if situation and re.match(_IMPERATIVE, situation["advice"]):
            # "before you move off, always check for pedestrians ...": what the advice watches
            advice = situation["advice"]
            remark = advice if _WATCH_START.match(advice) else situation["cond"]
        elif not _WATCH_START.match(remark):
            return text
        remark = _WATCH_START.sub("find ", remark, count=1)
    remark = _ADVICE.sub("", remark).rstrip(" ,.!")
    if remark.startswith(("you ", "we ")):
        # "(whenever) you are following a bus in your lane": the lane is the learner's own
        remark = re.sub(r"\b(?:in|within) (?:your|our) (?:own )?lane\b", "in the same lane", remark)
    for pattern, replacement in _REWRITES:
        remark = pattern.sub(replacement, remark)
    return " ".join(remark.split())
