"""Reading common descriptions into a plan by fixed phrase rules, before asking the model.

Most scenario descriptions are built from a small stock of phrases: a road user ("vehicles",
"the ego car", "cyclists"), a motion ("speeding up", "making a left turn", "standing still"), a
place on the map ("in a bike lane", "near an intersection") and a relation to other road users
("within 5 m of a stop sign", "behind the ego vehicle", "following another vehicle").
:func:`read_plan` recognises those phrases and builds the same plan the model's plan step
(:mod:`scenariominer.mine.plan`) would, so :func:`scenariominer.mine.plan_program.compile_plan`
turns it into a program with no model call. By default it reads a description only when **every**
word is accounted for (a phrase of the tables below, or a filler such as "that are"); any word it
does not know makes it return ``None`` and the model reads the description instead.

With ``partial=True`` it also reads a description some of whose words it does not know, as long
as it reads the subject: the plan of the phrases it knows, with the other words listed under
``unread`` (shown to the user, who should check the result). On the descriptions the rules could
not read in full, such a partial plan agreed with the reference far better than the 1.5B model's
plan (docs/mining.md), so the mining loop prefers it (``mining.generation.plan_partial``).

The tables map English phrasing to the predicates, with the settings the predicates' docstrings
and the evaluation set's dev part use for each phrase (``scenariominer.eval.nl2prog``). They were
written from the dev split, the example bank and (from ``plan-reader/3``) the 152 published RefAV
descriptions outside the ``published`` sample; the ``holdout`` and ``published`` splits score them.
Units are converted (km/h, mph, "meters per second" to m/s).
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from typing import Any

__all__ = ["PLAN_READER_VERSION", "one_or_many", "read_plan", "rules_plan", "subject_categories"]

#: Version of the phrase tables; enters the program-cache key (``mine.loop.plan_cache_key``).
PLAN_READER_VERSION = "plan-reader/7"

#: Road users: (phrase pattern, categories). Longer phrases first; plural forms included.
_CATEGORY_PHRASES: tuple[tuple[str, tuple[str, ...]], ...] = (
    (r"(?:the )?ego(?: vehicle| car)?|(?:the )?self[- ]driving (?:car|vehicle)", ("EGO_VEHICLE",)),
    (r"our (?:car|vehicle)", ("EGO_VEHICLE",)),
    (r"vulnerable road users?|vrus?", ("VULNERABLE_ROAD_USER",)),
    (r"people riding (?:bicycles|bikes)|bicycle riders?|bike riders?", ("BICYCLIST",)),
    (r"people riding motorcycles|motorcycle riders?|motorcyclists?", ("MOTORCYCLIST",)),
    (r"scooter riders?|wheeled riders?", ("WHEELED_RIDER",)),
    (r"(?:bi)?cyclists?|(?:bi)?cycles?|bikes?", ("BICYCLE", "BICYCLIST")),
    (r"motorcycles?|motorbikes?", ("MOTORCYCLE",)),
    (r"school bus(?:es)?", ("SCHOOL_BUS",)),
    (r"articulated bus(?:es)?|bendy bus(?:es)?", ("ARTICULATED_BUS",)),
    (r"city bus(?:es)?", ("BUS",)),
    (r"bus(?:es)?", ("BUS", "ARTICULATED_BUS", "SCHOOL_BUS")),
    (r"box trucks?|delivery trucks?", ("BOX_TRUCK",)),
    (r"truck cabs?|semi[- ]trucks?|tractor units?", ("TRUCK_CAB",)),
    (r"trucks?|lorr(?:y|ies)", ("TRUCK", "BOX_TRUCK", "TRUCK_CAB")),
    (r"(?:large|big|heavy) vehicles?", ("LARGE_VEHICLE",)),
    (r"(?:vehicular )?trailers?", ("VEHICULAR_TRAILER",)),
    (r"trams?|streetcars?|trains?|trolleys?|railed vehicles?", ("RAILED_VEHICLE",)),
    (r"cars?|sedans?|suvs?|vans?|pickups?|passenger vehicles?|regular vehicles?", ("REGULAR_VEHICLE",)),
    (r"(?:police officers?|traffic officers?|flaggers?|official signall?ers?)", ("OFFICIAL_SIGNALER",)),
    (r"(?:motor )?vehicles?", ("VEHICLE",)),
    (r"(?:electric |e-)?scooters?|wheeled devices?|skateboards?", ("WHEELED_DEVICE",)),
    (
        r"(?:people|persons?|pedestrians?) in (?:a )?wheelchairs?|wheelchair users?|wheelchairs?",
        ("WHEELCHAIR",),
    ),
    (r"strollers?|prams?|pushchairs?", ("STROLLER",)),
    (r"pedestrians?|people|persons?|someone|somebody|peds?|walkers?", ("PEDESTRIAN",)),
    (r"dogs?", ("DOG",)),
    (r"animals?", ("ANIMAL", "DOG")),
    (r"bollards?", ("BOLLARD",)),
    (r"(?:traffic |construction )?cones?", ("CONSTRUCTION_CONE",)),
    (r"(?:construction )?barrels?", ("CONSTRUCTION_BARREL",)),
    (r"stop signs?", ("STOP_SIGN",)),
    (r"signs?", ("SIGN",)),
    (r"objects?|things?|anything|everything|road users?|actors?|agents?", ("ANY",)),
    # last: "traffic" begins other road users' names ("traffic cone", "traffic officer")
    (r"traffic", ("VEHICLE",)),
)

#: A speed condition for "moving" and for the riding/walking verbs (the predicate's default).
_MOVING = ("has_velocity", "min_velocity=0.5")
_STOPPED = ("has_velocity", "min_velocity=0, max_velocity=0.5")
#: "stopped": at rest at the timestamp, parked objects included (the Argoverse 2 scenario-mining
#: ground truth of "stopped car" refers to the parked cars too); compiled by
#: :mod:`scenariominer.mine.plan_program` as ``stationary`` or ``has_velocity(<= 0.5 m/s)``.
_STOPPED_OR_PARKED = ("stopped", None)

#: Adjectives before a road user: (pattern, condition function, argument).
_MODIFIERS: tuple[tuple[str, str, str | None], ...] = (
    (r"moving", *_MOVING),
    (r"parked|stationary", "stationary", None),
    (r"active|non-stationary", "not stationary", None),
    (r"jaywalking", "jaywalking", None),
    (r"stopped|halted", *_STOPPED_OR_PARKED),
    (r"fast|speeding|fast-moving", "has_velocity", "min_velocity=10"),
    (r"turning", "turning", None),
    (r"accelerating", "accelerating", "min_accel=1.0"),
    (r"braking|decelerating", "accelerating", "min_accel=-inf, max_accel=-1.0"),
)

_WORD_NUMBERS = {
    "one": "1", "two": "2", "three": "3", "four": "4", "five": "5", "six": "6", "seven": "7",
    "eight": "8", "nine": "9", "ten": "10", "twenty": "20", "thirty": "30", "fifty": "50",
}  # fmt: skip
_ORDINALS = {"first": "1", "second": "2", "third": "3", "fourth": "4", "fifth": "5"}
_TO_MPS = {
    "meters per second": 1.0, "metres per second": 1.0, "m/s": 1.0, "mps": 1.0,
    "kilometers per hour": 1 / 3.6, "kilometres per hour": 1 / 3.6, "km/h": 1 / 3.6, "kph": 1 / 3.6,
    "kmh": 1 / 3.6, "miles per hour": 0.44704, "mph": 0.44704,
}  # fmt: skip
#: Words that carry no condition of their own.
_FILLERS = frozenset(
    {"that", "which", "who", "are", "is", "be", "being", "the", "a", "an", "any", "all", "and", "but"}
    | {"while", "also", "currently", "there", "driving", "standing"}
)


@dataclass
class _Reading:
    """The plan being assembled while phrases are consumed."""

    subject_words: str = ""
    subject_phrase: str = ""  # with its adjectives ("moving cyclists"): the subject as other road users
    subject: tuple[str, ...] = ()
    conditions: list[dict[str, Any]] = field(default_factory=list)
    related: list[dict[str, Any]] = field(default_factory=list)
    relations: list[dict[str, Any]] = field(default_factory=list)
    assumed: list[str] = field(default_factory=list)  # relations a partial reading adds on its own

    def condition(self, function: str, argument: str | None = None, *, negated: bool = False) -> None:
        """Add a condition on the subject (once: "stopped or nearly stopped" gives one)."""
        self.conditions.extend(
            c for c in _conditions(function, argument, negated) if c not in self.conditions
        )

    def relate(
        self,
        function: str,
        other: str,
        *,
        direction: str | None = None,
        argument: str | None = None,
        reverse: bool = False,
        any_direction: tuple[str, ...] = (),
    ) -> None:
        """A relation of the subject to the road users ``other`` (read by :func:`_object`)."""
        words = self._object(other)
        subject_words, other_words = (words, self.subject_words) if reverse else (self.subject_words, words)
        relation: dict[str, Any] = {
            "subject_words": subject_words,
            "function": function,
            "other_words": other_words,
            "direction": direction,
            "argument": argument,
        }
        if any_direction:
            relation["any_direction"] = list(any_direction)
        self.relations.append(relation)

    def _object(self, phrase: str) -> str:
        """Register the road users of ``phrase`` ("a moving vehicle") as a related object; its words."""
        found = _NOUN_PHRASE.fullmatch(phrase.strip())
        if found is None:
            raise _Unread(phrase)
        categories = _categories(found.group("noun"))
        if categories == ("EGO_VEHICLE",) and not found.group("mods"):
            words = "ego vehicle"
        else:
            words = " ".join(phrase.split())
        if all(obj["words"] != words for obj in self.related):
            conditions = _modifier_conditions(found.group("mods"))
            category = one_or_many(categories)
            self.related.append({"words": words, "category": category, "conditions": conditions})
        return words


#: Words that stand for more than one condition (function, argument, negated).
_COMPOUND: dict[str, tuple[tuple[str, str | None, bool], ...]] = {
    "not stationary": (("stationary", None, True),),
    "jaywalking": (("on_road", None, False), ("at_pedestrian_crossing", None, True)),
}


def _conditions(function: str, argument: str | None, negated: bool) -> list[dict[str, Any]]:
    """The plan's condition entries for one phrase (a compound word gives several)."""
    parts = _COMPOUND.get(function, ((function, argument, False),))
    return [{"function": f, "negated": n != negated, "argument": a} for f, a, n in parts]


