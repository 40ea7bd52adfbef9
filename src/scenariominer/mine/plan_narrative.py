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
    "cut": "cutting",
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
#: Rewordings applied in order: (pattern, replacement).
_REWRITES: tuple[tuple[re.Pattern[str], str], ...] = (
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
    (re.compile(r"\bintersection area\b"), "intersection"),
    (re.compile(r"\b(?:as|while|when) (?:it|they) (?:left|leaves?|was leaving|were leaving|exit(?:s|ed)?)"
                r" (?:the|an) intersection\b"), "near an intersection"),
    (re.compile(r"\bout (on|in) the (road|street)\b"), r"\1 the \2"),
    (re.compile(r" (?:down|along|up) the (?:road|street)$"), ""),
)  # fmt: skip


def present_tense(text: str) -> str:
    """``text`` (lower case) with a story's wording put in the present tense the tables read.

    "a car that overtook us on the left" -> "a car that overtaking the ego vehicle on the left";
    "we took a left turn through the intersection" -> "the ego vehicle taking a left turn through
    the intersection"; "buses that had come to a stop" -> "buses that are stopped".
    """
    for pattern, replacement in _REWRITES:
        text = pattern.sub(replacement, text)
    return _ACTION.sub(lambda m: f"{m['lead']}{m['adverbs']} {PAST_FORMS[m['verb']]}", text)
