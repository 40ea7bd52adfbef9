"""A scenario written in the Scenic language, put in the plain words the phrase rules read.

Scenario-based testing teams write scenarios in Scenic: objects are created with ``new`` and
specifiers, conditions with ``require``, and the object sought is named at the end:
``ego = new Car; ped = new Pedestrian right of ego; require (distance from ego to ped) < 25;
find ped``. :func:`scenic_program` reads the statements (separated by ``;`` or new lines) and
words everything said about the object found, with every other object named by its kind: the
example becomes "pedestrian to the right of the ego vehicle within 25 m of the ego vehicle".

Read: classes (``Car`` a regular vehicle, ``Vehicle``, ``BoxTruck``, ``Pedestrian``, ...; the
object named ``ego`` is the ego vehicle; ``new A or new B`` either), specifiers (``left of``,
``right of``, ``ahead of``, ``behind``, ``facing toward``, ``facing 180 deg relative to
X.heading``, ``moving perpendicular to``, ``crossing in front of``, ``following X``, regions such
as ``in drivableArea``, ``on busLane``, ``at crosswalk``), behaviours (``with behavior TurnLeft``,
``LaneChangeBehavior(laneSectionToSwitch=leftLaneSec)``, a ``behavior Name(): do TurnRight``
defined before), ``require`` conditions (``(speed of X) > 10``, ``(acceleration of X) < -1.5``,
``(lateral acceleration of X) > 1.5``, ``(distance from X to Y) < 5``, ``at least 3 Pedestrian
objects within 15 of X``, ``X is parked``, ``X walks toward Y``, ``not (X in drivableArea)``),
``do ... until <condition>`` and the words after ``find X while``. A statement this reading does
not know leaves the text unchanged, for the other readers (and the language model) to read.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field

__all__ = ["scenic_program"]

_N = r"-?\d+(?:\.\d+)?"
_NAME = r"[A-Za-z_]\w*"
_CREATE = re.compile(rf"^(?P<var>{_NAME})\s*=\s*(?P<rest>new\s+.+)$")
_CLASS = re.compile(r"new\s+(?P<cls>[A-Z]\w*)")
_FIND = re.compile(
    rf"^(?:find|return|select|search|show)\s+(?P<var>{_NAME})\b(?:\s+(?P<more>.+))?$", re.IGNORECASE
)
#: "require <condition>", "do brake until <condition>": a condition on the objects.
_CONDITION = re.compile(r"^(?:require|do\s+\w+\s+until)\s+(?P<cond>.+)$")
_BEHAVIOR_DEF = re.compile(rf"^behavior\s+(?P<name>{_NAME})\s*\([^)]*\)\s*:\s*(?P<body>.+)$")
#: Scenic's classes, as the kind the phrase tables read.
_CLASSES = {
    "car": "car", "vehicle": "vehicle", "truck": "truck", "boxtruck": "box truck", "bus": "bus",
    "pedestrian": "pedestrian", "bicycle": "bicycle", "bike": "bicycle", "motorcycle": "motorcycle",
    "constructioncone": "construction cone", "cone": "construction cone", "bollard": "bollard",
    "constructionbarrel": "construction barrel", "stroller": "stroller", "wheeleddevice": "wheeled device",
    "wheelchair": "wheelchair", "scooter": "wheeled device", "trafficcone": "construction cone",
    "schoolbus": "school bus", "articulatedbus": "articulated bus", "largevehicle": "large vehicle",
    "object": "object", "agent": "object", "trailer": "trailer",
}  # fmt: skip
#: Scenic's regions, as places.
_REGIONS = {
    "drivablearea": "the drivable area", "road": "the road", "roadway": "the road",
    "crosswalk": "a crosswalk", "pedestriancrossing": "a crosswalk", "intersection": "an intersection",
    "buslane": "a bus lane", "bikelane": "a bike lane", "bicyclelane": "a bike lane",
    "sidewalk": "the sidewalk",
}  # fmt: skip
#: Behaviours, as the action they perform ("" adds nothing to find).
_BEHAVIORS = (
    (re.compile(r"^(?:lanechange|changelane)\w*\(.*left.*\)$"), "changing lanes to the left"),
    (re.compile(r"^(?:lanechange|changelane)\w*\(.*right.*\)$"), "changing lanes to the right"),
    (re.compile(r"^(?:lanechange|changelane)\w*$"), "changing lanes"),
    (re.compile(r"^(?:turnleft|leftturn)\w*$"), "turning left"),
    (re.compile(r"^(?:turnright|rightturn)\w*$"), "turning right"),
    (re.compile(r"^(?:brake|braking|hardbrake|emergencybrake)\w*$"), "braking"),
    (re.compile(r"^(?:followlane|drive|driving|cruise|keeplane|followtrajectory)\w*$"), ""),
    (re.compile(r"^(?:stop|stopped|park|parked|idle|wait)\w*$"), "stopped"),
    (re.compile(r"^(?:walk|walking|crossstreet|crossing)\w*$"), "moving"),
)
#: A specifier relating an object to another, worded from the other's side.
_INVERSE = {
    "crossing in front of": "with {} crossing in front of it",
    "following": "being followed by {}",
    "behind": "with {} behind it",
    "ahead of": "with {} ahead of it",
    "in front of": "with {} in front of it",
    "left of": "with {} to the left of it",
    "right of": "with {} to the right of it",
    "facing toward": "being faced by {}",
}
_COMPARE = {">": "more than", ">=": "at least", "<": "less than", "<=": "at most"}


class Unreadable(ValueError):
    """A statement of the program this reading does not know."""


@dataclass
class _Scene:
    kinds: dict[str, str] = field(default_factory=dict)
    words: dict[str, list[str]] = field(default_factory=dict)
    behaviors: dict[str, str] = field(default_factory=dict)
    #: (object, relation, other object): read from the other's side when it is the one found
    links: list[tuple[str, str, str]] = field(default_factory=list)

    def name(self, var: str) -> str:
        """How another object is named: its kind, or a place."""
        if var.lower() == "ego":
            return "the ego vehicle"
        if var in self.kinds:
            kind = self.kinds[var]
            return f"an {kind}" if kind[0] in "aeiou" else f"a {kind}"
        if (region := _REGIONS.get(var.lower())) is not None:
            return region
        raise Unreadable(var)

    def say(self, var: str, words: str) -> None:
        if var not in self.kinds:
            raise Unreadable(var)
        if words:
            self.words[var].append(words)


def scenic_program(description: str) -> str:
    """``description`` in words when it is a Scenic program naming the object to find, else as is."""
    statements = [s.strip() for s in re.split(r"[;\n]+", description) if s.strip()]
    if len(statements) < 2 or not any(_CREATE.match(s) for s in statements):
        return description
    found = _FIND.match(statements[-1].rstrip("."))
    if found is None:
        return description
    scene = _Scene()
    try:
        for statement in statements[:-1]:
            _read(statement, scene)
        var = found["var"]
        if var not in scene.kinds:
            return description
    except Unreadable:
        # a Scenic program with a statement this reading does not know: without its "find x", so
        # that no other reader takes the bare name of the object for the whole request
        return "; ".join(statements[:-1])
    kind = "ego vehicle" if var.lower() == "ego" else scene.kinds[var]
    words = [w for w in scene.words[var] if w]
    for subject, relation, other in scene.links:
        if other == var and subject != var:
            # "ped = new Pedestrian crossing in front of v; find v": v has it crossing in front
            words.append(_INVERSE[relation].format(scene.name(subject)))
    # "to the left of the ego vehicle", "within 10 m of the ego vehicle": one bounded position
    for i, word in enumerate(words):
        if (near := re.match(r"^within (\S+ m) of (.+)$", word)) and any(
            re.match(rf"^(?:to the (?:left|right) of|ahead of|behind|in front of) {re.escape(near[2])}$", w)
            for w in words
        ):
            words[i] = f"within {near[1]}"
    # "behind lead ..., following lead": following says it
    words = [w for w in words if not (w.startswith("behind ") and f"following {w[7:]}" in words)]
    if found["more"]:
        more = re.sub(r"^(?:while|when|whenever|during)\s+(?:it\s+(?:is\s+)?)?", "", found["more"].strip())
        more = re.sub(r"\bin either direction\b", "", more)
        words.append(more)
    return " ".join([kind, *words]).strip() + "."


def _read(statement: str, scene: _Scene) -> None:
    if match := _BEHAVIOR_DEF.match(statement):
        action = re.sub(r"^do\s+", "", match["body"].strip())
        scene.behaviors[match["name"].lower()] = _behavior_words(action, scene)
    elif match := _CREATE.match(statement):
        _create(match["var"], match["rest"], scene)
    elif match := _CONDITION.match(statement):
        _require(match["cond"].strip(), scene)
    else:
        raise Unreadable(statement)


def _create(var: str, rest: str, scene: _Scene) -> None:
    """``var = new Class specifiers``: its kind and what the specifiers say of it."""
    classes = [_CLASSES.get(c.lower()) for c in _CLASS.findall(rest)]
    if not classes or None in classes:
        raise Unreadable(rest)
    scene.kinds[var] = " or ".join(c for c in classes if c)
    scene.words[var] = []
    specifiers = _CLASS.sub("", rest).replace(" or ", " ").strip()
    for spec in (
        s.strip() for s in re.split(r",(?![^()]*\))|\s+(?=with behavior\b)", specifiers) if s.strip()
    ):
        scene.say(var, _specifier(spec, scene))
        if link := re.match(rf"^(?P<rel>{'|'.join(_INVERSE)})\s+(?P<other>{_NAME})\b", spec):
            scene.links.append((var, link["rel"], link["other"]))


def _specifier(spec: str, scene: _Scene) -> str:
    spec = re.sub(r"\s+by\s+(?:\([^)]*\)|[\d.]+)\s*$", "", spec)  # an offset places it, no condition
    if match := re.match(rf"^(?:in|on|at)\s+(?P<place>{_NAME})$", spec):
        place = match["place"].lower()
        if place in ("lane", "lanes", "roadlane"):
            return ""
        if place == "intersection":
            return "on an intersection"
        if (region := _REGIONS.get(place)) is None:
            raise Unreadable(spec)
        if "crosswalk" in place or "crossing" in place:
            return f"at {region}"
        return (
            f"in {region}"
            if place in ("drivablearea", "buslane", "bikelane", "bicyclelane")
            else f"on {region}"
        )
    if match := re.match(rf"^(?P<side>left|right) of\s+(?P<other>{_NAME})$", spec):
        return f"to the {match['side']} of {scene.name(match['other'])}"
    if match := re.match(rf"^(?P<where>ahead of|behind|in front of)\s+(?P<other>{_NAME})$", spec):
        return f"{match['where']} {scene.name(match['other'])}"
    if match := re.match(rf"^facing (?:toward|towards)\s+(?P<other>{_NAME})$", spec):
        return f"facing {scene.name(match['other'])}"
    if match := re.match(
        rf"^(?:facing|heading) 180 deg(?:rees)? relative to\s+(?P<other>{_NAME})\.heading$", spec
    ):
        return f"travelling in the opposite direction to {scene.name(match['other'])}"
    if match := re.match(
        rf"^(?:facing|heading) 0 deg(?:rees)? relative to\s+(?P<other>{_NAME})\.heading$", spec
    ):
        return f"travelling in the same direction as {scene.name(match['other'])}"
    if match := re.match(
        rf"^(?:(?:moving|facing|heading|driving) perpendicular to|(?:facing|heading) (?:-?90) deg(?:rees)?"
        rf" relative to)\s+(?P<other>{_NAME})(?:\.heading)?$",
        spec,
    ):
        return f"moving perpendicular to {scene.name(match['other'])}"
    if match := re.match(rf"^crossing in front of\s+(?P<other>{_NAME})$", spec):
        return f"crossing in front of {scene.name(match['other'])}"
    if match := re.match(rf"^following\s+(?P<other>{_NAME})(?: in the same lane)?$", spec):
        return f"following {scene.name(match['other'])}"
    if match := re.match(r"^with behavior\s+(?P<behavior>.+)$", spec):
        return _behavior_words(match["behavior"], scene)
    if spec in ("driving", "moving", "walking"):
        return "moving"
    raise Unreadable(spec)


def _behavior_words(behavior: str, scene: _Scene) -> str:
    key = re.sub(r"\s+", "", behavior).lower()
    if key in scene.behaviors:
        return scene.behaviors[key]
    for pattern, words in _BEHAVIORS:
        if pattern.match(key):
            return words
    raise Unreadable(behavior)


def _require(cond: str, scene: _Scene) -> None:
    """A ``require`` (or ``until``) condition: said of the object it is about."""
    if match := re.match(rf"^\((?P<what>speed|acceleration|lateral acceleration) of (?P<var>{_NAME})\)\s*"
                         rf"(?P<op>[<>]=?)\s*(?P<n>{_N})(?P<rest>.*)$", cond):  # fmt: skip
        scene.say(match["var"], _measure(match["what"], match["op"], float(match["n"]), match["rest"]))
    elif match := re.match(rf"^\(distance (?:from|between) (?P<a>{_NAME}) (?:to|and) (?P<b>{_NAME})\)\s*"
                           rf"(?P<op><=?)\s*(?P<n>{_N})$", cond):  # fmt: skip
        a, b = match["a"], match["b"]
        var, other = (a, b) if a in scene.kinds and (a.lower() != "ego" or b not in scene.kinds) else (b, a)
        scene.say(var, f"within {_number(match['n'])} m of {scene.name(other)}")
    elif match := re.match(rf"^at least (?P<n>\d+) (?P<cls>[A-Z]\w*) objects? within (?P<d>{_N})(?: m)? of"
                           rf" (?P<var>{_NAME})$", cond):  # fmt: skip
        kind = _CLASSES.get(match["cls"].lower())
        if kind is None:
            raise Unreadable(cond)
        scene.say(match["var"], f"with at least {match['n']} {kind}s within {_number(match['d'])} m")
    elif match := re.match(rf"^not \(?(?P<var>{_NAME}) (?:in|on) (?P<place>{_NAME})\)?$", cond):
        scene.say(match["var"], f"not in {scene.name(match['place'])}")
    elif match := re.match(
        rf"^(?P<var>{_NAME}) (?:is |stays |remains )?(?P<state>parked|stopped|stationary)\b", cond
    ):
        scene.say(match["var"], "parked" if match["state"] != "stopped" else "stopped")
    elif match := re.match(rf"^(?P<var>{_NAME}) is not (?P<what>turning|moving|parked|stopped)$", cond):
        scene.say(match["var"], f"not {match['what']}")
    elif match := re.match(rf"^(?P<var>{_NAME}) (?:is )?(?:turns|turning) (?P<side>left|right)$", cond):
        scene.say(match["var"], f"turning {match['side']}")
    elif match := re.match(
        rf"^(?P<var>{_NAME}) (?:is )?(?:changes|changing) lanes?(?: to the (?P<side>left|right))?$", cond
    ):
        scene.say(match["var"], "changing lanes" + (f" to the {match['side']}" if match["side"] else ""))
    elif match := re.match(rf"^(?P<var>{_NAME}) is (?P<what>moving|turning)$", cond):
        scene.say(match["var"], match["what"])
    elif match := re.match(rf"^(?P<var>{_NAME}) (?:walks|moves|drives|heads|is heading|is walking)"
                           r" (?:toward|towards)"
                           rf" (?P<other>{_NAME})$", cond):  # fmt: skip
        scene.say(match["var"], f"heading toward {scene.name(match['other'])}")
    elif match := re.match(rf"^(?P<var>{_NAME}) (?:is )?(?:driving|moving|travell?ing|heading)"
                           r" (?:in )?the same"
                           rf" direction as (?P<other>{_NAME})$", cond):  # fmt: skip
        var, other = match["var"], match["other"]
        scene.say(other, f"travelling in the same direction as {scene.name(var)}")
    elif match := re.match(
        rf"^(?P<var>{_NAME}) follows (?P<other>{_NAME})(?: in (?:its|the same) lane)?$", cond
    ):
        var, other = match["var"], match["other"]
        scene.words[other] = [w for w in scene.words.get(other, []) if not w.startswith("ahead of")]
        scene.say(other, f"being followed by {scene.name(var)}")
        scene.say(var, f"following {scene.name(other)}")
    else:
        raise Unreadable(cond)


def _measure(what: str, op: str, n: float, rest: str) -> str:
    side = re.search(r"\b(left|right)\b", rest)
    if what == "speed":
        return f"moving {'faster' if op.startswith('>') else 'slower'} than {_number(n)} m/s"
    if what == "lateral acceleration":
        toward = f" to the {side[1]}" if side else ""
        return f"with a lateral acceleration of {_COMPARE[op]} {_number(n)} m/s^2{toward}"
    if n < 0 and op.startswith("<"):
        return f"decelerating at more than {_number(-n)} m/s^2"
    return f"accelerating at {_COMPARE[op]} {_number(n)} m/s^2"


def _number(n: float | str) -> str:
    value = float(n)
    return str(int(value)) if value.is_integer() else str(value)
