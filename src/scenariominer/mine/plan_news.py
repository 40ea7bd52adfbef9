"""A news story's wording of driving scenes, put in the form the phrase rules read.

A journalist writes for readers, not engineers: the ego vehicle is "the robotaxi", pedestrians are
"people on foot", a lane change is "drifting over one lane to the right", following is "tagging
along behind" or "hanging on its tail", a stop is "a complete standstill", accelerating is "stepping
on the gas". :func:`news_wording` puts such wording in the plain terms of the rest of the
normalisation (:mod:`scenariominer.mine.plan_wording`); each rewrite keeps the meaning.
"""

from __future__ import annotations

import re

__all__ = ["news_wording"]

#: A news story's names for the ego vehicle.
_EGO_NAMES = (
    r"(?:the |a |an |our )?(?:robo-?taxi|robot(?:ic)? (?:car|taxi)|driverless (?:car|vehicle|taxi)"
    r"|self[- ]driving (?:car|vehicle|taxi|cab)|autonomous (?:car|vehicle|taxi))(?![\w-])"
)
_REWRITES: tuple[tuple[re.Pattern[str], str], ...] = (
    # one name for the ego vehicle, so that "the robotaxi's lane" reads as "the ego vehicle's lane"
    (re.compile(_EGO_NAMES), "the ego vehicle"),
    # road users: "people on foot", "someone on foot", "drivers", "big rigs"
    (re.compile(r"\b(?:people|persons|folks) on foot\b"), "pedestrians"),
    (re.compile(r"\b(?:someone|somebody|a person) on foot\b"), "a pedestrian"),
    (re.compile(r"\b(?:drivers|motorists)\b"), "cars"),
    (re.compile(r"\b(?:a |an )?big rig'?s cab(?: with no trailer(?: attached)?)?\b"), "a truck cab"),
    (re.compile(r"\btraffic of (?:every|any|all) (?:kinds?|sorts?|types?)\b"), "vehicles"),
    (re.compile(r"\bcross traffic\b"), "traffic"),
    # a headline's verbs
    (re.compile(r"\bslams? (?:on )?(?:the |its |their )?brakes\b,?(?= decelerating)"), ""),
    (re.compile(r"\bslams? (?:on )?(?:the |its |their )?brakes\b"), "braking hard"),
    (
        re.compile(
            r"\bsits? parked for (?:the |an? )?(?:entire|whole) (?:drive|log|trip|clip|ride|recording)\b"
        ),
        "parked",
    ),
    (
        re.compile(
            r"\b(?:tops|speeds past|breaks) (?=\d+(?:\.\d+)? ?(?:m/s(?![\^²2])|km/h|kph|mph"
            r"|(?:metres?|meters?|kilometres?|kilometers?|miles?) (?:per|an|a) (?:second|hour)(?! squared)))"
        ),
        "faster than ",
    ),
    (re.compile(r"\bhalts\b"), "stopped"),
    (re.compile(r"\bcomes to (?:a )?(?:full |complete )?stop\b"), "stopped"),
    (
        re.compile(r"\bcuts across (?:the path of |(?P<who>[\w ]+?)'s path\b)"),
        r"crossing in front of \g<who>",
    ),
    (
        re.compile(
            r"\b(?:finds|spots|sees|has) (\d+ [\w ]+?) within (\d+(?:\.\d+)? ?(?:m|meters|metres)) ahead\b"
        ),
        r"with \1 ahead within \2",
    ),
    # manoeuvres
    (re.compile(r"\bswing(?:s|ing)? (?:into|through) (?:a|an) (left|right)[- ]turn\b"), r"turning \1"),
    (re.compile(r"\bswing(?:s|ing)? (left|right)\b(?!.*\b(?:sideways|lateral) acceleration)"), r"turning \1"),
    (
        re.compile(
            r"\b(?:drifting|drifts|moving|moves|shifting|shifts) over (?:one |1 |a )?lanes?"
            r" to the (left|right)\b"
        ),
        r"changing lanes to the \1",
    ),
    (
        re.compile(r"\b(?:stepping|steps|stepped) on the (?:gas|accelerator)\b|\bhitting the gas\b"),
        "accelerating",
    ),
    # (a vehicle "waiting at a standstill in traffic" is read as waiting: stopped for a moment)
    (re.compile(r"(?<!waiting )\b(?:at|to) a (?:complete |full |dead )?standstill\b"), "stopped"),
    (re.compile(r"\bsitting still\b"), "stopped"),
    (re.compile(r"(?<=still |opped )right at (?=an? |the )"), "at "),
    # following: "tagging along behind X", "stuck trailing behind X", "hanging on X's tail"
    (re.compile(r"\b(?:stuck )?(?:tagging along|trailing|tailing) (?:right )?behind\b"), "following"),
    (re.compile(r"\bstuck (?=following)"), ""),
    (re.compile(r"\b(?:was |is |got |were )?stuck behind\b"), "following"),
    (re.compile(r"\bhanging on (the ego vehicle|[\w ]+?)'s tail\b"), r"following \1"),
    # directions and places
    (re.compile(r"\bcoming the other way from\b"), "travelling in the opposite direction to"),
    (re.compile(r"\bmaking (?:their|its|his|her) way (?=towards?\b)"), "walking "),
    (re.compile(r"\bon the far side of the (road|street)\b"), r"on the other side of the \1"),
    (
        re.compile(r"\b(?:well )?away from where (?:cars|vehicles|traffic) (?:can )?(?:drive|go|run)\b"),
        "outside the drivable area",
    ),
    (re.compile(r"\b(?:strolling|walking|wandering) along\b"), "walking"),
    (
        re.compile(
            r"\ba lane (?:set aside|reserved|marked|meant|designated) for (?:bicycles|bikes|cyclists)\b"
        ),
        "a bike lane",
    ),
    (re.compile(r"\ba lane (?:set aside|reserved|marked|meant|designated) for buses\b"), "a bus lane"),
    # "riding right alongside on its left": right beside it on that side
    (
        re.compile(
            r"\b(?:riding|driving|travell?ing|running|rolling) (right |directly )?alongside"
            r" (?:on )?(?:its|their) (left|right)\b"
        ),
        r"\1beside it on its \2",
    ),
    (re.compile(r"\bclose by$"), "nearby"),
    # "someone walking across just in front of the bumper": crossing in front of it
    (
        re.compile(
            r"\b(walking|running|stepping|darting|dashing) across (?:just |right )?in front of"
            r" (?:the|its|their) (?:bumper|hood|bonnet|nose|front)\b"
        ),
        "crossing in front of it",
    ),
    # "with an open road ahead: no car in front within 30 metres": the definition after the colon
    (re.compile(r"\bwith (?:an? )?(?:open|clear|empty) (?:road|lane|path|way)(?: ahead)?: (?=no )"), "with "),
)


def news_wording(text: str) -> str:
    """``text`` (lower case) with a news story's wording put in the plain terms the rules read."""
    for pattern, replacement in _REWRITES:
        text = pattern.sub(replacement, text)
    return text
