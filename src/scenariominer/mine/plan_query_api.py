"""A query to a scenario API (GraphQL or a MongoDB filter), put in the plain words the rules read.

Developers who reach the data through an API write the request as the query they would send:
``{ objects(category: BUS, turning: LEFT) { trackId timestamps } }`` (GraphQL) or
``db.tracks.find({category: 'BUS', 'motion.speed_mps': {$gte: 12}})`` (a MongoDB filter).
:func:`query_api_request` reads the arguments (GraphQL) or the filter document (MongoDB) as
field-value pairs and words each one: the category names the road user, a true flag is its state
("parked", "on road"), a false one its negation, a bound says how much ("speed at least 12 m/s":
``min``/``max`` and ``$gte``/``$lte``/``$gt``/``$lt``, the unit from the field's suffix), and a
field whose value names another road user is a relation ("near a construction cone within 5 m",
"following a bus", ``$elemMatch`` included). Field names are the writer's own, so they are read as
words (``laneChange: LEFT`` -> "changing lanes to the left", ``'map.on_intersection': true`` ->
"on intersection"). A text that is neither query, or one that does not parse, comes back unchanged.
"""

from __future__ import annotations

import json
import re
from typing import Any

__all__ = ["query_api_request"]

_GRAPHQL = re.compile(
    r"^\s*(?:query\s*\w*\s*)?\{\s*(?P<field>\w+)\s*\((?P<args>.*)\)\s*\{[^()]*\}\s*\}\s*$", re.DOTALL
)
_MONGO = re.compile(r"^\s*db\.\w+\.find\(\s*(?P<doc>\{.*\})\s*(?:,\s*\{[^{}]*\}\s*)?\)\s*;?\s*$", re.DOTALL)
_UNITS = (("mps2", "m/s^2"), ("mps", "m/s"), ("kmh", "km/h"), ("meters", "m"), ("metres", "m"), ("m", "m"))
_BOUNDS = {"$gte": "at least", "$gt": "more than", "$lte": "at most", "$lt": "less than"}
_SIDES = {
    "ahead": "ahead of it", "forward": "ahead of it", "front": "in front of it", "behind": "behind it",
    "backward": "behind it", "back": "behind it", "left": "to its left", "right": "to its right",
}  # fmt: skip
#: Field words that name a relation to another road user ("{}": the other road user).
_RELATIONS = {
    "near": "near {}", "nearby": "near {}", "close to": "near {}", "following": "following {}",
    "following lead": "following {}", "follows": "following {}",
    "crossed by": "with {} crossing in front of it",
    "crossing in front of": "crossing in front of {}", "moving toward": "moving toward {}",
    "heading toward": "heading toward {}", "facing": "facing {}", "same lane as": "in the same lane as {}",
    "in same lane as": "in the same lane as {}", "oncoming": "with {} travelling in the opposite direction",
}  # fmt: skip


def query_api_request(description: str) -> str:
    """``description`` in words when it is a GraphQL query or a MongoDB filter, else as it is."""
    if match := _GRAPHQL.match(description):
        text = "{" + match["args"] + "}"
        if match["field"].lower().startswith("objectsindirection"):
            # objectsInDirection(of: EGO_VEHICLE, direction: LEFT, category: PEDESTRIAN, withinMeters: 15)
            return _in_direction(text, description)
    elif match := _MONGO.match(description):
        text = match["doc"]
    else:
        return description
    try:
        document = _parse(text)
    except ValueError:
        return description
    if not isinstance(document, dict):
        return description
    try:
        words = _document_words(document)
    except ValueError:  # a field this reading does not know
        return description
    return " and ".join(w for w in words if w) + "." if words else description


