"""A search written as a set in set-builder notation, put in the words the phrase rules read.

A paper defines the scenes it studies as sets: "{a ∈ V : v(a) > 10 m/s}", "{(a, t) : a ∈
Pedestrians, d(a, ego) < 5 m}", "the set of all vehicles a such that a is on an intersection and a
is turning left". :func:`set_wording` rewrites such a set as a filter over the named road users
("vehicles where speed > 10 m/s", "pedestrians where dist_to_ego < 5 m"), which
:mod:`scenariominer.mine.plan_filters` then puts in words; each rewrite keeps the meaning. A text
with no set in it comes back as it went in.
"""

from __future__ import annotations

import re
from collections.abc import Callable

__all__ = ["set_wording"]

#: Logic and comparison symbols, as a filter writes them.
_SYMBOLS: tuple[tuple[str, str], ...] = (
    ("∉", " not in "), ("∈", " in "), ("∧", " and "), ("∨", " or "), ("¬", " not "), ("≤", " <= "),
    ("≥", " >= "), ("≠", " != "), ("∃", " exists "), ("−", "-"), ("·", " "), ("\\land", " and "),
    ("\\wedge", " and "), ("\\lor", " or "), ("\\neg", " not "), ("\\leq", " <= "), ("\\le", " <= "),
    ("\\geq", " >= "), ("\\ge", " >= "), ("\\in", " in "), ("\\mid", " | "), ("∖", " minus "),
    ("∪", " or "), ("∄", " no "), ("∩", " meets "), ("∅", "empty"), ("°", " deg"),
)  # fmt: skip
#: One-letter and other names of road-user sets: name -> the road users' words.
_SET_NAMES = {
    "v": "vehicles", "veh": "vehicles", "p": "pedestrians", "ped": "pedestrians", "peds": "pedestrians",
    "a": "objects", "o": "objects", "objects": "objects", "agents": "objects", "b": "buses",
    "c": "cars", "t": "trucks", "any": "objects",
}  # fmt: skip
_VAR = r"[a-z](?:_?\d)?"
#: "{a ∈ V : ...}", "{(a, t) : ...}", "{a | ...}": the head, then the condition; a name before it
#: ("Brake = {...}", "Bike lanes: {...}") and a gloss after it ("}, passenger cars braking") dropped.
_BRACED = re.compile(
    r"^(?:[\w' -]{1,30}?\s*[=:]\s*)?\{\s*(?P<head>[^:|{}]+?)\s*(?::|\||\bs\.t\.|\bsuch that\b)\s*"
    r"(?P<cond>.+)\s*\}(?:[.;:,]\s*.*)?$"
)
#: "the set of (all) vehicles a such that ...": the road users, then the condition.
_WORDED = re.compile(
    rf"^(?:the )?set of (?:all )?(?P<users>[a-z][a-z ]*?)\s+(?P<var>{_VAR})\s+(?:such that|s\.t\.|where|with)"
    r"\s+(?P<cond>.+)$"
)
#: "a ∈ V", "(a, t) in vehicles × T": a variable's road users.
_MEMBER = re.compile(
    rf"\(?\s*(?P<var>{_VAR})\s*(?:,\s*t\s*)?\)?\s+in\s+(?P<set>[a-z_]+(?: or [a-z_]+)*)"
    r"(?P<minus> minus \{\s*ego\s*\})?(?:\s*×\s*\w+)?"
)
#: The variable as a function's argument, at a time step or not: "(a)", "(a, t)".
_CALL = r"\s*\(\s*{v}\s*(?:,\s*t\s*)?\)"
#: The variable or a point of its box ("centre(p, t)", "box(v)"), before a place it is in or not.
_OF = r"\b(?:(?:centre|center|box|pos|p)" + _CALL + r"|{v})"
#: Functions of the variable, as the filter fields they are: (pattern with {v}, replacement).
_TERMS: tuple[tuple[str, str | Callable[[re.Match[str]], str]], ...] = (
    (r"(?:\|\||‖|\|)\s*v(?:el)?" + _CALL + r"\s*(?:\|\||‖|\|)", "speed"),
    (r"\b(?:v|vel|speed|velocity)" + _CALL, "speed"),
    (r"\b(?:d|dist|distance)\s*\(\s*{v}\s*,\s*(?:ego|e)\s*(?:,\s*t\s*)?\)", "dist_to_ego"),
    (r"(?:\|\||‖|\|)\s*p\s*\(\s*{v}\s*\)\s*-\s*p\s*\(\s*(?:ego|e)\s*\)\s*(?:\|\||‖|\|)", "dist_to_ego"),
    (r"\b(?:a|acc|accel|a_x|a_long)" + _CALL, "accel_long"),
    (r"\b(?:a_y|a_lat|lat_acc|lat_accel)" + _CALL, "lat_accel"),
    (
        r"\b(?:d|dist|distance)\s*\(\s*{v}\s*,\s*(?:the )?intersection\s*(?:,\s*t\s*)?\)",
        "dist_to_intersection",
    ),
    # the angle between two directions of travel: "≥ 135°" opposite, "45° < ... < 135°" perpendicular
    (r"\b\d+ deg < angle\s*\(.*?\)\)\s*< \d+ deg", "moving perpendicular to the ego vehicle"),
    (
        r"\bangle\s*\(.*?\)\)\s*>=?\s*(?:1[3-7]\d|180) deg",
        "travelling in the opposite direction to the ego vehicle",
    ),
    (
        r"\bangle\s*\(.*?\)\)\s*<=?\s*(?:[1-3]?\d|4[0-5]) deg",
        "travelling in the same direction as the ego vehicle",
    ),
    # places: "centre(p, t) ∉ DrivableArea", "v ∈ DrivableArea(t) ∧ v ∉ Road(t)", "box(p) ∩ crosswalk ≠ ∅"
    (
        _OF + r"\s+not in\s+drivable_?area(?:\(t\))?",
        "not in the drivable area",
    ),
    (
        _OF + r"\s+in\s+drivable_?area(?:\(t\))?",
        "in the drivable area",
    ),
    (
        _OF + r"\s+not in\s+road(?:\(t\))?",
        "not on the road",
    ),
    (
        _OF + r"\s+in\s+road(?:\(t\))?",
        "on the road",
    ),
    (r"\bbox" + _CALL + r"\s*meets\s*(?:a |the )?crosswalk\s*!=\s*empty", "on a crosswalk"),
    (r"\b(?:centre|center)" + _CALL + r"\s+(?:is |lies )?", ""),
    (
        r"\blane" + _CALL + r"\s+(?:belongs to|is|=+|equals)\s+the ego'?s? lane(?: at t)?",
        "in the same lane as the ego vehicle",
    ),
    (r"\b{v}'s\s+(?:centre|center)\s+(?:is |lies )?", ""),
    # a predicate of the variable: "on_road(a)", "turning(a, left)", "stationary(a, t)"
    (
        r"\b(?P<fn>[a-z]+(?:_[a-z]+)*)\s*\(\s*{v}\s*(?:,\s*t\s*)?(?:,\s*'?(?P<arg>left|right|ego)'?\s*)?\)",
        lambda m: " ".join(m["fn"].split("_")) + (f" {m['arg']}" if m["arg"] else ""),
    ),
    # "a is on an intersection", "a lies in front of ...", "p on a road lane": the state itself
    (r"\b{v} (?:is|are|lies|is located|sits) ", ""),
    (r"\b{v} (?=on |in |near |at |to the |ahead |behind |crosses |crossing )", ""),
    (r"\btoward(?:s)? the (left|right)\b", r"to the \1"),
    (
        r"\bin the middle of an? lane change (?:toward|towards|to) (?:its|the) (left|right)\b",
        r"changing lanes to the \1",
    ),
    (r"\bon an? lane(?: segment)? (?:inside|within|in) (an?|the) intersection\b", r"on \1 intersection"),
    (r"\bcross(?:es|ing) the half-midplane ahead of\b", "crossing in front of"),
    (r"\b(?:with )?(?:a )?(?:box |bounding[- ]box )?(?:distance|gap)\s*(?=<)", "dist "),
    (
        r"\bon the side of the road opposite (?:to|from) (?:the )?ego(?: vehicle)?(?:'s)?",
        "on the other side of the road from the ego vehicle",
    ),
    (r"\b(bus|bike|vehicle)-type lane\b", r"\1 lane"),
)


