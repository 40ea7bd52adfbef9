"""A set stated with quantifiers, put in the plain words the phrase rules read.

A formal-methods engineer writes the set to find in first-order logic:
``{v ∈ Vehicles | ∃p ∈ Pedestrians: ahead(p, v) ∧ dist(p, v) ≤ 15 m}``. :func:`quantified_set`
turns such a set into a logic-programming rule (``find(V) :- vehicle(V), pedestrian(P), ahead(P,
V), distance(P, V, D1), D1 =< 15.``) and reads that with :func:`scenariominer.mine.plan_logic.
logic_rule`, so both registers are worded the same way: the set's members are the road users
found; ``∃x ∈ Set:`` names another road user; a measure compared with a number is a bound
(``speed(v) ≥ 0.5 m/s``, ``dist(p, v) ≤ 15 m``, ``a_long(v) ≤ −1 m/s²``); ``cat(x) = BOX_TRUCK``
names the kind; ``¬`` negates one predicate; ``x ≠ ego`` says nothing (the ego vehicle is no
member of another kind). A gloss after the closing brace is ignored. A set with a negated
quantifier, an angle, a union of kinds or anything else this reading does not know comes back
unchanged, for the other readers (and the language model).
"""

from __future__ import annotations

import re

from scenariominer.mine.plan_graph import node_label, top_level_split
from scenariominer.mine.plan_logic import logic_rule
from scenariominer.mine.plan_nouns import singular

__all__ = ["quantified_set"]

_SET = re.compile(
    r"^\s*(?:[A-Z]\w*\s*[:=]+\s*)?\{\s*(?P<var>\w+)(?:\s*∈\s*(?P<kind>[^|}]+?))?\s*\|\s*(?P<body>[^{}]+)\}"
)
_EXISTS = re.compile(r"^∃\s*(?P<var>\w+)\s*∈\s*(?P<kind>[\w ]+?)\s*(?P<sep>[:.(])\s*(?P<rest>.+)$", re.DOTALL)
_NUMBER = r"[-−]?\d+(?:\.\d+)?"
_COMPARE = re.compile(
    rf"^(?P<lhs>.+?)\s*(?P<op>≤|≥|<=|>=|<|>|=|≠)\s*(?P<rhs>{_NUMBER}|\w+)\s*(?P<unit>[a-z/²^0-9]*)$"
)
_CALL = re.compile(r"^(?P<name>[A-Za-z_]\w*)\s*\((?P<args>.*)\)$", re.DOTALL)
#: "cat(x) ∈ VulnerableRoadUser", "pos(v) ∉ DrivableArea": a kind, or a place it is (not) in.
_MEMBER = re.compile(r"^(?P<lhs>\w+\(\w+\))\s*(?P<op>∈|∉)\s*(?P<set>\w+)$")
#: Functions naming a road user's kind ("cat(x)") and where it is ("pos(x)").
_KIND_FUNCTIONS = ("cat", "category", "class", "type", "kind")
_WHERE_FUNCTIONS = ("pos", "position", "loc", "location", "centre", "center")
_OPS = {"≤": "=<", "<=": "=<", "≥": ">=", ">=": ">=", "<": "<", ">": ">", "=": "=:="}


class _Unknown(Exception):
    """A part of the set this reading does not put in words."""


def quantified_set(description: str) -> str:
    """``description`` as plain words when it is a set stated with quantifiers, else unchanged."""
    found = _SET.match(description)
    if found is None or "∃" not in description and "∧" not in description and "(" not in found["body"]:
        return description
    try:
        state = _State()
        var = found["var"]
        if var.lower() == "ego":
            state.goals.append("ego(EGO)")
        elif found["kind"]:
            state.goals.append(f"{_kind(found['kind'])}({_variable(var)})")
        else:
            raise _Unknown("a member of no kind")
        _conjunction(found["body"], state)
        if any("EGO" in goal for goal in state.goals) and "ego(EGO)" not in state.goals:
            state.goals.append("ego(EGO)")
        rule = f"find({_variable(var)}) :- {', '.join(state.goals)}."
    except _Unknown:
        return description
    read = logic_rule(rule)
    return description if read == rule else read


class _State:
    def __init__(self) -> None:
        self.goals: list[str] = []
        self.values = 0


def _variable(name: str) -> str:
    return "EGO" if name.lower() == "ego" else name.upper()


