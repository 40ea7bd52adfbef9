r"""A logic-programming rule (Prolog or Datalog style), put in the plain words the phrase rules read.

Some users state a scenario as a rule: ``find(X) :- bus(X), turning(X, left).`` The head names
the road user to find (its first variable; a time variable such as ``T`` beside it is ignored),
and the body is a conjunction of goals over variables (upper case) and constants (lower case):

- a category goal gives a variable its kind: ``bus(X)``, ``box_truck(X)``, ``ego(E)``, also
  ``category(X, bus)`` / ``type(X, 'BUS')`` / ``is_a(X, pedestrian)``; a constant that names a road
  user or a place stands for one (``ahead_of(X, ego)``, ``on(X, crosswalk)``);
- a goal on one road user is a state or an action: ``parked(X)``, ``turning(X, left)``,
  ``changing_lanes(X, right)``, ``in_intersection(X)``;
- a goal on two is a relation, read as words the way a graph relationship is
  (:func:`scenariominer.mine.plan_graph.relationship_words`): ``follows(X, Y)`` -> "following",
  ``crossing_in_front_of(P, V)``, ``same_lane(X, Y)``; a number after them is the distance
  (``near(X, Y, 10)``);
- a measured value is bound and compared: ``speed(X, S), S > 10``, ``accel(X, A), A < -2``,
  ``distance(X, P, D), D < 5``; a count: ``count(P, (pedestrian(P), near(E, P)), N), N >= 3``
  (also ``aggregate_all(count, ..., N)``);
- ``\+ goal``, ``not goal`` and ``not(goal)`` negate one goal.

The rule is turned into the same structure a graph pattern query is
(:class:`scenariominer.mine.plan_graph.GraphQuery`) and worded the same way, so both registers
read alike. A rule with alternatives (``;``), a goal this reading does not know, or a condition on
another road user than the one found comes back unchanged, for the other readers (and the
language model) to read.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field

from scenariominer.mine.plan_graph import (
    GraphQuery,
    Unreadable,
    distance_test,
    label_phrase,
    node_label,
    property_words,
    query_words,
    relationship_words,
    top_level_split,
)

__all__ = ["logic_rule", "state_words"]

_RULE = re.compile(
    r"^\s*(?:(?P<head>[a-z]\w*)\s*\((?P<args>[^()]*)\)\s*(?::-|<-|←)|\?-)\s*(?P<body>.+?)\s*\.?\s*$",
    re.DOTALL,
)
_GOAL = re.compile(r"^(?P<name>[a-z]\w*)\s*(?:\((?P<args>.*)\))?$", re.DOTALL)
_NEGATION = re.compile(r"^(?:\\\+|not\b|~|¬)\s*(?P<goal>.+)$", re.DOTALL)
_NUMBER = r"-?\d+(?:\.\d+)?"
_OPERAND = rf"(?:[A-Z_]\w*|{_NUMBER})"
_COMPARISON = re.compile(
    rf"^(?P<left>{_OPERAND})\s*(?P<op>>=|=<|<=|=:=|==|\\=|!=|>|<|=)\s*(?P<right>{_OPERAND})$"
)
#: A comparison with its sides swapped ("10 > D" is "D < 10").
_FLIPPED = {">": "<", "<": ">", ">=": "<=", "<=": ">=", "=": "=", "!=": "!="}
#: Goals that give their first variable a kind by a second, constant argument ("type(X, bus)").
_KIND_GOALS = frozenset(
    {
        "category",
        "type",
        "class",
        "kind",
        "isa",
        "is_a",
        "is",
        "label",
        "object_type",
        "cat",
        "has_category",
        "has_type",
    }
)
#: Goals that only say a variable is some road user or some time ("object(X)", "timestamp(T)").
_ANY_GOALS = frozenset(
    {"object", "obj", "track", "agent", "actor", "entity", "road_user", "roaduser", "thing"}
)
_TIME_GOALS = frozenset({"time", "timestamp", "frame", "t", "at_time", "moment", "tick"})
#: Names a variable of time usually has.
_TIME_NAME = re.compile(r"^(?:T\d*|Ts|Time\w*|Timestamp\w*|Frame\w*|Tick)$")
#: Goals that bind a measured value of one road user ("speed(X, S)").
_VALUE_GOALS = re.compile(
    r"^(?:abs_?)?(?:(?:long|lon|longitudinal|forward)_)?(?:speed|velocity|vel|accel|acceleration|acc)(?:_\w+)?$"
)
#: Goals that bind the distance between two ("distance(X, Y, D)").
_DISTANCE_GOALS = re.compile(r"^(?:dist|distance|euclidean_distance|range)(?:_to|_between|_m)?$")
_COUNT_GOALS = frozenset({"count", "aggregate_all"})
#: Goals naming the kind of lane a road user is in ("lane_type(X, bus)", "in_lane(X, bike_lane)").
_LANE_GOAL = re.compile(r"(?:(?:on|in|at)_?)?lane(?:_type|_kind)?(?:_(?:at|of|is))?")
#: Relation names that mean a phrase the graph wording knows ("within_distance(X, Y, 10)").
_RELATION_WORDS = {
    "within distance": "within",
    "within dist": "within",
    "within range": "within",
    "in range of": "within",
    "distance less than": "within",
    "nearby": "near",
    "is near": "near",
    "crossing": "crossing in front of",
    "crossing in front": "crossing in front of",
    "ahead": "ahead of",
    "in front": "in front of",
    "crossing path of": "crossing in front of",
}
#: Map features a state goal names without an article ("in_intersection" -> "in an intersection").
_PLACES = {
    "intersection": "an intersection",
    "junction": "an intersection",
    "crosswalk": "a crosswalk",
    "pedestrian crossing": "a crosswalk",
    "road": "the road",
    "drivable area": "the drivable area",
    "bus lane": "a bus lane",
    "bike lane": "a bike lane",
}


@dataclass
class _Rule:
    query: GraphQuery = field(default_factory=GraphQuery)
    #: value variable -> (road user, measured property) or ("count", counted variable)
    values: dict[str, tuple[str, str]] = field(default_factory=dict)
    time: set[str] = field(default_factory=set)
    #: variables only said to be some road user ("object(X)")
    generic: set[str] = field(default_factory=set)
    constants: int = 0


def logic_rule(description: str) -> str:
    """``description`` as plain words when it is a logic-programming rule, else unchanged."""
    found = _RULE.match(description)
    if found is None or ";" in found.group("body"):
        return description
    rule = _Rule()
    try:
        goals = top_level_split(found.group("body"), ",")
        rule.time = _time_variables(found.group("args") or "", goals)
        for goal in goals:
            _read_goal(goal.strip(), rule, negated=False)
        returned = _returned(found.group("args"), goals, rule)
        for var in rule.generic:
            rule.query.labels.setdefault(var, "object")
        return query_words(rule.query, returned)
    except Unreadable:
        return description


def _is_variable(arg: str) -> bool:
    return re.fullmatch(r"[A-Z_]\w*", arg) is not None


def _time_variables(head_args: str, goals: list[str]) -> set[str]:
    """Variables of time: bound by a time goal, or named like one and given no kind."""
    time: set[str] = set()
    for goal in goals:
        found = _GOAL.match(goal.strip())
        if found and found.group("name") in _TIME_GOALS and found.group("args"):
            time |= {a.strip() for a in found.group("args").split(",") if _is_variable(a.strip())}
    kinded = {
        found.group("args").strip()
        for goal in goals
        if (found := _GOAL.match(goal.strip())) and found.group("args") and node_label(found.group("name"))
    }
    names = re.findall(r"\b[A-Z]\w*\b", " ".join([head_args, *goals]))
    return time | {name for name in names if _TIME_NAME.match(name) and name not in kinded}


def _arguments(args: str | None, rule: _Rule) -> list[str]:
    """A goal's arguments, time variables left out, quotes taken off constants."""
    if not args:
        return []
    out = [a.strip() for a in top_level_split(args, ",")]
    # time variables and anonymous ones ("_", "_Dir": any value) say nothing of the road user
    return [
        a.strip("'\"") if a[:1] in "'\"" else a for a in out if a not in rule.time and not a.startswith("_")
    ]