def _users(name: str) -> str:
    """A set's name as road-user words ("V" -> "vehicles", "box_trucks" -> "box trucks")."""
    name = name.strip().lower()
    return _SET_NAMES.get(name, " ".join(name.split("_")))


def _one(users: str) -> str:
    """One of a set's road users: "pedestrians" -> "a pedestrian", "buses" -> "a bus"."""
    one = re.sub(r"(?:(?<=bus)es|s)$", "", users)
    return ("an " if one[:1] in "aeiou" else "a ") + one


def _others(cond: str, var: str) -> str:
    """Other road users of the condition, as "with" clauses.

    "exists p in pedestrians: d(a, p) < 5 m" -> "with a pedestrian within 5 m".
    """
    members = {
        m["var"]: _users(m["set"])
        for m in re.finditer(rf"(?:\bexists\s+)?\b(?P<var>{_VAR})\s+in\s+(?P<set>[a-z_]+)", cond)
        if m["var"] != var
    }
    # "|{p ∈ Pedestrians : d(v, p) ≤ 5 m}| ≥ 3": a count of them within a distance
    cond = re.sub(
        rf"\|\s*\{{\s*(?P<w>{_VAR})\s+in\s+(?P<set>[a-z_]+)\s*(?::|\|)\s*(?:d|dist|distance)\s*\(\s*"
        rf"(?:{re.escape(var)}\s*,\s*(?P=w)|(?P=w)\s*,\s*{re.escape(var)})\s*\)\s*<=?\s*(?P<d>\d+(?:\.\d+)?)\s*m?"
        r"\s*\}\s*\|\s*>=\s*(?P<n>\d+)",
        lambda m: f"with at least {m['n']} {_users(m['set'])} within {m['d']} m",
        cond,
    )
    for other, users in members.items():
        cond = re.sub(
            rf"(?:\bexists\s+)?\b{re.escape(other)}\s+in\s+[a-z_]+\s*(?::|\.|,|\bsuch that\b|\bwith\b)?",
            " ",
            cond,
        )
        # "p crosses ... ahead of v": the other road user by its name
        cond = re.sub(rf"(?<=ahead of |front of ){re.escape(other)}\b", _one(users), cond)
        distance = (
            rf"\b(?:d|dist|distance)\s*\(\s*(?:{re.escape(var)}\s*,\s*{re.escape(other)}|{re.escape(other)}"
            rf"\s*,\s*{re.escape(var)})\s*(?:,\s*t\s*)?\)\s*<=?\s*(?P<d>\d+(?:\.\d+)?)\s*(?:m\b)?"
        )
        cond = re.sub(distance, f"with {_one(users)} within \\g<d> m", cond)
    return cond


