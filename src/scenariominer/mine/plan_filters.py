"""Filter expressions, put in the words the phrase rules read.

A data scientist writes a scenario as the filter of a query over a track table: field names with
underscores, comparison operators, ``AND``/``OR``/``NOT`` and their C forms, a category test
("category == BOX_TRUCK", "class IN (BUS, BOX_TRUCK)"), a speed or a distance bound
("speed_mps > 10", "dist_to_ego < 15 m"), a flag ("is_parked = true", "on_intersection == false").
:func:`filter_wording` rewrites such a filter into the plain wording of the rest of the
normalisation (:mod:`scenariominer.mine.plan_wording`): "box truck", "bus or box truck", "moving
faster than 10 m/s", "within 15 m of the ego vehicle", "parked", "not on intersection". A text
without any filter syntax comes back as it went in.
"""

from __future__ import annotations

import re
from collections.abc import Callable

from scenariominer.mine.plan_nouns import NOUN

__all__ = ["filter_wording"]

_NUMBER = r"\d+(?:\.\d+)?"
#: The field that holds a track's category.
_CATEGORY_FIELD = (
    r"(?:category|class|(?:object|actor|agent|track)_?(?:class|type|category)|obj_?type|type|label|cat)"
)
#: A speed field; a unit in its name ("speed_mps", "v_kmh") is kept.
_SPEED_FIELD = r"(?:abs_?)?(?:speed|velocity|vel|v)(?:_(?P<field_unit>mps|ms|m_s|kmh|kph|mph))?"
_SPEED_UNIT = r"(?P<unit>m/s|mps|km/h|kmh|kph|mph)"
#: A distance to the ego vehicle ("dist_to_ego", "box_dist_to_ego", "distance from ego", "ego_dist", "range").
_EGO_DISTANCE = (
    r"(?:(?:box_?)?dist(?:ance)?(?:_| )?(?:to|from)?(?:_| )?(?:the )?ego(?:_vehicle| vehicle)?"
    r"|ego_?dist(?:ance)?|range_?to_?ego|range)(?:_m)?"
)
_TRUE = r"(?:true|1|yes)"
_FALSE = r"(?:false|0|no)"
_UNITS = {"ms": "m/s", "m_s": "m/s", "mps": "m/s", "kmh": "km/h", "kph": "km/h"}


#: Marks the words of a category test until :func:`filter_wording` puts them first.
_MARK = "\x00"


def _category_words(name: str) -> str:
    """A category name as words, marked: "box_truck" -> "box truck", "'BUS'" -> "bus"."""
    return _MARK + " ".join(name.strip(" '\"").replace("_", " ").split()) + _MARK


def _category_list(match: re.Match[str]) -> str:
    names = [n.strip(" '\"") for n in re.split(r"[,|]| or ", match.group("names"))]
    return _category_words(" or ".join(n for n in names if n))


def _speed(match: re.Match[str]) -> str:
    unit = match.group("unit") or match.group("field_unit") or "m/s"
    unit = _UNITS.get(unit, unit)
    value = match.group("value")
    return {
        ">": f"moving faster than {value} {unit}",
        ">=": f"moving faster than {value} {unit}",
        "<": f"moving slower than {value} {unit}",
        "<=": f"moving slower than {value} {unit}",
    }[match.group("op")]


def _ego_distance(match: re.Match[str]) -> str:
    value = match.group("value")
    if match.group("op") in ("<", "<="):
        return f"within {value} m of the ego vehicle"
    return f"not within {value} m of the ego vehicle"


def _flag(match: re.Match[str]) -> str:
    name = " ".join(match.group("name").split("_"))
    negated = (match.group("op") in ("!=",)) != bool(re.fullmatch(_FALSE, match.group("value")))
    return f"not {name}" if negated else name


def _speed_range(match: re.Match[str]) -> str:
    """A speed range: "5 m/s <= speed <= 10 m/s" -> "moving between 5 and 10 m/s"."""
    unit = match.group("unit2") or match.group("unit") or "m/s"
    return f"moving between {match.group('low')} and {match.group('high')} {_UNITS.get(unit, unit)}"


def _count(match: re.Match[str]) -> str:
    """A count: "count(peds within 15 m) >= 3" -> "with at least 3 peds within 15 m"."""
    least = int(float(match.group("n"))) + (1 if match.group("op") == ">" else 0)
    other = "other " if match.group("other") else ""
    return f"with at least {least} {other}{match.group('who').replace('_', ' ')} within {match.group('d')} m"


