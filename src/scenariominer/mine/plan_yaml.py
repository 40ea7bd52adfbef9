"""A request written as a parameter block in YAML style, put as one specification line.

One ``key: value`` per line (or a one-line ``{key: value, ...}``); keys in snake case, units in key
names ("max_distance_m", "speed_min_kmh"), lists in brackets, flags as true/false, and a key without
a value grouping the lines indented under it. The block becomes the "key: value; key: value" line
that :mod:`scenariominer.mine.plan_wording` reads as a specification, each part in plain words:

* "actor: bus / state: stopped / map: near intersection" -> "actor: bus; state: stopped; map: near
  intersection";
* a flag, a limit, a lane, a place: "on_road: false" -> "not on road", "max_distance_m: 20" -> a
  range of 20 m, "lane: same as ego", "lane_type: BUS", "location: drivable_area";
* a relation named by its key: "following: ego", "moving_toward: pedestrian", "crossed_by: ...",
  "travel_direction: opposite" (with "reference: ego"), "road_side: opposite", "facing: ego" with
  "angle_deg: 30";
* a group naming another road user and its limits: "near: {target: ego, radius_m: 5}" -> "within 5
  m of the ego vehicle", "nearby_pedestrians: {min_count: 2, radius_m: 3}" -> "with at least 2
  pedestrians within 3 m", "behind: {category: VEHICLE, within_m: 10, lateral_m: 1}" -> "with a
  vehicle directly behind it within 10 m";
* a group of limits on one quantity: "speed: {min_mph: 20}", "braking: {decel_min_mps2: 2}",
  "lateral_accel: {left_min_mps2: 1.5}".

:func:`yaml_block` reads the text with its line breaks (before they are joined).
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field

__all__ = ["yaml_block"]

#: One line of a parameter block: an optional list dash, a key, a colon, a value (maybe none).
_YAML_LINE = re.compile(r"^(?P<indent>\s*)(?:-\s+)?(?P<key>[a-z][a-z0-9_ .-]*?)\s*:\s*(?P<value>.*?)\s*$")
_TRUE = frozenset(("true", "yes", "y", "on", "1"))
_FALSE = frozenset(("false", "no", "n", "off", "0", "none"))
_NUMBER = re.compile(
    r"^(?:[<>]=?\s*)?(\d+(?:\.\d+)?)\s*(m/s²|m/s2|m/s|mps|km/h|kmh|kph|mph|m|metres|meters)?$"
)
#: The words of a key that names a limit ("max_distance_m", "speed_min_mps", "decel_min_mps2").
_LIMIT_WHAT = {
    **dict.fromkeys(("distance", "dist", "range", "radius", "gap", "within"), "distance"),
    **dict.fromkeys(("speed", "velocity"), "speed"),
    **dict.fromkeys(("decel", "deceleration", "braking"), "braking"),
    **dict.fromkeys(("accel", "acceleration"), "acceleration"),
}
_LIMIT_BOUND = {
    "max": "max",
    "maximum": "max",
    "upper": "max",
    "min": "min",
    "minimum": "min",
    "lower": "min",
}
_LIMIT_UNIT = {
    "m": "m", "metres": "m", "meters": "m", "mps": "m/s", "ms": "m/s", "m/s": "m/s", "kmh": "km/h",
    "kph": "km/h", "km/h": "km/h", "mph": "mph", "mps2": "m/s²", "m/s2": "m/s²", "m/s²": "m/s²",
}  # fmt: skip
#: Keys that name the road users asked for.
_ACTOR_KEYS = frozenset(
    (
        "actor", "subject", "agent", "object", "target", "road user", "type", "category", "actors", "objects",
        "agents", "targets", "categories", "class", "object type", "actor type", "object class", "return",
        "select", "find", "output",
    )
)  # fmt: skip
#: Keys that name the other road user of a group or of the part before them.
_OTHER_KEYS = frozenset(
    ("category", "target", "type", "object", "class", "actor", "agent", "other", "to", "of", "relative to",
     "reference", "ref", "wrt", "with respect to", "from")
)  # fmt: skip
_REFERENCE_KEYS = frozenset(("of", "from", "to", "relative to", "reference", "ref", "wrt", "with respect to"))
_COUNT_KEYS = frozenset(("min count", "count", "min objects", "at least", "min number", "number", "min"))
_LATERAL_KEYS = frozenset(
    ("lateral", "lateral m", "lateral thresh", "lateral distance", "lateral distance m")
)
_ANGLE_KEYS = frozenset(("angle", "angle deg", "within angle", "max angle", "max angle deg", "angle degrees"))
#: A relation named by its key, and the words that say it before the other road user.
_RELATIONS = {
    **dict.fromkeys(
        ("following", "follows", "lead vehicle", "leading vehicle", "leader", "lead"), "following"
    ),
    **dict.fromkeys(("facing", "facing toward", "facing towards", "looking at"), "facing"),
    **dict.fromkeys(
        ("approaching", "moving toward", "moving towards", "heading toward", "heading towards", "toward"),
        "heading toward",
    ),
    **dict.fromkeys(("crossed by", "being crossed by"), "being crossed by"),
    **dict.fromkeys(("crossing", "crossing in front of", "cuts in front of"), "crossing in front of"),
    **dict.fromkeys(("near", "close to", "nearby", "next to"), "near"),
    **dict.fromkeys(
        ("same lane as", "same lane", "in same lane as", "shares lane with"), "in the same lane as"
    ),
    "overtaking": "overtaking",
    "passing": "passing",
}
#: A group that names where the other road user is ("objects_ahead", "behind").
_DIRECTIONS = {
    "ahead": "ahead", "in front": "ahead", "front": "ahead", "forward": "ahead", "behind": "behind it",
    "back": "behind it", "rear": "behind it", "left": "on its left", "right": "on its right",
}  # fmt: skip
#: Places named by a value ("location: drivable_area").
_PLACES = {
    "drivable area": "in the drivable area",
    "on road": "on the road",
    "road": "on the road",
    "pedestrian crossing": "at a pedestrian crossing",
    "crosswalk": "at a pedestrian crossing",
    "intersection": "on an intersection",
    "junction": "on an intersection",
    "bike lane": "on a bike lane",
    "bus lane": "on a bus lane",
}
#: "lane: same as ego", "lane: ego lane", "lane: same": the lane of another object.
_SAME_LANE = re.compile(r"^(?:same(?: lane)?(?: as (?P<other>.+))?|(?P<own>ego|the ego)(?:'s)? lane)$")
#: "position: ahead", "side: left of ego": a place relative to another object.
_PLACE = {
    "ahead": "in front of", "in front": "in front of", "front": "in front of", "forward": "in front of",
    "behind": "behind", "back": "behind", "rear": "behind", "left": "on the left of",
    "right": "on the right of",
}  # fmt: skip
_PLACE_VALUE = re.compile(
    rf"^(?P<place>{'|'.join(sorted(_PLACE, key=len, reverse=True))})(?: of (?P<other>.+))?$"
)


@dataclass
class _Entry:
    """One line of a block: its key in words, its value ("" for a group) and the lines under it."""

    key: str
    value: str
    children: list[_Entry] = field(default_factory=list)


def _words(text: str) -> str:
    return " ".join(text.strip("'\"").replace("_", " ").replace("-", " ").split())


def _entries(lines: list[str]) -> list[_Entry] | None:
    """The lines as a tree by indentation, or ``None`` when a line is no ``key: value``."""
    root: list[_Entry] = []
    stack: list[tuple[int, list[_Entry]]] = [(-1, root)]
    for line in lines:
        found = _YAML_LINE.match(line)
        if found is None:
            return None
        indent = len(found["indent"])
        value = found["value"].strip().strip("'\"")
        if value.startswith("[") and value.endswith("]"):
            value = " or ".join(_words(v) for v in value[1:-1].split(",") if v.strip())
        entry = _Entry(_words(found["key"]), " ".join(value.replace("_", " ").split()))
        while stack[-1][0] >= indent:
            stack.pop()
        stack[-1][1].append(entry)
        if not entry.value:
            stack.append((indent, entry.children))
    return root


def _object(value: str) -> str:
    """Another road user named by a value: "ego" -> "the ego vehicle", "pedestrian" -> "a pedestrian"."""
    value = value.strip()
    if value in ("ego", "the ego", "ego vehicle", "the ego vehicle", "av", "the av", "self"):
        return "the ego vehicle"
    if value in ("any", "anything", "object", "objects"):
        return "an object"
    if re.match(r"^(?:an?|the|some|any|another) ", value) or value.endswith("s"):
        return value
    return f"{'an' if value[0] in 'aeiou' else 'a'} {value}"


def _plural(value: str) -> str:
    """Road users named by a value, in the plural ("pedestrian" -> "pedestrians", "any" -> "objects")."""
    if value in ("any", "anything", "object"):
        return "objects"
    if value.endswith("s"):
        return value + "es" if value.endswith("bus") else value
    return value + "s"


def _limit(key: str) -> tuple[str, str, str, str] | None:
    """(what, bound, unit, side) of a key naming a limit ("speed max mps" -> ("speed", "max", "m/s", ""))."""
    words = key.split()
    what = [_LIMIT_WHAT[w] for w in words if w in _LIMIT_WHAT]
    known = {*_LIMIT_WHAT, *_LIMIT_BOUND, *_LIMIT_UNIT, "left", "right"}
    if len(what) != 1 or any(w not in known for w in words):
        return None
    bound = next((_LIMIT_BOUND[w] for w in words if w in _LIMIT_BOUND), "")
    unit = next((_LIMIT_UNIT[w] for w in words if w in _LIMIT_UNIT), "")
    side = next((w for w in words if w in ("left", "right")), "")
    return what[0], bound, unit, side


def _limit_part(what: str, bound: str, unit: str, side: str, number: str) -> str:
    """A part stating a limit of ``what``."""
    if what == "speed":
        return f"speed: {'faster' if bound == 'min' else 'slower'} than {number} {unit or 'm/s'}"
    if what == "braking":
        return f"condition: braking harder than {number} m/s²"
    if what == "acceleration" and side == "either":
        return f"condition: with a lateral acceleration of more than {number} m/s²"
    if what == "acceleration" and side:
        return f"condition: with a lateral acceleration to the {side} of more than {number} m/s²"
    if what == "acceleration":
        return f"condition: accelerating at more than {number} m/s²"
    if bound == "min":
        return f"condition: at least {number} {unit or 'm'} away"
    return f"range: {number} {unit or 'm'}"


def _flat_part(key: str, value: str) -> str:
    """One ``key: value`` line as a part of a specification line."""
    number = _NUMBER.match(value)
    if key in _ACTOR_KEYS:
        return f"actor: {_plural(value) if value in ('any', 'anything', 'object') else value}"
    if (limit := _limit(key)) is not None and number is not None:
        return _limit_part(*limit[:2], _LIMIT_UNIT.get(number[2] or "", limit[2]), limit[3], number[1])
    if value in _TRUE:  # "stopped: true" -> a condition named by the key
        return f"condition: {key}"
    if value in _FALSE:
        return f"condition: not {key}"
    if key in ("exclude", "excluding", "except", "not", "exclude categories", "excluded categories"):
        return f"condition: not {_PLACES[value]}" if value in _PLACES else f"condition: other than {value}"
    if key in ("location", "where", "map", "area", "on", "in", "at", "place", "context") and value in _PLACES:
        return f"condition: {_PLACES[value]}"
    if key in ("lane type", "lane kind"):
        return f"condition: on a {value} lane"
    if key in _RELATIONS and not number:
        return f"condition: {_RELATIONS[key]} {_object(value)}"
    if key in (
        "travel direction",
        "direction of travel",
        "heading",
        "relative heading",
        "relative direction",
    ):
        if value in ("opposite", "same", "oncoming"):
            way = "opposite" if value == "oncoming" else value
            return f"condition: travelling in the {way} direction to the ego vehicle"
        if value == "perpendicular":
            return "condition: travelling perpendicular to the ego vehicle"
    if key in ("road side", "side of road", "side of the road") and value in ("opposite", "same"):
        return f"condition: on the {value} side of the road from the ego vehicle"
    if "intersection" in key.split() and number is not None:  # "near_intersection_m: 10"
        return f"condition: within {number[1]} m of an intersection"
    if re.match(r"^\w+ing\b", key) and value in ("left", "right"):  # "changing lanes: left"
        return f"motion: {key} {'to the ' if key.startswith('changing') else ''}{value}"
    if key == "lane" and (same := _SAME_LANE.match(value)) is not None:
        return f"condition: in the same lane as {_object(same['other'] or 'ego')}"
    if key == "side" and value in ("left", "right"):  # a side of the part before it (:func:`_attached`)
        return f"side: {value}"
    if key in ("position", "relative position", "side", "location") and (place := _PLACE_VALUE.match(value)):
        return f"condition: {_PLACE[place['place']]} {_object(place['other'] or 'ego')}"
    return f"{key}: {value}"


def _group_part(key: str, children: list[_Entry]) -> list[str]:
    """The parts of a group: a relation to the road user it names, limits on one quantity, or its lines."""
    fields = {c.key: c.value for c in children if c.value}
    other = next((fields[k] for k in _OTHER_KEYS if k in fields), "")
    count = next((fields[k] for k in _COUNT_KEYS if k in fields and fields[k].isdigit()), "")
    distance = ""
    for k, v in fields.items():
        if (limit := _limit(k)) is not None and limit[0] == "distance" and (number := _NUMBER.match(v)):
            distance = f"{number[1]} {_LIMIT_UNIT.get(number[2] or '', limit[2]) or 'm'}"
    lateral = next((fields[k] for k in _LATERAL_KEYS if k in fields), "")
    words = key.split()
    # limits on one quantity: "speed: {min_mph: 20}", "lateral_accel: {left_min_mps2: 1.5}"
    if len(words) <= 2 and all(w in _LIMIT_WHAT or w == "lateral" for w in words):
        quantity = next(_LIMIT_WHAT[w] for w in words if w in _LIMIT_WHAT)
        parts = []
        for k, v in fields.items():
            limit = _limit(f"{words[-1]} {k}")
            if limit is not None and (number := _NUMBER.match(v)):
                unit = _LIMIT_UNIT.get(number[2] or "", limit[2])
                # a lateral acceleration with no side named: either side
                side = limit[3] or ("either" if "lateral" in words else "")
                parts.append(_limit_part(quantity, limit[1], unit, side, number[1]))
        return parts or [_flat_part(k, v) for k, v in fields.items()]
    if key in ("heading", "relative heading", "relative direction", "travel direction") and "value" in fields:
        return [
            _flat_part("relative heading", fields["value"]).replace(
                "the ego vehicle", _object(other or "ego")
            )
        ]
    # a road user named in the key: "nearby_pedestrians", "objects_ahead"
    named = [
        w for w in words if w not in _DIRECTIONS and w not in ("near", "nearby", "close", "objects", "with")
    ]
    other = other or (" ".join(named) if named and len(named) == len(words) - 1 else "")
    direction = next((_DIRECTIONS[w] for w in (key, *words) if w in _DIRECTIONS), "")
    within = f" within {distance}" if distance else ""
    if direction and other:
        directly = "directly " if lateral and float(re.sub(r"[^\d.]", "", lateral) or 9) <= 1 else ""
        return [f"condition: with {_object(other)} {directly}{direction}{within}"]
    if _RELATIONS.get(key) == "near" or words[0] in ("nearby", "near") or count:
        if count:
            return [f"condition: with at least {count} {_plural(other or 'object')}{within}"]
        return [f"condition: within {distance or '10 m'} of {_object(other or 'object')}"]
    if key in _RELATIONS and other:
        return [f"condition: {_RELATIONS[key]} {_object(other)}{within}"]
    return [_flat_part(c.key, c.value) for c in children if c.value]


def _flow_items(text: str) -> list[str]:
    """The items of a one-line mapping "{a: b, c: [d, e]}", split at commas outside brackets."""
    items, depth, start = [], 0, 0
    body = text[1:-1]
    for i, char in enumerate(body):
        depth += char in "[{"
        depth -= char in "]}"
        if char == "," and depth == 0:
            items.append(body[start:i])
            start = i + 1
    items.append(body[start:])
    return [item.strip() for item in items if item.strip()]


def _attached(parts: list[str]) -> list[str]:
    """``parts`` with the keys that qualify another part folded into it.

    A reference ("of: truck", "relative_to: vehicle") names the object of the part before it (or,
    when that names none, of the next); an angle ("angle_deg: 30") bounds the facing before it; a
    side ("direction: right") is the side of the lane change, turn or crossing before it, or else a
    place beside the reference.
    """
    out: list[str] = []
    pending = ""
    for part in parts:
        key, _, value = part.partition(": ")
        last = out[-1] if out else ""
        last_key, _, last_value = last.partition(": ")
        if key in _REFERENCE_KEYS:
            if last_key == "range":  # "range: 10 m" of X -> "within 10 m of X"
                out[-1] = f"condition: within {last_value} of {_object(value)}"
            elif "the ego vehicle" in last:
                out[-1] = last.replace("the ego vehicle", _object(value))
            else:
                pending = _object(value)
            continue
        if key in _ANGLE_KEYS and "facing" in last and (number := _NUMBER.match(value)):
            out[-1] = f"{last} within {number[1]} degrees"
            continue
        if key in ("direction", "side", "turn direction") and value in ("left", "right"):
            if last_key in ("motion", "state", "maneuver", "manoeuvre", "action") or "changing lanes" in last:
                out[-1] = f"{last} {'to the ' if 'lane' in last else ''}{value}"
                continue
            if "crossed by" in last:
                out[-1] = f"{last} on its {value}"
                continue
            part = f"condition: on the {value} of {pending or 'the ego vehicle'}"
            pending = ""
        elif pending and "the ego vehicle" in part:
            part, pending = part.replace("the ego vehicle", pending), ""
        out.append(part)
    return out


def yaml_block(text: str) -> str:
    r"""A parameter block (two or more ``key: value`` lines, or a one-line "{...}") as one line.

    "actor: bus\nstate: stopped" -> "actor: bus; state: stopped"; "object: pedestrian\nnear:\n
    target: ego\n  radius_m: 5" -> "actor: pedestrian; condition: within 5 m of the ego vehicle".
    A text that is not such a block is returned as it is.
    """
    stripped = text.strip()
    if stripped.startswith("{") and stripped.endswith("}") and ":" in stripped:
        lines = _flow_items(stripped)
    else:
        lines = [line for line in stripped.splitlines() if line.strip() and not line.strip().startswith("#")]
    entries = _entries(lines) if len(lines) >= 2 else None
    if entries is None:
        return text
    parts: list[str] = []
    for entry in entries:
        if entry.value:
            parts.append(_flat_part(entry.key, entry.value))
        elif entry.key in ("ego", "ego vehicle", "av"):  # the lines under it describe the ego vehicle
            parts.extend(
                f"ego: {c.value}"
                if c.key in ("action", "motion", "manoeuvre", "maneuver", "state")
                else _flat_part(c.key, c.value)
                for c in entry.children
                if c.value
            )
        elif entry.key in _ACTOR_KEYS:  # "target:\n  category: truck\n  motion: ...": its lines
            parts.extend(_flat_part(c.key, c.value) for c in entry.children if c.value)
        else:
            parts.extend(_group_part(entry.key, entry.children))
    return "; ".join(_attached(parts)) if len(parts) >= 2 else text