class _Unread(ValueError):
    """A phrase the tables do not cover: the description goes to the model."""


def _alternation(patterns: Any) -> str:
    return "|".join(f"(?:{p})" for p in patterns)


_CATEGORY_RE = _alternation(p for p, _ in _CATEGORY_PHRASES)
_MODIFIER_RE = _alternation(p for p, _, _ in _MODIFIERS)
_DETERMINER = r"(?:(?:a|an|the|any|another|other|some|all|its|their)\s+)"
_NOUN = rf"(?:{_CATEGORY_RE})(?:\s+(?:or|and)\s+(?:other\s+)?(?:{_CATEGORY_RE}))?"
_NOUN_PHRASE = re.compile(rf"{_DETERMINER}*(?P<mods>(?:(?:{_MODIFIER_RE})\s+)*)(?P<noun>{_NOUN})")
_NP = rf"(?:(?:{_DETERMINER}*)(?:(?:{_MODIFIER_RE})\s+)*(?:{_NOUN}))"


def _categories(noun: str) -> tuple[str, ...]:
    """The categories of a road-user noun, with "X or (other) Y" as the union of both."""
    found: list[str] = []
    for part in re.split(r"\s+(?:or|and)\s+(?:other\s+)?", noun.strip()):
        for pattern, categories in _CATEGORY_PHRASES:
            if re.fullmatch(pattern, part):
                found.extend(c for c in categories if c not in found)
                break
        else:
            raise _Unread(part)
    return tuple(found)