_DIRECTIONS = {
    "opposite": "travelling in the opposite direction to",
    "perpendicular": "travelling perpendicular to",
    "same": "travelling in the same direction as",
}
#: A road user named as a function's argument ("facing(ego)", "near(vehicle, dist <= 5 m)").
_ARG = r"\s*(?:vs\.?\s*)?(?P<who>[a-z][a-z_ ]*?)\s*"
#: Function calls and fields of a filter, put in words first: (pattern, replacement).
_CALLS: tuple[tuple[re.Pattern[str], str | Callable[[re.Match[str]], str]], ...] = (
    # comments: "-- jaywalkers", "/* oncoming traffic */", "// ..."
    (re.compile(r"\s*/\*.*?\*/|\s+(?:--|//)\s.*$"), ""),
    (
        re.compile(rf"\b(?:objects|tracks|actors|agents)\s*\(\s*{_CATEGORY_FIELD}\s*=\s*'?any'?\s*\)"),
        "objects",
    ),
    (re.compile(rf"\bfacing\({_ARG}\)"), r"facing \g<who>"),
    (re.compile(rf"\bfollowing\(\s*(?:lead\s*=\s*)?{_ARG}\)"), r"following \g<who>"),
    (re.compile(rf"\bfollowed_by\({_ARG}\)"), r"followed by \g<who>"),
    (re.compile(rf"\b(?:in_)?same_lane(?:_as)?\({_ARG}\)"), r"in the same lane as \g<who>"),
    (
        re.compile(rf"\bcrossed_by\({_ARG}(?:,\s*(?:side|direction)\s*=\s*'?(?:front|forward)'?\s*)?\)"),
        r"being crossed by \g<who>",
    ),
    (
        re.compile(rf"\bnear\({_ARG},\s*(?:dist|distance|d)\s*<=?\s*(?P<d>{_NUMBER})\s*(?:m\b)?\s*\)"),
        r"within \g<d> m of \g<who>",
    ),
    (re.compile(rf"\bnear\({_ARG}\)"), r"near \g<who>"),
    (re.compile(rf"\b(?:moving|heading|driving)_?towards?\({_ARG}\)"), r"heading toward \g<who>"),
    (
        re.compile(
            r"\b(?:travel_?dir(?:ection)?|dir(?:ection)?_?rel|rel(?:ative)?_?dir(?:ection)?|heading_?rel)"
            rf"(?:\s*relative_to)?\s*\({_ARG}\)\s*==?\s*'?(?P<dir>opposite|perpendicular|same)'?"
        ),
        lambda m: f"{_DIRECTIONS[m['dir']]} {m['who']}",
    ),
    (
        re.compile(rf"\broad_?side\({_ARG}\)\s*==?\s*'?(?:opposite|other)'?"),
        r"on the other side of the road from \g<who>",
    ),
    (
        re.compile(
            rf"\bcount\(\s*(?P<other>other )?(?P<who>[a-z][a-z_ ]*?)\s+within\s+(?P<d>{_NUMBER})\s*m\s*\)"
            rf"\s*(?P<op>>=|>)\s*(?P<n>{_NUMBER})"
        ),
        _count,
    ),
    (
        re.compile(
            rf"\bn_(?P<other>other_)?(?P<who>[a-z]+)\(\s*(?:dist|distance|d)\s*<=?\s*(?P<d>{_NUMBER})\s*m?\s*\)"
            rf"\s*(?P<op>>=|>)\s*(?P<n>{_NUMBER})"
        ),
        _count,
    ),
    (
        re.compile(
            r"\blat(?:eral)?_?acc(?:el(?:eration)?)?\s*>=?\s*(?P<n>\d+(?:\.\d+)?)\s*(?:m/s\^?2|m/s²)?\s+or\s+"
            r"lat(?:eral)?_?acc(?:el(?:eration)?)?\s*<=?\s*-(?P=n)\s*(?:m/s\^?2|m/s²)?"
        ),
        r"with a lateral acceleration of more than \g<n> m/s^2 in either direction",
    ),
    (
        re.compile(
            r"\bdist(?:ance)?\(\s*(?:box|self|it)?\s*,?\s*(?:cross_?walk|ped_?crossing)\s*\)\s*(?:==|<=|=)\s*0\s*(?:m\b)?"
        ),
        "on a crosswalk",
    ),
    (re.compile(r"\bnear_intersection\b"), "near an intersection"),
    (
        re.compile(
            r",?\s*(?:angle|heading_?diff|yaw_?diff)\s*<=?\s*(?P<n>\d+(?:\.\d+)?)\s*(?:deg(?:rees)?|°)"
        ),
        r" within \g<n> degrees",
    ),
    (re.compile(r"\s+in\s+(?:direction|dir)\s*==?\s*'?(forward|front|ahead)'?"), " ahead"),
    (re.compile(r"\s+in\s+(?:direction|dir)\s*==?\s*'?(backward|back|behind)'?"), " behind"),
    (re.compile(r"\s+in\s+(?:direction|dir)\s*==?\s*'?(left|right)'?"), r" on its \1"),
    # fields: "turn == right", "turn_dir = 'left'", "lane_change = right", "lane_type == 'BUS'"
    (re.compile(r"\b(?:turn(?:_?dir(?:ection)?)?|turning)\s*==?\s*'?(left|right)'?"), r"turning \1"),
    (
        re.compile(r"\blane_?change(?:_?dir(?:ection)?)?\s*==?\s*'?(left|right)'?"),
        r"changing lanes to the \1",
    ),
    (re.compile(r"\blane_?type\s*==?\s*'?(bus|bike|vehicle)'?"), r"in a \1 lane"),
    # "accel_long <= -2 m/s^2": braking; "accel_long >= 1": accelerating; "lat_accel >= 2": lateral
    (
        re.compile(
            r"\b(?:accel(?:eration)?_?long(?:itudinal)?|long(?:itudinal)?_?accel(?:eration)?|accel(?:eration)?|a_x)"
            rf"\s*<=?\s*-(?P<n>{_NUMBER})\s*(?:m/s\^?2|m/s²)?"
        ),
        r"braking harder than \g<n> m/s^2",
    ),
    (
        re.compile(
            r"\b(?:with )?(?:accel(?:eration)?_?long(?:itudinal)?|long(?:itudinal)?_?accel(?:eration)?|a_x)"
            rf"\s*>=?\s*(?P<n>{_NUMBER})\s*(?:m/s\^?2|m/s²)?"
        ),
        r"accelerating more than \g<n> m/s^2",
    ),
    (
        re.compile(
            rf"\b(?:with )?(?:\|\s*)?lat(?:eral)?_?acc(?:el(?:eration)?)?\s*\|?\s*>=?\s*(?P<n>{_NUMBER})\s*"
            r"(?:m/s\^?2|m/s²)?"
        ),
        r"with lateral acceleration more than \g<n> m/s^2",
    ),
    # "5 m/s <= speed <= 10 m/s": between
    (
        re.compile(
            rf"\b(?P<low>{_NUMBER})\s*(?:{_SPEED_UNIT})?\s*<=?\s*{_SPEED_FIELD}\s*<=?\s*(?P<high>{_NUMBER})\s*"
            rf"(?P<unit2>m/s|mps|km/h|kmh|kph|mph)?"
        ),
        _speed_range,
    ),
    (
        re.compile(rf"\bdist(?:ance)?_?to_?(?:the_?)?intersection\s*<=?\s*(?P<d>{_NUMBER})\s*(?:m\b)?"),
        r"within \g<d> m of an intersection",
    ),
)