def _condition(cond: str, var: str) -> str:
    """The condition on ``var`` as filter text ("v(a) > 10 m/s" -> "speed > 10 m/s")."""
    cond = _others(cond, var)
    cond = re.sub(r"\s+at t\b|\s+at time t\b", "", cond)
    # a condition's own membership test names a category ("a in pedestrians"): already the subject
    cond = re.sub(
        rf"\b{re.escape(var)}\s+in\s+(?!drivable|road\b|road\(|crosswalk|lane)[a-z_]+(?: or [a-z_]+)*"
        r"(?: minus \{\s*ego\s*\})?",
        "",
        cond,
    )
    for pattern, replacement in _TERMS:
        cond = re.sub(pattern.replace("{v}", re.escape(var)), replacement, cond)
    cond = re.sub(r"\s*(?:,|;)\s*", " and ", cond)
    cond = re.sub(r"(?<![<>!=])=(?!=)", "==", cond)  # a filter's equality
    cond = re.sub(r"^(?:\s*and\s+)+|(?:\s+and\s*)+$", "", cond.strip())
    return " ".join(re.sub(r"(?:\band\s+){2,}", "and ", cond).split())


def set_wording(text: str) -> str:
    """``text`` (lower case) with a set in set-builder notation as a filter; other text unchanged."""
    if not re.search(r"[{∈∧∨]|\\in\b|\bset of\b|\bs\.t\.", text):
        return text
    for symbol, words in _SYMBOLS:
        text = text.replace(symbol, words)
    text = " ".join(text.split())
    braced, worded = _BRACED.match(text), _WORDED.match(text)
    if worded is not None:
        users, var, cond = worded["users"], worded["var"], worded["cond"]
    elif braced is not None:
        head, cond = braced["head"], braced["cond"]
        member = _MEMBER.search(head) or _MEMBER.search(cond)
        ego = re.match(rf"\s*\(?\s*(?P<var>{_VAR})\s*(?:,\s*t\s*)?\)?\s*$", head)
        if ego is not None and re.match(rf"{ego['var']}\s*=+\s*ego\b", cond):
            # "{(e, t) : e = ego, speed(e, t) >= 0.5 m/s}": the ego vehicle itself
            cond = re.sub(rf"^{ego['var']}\s*=+\s*ego\b\s*,?\s*", "", cond)
            return f"the ego vehicle {_condition(cond, ego['var'])}"
        if member is None:
            return text
        users, var = " or ".join(_users(s) for s in member["set"].split(" or ")), member["var"]
        if member["minus"]:
            users += " other than the ego vehicle"
    else:
        return text
    cond = _condition(cond, var)
    # "where" only before a filter's comparison (which plan_filters reads); plain words follow directly
    return f"{users} {'where ' if re.search(r'[<>=]', cond) else ''}{cond}".strip()