def _in_direction(text: str, description: str) -> str:
    try:
        fields = {_key_words(k): v for k, v in _parse(text).items()}
        side = {"left": "to the left of", "right": "to the right of", "ahead": "ahead of",
                "forward": "ahead of",
                "behind": "behind", "backward": "behind"}[str(fields["direction"]).lower()]  # fmt: skip
        within = next((v for k, v in fields.items() if k.startswith("within")), None)
        bound = f" within {within} m" if within is not None else ""
        return f"{_kind(fields['category'])} {side} {_article(_kind(fields['of']))}{bound}."
    except (ValueError, KeyError, AttributeError):
        return description


def _parse(text: str) -> Any:
    """A GraphQL argument list or a MongoDB document (unquoted keys, enums, single quotes) as JSON."""
    text = re.sub(r"'([^'\"]*)'", r'"\1"', text)
    text = re.sub(r"(?<=[{,\[])\s*(\$?[A-Za-z_][\w.$]*)\s*:", r' "\1":', text)
    text = re.sub(r"(?<=[:,\[])\s*([A-Z][A-Z0-9_]*)\s*(?=[,}\]])", r' "\1"', text)
    try:
        return json.loads(text)
    except json.JSONDecodeError as exc:
        raise ValueError(str(exc)) from None


def _key_words(key: str) -> str:
    key = re.sub(r"(?<=[a-z0-9])(?=[A-Z])", "_", key).lower()
    return " ".join(key.replace(".", "_").replace("$", "").split("_")).strip()


def _kind(value: Any) -> str:
    if isinstance(value, list):
        return " or ".join(_kind(v) for v in value)
    if isinstance(value, dict) and "$in" in value:
        return _kind(value["$in"])
    kind = str(value).replace("_", " ").lower()
    return "object" if kind == "any" else kind


def _document_words(document: dict[str, Any]) -> list[str]:
    subject: list[str] = []
    words: list[str] = []
    for key, value in document.items():
        if key == "$and" and isinstance(value, list):
            # "{$and: [{category: 'BUS'}, {'map.on_road': true}]}": one document
            merged: dict[str, Any] = {}
            for part in value:
                if not isinstance(part, dict) or set(part) & set(merged):
                    raise ValueError(key)
                merged.update(part)
            return _document_words({**{k: v for k, v in document.items() if k != "$and"}, **merged})
        name = _key_words(key)
        if re.fullmatch(r"(?:category|class|type|object type)(?: group)?(?: in)?", name):
            if isinstance(value, dict) and "$not" in value:
                words.extend(f"other than {k}" for k in _kind(value["$not"]).split(" or "))
            else:
                subject.append(_kind(value))
        elif re.fullmatch(r"(?:category|class|type) not(?: in)?", name):
            words.extend(f"other than {k}" for k in _kind(value).split(" or "))
        else:
            words.append(_field_words(name, value))
    if "ego vehicle" in subject and len(subject) > 1:
        subject.remove("ego vehicle")
    # "vehicle", "bus": the most specific kind names the road user
    return [subject[-1] if subject else "object", *words]