#: (pattern, replacement), applied in order to the lower-cased text.
_REWRITES: tuple[tuple[re.Pattern[str], str | Callable[[re.Match[str]], str]], ...] = (
    # a query's head: "SELECT * FROM tracks WHERE ...", "filter: ...", "WHERE ..."
    (re.compile(r"^select\b.*?\bwhere\s+"), ""),
    (re.compile(r"^(?:filter|query)\s*:\s*|^where\s+(?=.*(?:[<>=!&|]|[a-z]_[a-z]))"), ""),
    (re.compile(r"\s*&&\s*"), " and "),
    (re.compile(r"\s*\|\|\s*"), " or "),
    (re.compile(r"(?<![\w!])!\s*(?=[a-z_(])"), "not "),
    # "category IN (BUS, BOX_TRUCK)": the categories joined by "or"
    (re.compile(rf"\b{_CATEGORY_FIELD}\s+in\s*[(\[{{](?P<names>[^)\]}}]*)[)\]}}]"), _category_list),
    # "category == BOX_TRUCK", "class: bus", "type = 'PEDESTRIAN'": the category
    (
        re.compile(rf"\b{_CATEGORY_FIELD}\s*(?:==|=|:|\bis\b)\s*(?P<name>['\"]?[a-z][a-z_]*['\"]?)"),
        lambda m: _category_words(m.group("name")),
    ),
    (
        re.compile(rf"\b{_CATEGORY_FIELD}\s*!=\s*(?P<name>['\"]?[a-z][a-z_]*['\"]?)"),
        lambda m: "not " + _category_words(m.group("name")).strip(_MARK),
    ),
    # "speed_mps > 10", "v >= 5 m/s", "velocity < 2 mph"
    (
        re.compile(rf"\b{_SPEED_FIELD}\s*(?P<op><=|>=|<|>)\s*(?P<value>{_NUMBER})\s*{_SPEED_UNIT}?(?![\w/])"),
        _speed,
    ),
    # "dist_to_ego < 15 m", "distance to ego <= 20"
    (
        re.compile(
            rf"\b{_EGO_DISTANCE}\s*(?P<op><=|>=|<|>)\s*(?P<value>{_NUMBER})\s*(?:m|metres?|meters?)?\b"
        ),
        _ego_distance,
    ),
    # "speed == 0": at rest (before the flags, where "= 0" means false)
    (re.compile(rf"\b{_SPEED_FIELD}\s*==?\s*0(?:\.0+)?\s*(?:m/s|mps|km/h|kmh|kph|mph)?(?![\w.])"), "stopped"),
    # flags: "is_parked = true", "on_intersection == false", "in_drivable_area != 1"
    (
        re.compile(
            rf"\b(?:is_)?(?P<name>[a-z]+(?:_[a-z]+)*)\s*(?P<op>==|!=|=)\s*(?P<value>{_TRUE}|{_FALSE})\b"
        ),
        _flag,
    ),
    (re.compile(r"\bis_(?=[a-z])"), ""),
    (re.compile(r"\blane_?change_?(left|right)\b"), r"changing lanes to the \1"),
)
#: Text written as a filter: an operator, a field or function name with an underscore or a bracket.
_SYNTAX = re.compile(r"[<>]=?|[!=]=|(?<![\w-])[a-z]+_[a-z_]+\b|\b[a-z_]+\(|&&|\|\|")
#: In a filter only: what is left of its syntax once its fields are words (in order).
_CLEANUP: tuple[tuple[re.Pattern[str], str], ...] = (
    # a gloss in brackets ("(hard braking)", "(jogging/running)", "(e.g. lots/driveways)")
    (re.compile(r"(?<=\S)\s*\((?:e\.g\.|i\.e\.)?[^()<>=\d]*\)"), ""),
    (re.compile(rf"\b(?:box_?)?dist(?:ance)?\s*<=?\s*(?P<d>{_NUMBER})\s*(?:m\b)?"), r"within \g<d> m"),
    (re.compile(r"(?<!the )(?<!its )\b(?:located |positioned )?(left|right) of\b"), r"to the \1 of"),
    (re.compile(r"\bon (?:the )?(left|right)(?:[- ]hand)? side\b"), r"on its \1"),
    (re.compile(r"\s+\|\s+"), " and "),
    (re.compile(r"\bwith (?=moving (?:faster|slower|between)\b)"), ""),
    (
        re.compile(rf"\s(?:where|such that|s\.t\.|:)\s+(?=(?:an?\s|another\s|\d+\s)?(?:{NOUN})(?![\w-]))"),
        " with ",
    ),
    (re.compile(r"\s(?:where|such that|s\.t\.)\s+"), " "),
    (re.compile(r"^(\S[^,]*?)\s*,\s*(?=within \d)"), r"\1 "),
    (re.compile(r"\s*,?\s+and (?=within \d)"), " "),
    (re.compile(r"\s+and\s*$"), ""),
)
#: A category test after other conditions ("speed > 10 and category == bus").
_LATE_CATEGORY = re.compile(rf"{_MARK}(?P<category>[^{_MARK}]*){_MARK}")
_JOINT = re.compile(r"^(?:\s*(?:,|and)\s*)+|(?:\s*(?:,|and)\s*)+$")


