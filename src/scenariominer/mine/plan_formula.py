"""A spreadsheet formula over a table of tracked objects, put in the plain words the phrase rules read.

Analysts who live in spreadsheets write a search as the formula they would type over a table with
one row per tracked object: ``=FILTER(Tracks, Tracks[category]='BUS', Tracks[turn]='left')`` or
``=COUNTIFS(category, 'PEDESTRIAN', dist_to_ego_m, '<5')``. :func:`spreadsheet_formula` reads the
tests of such a formula as conditions on one road user:

- ``FILTER(range, test, ...)`` (tests joined by ``AND(...)`` or multiplied, ``(a)*(b)``, as Excel
  combines them; a text argument such as an if-empty message is skipped), ``COUNTIF``/``COUNTIFS``
  (range and criterion pairs, a criterion may carry its comparison: ``'<5'``, ``'<>BUS'``),
  ``UNIQUE``/``ROWS``/``COUNTA``/``SORT`` around them, and ``NOT(test)``; Google Sheets'
  ``QUERY(range, "select * where ...")`` gives its query text to the reader of filters;
- a column is named by itself, as ``Table[column]`` or ``Table[@column]``; the category column
  (``category``, ``class``, ``type``, ...) names the road user; speed and acceleration columns are
  bounds (their unit from the name, ``speed_kmh``); a distance column names what it is measured to
  (``dist_to_ego_m < 5``: within 5 m of the ego vehicle); a count column names what it counts and
  within what distance (``pedestrians_within_20m >= 3``); a flag column (``is_parked = TRUE``,
  ``in_intersection = 1``) is a state, and ``turn``, ``lane_change``, ``lane_type`` and ``status``
  columns name the turn, the lane change, the kind of lane and the state.

A formula with alternatives (``OR``, ``+``), cell ranges in place of column names, or a column
this reading does not know comes back unchanged, for the other readers (and the language model).
"""

from __future__ import annotations

import re
from typing import NamedTuple

from scenariominer.mine.plan_graph import (
    GraphQuery,
    Unreadable,
    label_phrase,
    node_label,
    property_words,
    query_words,
    relationship_words,
    top_level_split,
)
from scenariominer.mine.plan_logic import state_words
from scenariominer.mine.plan_nouns import singular

__all__ = ["spreadsheet_formula"]

_FORMULA = re.compile(r"^\s*=\s*(?P<body>[A-Za-z]+\s*\(.*\))\s*;?\s*$", re.DOTALL)
_CALL = re.compile(r"^(?P<name>[A-Za-z][\w.]*)\s*\((?P<args>.*)\)$", re.DOTALL)
_NUMBER = r"-?\d+(?:\.\d+)?"
_COLUMN = r"(?:[A-Za-z_]\w*\s*)?\[@?\s*(?P<bracketed>[^\[\]]+?)\s*\]|(?P<bare>[A-Za-z_][\w.]*)"
_TEST = re.compile(
    rf"^(?:{_COLUMN})\s*(?P<op><>|>=|<=|=|>|<)\s*(?P<value>'[^']*'|\"[^\"]*\"|{_NUMBER}|true|false)$",
    re.IGNORECASE,
)
#: The size of a column's value either way ("ABS(Tracks[lat_accel_mps2]) >= 2").
_ABSOLUTE = re.compile(
    rf"^abs\s*\(\s*(?:{_COLUMN})\s*\)\s*(?P<op>>=|<=|>|<)\s*(?P<value>{_NUMBER})$", re.IGNORECASE
)
#: A criterion of COUNTIF(S): an optional comparison and its value ("<5", "<>BUS", "BUS").
_CRITERION = re.compile(r"^(?P<op><>|>=|<=|=|>|<)?\s*(?P<value>.*)$", re.DOTALL)
#: Functions around the one that tests, read as the set they wrap.
_WRAPPERS = frozenset({"unique", "rows", "counta", "count", "sort", "sortby", "take", "iferror", "index"})
_CATEGORY_COLUMNS = re.compile(
    r"^(?:object_|agent_|actor_|track_)?(?:category|class|type|kind|label|cat)(?:_name|_group)?$|^group$",
    re.IGNORECASE,
)