def one_or_many(categories: tuple[str, ...]) -> str | list[str]:
    """A plan's category value: one name, or the list of several (a union)."""
    return categories[0] if len(categories) == 1 else list(categories)


def _modifier_conditions(mods: str | None) -> list[dict[str, Any]]:
    """The plan's condition entries of the adjectives ``mods`` ("moving parked")."""
    out: list[dict[str, Any]] = []
    for word in re.findall(_MODIFIER_RE, mods or ""):
        for pattern, function, argument in _MODIFIERS:
            if re.fullmatch(pattern, word):
                out.extend(_conditions(function, argument, False))
                break
    return out


def _speed_mps(value: str, unit: str | None) -> float:
    return round(float(value) * _TO_MPS[unit or "m/s"], 2)


@dataclass(frozen=True)
class _Phrase:
    """One phrase after the subject and what it means.

    ``{obj}`` in the pattern stands for the other road users (the phrase is then a relation to
    them); ``{name}`` in ``argument``/``direction`` is filled from the pattern's named group
    (``{speed}`` from ``value`` and ``unit``, in m/s); a ``neg`` group negates a condition.
    """

    pattern: str
    function: str | None  # None: the phrase carries no condition ("in traffic")
    argument: str | None = None
    direction: str | None = None
    reverse: bool = False  # the other road users do it to the subject ("crossing in front of X")
    to_subject: bool = False  # a relation among the subject's own members ("close together")
    sides: tuple[str, ...] = ()  # one relation per direction, all required ("on both sides")
    any_side: bool = False  # with ``sides``: one relation holding in any of them ("on either side")
    implied: str | None = None  # the other road users when the phrase names none ("ahead": the ego)


_NUMBER = r"\d+(?:\.\d+)?"
_DIST = rf"(?P<dist>{_NUMBER}) ?(?:m|meters?|metres?)"
_SPEED = rf"(?P<value>{_NUMBER}) ?(?P<unit>{'|'.join(_TO_MPS)})?"
_GOING = r"(?:(?:moving|going|driving|travell?ing) )?"
_HAVE = r"(?:that have|that has|having|with)"
_CROSSWALK = r"(?:a |the |any )?(?:crosswalk|zebra crossing|pedestrian crossing|designated crossing)s?"
_INTERSECTION = r"(?:an |the |a )?(?:intersection|junction)s?"
_NOT = r"(?P<neg>not |without )?"
#: How many of the other road users a relation needs: "multiple X", "at least 2 X", "3 or more X".
_QUANTITY = r"(?:(?P<multi>multiple|several|many) |(?:at least )?(?P<qty>\d+) (?:or more )?)?"
#: The keyword that takes that count, per relation function.
_COUNT_KEYWORD = {"has_objects_in_relative_direction": "min_number", "near_objects": "min_objects"}
_ACCEL = (
    r"(?P<accel>\d+(?:\.\d+)?) ?(?:m/s2|m/s²|m/s\^2|(?:meters|metres) per second(?: squared| per second)?)"
)
_NEAR = r"(?:near|close to|approaching|as (?:they|it) approach(?:es)?|next to|by)"
_IN_LANE = (
    r"(?:(?:riding |driving |cycling )?(?:in|on|inside|within|using|along|through|blocking)) (?:a |the )?"
)
_ON_X = "on_intersection"
_SPEEDING_UP = ("accelerating", "min_accel=1.0")
_TURNING = ("turning", "direction='{dir}'")
_BESIDE = "within_distance=5, lateral_thresh=2"
_ALONG = "within_distance=25, lateral_thresh=1"
_EGO = "the ego vehicle"

_IN_LINE_AHEAD = r"(?P<rank>\d+) (?:cars?|vehicles?) (?:ahead|in front|forward)"
_IN_LINE_BEHIND = r"(?P<rank>\d+) (?:cars?|vehicles?) (?:behind|back)"