_LATERAL = re.compile(
    rf",?\s*(?:and\s+)?\blat(?:eral)?(?:_?(?:dist(?:ance)?|offset|gap))?\s*<=?\s*(?P<n>{_NUMBER})\s*(?:m\b)?"
)
_SIDEWAYS = re.compile(r"\b(?=behind\b|ahead\b|in front\b|on its (?:left|right)\b|to its (?:left|right)\b)")


def _lateral(text: str) -> str:
    """A lateral bound of 1 m ("lateral <= 1 m") as "directly" before the direction it bounds."""
    found = _LATERAL.search(text)
    if found is None:
        return text
    text = text[: found.start()] + text[found.end() :]
    if float(found.group("n")) == 1:
        text = _SIDEWAYS.sub("directly ", text, count=1)
    return text


def filter_wording(text: str) -> str:
    """``text`` (lower case) with its filter syntax put in words; other text unchanged."""
    if _SYNTAX.search(text) is None:
        return text
    for pattern, replacement in (*_CALLS, *_REWRITES, *_CLEANUP):
        text = pattern.sub(replacement, text)
    text = _lateral(text)
    # the road user first, as a sentence names it ("bus and moving faster than 10 m/s")
    late = _LATE_CATEGORY.search(text)
    if late and late.start() > 0 and not text[: late.start()].rstrip().endswith("not"):
        rest = [_JOINT.sub("", part) for part in (text[: late.start()], text[late.end() :])]
        text = " and ".join([late.group("category"), *(part for part in rest if part.strip())])
    return " ".join(text.replace(_MARK, " ").split())