def _returned(head_args: str | None, goals: list[str], rule: _Rule) -> str:
    """The variable the rule finds: the head's first (not of time), else the first goal's."""
    if head_args is not None:
        candidates = [a.strip() for a in head_args.split(",") if _is_variable(a.strip())]
    else:
        first = _GOAL.match(goals[0].strip())
        candidates = [a.strip() for a in (first.group("args") or "").split(",")] if first else []
    for var in candidates:
        if var not in rule.time and var != "_":
            return var
    raise Unreadable("no road user to find")


def _node(arg: str, rule: _Rule) -> str:
    """A goal's argument as a node: a variable, or a constant that names a road user or place."""
    if _is_variable(arg):
        return arg
    label = node_label(arg)
    if label is None:
        raise Unreadable(f"not a road user or place: {arg}")
    rule.constants += 1
    var = f"_c{rule.constants}"
    rule.query.labels[var] = label
    return var


def _read_goal(goal: str, rule: _Rule, *, negated: bool) -> None:
    """One goal of the body into ``rule``."""
    query = rule.query
    while (inner := re.fullmatch(r"\((?P<g>.+)\)", goal, re.DOTALL)) is not None:
        goal = inner.group("g").strip()
    if (negation := _NEGATION.match(goal)) is not None:
        _read_goal(negation.group("goal").strip(), rule, negated=not negated)
        return
    if (cmp := _COMPARISON.match(goal)) is not None:
        _read_comparison(cmp, rule, negated=negated)
        return
    found = _GOAL.match(goal)
    if found is None:
        raise Unreadable(goal)
    name, args = found.group("name").lower(), _arguments(found.group("args"), rule)
    if name in _TIME_GOALS:
        return
    if name in _ANY_GOALS and len(args) == 1 and _is_variable(args[0]) and not negated:
        rule.generic.add(args[0])
        return
    if name in _COUNT_GOALS:
        _read_count(found.group("args") or "", rule, negated=negated)
        return
    label = node_label(re.sub(r"^(?:is_an?|isa|is)_", "", name))
    if len(args) == 1 and label is not None and _is_variable(args[0]) and negated:
        # "\\+ bus(X)": of any kind but that one
        query.conditions.append((args[0], f"other than {label_phrase(label)}"))
        return
    if len(args) == 1 and label is not None and _is_variable(args[0]):
        if args[0] in query.labels:
            raise Unreadable(f"a second kind: {goal}")
        query.labels[args[0]] = label
        return
    if (name in _KIND_GOALS or name in _ANY_GOALS) and len(args) == 2:
        kind = node_label(args[1])
        if kind is None or negated or not _is_variable(args[0]):
            raise Unreadable(goal)
        query.labels[args[0]] = kind
        return
    if _VALUE_GOALS.match(name) and len(args) == 2 and _is_variable(args[1]) and not negated:
        rule.values[args[1]] = (args[0], name)
        return
    if _LANE_GOAL.fullmatch(name) and len(args) == 2 and not _is_variable(args[1]):
        query.conditions.append((args[0], state_words(name, args[1], negated=negated)))
        return
    to_place = re.fullmatch(r"(?:dist|distance)_(?:to|from)_(?P<place>\w+?)(?:_m)?", name)
    if to_place is not None and len(args) == 2 and _is_variable(args[1]) and not negated:
        # "distance_to_intersection(X, D), D =< 10"
        query.relationships[args[1]] = len(query.edges)
        query.edges.append(
            (_node(args[0], rule), "within", None, _node(to_place.group("place"), rule), False)
        )
        return
    if _DISTANCE_GOALS.match(name) and len(args) == 3 and _is_variable(args[2]) and not negated:
        query.relationships[args[2]] = len(query.edges)
        query.edges.append((_node(args[0], rule), "within", None, _node(args[1], rule), False))
        return
    if len(args) == 1:
        query.conditions.append((args[0], state_words(name, None, negated=negated)))
        return
    if len(args) == 2 and node_label(args[1]) is None and not _is_variable(args[1]):
        # a constant that is no road user: a direction or a kind of place ("turning(X, left)")
        query.conditions.append((args[0], state_words(name, args[1], negated=negated)))
        return
    if len(args) in (2, 3):
        distance = None
        if len(args) == 3 and _is_variable(args[2]) and not negated:
            query.relationships[args[2]] = len(query.edges)  # "near(X, Y, D), D < 5"
        elif len(args) == 3:
            if not re.fullmatch(_NUMBER, args[2]):
                raise Unreadable(goal)
            distance = args[2]
        words, _ = relationship_words(name, None)
        words = _RELATION_WORDS.get(words, words)
        query.edges.append((_node(args[0], rule), words, distance, _node(args[1], rule), negated))
        return
    raise Unreadable(goal)