def _field_words(name: str, value: Any) -> str:
    """One field of the query in words."""
    name = re.sub(r"^(?:motion|map|state|relative|relation|kinematics|geometry|context|is) ", "", name)
    name = re.sub(
        r"\b(?:long(?:itudinal)? )?accel\b", "acceleration", re.sub(r"^long(?:itudinal)? (?=accel)", "", name)
    )
    if match := re.fullmatch(r"(?:nearby |near )?(\w+(?: \w+)?) count within (\d+(?:\.\d+)?) ?m", name):
        # "'nearby.pedestrian.count_within_15m': {$gte: 3}": at least 3 pedestrians within 15 m
        bound = value.get("$gte", value.get("$gt")) if isinstance(value, dict) else value
        if bound is None:
            raise ValueError(name)
        least = bound + 1 if isinstance(value, dict) and "$gt" in value else bound
        side, _, kind = match[1].rpartition(" ")
        where = f" {_SIDES[side]}" if side in _SIDES else ""
        return f"with at least {least} {kind}s{where} within {match[2]} m"
    if (match := re.fullmatch(r"(?P<place>.+?) distance(?: m)?", name)) and isinstance(value, dict):
        # "'map.pedestrian_crossing.distance_m': {$lte: 0}": within that distance of the place
        bound = value.get("$lte", value.get("$lt"))
        if bound is None or set(value) - {"$lte", "$lt"}:
            raise ValueError(name)
        return f"within {bound} m of {_PLACES.get(match['place'], _article(match['place']))}"
    if re.search(r"\bangle(?: deg)?$", name):
        return ""  # how exactly it faces or heads: the relation says it
    if value is True or (isinstance(value, dict) and value.get("$exists") is True):
        return _flag(name)
    if value is False or (isinstance(value, dict) and value.get("$exists") is False):
        return "not " + _flag(name)
    if isinstance(value, dict) and "$elemMatch" in value:
        value = value["$elemMatch"]
    if isinstance(value, str):
        return _enum(name, value.lower())
    if isinstance(value, (int, float)):
        return _bounded(name, {"$gte": value, "$lte": value} if name.endswith("count") else {"$gte": value})
    if isinstance(value, list):
        return _enum(name, " or ".join(str(v).lower() for v in value))
    if isinstance(value, dict) and "$in" in value:
        return _enum(name, " or ".join(str(v).lower() for v in value["$in"]))
    if isinstance(value, dict):
        return _nested(name, value)
    raise ValueError(name)


#: Map features as the place a distance is measured to.
_PLACES = {
    "pedestrian crossing": "a crosswalk", "crosswalk": "a crosswalk", "intersection": "an intersection",
    "nearby ego": "the ego vehicle", "ego": "the ego vehicle", "relative to ego": "the ego vehicle",
    "to ego": "the ego vehicle",
}  # fmt: skip


def _flag(name: str) -> str:
    name = re.sub(r"\b(?:whole log|entire log|all log)\b", "", name).strip()
    return {
        "parked": "parked", "exclude parked": "not parked", "include parked": "",
        "following lead": "following a vehicle",
    }.get(name, name)  # fmt: skip


def _enum(name: str, value: str) -> str:
    value = value.replace("_", " ")
    if name in ("lane change", "lane changing", "changing lanes"):
        return "changing lanes" if " or " in value else f"changing lanes to the {value}"
    if name in ("turning", "turn", "turn direction"):
        return "turning" if " or " in value else f"turning {value}"
    if name in ("lane type", "lane"):
        return f"in a {value} lane"
    if name in ("state", "status"):
        return value
    if name.endswith("angle deg") or name.endswith("angle"):
        return ""  # how exactly it faces: "facing" says it
    if name.endswith("position"):
        return f"{_SIDES.get(value, value)}".replace("it", "the ego vehicle")
    if name.endswith("road side vs ego") or name.endswith("side of road"):
        return f"on the {value} side of the road from the ego vehicle"
    relation = re.sub(r" category(?: group)?$", "", name)
    if relation in _RELATIONS:
        return _RELATIONS[relation].format(_article(_kind(value)))
    return f"{name} {value}"


def _bounded(name: str, bounds: dict[str, Any]) -> str:
    if name in ("speed mps", "speed", "velocity", "velocity mps", "speed m/s"):
        return _speed(bounds)
    unit = ""
    for suffix, words in _UNITS:
        if name.endswith(" " + suffix):
            name, unit = name[: -len(suffix) - 1], " " + words
            break
    parts = []
    for op, number in bounds.items():
        if op.startswith("min") or op == "$gte":
            parts.append(f"at least {number}{unit}")
        elif op.startswith("max") or op == "$lte":
            parts.append(f"at most {number}{unit}")
        elif op in _BOUNDS:
            parts.append(f"{_BOUNDS[op]} {number}{unit}")
        else:
            raise ValueError(op)
    if bounds.keys() == {"$gte", "$lte"} and len(set(bounds.values())) == 1:
        parts = [f"at least {bounds['$gte']}{unit}"]
    return " and ".join(f"{name} {p}" for p in parts)