class _Test(NamedTuple):
    """One test of a formula: a column compared with a value, or a count of other rows (``inner``)."""

    column: str
    op: str
    value: str
    inner: tuple[_Test, ...] = ()


#: A count of other rows compared with a number ("COUNTIFS(category, 'PEDESTRIAN', ...) >= 2").
_COUNTED = re.compile(
    r"^(?P<call>countifs?\s*\(.*\))\s*(?P<op>>=|>)\s*(?P<n>\d+)$", re.IGNORECASE | re.DOTALL
)


def spreadsheet_formula(description: str) -> str:
    """``description`` as plain words when it is a spreadsheet formula over tracked objects, else as is."""
    found = _FORMULA.match(description)
    if found is None:
        return description
    sql = re.match(r"^query\s*\(\s*[^,()]+,\s*(?P<q>'[^']*'|\"[^\"]*\")", found.group("body"), re.IGNORECASE)
    if sql is not None:
        return _unquoted(sql.group("q"))  # Google Sheets' QUERY: its SQL-like text, for the filter reader
    query = GraphQuery(labels={})
    try:
        for test in _tests(found.group("body").strip()):
            _read_test(test, query)
        query.labels.setdefault("x", "object")
        return query_words(query, "x")
    except Unreadable:
        return description


def _tests(expression: str) -> list[_Test]:
    """The tests of a formula; ``NOT`` flips the comparison."""
    expression = expression.strip()
    while _wrapped(expression):
        expression = expression[1:-1].strip()
    if (absolute := _ABSOLUTE.match(expression)) is not None:
        column = absolute.group("bracketed") or absolute.group("bare")
        value = _unquoted(absolute.group("value"))
        return [_Test(f"abs_{column.strip().split('.')[-1]}", absolute.group("op"), value)]
    if (counted := _COUNTED.match(expression)) is not None:
        return [_Test("", counted.group("op"), counted.group("n"), tuple(_tests(counted.group("call"))))]
    call = _CALL.match(expression)
    if call is None:
        if (test := _TEST.match(expression)) is not None:
            column = test.group("bracketed") or test.group("bare")
            return [_Test(column.strip().split(".")[-1], test.group("op"), _unquoted(test.group("value")))]
        products = top_level_split(expression, "*")
        if len(products) > 1:
            return [t for part in products for t in _tests(part)]
        if (flag := re.fullmatch(_COLUMN, expression)) is not None:
            # a column of flags on its own: its rows that are TRUE ("Tracks[on_crosswalk]")
            return [_Test((flag.group("bracketed") or flag.group("bare")).split(".")[-1], "=", "true")]
        raise Unreadable(expression)
    name, args = call.group("name").lower(), [a.strip() for a in top_level_split(call.group("args"), ",")]
    if name in _WRAPPERS:
        return [t for a in args[:1] for t in _tests(a)]
    if name == "and":
        return [t for a in args for t in _tests(a)]
    if name == "not" and len(args) == 1:
        flipped = {"=": "<>", "<>": "=", ">": "<=", "<=": ">", "<": ">=", ">=": "<"}
        tests = _tests(args[0])
        if any(t.inner for t in tests):
            raise Unreadable("a negated count")
        return [t._replace(op=flipped[t.op]) for t in tests]
    if name == "filter" and len(args) >= 2:
        # the first argument is the table; a text argument is a message for no match
        return [t for a in args[1:] if not re.fullmatch(r"'[^']*'|\"[^\"]*\"", a) for t in _tests(a)]
    if name in ("countif", "countifs") and len(args) >= 2 and len(args) % 2 == 0:
        tests = []
        for column, criterion in zip(args[::2], args[1::2], strict=True):
            named = re.fullmatch(_COLUMN, column)
            crit = _CRITERION.match(_unquoted(criterion))
            if named is None or crit is None or not crit.group("value"):
                raise Unreadable(f"{column}, {criterion}")
            column_name = (named.group("bracketed") or named.group("bare")).split(".")[-1]
            tests.append(_Test(column_name, crit.group("op") or "=", crit.group("value").strip()))
        return tests
    raise Unreadable(name)


