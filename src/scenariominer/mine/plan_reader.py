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

The tables (:mod:`scenariominer.mine.plan_phrases`) map English phrasing to the predicates, with
the settings the predicates' docstrings and the evaluation set's dev part use for each phrase
(``scenariominer.eval.nl2prog``). They were written from the dev split, the example bank, (from
``plan-reader/3``) the 152 published RefAV descriptions outside the ``published`` sample and (from
``plan-reader/8``) the spent held-out splits' partial readings; each new hold-out scores them once.
Units are converted (km/h, mph, "meters per second" to m/s).
"""

from __future__ import annotations

import logging
import re
from dataclasses import dataclass, field
from typing import Any

from scenariominer.mine.plan_phrases import (
    CATEGORY_PHRASES,
    COUNT_KEYWORD,
    EGO,
    EXCEPT,
    FILLERS,
    HARD_BRAKING,
    LAST,
    MODIFIERS,
    PHRASES,
    SLOW,
    TO_MPS,
    Phrase,
)
from scenariominer.mine.plan_wording import CATEGORY_RE as _CATEGORY_RE
from scenariominer.mine.plan_wording import MODIFIER_RE as _MODIFIER_RE
from scenariominer.mine.plan_wording import NOUN_PHRASE as _NOUN_PHRASE
from scenariominer.mine.plan_wording import NP as _NP
from scenariominer.mine.plan_wording import SUBJECT as _SUBJECT
from scenariominer.mine.plan_wording import normalised_text as _normalised_text

__all__ = ["PLAN_READER_VERSION", "one_or_many", "read_plan", "rules_plan", "subject_categories"]

#: Version of the phrase tables; enters the program-cache key (``mine.loop.plan_cache_key``).
PLAN_READER_VERSION = "plan-reader/57"


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
    swerve: str | None = None  # the "swerving" word read, if any (its side in the name)
    stated_lateral: list[dict[str, Any]] = field(default_factory=list)  # lateral accelerations stated

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
        negated: bool = False,
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
        if negated:  # "with no vehicle ahead": the subject's timestamps without one
            relation["negated"] = True
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
    "going straight": (("turning", None, True), ("has_velocity", "min_velocity=0.5", False)),
    "parking lot": (("in_drivable_area", None, False), ("on_road", None, True)),
    # "crossing the street", no one named: on the road and moving
    "crossing": (("on_road", None, False), ("has_velocity", "min_velocity=0.5", False)),
    "crossing at crosswalk": (
        ("at_pedestrian_crossing", None, False),
        ("has_velocity", "min_velocity=0.5", False),
    ),
    # swerving: a sideways acceleration of 2 m/s^2 or more (the motion predicates' "large"), not
    # from a turn
    "swerving": (("turning", None, True), ("lateral_acceleration_either_way", "accel=2", False)),
    "swerving left": (("turning", None, True), ("has_lateral_acceleration", "min_accel=2", False)),
    "swerving right": (("turning", None, True), ("has_lateral_acceleration", "max_accel=-2", False)),
}


def _conditions(function: str, argument: str | None, negated: bool) -> list[dict[str, Any]]:
    """The plan's condition entries for one phrase (a compound word gives several)."""
    parts = _COMPOUND.get(function, ((function, argument, False),))
    return [{"function": f, "negated": n != negated, "argument": a} for f, a, n in parts]


class _Unread(ValueError):
    """A phrase the tables do not cover: the description goes to the model."""


def _categories(noun: str) -> tuple[str, ...]:
    """The categories of a road-user noun, with "X or (other) Y" as the union of both."""
    found: list[str] = []
    for part in re.split(r"\s+(?:or|and)\s+(?:other\s+)?", noun.strip()):
        for pattern, categories in CATEGORY_PHRASES:
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
        for pattern, function, argument in MODIFIERS:
            if re.fullmatch(pattern, word):
                out.extend(_conditions(function, argument, False))
                break
    return out


def _speed_mps(value: str, unit: str | None) -> float:
    return round(float(value) * TO_MPS[unit or "m/s"], 2)


#: "not" before a relation to another road user ("cars not following any vehicle"): it must not hold.
_NOT_RELATED = r"(?:(?P<notrel>not|never|are not|is not|aren't|isn't) )?"


def _compiled(phrase: Phrase) -> re.Pattern[str]:
    pattern = phrase.pattern.replace("{obj}", f"(?P<obj>{_NP})")
    if "{obj}" in phrase.pattern and not re.search(r"\(\?P<(?:neg|no|without)>", phrase.pattern):
        pattern = _NOT_RELATED + f"(?:{pattern})"
    return re.compile(r"(?<![\w-])" + pattern + r"(?![\w-])")