def state_words(name: str, value: str | None, *, negated: bool) -> str:
    """One road user's test (a goal, a flag, a column) in words ("in_intersection": "in an intersection")."""
    if value is None:
        words = relationship_words(re.sub(r"^(?:is|has)_", "", name), None)[
            0
        ]  # "changes_lane": "changing lane"
        words = f"not {words}" if negated else words
    elif not negated:
        value = value.lower()
        side = re.search(r"(?:^|_)(left|right)(?:_|$)", value)
        if _LANE_GOAL.fullmatch(name):
            lane = re.sub(r"(?:_lane)?$", " lane", value, count=1).replace("_", " ")
            words = f"in {_PLACES.get(lane, 'a ' + lane)}"
        elif side is not None and ("lane" in name or "lane" in value):
            # "lane_change(X, left)", "action(X, lane_change_left)"
            words = f"changing lanes to the {side.group(1)}"
        elif side is not None and ("turn" in name or "turn" in value):
            words = f"turning {side.group(1)}"  # "turns(X, right)", "action(X, turn_left)"
        elif re.fullmatch(r"on|in|at|inside|located(?:_\w+)?", name) and value.replace("_", " ") in _PLACES:
            words = f"{'in' if 'intersection' in value or 'junction' in value else 'on'} {_PLACES[value]}"
        else:
            words = property_words(name, "=", value)
    else:
        raise Unreadable(f"not {name}({value})")
    words = re.sub(r"\b(?:overlaps|overlapping|located on|located in|within)(?= \w)", "on", words)
    for place, phrase in _PLACES.items():
        words = re.sub(rf"\b(in|on|at|near|inside) {place}\b", rf"\1 {phrase}", words)
    return words