#: Phrases after the subject, tried in this order; each match is consumed.
_PHRASES: tuple[_Phrase, ...] = (
    # "two cars ahead (of X)": the second vehicle in line ahead of X, the ego when none is named
    _Phrase(_IN_LINE_AHEAD + r" (?:of|from) {obj}", "in_line", "rank={rank}", "forward"),
    _Phrase(_IN_LINE_BEHIND + r" (?:(?:of|from) )?{obj}", "in_line", "rank={rank}", "backward"),
    _Phrase(_IN_LINE_AHEAD, "in_line", "rank={rank}", "forward", implied=_EGO),
    _Phrase(_IN_LINE_BEHIND, "in_line", "rank={rank}", "backward", implied=_EGO),
    # stated numbers first, so "within 5 m of X" is not read as a bare relation
    _Phrase(
        r"surrounded by (?P<count>\d+) or more {obj} within " + _DIST,
        "near_objects", "distance_thresh={dist}, min_objects={count}",
    ),
    _Phrase(
        r"(?:with|having) (?:at least )?(?P<count>\d+)(?: or more)? {obj} within " + _DIST,
        "near_objects", "distance_thresh={dist}, min_objects={count}",
    ),
    _Phrase(r"within " + _DIST + " of " + _INTERSECTION, "near_intersection", "threshold={dist}"),
    _Phrase(
        r"within " + _DIST + r" (?:ahead of|in front of) {obj}",
        "get_objects_in_relative_direction", "within_distance={dist}, lateral_thresh=1", "forward",
    ),
    _Phrase(
        r"within " + _DIST + r" (?:behind|in back of) {obj}",
        "get_objects_in_relative_direction", "within_distance={dist}, lateral_thresh=1", "backward",
    ),
    _Phrase(
        r"within " + _DIST + r" (?:to|on) the (?P<dir>left|right)(?: side)? of {obj}",
        "get_objects_in_relative_direction", "within_distance={dist}", "{dir}",
    ),
    _Phrase(
        r"(?:directly )?(?:ahead of|in front of) {obj} within " + _DIST,
        "get_objects_in_relative_direction", "within_distance={dist}, lateral_thresh=1", "forward",
    ),
    # a place with no road user named is the ego's ("within 50 meters ahead", "to the right")
    _Phrase(
        r"within " + _DIST + r" (?:ahead|in front)(?! of)",
        "get_objects_in_relative_direction", "within_distance={dist}, lateral_thresh=1", "forward",
        implied=_EGO,
    ),
    _Phrase(
        r"within " + _DIST + r" (?:behind|in back)(?= ,|\s*$)",
        "get_objects_in_relative_direction", "within_distance={dist}, lateral_thresh=1", "backward",
        implied=_EGO,
    ),
    _Phrase(
        r"within " + _DIST + r" (?:to|on) the (?P<dir>left|right)(?: side)?(?! of)",
        "get_objects_in_relative_direction", "within_distance={dist}", "{dir}", implied=_EGO,
    ),
    _Phrase(
        r"within " + _DIST + r" (?:on|to) either side(?! of)",
        "get_objects_in_relative_direction", "within_distance={dist}", sides=("left", "right"), any_side=True,
        implied=_EGO,
    ),
    _Phrase(
        r"(?:pointed|facing|pointing) (?:at|towards?) {obj} (?:less than|within|under) "
        + _DIST + "(?: away)?",
        "facing_toward", "within_angle=30, max_distance={dist}",
    ),
    _Phrase(
        r"within " + _DIST + r" (?:on|to) either side of {obj}",
        "get_objects_in_relative_direction", "within_distance={dist}", sides=("left", "right"), any_side=True,
    ),
    _Phrase(
        r"within " + _DIST + r" of (?:each other|one another)",
        "near_objects", "distance_thresh={dist}", to_subject=True,
    ),
    _Phrase(r"within " + _DIST + " of {obj}", "near_objects", "distance_thresh={dist}"),
    _Phrase(r"accelerating (?:at )?(?:more than|over|faster than|above|at least) " + _ACCEL,
            "accelerating", "min_accel={accel}"),
    _Phrase(
        _GOING + r"(?:faster than|above|over|at more than) " + _SPEED, "has_velocity", "min_velocity={speed}"
    ),
    _Phrase(
        _GOING + r"(?:slower than|below|under|at less than) " + _SPEED,
        "has_velocity", "min_velocity=0, max_velocity={speed}",
    ),
    # relations to other road users
    _Phrase(
        r"(?:crossing|walking across|running across)(?: the road| the street)? in front of {obj}",
        "being_crossed_by", direction="forward", reverse=True,
    ),
    _Phrase(
        r"(?:with|having) {obj} (?:walking |running |cycling )?(?:crossing|across) in front of (?:them|it)",
        "being_crossed_by", direction="forward",
    ),
    _Phrase(r"being crossed by {obj}", "being_crossed_by", direction="forward"),
    # overtaking: the overtaker crosses the other's left side from behind to ahead (clockwise)
    _Phrase(r"(?:overtaking|passing) {obj} on the right", "being_crossed_by",
            "in_direction='counterclockwise', forward_thresh=4", "right", reverse=True),
    _Phrase(r"(?:overtaking|passing) {obj}(?: on the left)?", "being_crossed_by",
            "in_direction='clockwise', forward_thresh=4", "left", reverse=True),
    _Phrase(r"being (?:overtaken|passed) on the right by {obj}", "being_crossed_by",
            "in_direction='counterclockwise', forward_thresh=4", "right"),
    _Phrase(r"being (?:overtaken|passed) by {obj} on the right", "being_crossed_by",
            "in_direction='counterclockwise', forward_thresh=4", "right"),
    _Phrase(r"being (?:overtaken|passed) (?:on the left )?by {obj}(?: on the left)?", "being_crossed_by",
            "in_direction='clockwise', forward_thresh=4", "left"),
    # ... by a vehicle, when the overtaker is not named
    _Phrase(r"(?:being |getting )?(?:overtaken|passed) (?:on|from) (?:the )?right", "being_crossed_by",
            "in_direction='counterclockwise', forward_thresh=4", "right", implied="vehicles"),
    _Phrase(r"(?:being |getting )(?:overtaken|passed)(?: (?:on|from) (?:the )?left)?", "being_crossed_by",
            "in_direction='clockwise', forward_thresh=4", "left", implied="vehicles"),
    _Phrase(r"(?:following|tailgating|(?:driving |travell?ing )?(?:closely )?behind) {obj}"
            r" in (?:the )?same lane",
            "following"),
    _Phrase(r"(?:following|tailgating|(?:following |driving |riding |travell?ing )?closely behind"
            r"|driving behind) {obj}"
            r"(?: too closely| closely)?", "following"),
    _Phrase(r"being (?:followed|tailgated) by {obj}", "following", reverse=True),
    _Phrase(r"(?:in (?:the )?same lane as|sharing (?:a |the )?lane with) {obj}", "in_same_lane"),
    _Phrase(
        r"(?:approaching|closing in on|(?:heading|moving|driving|going|walking) towards?) {obj}",
        "heading_toward", "max_distance=30",
    ),
    _Phrase(
        r"(?:(?:directly )?facing(?: towards?)?|looking (?:towards?|at)|turned towards?) {obj}",
        "facing_toward", "within_angle=30, max_distance=20",
    ),
    _Phrase(
        r"on the (?:other|opposite) side of the road(?: from| to| than)? {obj}",
        "on_relative_side_of_road", "side='opposite'",
    ),
    _Phrase(r"on the same side of the road as {obj}", "on_relative_side_of_road", "side='same'"),
    _Phrase(
        r"(?:travell?ing|heading|driving|moving|going|riding) (?:in (?:the )?)?(?P<dir>same|opposite)"
        r"(?: direction)? (?:as|to) {obj}",
        "heading_in_relative_direction_to", direction="{dir}",
    ),
    _Phrase(
        _HAVE + r" " + _QUANTITY + r"{obj} (?:(?:on |to )(?:both )?(?:their |its |the )?left and right"
        r"|on both (?:their |its )?sides)",
        "has_objects_in_relative_direction", _BESIDE, sides=("left", "right"),
    ),
    _Phrase(
        r"(?:surrounded|boxed in|hemmed in) by {obj} on all (?:four )?sides",
        "has_objects_in_relative_direction", _BESIDE, sides=("left", "right", "forward", "backward"),
    ),
    _Phrase(
        r"(?:boxed|hemmed|squeezed) in by {obj} (?:(?:on |to )(?:both )?(?:their |its |the )?left and right"
        r"|on both (?:their |its )?sides)",
        "has_objects_in_relative_direction", _BESIDE, sides=("left", "right"),
    ),
    # "between two parked cars": one on the subject's left and one on its right, relative to the
    # subject's own heading (a pedestrian crossing through a gap has the cars to its sides)
    _Phrase(
        r"(?:passing |crossing |walking |riding |driving |squeezing )?(?:in )?between (?:2 )?{obj}",
        "has_objects_in_relative_direction", _BESIDE, sides=("left", "right"),
    ),
    _Phrase(
        _HAVE + r" " + _QUANTITY
        + r"{obj} (?:on |to )(?:their |its |the )(?P<dir>left|right)(?: side| hand side)?",
        "has_objects_in_relative_direction", _BESIDE, "{dir}",
    ),
    _Phrase(
        _HAVE + r" " + _QUANTITY + r"{obj} (?:on |to )either side",
        "has_objects_in_relative_direction", _BESIDE, sides=("left", "right"), any_side=True,
    ),
    _Phrase(_HAVE + r" " + _QUANTITY + r"{obj} (?:right |directly |just )?behind(?: them| it)?",
            "has_objects_in_relative_direction",
            _ALONG, "backward"),
    _Phrase(
        _HAVE + r" " + _QUANTITY + r"{obj} (?:in front|ahead)(?: of (?:them|it))?",
        "has_objects_in_relative_direction", _ALONG, "forward",
    ),
    _Phrase(
        r"(?:towing|pulling) {obj}",
        "has_objects_in_relative_direction", "within_distance=2, lateral_thresh=0.5", "backward",
    ),
    _Phrase(r"(?:behind|in back of) {obj}", "get_objects_in_relative_direction", _ALONG, "backward"),
    _Phrase(r"(?:ahead of|in front of) {obj}", "get_objects_in_relative_direction", _ALONG, "forward"),
    _Phrase(
        r"(?:crossing|walking across|running across)(?: the road| the street)? (?:ahead|in front)(?! of)",
        "being_crossed_by", direction="forward", reverse=True, implied=_EGO,
    ),
    _Phrase(r"(?:directly |straight )?ahead(?! of)", "get_objects_in_relative_direction", _ALONG, "forward",
            implied=_EGO),
    _Phrase(
        r"(?:directly |immediately )?(?:to|on) either side of {obj}",
        "get_objects_in_relative_direction", "within_distance=10", sides=("left", "right"), any_side=True,
    ),
    _Phrase(
        r"(?:directly |immediately )?(?:to the|on the) (?P<dir>left|right)(?: side| hand side)? of {obj}",
        "get_objects_in_relative_direction", "within_distance=10", "{dir}",
    ),
    _Phrase(r"(?:pushed|pulled|walked|carried) by {obj}", "near_objects", "distance_thresh=1"),
    _Phrase(r"(?:with|having) " + _QUANTITY + r"{obj} (?:nearby|close by|around)", "near_objects",
            "distance_thresh=10"),
    _Phrase(
        r"(?:walking |moving |standing |riding )?(?:close together|side by side|in a group|together"
        r"|(?:near|close to|next to) (?:each other|one another))",
        "near_objects", "distance_thresh=2", to_subject=True,
    ),
    _Phrase(r"(?:going|driving|passing) close by {obj}", "near_objects", "distance_thresh=5"),
    _Phrase(r"(?:going past|driving past|passing by) {obj}", "near_objects", "distance_thresh=20"),
    # places on the map (before the bare "near X", which would read "an intersection" as a road user)
    _Phrase(
        _IN_LANE + r"(?:bike|bicycle|cycle) lanes?",
        "on_lane_type", "lane_type='BIKE'",
    ),
    _Phrase(_IN_LANE + r"bus lanes?", "on_lane_type", "lane_type='BUS'"),
    _Phrase(_IN_LANE + r"(?:vehicle|car|traffic|driving) lanes?", "on_lane_type", "lane_type='VEHICLE'"),
    _Phrase(_NEAR + " " + _INTERSECTION, "near_intersection", "threshold=15"),
    _Phrase(
        r"(?P<neg>(?:but )?(?:outside|not in|not inside|not on))(?: of)?(?: it| " + _INTERSECTION + ")", _ON_X
    ),
    _Phrase(r"(?:in|on|inside|within|at|through|crossing|in the middle of) " + _INTERSECTION, _ON_X),
    _Phrase(_NEAR + " " + _CROSSWALK, "at_pedestrian_crossing", "within_distance=5"),
    _Phrase(r"(?P<neg>away from|not at|not on|not using|without using|outside(?: of)?) " + _CROSSWALK,
            "at_pedestrian_crossing"),
    _Phrase(r"(?:on|in|inside|within|(?:driving |walking |going )?across) " + _CROSSWALK,
            "at_pedestrian_crossing", "within_distance=0"),
    _Phrase(r"(?:at|using) " + _CROSSWALK, "at_pedestrian_crossing"),
    _Phrase(r"(?:at|near|approaching) (?:a |the )?stop signs?", "at_stop_sign"),
    _Phrase(r"(?:on|in|within|inside) the drivable area", "in_drivable_area"),
    _Phrase(r"(?P<neg>off the (?:road|street)|not on the (?:road|street))", "on_road"),
    _Phrase(r"(?P<neg>outside|off|not (?:on|in)) the drivable area", "in_drivable_area"),
    _Phrase(r"(?P<neg>on|along) the (?:sidewalk|pavement)", "in_drivable_area"),
    _Phrase(r"(?:on|in) (?:the )?(?:road|street|roadway|carriageway)", "on_road"),
    _Phrase(r"in traffic", None),
    _Phrase(r"jaywalking", "jaywalking"),
    # bare relations (after the map phrases)
    _Phrase(r"(?:near|next to|beside|alongside|nearby|around) " + _QUANTITY + "{obj}", "near_objects",
            "distance_thresh=10"),
    _Phrase(r"(?:close to|very close to|in close proximity to) " + _QUANTITY + "{obj}", "near_objects",
            "distance_thresh=5"),
    # motions of the subject
    _Phrase(
        r"(?:slamming on the brakes|braking hard|braking heavily|hard braking|heavy braking|emergency braking"
        r"|stopping suddenly|decelerating hard)",
        "accelerating", "min_accel=-inf, max_accel=-3.0",
    ),
    _Phrase(_NOT + r"(?:speeding up|accelerating|picking up speed|gaining speed)", *_SPEEDING_UP),
    _Phrase(
        _NOT + r"(?:slowing down|slowing|decelerating|braking|losing speed)",
        "accelerating", "min_accel=-inf, max_accel=-1.0",
    ),
    _Phrase(r"(?:making|taking|doing|performing) an? (?P<dir>left|right)(?: turn| hand turn)?", *_TURNING),
    _Phrase(r"turning (?:to the )?(?P<dir>left|right)", *_TURNING),
    _Phrase(_NOT + r"(?:making a turn|turning)", "turning"),
    _Phrase(
        r"(?:changing lanes?|switching lanes?|moving over|merging) (?:in)?to the (?P<dir>left|right)",
        "changing_lanes", "direction='{dir}'",
    ),
    _Phrase(
        r"(?:changing lanes?|switching lanes?|moving over|merging) into the lane"
        r" (?:on |to )(?:their |its |the )(?P<dir>left|right)",
        "changing_lanes", "direction='{dir}'",
    ),
    _Phrase(
        r"(?:making|performing|doing) an? (?P<dir>left|right) lane change",
        "changing_lanes", "direction='{dir}'",
    ),
    _Phrase(
        _NOT + r"(?:changing lanes?|switching lanes?|lane changing"
        r"|(?:performing|making|doing) a lane change)",
        "changing_lanes",
    ),
    _Phrase(r"(?:waiting )?(?:stopped|halted)", *_STOPPED_OR_PARKED),
    _Phrase(r"(?:waiting )?(?:standing still|at a standstill|not moving|at rest)", *_STOPPED),
    _Phrase(_NOT + r"(?:parked|stationary)", "stationary"),
    _Phrase(r"(?:that )?(?:has not|hasn't|have not|haven't|never) moved", "stationary"),
    _Phrase(r"(?:moving )?(?:at (?:a )?crawling speed|crawling|creeping)", "has_velocity",
            "min_velocity=0.5, max_velocity=3"),
    _Phrase(r"(?:at (?:a )?high speed|quickly)", "has_velocity", "min_velocity=10"),
    _Phrase(r"(?:moving|in motion|walking|riding|cycling|jogging|running|travell?ing)", *_MOVING),
)  # fmt: skip
_COMPILED = tuple(
    (re.compile(r"(?<![\w-])" + p.pattern.replace("{obj}", f"(?P<obj>{_NP})") + r"(?![\w-])"), p)
    for p in _PHRASES
)
_SUBJECT = re.compile(
    rf"^\s*(?:(?:all|the|a|an|any|some|every)\s+)*(?P<mods>(?:(?:{_MODIFIER_RE})\s+)*)(?P<noun>{_NOUN})(?![\w-])"
)