_COMPILED = tuple((_compiled(p), p) for p in PHRASES)


#: Words whose loss would invert a partial reading ("not facing traffic" read as "facing traffic").
_NEGATIONS = frozenset(
    {"not", "no", "without", "never", "nor", "neither", "non", "unless", "except"}
    | {"don't", "doesn't", "isn't", "aren't", "wasn't", "weren't", "won't", "cannot"}
)

#: A relative clause and what comes before it: "... the ego vehicle *that are* not ...".
_RELATIVE_CLAUSE = re.compile(r"(?P<before>\S.*?)\s(?:who|which|that)\s(?P<verb>are|were|have)?")


def _plural(words: str) -> bool:
    last = words.split()[-1] if words.split() else ""
    return last in {"people", "persons"} or (last.endswith("s") and not last.endswith(("ss", "us")))


def _clause_after_other(rest: str, subject_words: str) -> bool:
    """Whether a relative clause in ``rest`` may describe another road user than the subject.

    "... a bicyclist who is to the left of a vehicle" may; "pedestrians within 15 m of the ego
    vehicle that are not at a crosswalk" may not: "are" agrees with the plural subject, not with the
    singular road user just before it, so the clause reads as the subject's.
    """
    for found in _RELATIVE_CLAUSE.finditer(rest):
        if _ENDS_WITH_ROAD_USER.search(found.group("before")) is None:
            continue  # "turning somewhere that is not ...": no road user before it but the subject
        before = found.group("before").split()
        if not found.group("verb") or not _plural(subject_words) or (before and _plural(before[-1])):
            return True
    return False


_ENDS_WITH_ROAD_USER = re.compile(rf"(?<![\w-])(?:{_CATEGORY_RE})$")
_BEING_AFTER_OBJECT = re.compile(rf"(?<![\w-]){_NP} (?:is )?being(?![\w-])")


def _apply(phrase: Phrase, reading: _Reading, found: re.Match[str]) -> None:
    """Add what one matched phrase means to the plan being read."""
    if phrase.function is None:
        return
    groups = {k: v for k, v in found.groupdict().items() if v is not None}
    if phrase.function == EXCEPT:
        _leave_out(reading, groups["obj"])
        return
    if "value" in groups:
        groups["speed"] = str(_speed_mps(groups["value"], groups.get("unit")))
    if "low" in groups:  # "between 5 and 10 m/s": the unit stated once, after both
        groups["low_speed"] = str(_speed_mps(groups["low"], groups.get("unit")))
    # "directly ahead": a corridor 1 m either side of the other road user's path; else no limit
    groups["lateral"] = "lateral_thresh=1" if "directly" in groups else ""
    argument = phrase.argument.format(**groups) if phrase.argument else None
    argument = ", ".join(a for a in (argument or "").split(", ") if a) or None
    if "multi" in groups or "qty" in groups:
        if phrase.function not in COUNT_KEYWORD:
            raise _Unread(found.group(0))  # a count this relation cannot take
        count = 2 if "multi" in groups else int(groups["qty"])
        argument = ", ".join(a for a in (argument, f"{COUNT_KEYWORD[phrase.function]}={count}") if a)
    if "obj" in groups or phrase.to_subject or phrase.implied:
        implied = _last_other(reading) if phrase.implied == LAST else phrase.implied
        other = groups.get("obj", implied or reading.subject_phrase or reading.subject_words)
        negated = "no" in groups or "without" in groups or "notrel" in groups
        if negated and (phrase.reverse or phrase.sides or phrase.function in _NOT_NEGATABLE):
            raise _Unread(found.group(0))  # "with no X on both sides": the model reads it
        if phrase.any_side:
            reading.relate(phrase.function, other, argument=argument, any_direction=phrase.sides)
            return
        for direction in phrase.sides or (phrase.direction.format(**groups) if phrase.direction else None,):
            reading.relate(
                phrase.function,
                other,
                direction=direction,
                argument=argument,
                reverse=phrase.reverse,
                negated=negated,
            )
    else:
        reading.condition(phrase.function, argument, negated="neg" in groups)
        if phrase.function.startswith("swerving"):
            reading.swerve = phrase.function
        elif phrase.function in _LATERAL_FUNCTIONS:
            reading.stated_lateral.extend(_conditions(phrase.function, argument, "neg" in groups))


#: Conditions on a stated lateral acceleration (one side, or either way).
_LATERAL_FUNCTIONS = frozenset({"has_lateral_acceleration", "lateral_acceleration_either_way"})