def _wrapped(expression: str) -> bool:
    """Whether one pair of brackets encloses the whole of ``expression`` ("(a)" yes, "(a)*(b)" no)."""
    depth = 0
    for at, ch in enumerate(expression):
        depth += {"(": 1, ")": -1}.get(ch, 0)
        if depth == 0:
            return at == len(expression) - 1 and at > 0
    return False


def _unquoted(value: str) -> str:
    value = value.strip()
    return value[1:-1] if len(value) > 1 and value[0] == value[-1] and value[0] in "'\"" else value


def _read_test(test: _Test, query: GraphQuery) -> None:
    """One test of a column into ``query`` (the road user found is ``x``)."""
    if test.inner:
        _read_count(test, query)
        return
    column, op = test.column, test.op
    key = re.sub(r"[\s()/]+", "_", column.strip().lower()).strip("_")
    value = test.value.lower()
    truth = {"true": True, "1": True, "yes": True, "false": False, "0": False, "no": False}.get(value)
    if re.fullmatch(r"[a-z]{1,2}\d*(?::[a-z]{1,2}\d*)?", key):
        raise Unreadable(f"a cell range: {column}")
    if _CATEGORY_COLUMNS.match(key):
        label = "object" if value in ("any", "all", "*") else node_label(value)
        if label is None or op != "=" or "x" in query.labels:
            raise Unreadable(f"{column} {op} {value}")
        query.labels["x"] = label
        return
    if (counted := _count_column(key)) is not None:
        if op not in (">=", ">") or not re.fullmatch(r"\d+", value):
            raise Unreadable(f"{column} {op} {value}")
        label, distance = counted
        var = f"_n{len(query.edges)}"
        query.labels[var] = label
        query.counts[var] = int(value) + (1 if op == ">" else 0)
        query.edges.append(("x", "near", distance, var, False))
        return
    if (target := _distance_target(key)) is not None:
        _read_distance(target, op, value, query)
        return
    if re.fullmatch(r"lane(?:_type|_kind)?", key) and op == "=":
        query.conditions.append(("x", state_words("lane_type", value, negated=False)))
        return
    if (related := _related_column(key, value)) is not None and op == "=":
        words, label = related
        var = f"_r{len(query.edges)}"
        query.labels[var] = label
        query.edges.append(("x", words, None, var, False))
        return
    if (where := _relative_position(key, value)) is not None and op == "=":
        words, target = where
        var = f"_{target}"
        query.labels[var] = target
        query.edges.append(("x", words, None, var, False))
        return
    flag_of = re.fullmatch(r"(?:is_)?(?P<rel>[a-z_]+?)_(?P<who>ego|ego_vehicle|av|sdc)", key)
    if flag_of is not None and truth is not None and op in ("=", "<>"):
        # "same_lane_as_ego = TRUE": a relation with the ego vehicle
        words, _ = relationship_words(flag_of.group("rel"), None)
        var = "_ego"
        query.labels[var] = "ego"
        query.edges.append(("x", words, None, var, truth != (op == "=")))
        return
    if truth is not None and op in ("=", "<>"):
        query.conditions.append(("x", state_words(key, None, negated=truth != (op == "="))))
        return
    if re.fullmatch(r"(?:turn|turning|turn_dir(?:ection)?|maneuver|manoeuvre|action)", key) and op == "=":
        side = re.search(r"\b(left|right)\b", value.replace("_", " "))
        if side is not None and "lane" in value:
            query.conditions.append(("x", f"changing lanes to the {side.group(1)}"))
            return
        if side is not None:
            query.conditions.append(("x", f"turning {side.group(1)}"))
            return
    query.conditions.append(("x", _measure_words(key, op, value)))