#: Words whose loss would invert a partial reading ("not facing traffic" read as "facing traffic").
_NEGATIONS = frozenset(
    {"not", "no", "without", "never", "nor", "neither", "non", "unless", "except"}
    | {"don't", "doesn't", "isn't", "aren't", "wasn't", "weren't", "won't", "cannot"}
)

_BEING_AFTER_OBJECT = re.compile(rf"(?<![\w-]){_NP} (?:is )?being(?![\w-])")


def _apply(phrase: _Phrase, reading: _Reading, found: re.Match[str]) -> None:
    """Add what one matched phrase means to the plan being read."""
    if phrase.function is None:
        return
    groups = {k: v for k, v in found.groupdict().items() if v is not None}
    if "value" in groups:
        groups["speed"] = str(_speed_mps(groups["value"], groups.get("unit")))
    argument = phrase.argument.format(**groups) if phrase.argument else None
    if "multi" in groups or "qty" in groups:
        if phrase.function not in _COUNT_KEYWORD:
            raise _Unread(found.group(0))  # a count this relation cannot take
        count = 2 if "multi" in groups else int(groups["qty"])
        argument = ", ".join(a for a in (argument, f"{_COUNT_KEYWORD[phrase.function]}={count}") if a)
    if "obj" in groups or phrase.to_subject or phrase.implied:
        other = groups.get("obj", phrase.implied or reading.subject_phrase or reading.subject_words)
        if phrase.any_side:
            reading.relate(phrase.function, other, argument=argument, any_direction=phrase.sides)
            return
        for direction in phrase.sides or (phrase.direction.format(**groups) if phrase.direction else None,):
            reading.relate(
                phrase.function, other, direction=direction, argument=argument, reverse=phrase.reverse
            )
    else:
        reading.condition(phrase.function, argument, negated="neg" in groups)