def _read_comparison(cmp: re.Match[str], rule: _Rule, *, negated: bool) -> None:
    """``S > 10``, ``D < 5``, ``N >= 3``: a test of a bound value."""
    left, op, right = cmp.group("left"), cmp.group("op"), cmp.group("right")
    op = {"=<": "<=", "=:=": "=", "==": "=", "\\=": "!="}.get(op, op)
    if re.fullmatch(_NUMBER, left):
        left, right, op = right, left, _FLIPPED[op]
    if negated:
        op = {">": "<=", "<": ">=", ">=": "<", "<=": ">", "=": "!=", "!=": "="}[op]
    if not re.fullmatch(_NUMBER, right):
        raise Unreadable(cmp.group(0))
    if left in rule.query.relationships:
        distance_test(rule.query, left, "distance", op, right)
        return
    if left not in rule.values:
        raise Unreadable(cmp.group(0))
    owner, prop = rule.values[left]
    if owner == "count":
        if op not in (">", ">=", "="):
            raise Unreadable(cmp.group(0))
        rule.query.counts[prop] = int(float(right)) + (1 if op == ">" else 0)
        return
    rule.query.conditions.append((owner, property_words(prop, op, right)))


def _read_count(args: str, rule: _Rule, *, negated: bool) -> None:
    """``count(P, (goals), N)`` / ``aggregate_all(count, [P,] (goals), N)``: N counts P."""
    parts = [a.strip() for a in top_level_split(args, ",")]
    if parts and parts[0] == "count":
        parts = parts[1:]
    if negated or len(parts) not in (2, 3) or not _is_variable(parts[-1]):
        raise Unreadable(f"count({args})")
    inner = parts[-2]
    goals = top_level_split(inner.strip()[1:-1] if inner.strip().startswith("(") else inner, ",")
    for goal in goals:
        _read_goal(goal.strip(), rule, negated=False)
    counted = parts[0] if len(parts) == 3 else None
    if counted is None:
        kinded = [g for g in goals if (m := _GOAL.match(g.strip())) and node_label(m.group("name"))]
        if len(kinded) != 1:
            raise Unreadable(f"count({args})")
        counted = str(_GOAL.match(kinded[0].strip()).group("args")).strip()  # type: ignore[union-attr]
    rule.values[parts[-1]] = ("count", counted)
