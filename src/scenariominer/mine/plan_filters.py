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

__all__ = ["filter_wording"]

_NUMBER = r"\d+(?:\.\d+)?"
#: The field that holds a track's category.
_CATEGORY_FIELD = r"(?:category|class|object_?class|object_?type|obj_?type|type|label|cat)"
#: A speed field; a unit in its name ("speed_mps", "v_kmh") is kept.
_SPEED_FIELD = r"(?:abs_?)?(?:speed|velocity|vel|v)(?:_(?P<field_unit>mps|ms|m_s|kmh|kph|mph))?"
_SPEED_UNIT = r"(?P<unit>m/s|mps|km/h|kmh|kph|mph)"
#: A distance to the ego vehicle ("dist_to_ego", "distance from ego", "ego_dist", "range").
_EGO_DISTANCE = (
    r"(?:dist(?:ance)?(?:_| )?(?:to|from)?(?:_| )?(?:the )?ego(?:_vehicle| vehicle)?"
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
#: A category test after other conditions ("speed > 10 and category == bus").
_LATE_CATEGORY = re.compile(rf"{_MARK}(?P<category>[^{_MARK}]*){_MARK}")
_JOINT = re.compile(r"^(?:\s*(?:,|and)\s*)+|(?:\s*(?:,|and)\s*)+$")


def filter_wording(text: str) -> str:
    """``text`` (lower case) with its filter syntax put in words; other text unchanged."""
    for pattern, replacement in _REWRITES:
        text = pattern.sub(replacement, text)
    # the road user first, as a sentence names it ("bus and moving faster than 10 m/s")
    late = _LATE_CATEGORY.search(text)
    if late and late.start() > 0 and not text[: late.start()].rstrip().endswith("not"):
        rest = [_JOINT.sub("", part) for part in (text[: late.start()], text[late.end() :])]
        text = " and ".join([late.group("category"), *(part for part in rest if part.strip())])
    return " ".join(text.replace(_MARK, " ").split())