#: "a group of (at least N) X": the subject is each member of such a group.
_GROUP = re.compile(r"^\s*(?:an? |the )?groups? of (?:(?:at least )?(?P<size>\d+)(?: or more)? )?")
#: The size of "a group" with no number, and how close its members stand (the dev split's
#: "groups of three or more pedestrians": at least two others within 2 m).
_GROUP_SIZE = 3
_GROUP_DISTANCE = "distance_thresh=2"


def _as_group(reading: _Reading, size: int) -> None:
    """Keep the subject's members that have at least ``size - 1`` others of it close by.

    "within 5 meters of each other" sets how close; otherwise :data:`_GROUP_DISTANCE`.
    """
    if size < 2:
        raise _Unread(f"a group of {size}")
    count = f"min_objects={size - 1}"
    members = " ".join(reading.subject_phrase.split())
    for rel in reading.relations:
        if rel["function"] == "near_objects" and rel["other_words"] == members:
            rel["argument"] = ", ".join(a for a in (rel["argument"], count) if a)
            return
    reading.relate("near_objects", members, argument=f"{_GROUP_DISTANCE}, {count}")


def _keep_unread_road_users(reading: _Reading, rest: str) -> None:
    """Require the road users named among the words left out nearby (a partial reading).

    "person walking *two dogs*": the relation to the dogs is not read, but without any dog close by
    the description cannot hold, so the subject keeps the timestamps with one within 10 m (the bare
    "near X" of the tables) instead of every walking person. The ego, always present, is left out.
    """
    for found in re.finditer(rf"(?<![\w-])(?:{_CATEGORY_RE})(?![\w-])", rest):
        words = found.group(0)
        if words == "traffic" or words in {r["other_words"] for r in reading.relations}:
            continue  # "through traffic" is no one road user
        if _categories(words) == ("EGO_VEHICLE",):
            continue  # always there: a distance to it would be a guess, not a presence test
        reading.relate("near_objects", words, argument="distance_thresh=10")
        reading.assumed.append(f"near {words}")