def _argument(arg: str) -> str:
    """A term as an argument of a goal: a variable in capitals; ``pos(p)`` is ``p``."""
    arg = re.sub(rf"^(?:{'|'.join(_WHERE_FUNCTIONS)})\((\w+)\)$", r"\1", arg.strip())
    if re.fullmatch(r"\w+", arg) is None:
        raise _Unknown(arg)
    if arg.lower() == "ego":
        return "EGO"
    return arg.upper() if len(arg) <= 2 or arg[0].isupper() else arg.lower()


def _kind(name: str) -> str:
    """A set's name as a category goal's name ("ConstructionCones" -> "construction_cone")."""
    if re.search(r"∪|∩|\\", name):
        raise _Unknown("a union of kinds")
    words = _snake(name.strip()).replace("_", " ").split()
    if words in (["obj"], ["objects"], ["object"], ["tracks"], ["agents"]):
        return "object"
    phrase = " ".join([*words[:-1], singular(words[-1])]) if words else ""
    if node_label(phrase) is None:
        raise _Unknown(name)
    return phrase.replace(" ", "_")


def _conjunction(body: str, state: _State) -> None:
    for part in top_level_split(body.replace("∧", " ∧ "), " ∧ "):
        _conjunct(part.strip(), state)


def _conjunct(part: str, state: _State) -> None:
    """One conjunct into goals of the rule."""
    while part.startswith("(") and part.endswith(")"):
        part = part[1:-1].strip()
    if (exists := _EXISTS.match(part)) is not None:
        state.goals.append(f"{_kind(exists['kind'])}({_variable(exists['var'])})")
        rest = exists["rest"]
        _conjunction(rest[:-1] if exists["sep"] == "(" and rest.endswith(")") else rest, state)
        return
    if part.startswith("¬"):
        inner = part[1:].strip()
        if inner.startswith("∃") or _CALL.match(inner) is None:
            raise _Unknown(part)
        state.goals.append("\\+ " + _predicate(inner))
        return
    if (member := _MEMBER.match(part)) is not None:
        _membership(member, state)
        return
    if (cmp := _COMPARE.match(part)) is not None:
        _comparison(cmp, state)
        return
    state.goals.append(_predicate(part))


def _predicate(text: str) -> str:
    call = _CALL.match(text)
    if call is None:
        raise _Unknown(text)
    name = _snake(call["name"])
    args = [_argument(a) for a in top_level_split(call["args"], ",")]
    return f"{name}({', '.join(args)})"


def _membership(member: re.Match[str], state: _State) -> None:
    call = _CALL.match(member["lhs"])
    if call is None:
        raise _Unknown(member.group(0))
    arg = _argument(call["args"])
    if call["name"].lower() in _KIND_FUNCTIONS and member["op"] == "∈":
        state.goals.append(f"category({arg}, {_snake(member['set'])})")
        return
    place = node_label(_snake(member["set"]))
    if call["name"].lower() in _WHERE_FUNCTIONS and place is not None:
        negation = "" if member["op"] == "∈" else "\\+ "
        state.goals.append(f"{negation}in_{_snake(member['set'])}({arg})")
        return
    raise _Unknown(member.group(0))


def _snake(name: str) -> str:
    """A camelCase name in snake case ("crossesInFront" -> "crosses_in_front")."""
    return re.sub(r"(?<=[a-z0-9])(?=[A-Z])", "_", name).lower()


def _comparison(cmp: re.Match[str], state: _State) -> None:
    lhs, op, rhs = cmp["lhs"].strip(), cmp["op"], cmp["rhs"].replace("−", "-")
    if op == "≠":
        if rhs.lower() == "ego":
            return  # "v ≠ ego": a member of another kind is not the ego vehicle
        raise _Unknown(cmp.group(0))
    call = _CALL.match(lhs)
    if call is None:
        raise _Unknown(lhs)
    name = call["name"].lower()
    args = [_argument(a) for a in top_level_split(call["args"], ",")]
    if name in _KIND_FUNCTIONS and op == "=" and len(args) == 1:
        state.goals.append(f"category({args[0]}, {rhs.lower()})")
        return
    if re.fullmatch(_NUMBER, rhs) is None:
        raise _Unknown(cmp.group(0))
    state.values += 1
    value = f"Q{state.values}"
    if re.fullmatch(r"dist|distance|d", name) and len(args) == 2:
        state.goals.append(f"distance({args[0]}, {args[1]}, {value})")
    elif len(args) == 1:
        measure = re.sub(r"^a_?(?:long|lon)$|^a$", "accel", name)
        state.goals.append(f"{measure}({args[0]}, {value})")
    else:
        raise _Unknown(cmp.group(0))
    state.goals.append(f"{value} {_OPS[op]} {rhs}")