def _stated_lateral_wins(reading: _Reading) -> None:
    """A stated lateral acceleration defines the "swerving" of the same description.

    "vehicles swerving hard to the left, lateral acceleration over 2 m/s²": the stated acceleration
    (to the side "swerving" names) replaces the word's own reading (not turning, 2 m/s² or more).
    """
    if reading.swerve is None or not reading.stated_lateral:
        return
    own = _conditions(reading.swerve, None, False)
    stated = list(reading.stated_lateral)
    side = reading.swerve.removeprefix("swerving").strip()
    if side:  # "swerving left ..., lateral acceleration over 3": 3 to the left
        key = "min_accel={}" if side == "left" else "max_accel=-{}"
        stated = [
            {**c, "function": "has_lateral_acceleration", "argument": key.format(c["argument"].split("=")[1])}
            if c["function"] == "lateral_acceleration_either_way" and not c["negated"]
            else c
            for c in stated
        ]
    kept = [c for c in reading.conditions if c not in own and c not in reading.stated_lateral]
    reading.conditions[:] = kept + [c for i, c in enumerate(stated) if c not in stated[:i]]


def _stated_numbers_win(reading: _Reading) -> None:
    """Drop a word's own number when the description states one for the same thing.

    "slow cars under 30 km/h": the 5 m/s of "slow" goes; "braking hard, decelerating more than
    2 m/s²": the -3 m/s² of "hard" goes (and the -1 of a bare "braking"); a stated lateral
    acceleration replaces what "swerving" reads (:func:`_stated_lateral_wins`).
    """
    _stated_lateral_wins(reading)
    _standing_counts_below_walking_pace(reading)
    for (function, argument), key in ((SLOW, "max_velocity"), (HARD_BRAKING, "max_accel")):
        defaults = [{"function": function, "negated": False, "argument": argument}]
        if function == "accelerating":
            defaults.append({"function": function, "negated": False, "argument": _BRAKING_DEFAULT})
        stated = any(
            c["function"] == function and key in (c["argument"] or "") and c not in defaults
            for c in reading.conditions
        )
        if stated:
            reading.conditions[:] = [c for c in reading.conditions if c not in defaults]


def _standing_counts_below_walking_pace(reading: _Reading) -> None:
    """At rest counts under a stated top speed at walking pace or below ("slower than 1 mph").

    has_velocity's default lower bound (0.5 m/s) would otherwise leave nothing to find.
    """
    for cond in reading.conditions:
        arg = cond["argument"] or ""
        top = re.fullmatch(r"max_velocity=([\d.]+)", arg)
        if cond["function"] == "has_velocity" and top and float(top.group(1)) <= _MOVING_MPS:
            cond["argument"] = f"min_velocity=0, {arg}"


#: has_velocity's default lower bound (m/s): below it an object counts as not moving.
_MOVING_MPS = 0.5
#: The deceleration of a bare "braking" / "slowing down".
_BRAKING_DEFAULT = "min_accel=-inf, max_accel=-1.0"


def _leave_out(reading: _Reading, words: str) -> None:
    """Keep only the subject's members outside the categories of ``words`` ("other than buses").

    Raises:
        _Unread: ``words`` carry adjectives ("other than *moving* buses": not a category).
    """
    found = _NOUN_PHRASE.fullmatch(words.strip())
    if found is None or found.group("mods"):
        raise _Unread(words)
    for category in _categories(found.group("noun")):
        reading.condition("is_category", f"category='{category}'", negated=True)


#: Relations a "with no X" cannot negate (they return the other road users, or build several calls).
_NOT_NEGATABLE = frozenset({"get_objects_in_relative_direction", "in_line"})


def _last_other(reading: _Reading) -> str:
    """The other road user of the last relation read so far, or the ego when there is none."""
    for rel in reversed(reading.relations):
        for words in (rel["other_words"], rel["subject_words"]):
            if words != reading.subject_words:
                return str(words)
    return EGO


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


_LOG = logging.getLogger(__name__)