def read_plan(description: str, *, partial: bool = False) -> dict[str, Any] | None:
    """The plan of ``description`` when every word of it is one of the known phrases, else ``None``.

    The plan has the fields of :func:`scenariominer.mine.plan.plan_model` plus ``read_by =
    "rules"``; a category may be a list (the union of several, "buses"), and a related object may
    carry its own conditions ("a *moving* vehicle"), which the model's plans never do.

    Args:
        description: the request.
        partial: also read it when some words are not known phrases (the subject must be read,
            after at most two unknown words, and every known phrase must make sense); the plan
            then lists those words, in order, under ``unread`` (empty when every word was read).
            A road user named among them is still required within 10 m
            (:func:`_keep_unread_road_users`; listed under ``assumed``). A left-out negation or a
            relative clause after another road user ("... who is ...") makes it return ``None``.
    """
    group, subject, text = _leading_subject(description)
    skipped: list[str] = []
    if subject is None and partial and group is None:
        # unknown adjectives before the road user ("*unattended* stroller", "*lane splitting*
        # motorcycle"): at most two words, read as left out
        for n_words in (1, 2):
            prefix = re.match(rf"^\s*((?:[\w'-]+\s+){{{n_words}}})", text)
            if prefix is not None and (subject := _SUBJECT.match(text[prefix.end() :])) is not None:
                skipped, text = prefix.group(1).split(), text[prefix.end() :]
                break
    if subject is None or _NEGATIONS.intersection(skipped):
        return None
    try:
        reading = _Reading(
            subject_words=subject.group("noun"),
            subject_phrase=(subject.group("mods") or "") + subject.group("noun"),
            subject=_categories(subject.group("noun")),
        )
        reading.conditions.extend(_modifier_conditions(subject.group("mods")))
        rest = " " + text[subject.end() :] + " "
        if re.search(r"\S.*\b(?:who|which|that)\b", rest) or _BEING_AFTER_OBJECT.search(rest):
            # a relative clause after another road user ("... a bicyclist who is to the left of a
            # vehicle", "following a vehicle being overtaken") may describe that road user, not the
            # subject: the model reads it
            return None
        for pattern, phrase in _COMPILED:
            while (found := pattern.search(rest)) is not None:
                _apply(phrase, reading, found)
                rest = rest[: found.start()] + " , " + rest[found.end() :]
        if group is not None:
            _as_group(reading, int(group.group("size") or _GROUP_SIZE))
        unread = skipped + [word for word in re.findall(r"[\w'/.-]+", rest) if word not in _FILLERS]
        if unread and (not partial or _NEGATIONS.intersection(unread)):
            return None  # a negation left out would turn the reading into its opposite
        if unread:
            _keep_unread_road_users(reading, rest)
    except _Unread:
        return None
    return {
        "subject_words": reading.subject_words,
        "subject_category": one_or_many(reading.subject),
        "related": reading.related,
        "relations": reading.relations,
        "conditions": reading.conditions,
        "numbers": [],
        "read_by": "rules",
        **({"unread": unread, "assumed": reading.assumed} if partial else {}),
    }