def _read_distance(target: str, op: str, value: str, query: GraphQuery) -> None:
    """A distance column's test: within that many metres of ``target`` (0: on or in a place)."""
    if op in (">", ">=") and re.fullmatch(_NUMBER, value):
        # "NOT(dist_to_crosswalk_m <= 1)": not within 1 m of a crosswalk
        query.conditions.append(("x", f"not within {value} m of {label_phrase(target)}"))
        return
    var = f"_{target}"  # one node per kind named: a distance and a position to it are one relation
    query.labels[var] = target
    if op in ("=", "<=") and value == "0" and target in ("crosswalk", "intersection", "drivablearea"):
        query.edges.append(("x", "on", None, var, False))  # "dist_to_crosswalk_m = 0": on it
        return
    if op not in ("<", "<=") or not re.fullmatch(_NUMBER, value):
        raise Unreadable(f"distance {op} {value}")
    query.edges.append(("x", "within", value, var, False))


def _measure_words(key: str, op: str, value: str) -> str:
    """A speed or acceleration column's test in words; an ``abs_`` column either way."""
    key = re.sub(r"^(?P<abs>abs_)?(?:long|lon|longitudinal|fwd|forward)_", r"\g<abs>", key)
    lateral = re.fullmatch(r"(?P<abs>abs_)?(?:lat|lateral|side|sideways)_?(?:accel|acceleration|acc)\w*", key)
    if lateral is not None:
        if not lateral.group("abs") or op not in (">", ">=") or not re.fullmatch(_NUMBER, value):
            raise Unreadable(f"{key} {op} {value}")
        return f"with lateral acceleration above {value} m/s^2"  # the phrase rules: either side
    return property_words(key, op if op != "<>" else "!=", value)


def _read_count(test: _Test, query: GraphQuery) -> None:
    """``COUNTIFS(category, 'PEDESTRIAN', position, 'ahead', gap_m, '<=15') >= 1``: other road users.

    The counted rows name their kind, where they are from the road user found and how far; one
    or more of them is a relation with one, more a count.
    """
    label, where, distance = None, "near", None
    for inner in test.inner:
        key = re.sub(r"[\s()/]+", "_", inner.column.strip().lower()).strip("_")
        value = inner.value.lower()
        if _CATEGORY_COLUMNS.match(key) and inner.op == "=" and label is None:
            label = node_label(value)
        elif (position := _relative_position(key, value)) is not None and inner.op == "=":
            where = {"ahead of": "has ahead", "in front of": "has ahead", "behind": "has behind"}.get(
                position[0], f"has {position[0].removeprefix('to the ').removesuffix(' of')}"
            )
        elif re.search(r"(?:^|_)(?:dist|distance|gap|range)(?:_|$)", key) and inner.op in ("<", "<="):
            distance = inner.value if re.fullmatch(_NUMBER, inner.value) else None
            if distance is None:
                raise Unreadable(inner.value)
        else:
            raise Unreadable(f"{inner.column} {inner.op} {inner.value}")
    if label is None:
        raise Unreadable("a count of rows of no kind")
    least = int(test.value) + (1 if test.op == ">" else 0)
    var = f"_n{len(query.edges)}"
    query.labels[var] = label
    if least > 1:
        query.counts[var] = least
    query.edges.append(("x", where, distance, var, False))


#: Columns naming the kind of another road user the row's one relates to, with the relation.
_KIND = r"_(?:vehicle_|object_|agent_)?(?:category|class|type)"
_RELATED_COLUMNS = (
    (re.compile(rf"(?:lead|leader|leading|front|preceding){_KIND}"), "following"),
    (re.compile(rf"(?:followed_by|follower|following|trailing){_KIND}"), "being followed by"),
)