def read_plan(description: str, *, partial: bool = False) -> dict[str, Any] | None:
    """The plan of ``description`` when every word of it is one of the known phrases, else ``None``.

    A reader that fails on an odd text (a bug in a rule, not a refusal) is logged and the
    description is left unread, so the rewording and the model's own plan take over: a request
    never fails because a phrase rule did.

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
    try:
        return _read(description, partial=partial)
    except Exception as exc:  # noqa: BLE001 - any failure of a rule leaves the text to the model
        _LOG.warning("the phrase rules failed on %r: %s: %s", description[:120], type(exc).__name__, exc)
        return None


def _read(description: str, *, partial: bool) -> dict[str, Any] | None:
    """:func:`read_plan` without its guard."""
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
        own = _modifier_conditions(subject.group("mods"))
        if any(c["function"] == "oncoming" for c in own):
            raise _Unread("oncoming")  # oncoming toward whom: the model reads it
        reading.conditions.extend(own)
        rest = " " + text[subject.end() :] + " "
        if _clause_after_other(rest, reading.subject_words) or _BEING_AFTER_OBJECT.search(rest):
            # a relative clause after another road user ("... a pedestrian who is on a crosswalk")
            # describes that road user: read as its own conditions where it names no one else,
            # else ("... a bicyclist who is to the left of a vehicle", "following a vehicle being
            # overtaken") the model reads it
            return _with_clause_of_other(text, partial=partial)
        added: list[list[dict[str, Any]]] = []  # the conditions each matched phrase added
        for pattern, phrase in _COMPILED:
            while (found := pattern.search(rest)) is not None:
                before = list(reading.conditions)
                _apply(phrase, reading, found)
                added.append([c for c in reading.conditions if all(c is not b for b in before)])
                rest = f"{rest[: found.start()]} ,{_MARK}{len(added) - 1}{_MARK}, {rest[found.end() :]}"
        rest = _join_alternatives(reading, rest, added)
        if _ALTERNATIVES.search(rest):
            raise _Unread("or")  # "near X or following Y": alternatives of relations, the model reads them
        rest = _MARKER.sub("", rest)
        _stated_numbers_win(reading)
        if group is not None:
            _as_group(reading, int(group.group("size") or _GROUP_SIZE))
        unread = skipped + [word for word in re.findall(r"[\w'/.-]+", rest) if word not in FILLERS]
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


_CLAUSE_OF_OTHER = re.compile(
    rf"(?<![\w-])(?P<other>{_NP}) (?:who|which|that) (?:(?:is|are) )?(?P<clause>\S.*)$"
)


def _with_clause_of_other(text: str, *, partial: bool) -> dict[str, Any] | None:
    """The plan of ``text`` whose relative clause after another road user conditions that one.

    "vehicles approaching a pedestrian who is on a crosswalk": the pedestrian is on a crosswalk (a
    condition of the related object, as "a *moving* vehicle" is). The clause must read in full as
    conditions of that road user alone (no other road user in it), else ``None``: the model reads it.
    Where the whole rest does not read so, the longest first part that does is the clause and the
    words after it belong to the sentence ("behind the ego vehicle that is braking within 10 m").
    """
    subject = _SUBJECT.match(text)
    found = _CLAUSE_OF_OTHER.search(text, subject.end() if subject else 1)  # not the subject's own
    if found is None:
        return None
    other = _NOUN_PHRASE.fullmatch(found["other"])  # "another vehicle ...": read as "vehicle ..."
    if other is None:
        return None
    words = found["clause"].split()
    for cut in range(len(words), 0, -1):
        clause = read_plan(f"{other['mods'] or ''}{other['noun']} {' '.join(words[:cut])}")
        if clause is not None and not clause["relations"] and not clause["related"] and clause["conditions"]:
            break
    else:
        return None
    plan = read_plan(" ".join([text[: found.end("other")], *words[cut:]]), partial=partial)
    if plan is None:
        return None
    others = [obj for obj in plan["related"] if obj["category"] == clause["subject_category"]]
    if not others:
        return None
    conditions = others[-1]["conditions"]
    conditions.extend(c for c in clause["conditions"] if c not in conditions)
    return plan


#: Where a matched phrase was (its index in the list of what each phrase added, between marks).
_MARK = "\x00"
_MARKER = re.compile(rf"{_MARK}\d+{_MARK}")
#: Two phrases joined by "or" ("either turning or changing lanes"): their numbers.
_ALTERNATIVES = re.compile(rf"(?:\beither\s+)?,{_MARK}(\d+){_MARK},\s+or\s+,{_MARK}(\d+){_MARK},")


def _join_alternatives(reading: _Reading, rest: str, added: list[list[dict[str, Any]]]) -> str:
    """Join the conditions of two phrases read with "(either) A or B" into one ``any_of`` condition.

    Each alternative keeps its own conditions ("jaywalking" gives two, both required); a third
    "or C" joins the result. Phrases that added a relation rather than a condition are left as
    read, and the "or" then stays among the words not read. Returns ``rest`` without those words.
    """
    while True:
        for found in _ALTERNATIVES.finditer(rest):
            first, second = added[int(found.group(1))], added[int(found.group(2))]
            if first and second:
                break
        else:
            return rest
        joined = {"function": "any_of", "negated": False, "argument": None, "any_of": [first, second]}
        members = [*first, *second]
        kept = [c for c in reading.conditions if all(c is not m for m in members[1:])]
        reading.conditions[:] = [joined if c is members[0] else c for c in kept]
        added.append([joined])
        rest = f"{rest[: found.start()]},{_MARK}{len(added) - 1}{_MARK},{rest[found.end() :]}"


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