def rules_plan(description: str, *, partial: bool) -> dict[str, Any] | None:
    """The phrase rules' plan: read in full if they can, else (with ``partial``) in part, else ``None``.

    A plan read in part carries a non-empty ``unread``; one read in full has no such key.
    """
    return read_plan(description) or (read_plan(description, partial=True) if partial else None)


def subject_categories(words: str) -> tuple[str, ...] | None:
    """The categories of the road-user phrase ``words`` begins with, or ``None`` if none.

    "regular vehicles ..." is REGULAR_VEHICLE, "buses" the three bus categories.
    """
    _, subject, _ = _leading_subject(words)
    if subject is None:
        return None
    try:
        return _categories(subject.group("noun"))
    except _Unread:
        return None


def _leading_subject(description: str) -> tuple[re.Match[str] | None, re.Match[str] | None, str]:
    """The "a group of N" prefix, the road-user phrase after it, and the normalised text they match.

    The subject match runs on the text after the group prefix ("a group of 3 pedestrians": the
    pedestrians read as a group); each match is ``None`` when absent.
    """
    text = _normalised_text(description)
    group = _GROUP.match(text)
    if group is not None:
        text = text[group.end() :]
    return group, _SUBJECT.match(text), text


def _normalised_text(description: str) -> str:
    """Lower case, single spaces, no final full stop, number words as digits ("three" -> "3").

    A place in a line of vehicles is put in the one form the tables read: "the third car forward
    from X" -> "the car 3 cars forward from X"; "two cars back from X" (no subject) -> "vehicle 2
    cars back from X".
    """
    text = " ".join(description.lower().replace(",", " ").split()).rstrip(".!")
    text = re.sub(r"\bego-(vehicle|car)\b", r"ego \1", text)
    text = re.sub(r"\b(" + "|".join(_WORD_NUMBERS) + r")\b", lambda m: _WORD_NUMBERS[m.group(1)], text)
    text = re.sub(
        r"\b(" + "|".join(_ORDINALS) + r") (cars?|vehicles?) (?=ahead|in front|forward|behind|back)",
        lambda m: f"{m.group(2)} {_ORDINALS[m.group(1)]} {m.group(2)} ",
        text,
    )
    return re.sub(r"^(\d+ (?:cars?|vehicles?) (?:ahead|in front|forward|behind|back))", r"vehicle \1", text)