def _related_column(key: str, value: str) -> tuple[str, str] | None:
    """A column naming another road user's kind: the relation's words and that kind's label.

    "lead_vehicle_category = 'BUS'": following a bus. Also the side of the road relative to the
    ego vehicle ("road_side_vs_ego = 'opposite'").
    """
    side = re.fullmatch(r"(?:road_)?side(?:_of_road)?(?:_(?:vs|rel|relative|to|wrt|as))*_ego", key)
    if side is not None and value in ("same", "opposite"):
        same = value == "same"
        return ("on the same side of the road as" if same else "on the opposite side of the road from"), "ego"
    travel = re.fullmatch(
        r"(?:travel|heading|moving|motion|driving)_?(?:dir|direction)(?:_(?:vs|rel|relative|to|wrt|as))*_ego",
        key,
    )
    if travel is not None and value in ("same", "opposite", "perpendicular"):
        return relationship_words("travelling", f"{{direction: '{value}'}}")[0], "ego"
    label = node_label(value)
    if label is None:
        return None
    for pattern, words in _RELATED_COLUMNS:
        if pattern.fullmatch(key):
            return words, label
    # "moving_toward_category = 'PEDESTRIAN'": the relation named before the kind
    named = re.fullmatch(rf"(?P<rel>[a-z_]+?){_KIND}", key)
    if named is not None and not _CATEGORY_COLUMNS.match(key):
        return relationship_words(named.group("rel"), None)[0], label
    return None


#: Where a road user is, seen from another, as the phrase before that other one.
_POSITIONS = {
    "ahead": "ahead of",
    "front": "in front of",
    "in_front": "in front of",
    "behind": "behind",
    "rear": "behind",
    "left": "to the left of",
    "right": "to the right of",
}


def _relative_position(key: str, value: str) -> tuple[str, str] | None:
    """A column of where a road user is relative to another (``relative_position = 'ahead'``).

    Returns the relation's words and the other one's label (the ego vehicle unless the column
    names another), or ``None``.
    """
    found = re.fullmatch(
        r"(?:rel(?:ative)?_)?(?:position|pos|side|location|direction|dir|bearing)"
        r"(?:_(?:rel|relative|to|from|wrt|vs|of))*(?:_(?P<target>[a-z_]+))?",
        key,
    )
    words = _POSITIONS.get(value.replace(" ", "_").removeprefix("in_").removesuffix("_of"))
    if found is None or words is None:
        return None
    target = node_label(found.group("target") or "ego")
    return (words, target) if target is not None else None


def _count_column(key: str) -> tuple[str, str | None] | None:
    """A column counting road users: (their label, the distance it counts within) or ``None``.

    "pedestrians_within_20m" -> ("pedestrian", "20"), "num_peds_nearby" -> ("ped", None).
    """
    found = re.fullmatch(
        r"(?:n|num|number|count|nr)_(?:of_)?(?P<a>[a-z_]+?)(?:_(?:nearby|near|close))?(?:_(?:within|in|lt)_?(?P<d1>\d+)_?m)?"
        r"|(?P<b>[a-z_]+?)_(?:within|in|lt)_?(?P<d2>\d+)_?m(?:_(?:count|n|num))?"
        r"|(?P<c>[a-z_]+?)_(?:nearby_)?count(?:_(?:within|in|lt)_?(?P<d3>\d+)_?m)?",
        key,
    )
    if found is None:
        return None
    words = found.group("a") or found.group("b") or found.group("c")
    label = node_label(" ".join(singular(w) for w in words.split("_")))
    if label is None:
        return None
    return label, found.group("d1") or found.group("d2") or found.group("d3")


def _distance_target(key: str) -> str | None:
    """The label a distance column is measured to ("dist_to_ego_m" -> "ego"), else ``None``."""
    if not re.search(r"(?:^|_)(?:dist|distance|range|gap)(?:_|$)", key):
        return None
    words = [
        w
        for w in key.split("_")
        if w
        not in ("dist", "distance", "range", "gap", "m", "to", "from", "nearest", "closest", "the", "min")
    ]
    return node_label(" ".join(singular(w) for w in words)) if words else None