def _speed(bounds: dict[str, Any]) -> str:
    """A speed bound as the motion words: "moving faster than 5 m/s", "at a speed between 2 and 6 m/s"."""
    low = next((v for k, v in bounds.items() if k in ("$gte", "$gt") or k.startswith("min")), None)
    high = next((v for k, v in bounds.items() if k in ("$lte", "$lt") or k.startswith("max")), None)
    if low is not None and high is not None:
        return f"moving at a speed between {low} and {high} m/s"
    if low is not None:
        return f"moving faster than {low} m/s"
    if high is not None:
        return f"moving slower than {high} m/s"
    raise ValueError("speed")


def _nested(name: str, value: dict[str, Any]) -> str:
    """A field whose value is a document: a bound, or a relation to another road user."""
    if all(re.match(r"^(?:\$(?:gte|gt|lte|lt)|(?:min|max)\w*)$", k) for k in value):
        units = {re.sub(r"^(?:min|max)", "", k).lower() for k in value if not k.startswith("$")}
        unit = units.pop() if len(units) == 1 else ""
        return _bounded(f"{name} {unit}".strip(), value)
    fields = {_key_words(k): v for k, v in value.items()}
    other = _article(_kind(fields.pop("category", fields.pop("category group", fields.pop("of", "object")))))
    within = next((v for k, v in fields.items() if re.match(r"(?:within|distance|max)", k)), None)
    if isinstance(within, dict):  # "distance_m: {$lte: 10}"
        within = within.get("$lte", within.get("$lt"))
    count = next((v for k, v in fields.items() if re.match(r"(?:min count|count|min number)", k)), None)
    distance = (
        f" within {within} m" if isinstance(within, (int, float)) and not isinstance(within, bool) else ""
    )
    if name in ("has in direction", "objects in direction"):
        side = _SIDES.get(str(fields.get("direction", "")).lower())
        if side is None:
            raise ValueError(name)
        return f"with {other} {side}{distance}"
    if name in ("travel direction", "heading relative", "direction"):
        relation = str(fields.get("is", fields.get("direction", ""))).lower()
        rel = _article(_kind(fields.get("relative to", "ego vehicle")))
        return f"travelling in the {relation} direction {'as' if relation == 'same' else 'to'} {rel}"
    if name in ("side of road", "road side"):
        rel = _article(_kind(fields.get("relative to", "ego vehicle")))
        return f"on the {str(fields.get('side', '')).lower()} side of the road from {rel}"
    if name == "lateral acceleration":
        side = str(fields.get("direction", "")).lower()
        bound = next((v for k, v in fields.items() if k.startswith("min")), None)
        return f"with a lateral acceleration of at least {bound} m/s^2 to the {side}"
    if name in ("on pedestrian crossing", "at pedestrian crossing", "near intersection"):
        place = "a crosswalk" if "crossing" in name else "an intersection"
        return f"within {within} m of {place}" if within else f"on {place}"
    if name in _SIDES:
        # "'relative.forward': {$elemMatch: {category: 'PEDESTRIAN', distance_m: {$lte: 15}}}"
        return f"with {other} {_SIDES[name]}{distance}"
    if name in _RELATIONS:
        if isinstance(count, int) and count > 1:
            return f"with at least {count} {_kind(other.split(' ', 1)[-1])}s{distance or ' nearby'}"
        return _RELATIONS[name].format(other) + distance
    raise ValueError(name)


def _article(kind: str) -> str:
    if kind.startswith(("the ", "a ", "an ")) or kind == "ego vehicle":
        return "the ego vehicle" if kind == "ego vehicle" else kind
    return f"an {kind}" if kind[:1] in "aeiou" else f"a {kind}"
