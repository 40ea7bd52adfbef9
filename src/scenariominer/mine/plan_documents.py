"""Requests written as parts of other documents, put in the form the phrase rules read.

* a parameter block in YAML style, one ``key: value`` per line (nested keys indented, lists in
  brackets, flags as true/false, units in key names): "actor: bus / state: stopped / map: near
  intersection" -> "actor: bus; state: stopped; map: near intersection", which
  :mod:`scenariominer.mine.plan_wording` reads as a specification line; "on_road: false" -> "not on
  road", "changing_lanes: left" -> "changing lanes to the left", "max_distance_m: 20" -> a range of
  20 m, "lane: same as ego" -> "in the same lane as the ego vehicle";
* an issue tracker's ticket title: the ticket key and the bracketed tags before the title are
  dropped ("[LBL-12] [ped][crossing] Tag pedestrians crossing ..." -> "tag pedestrians crossing ...");
* a clause of a tender or contract: its number, "the supplier shall identify", "every instance of",
  "all occurrences wherein" are dropped, and "ensure that all trucks turning right are identified"
  is read as "trucks turning right".

:func:`yaml_block` reads the text with its line breaks (before they are joined);
:func:`document_wording` reads the joined lower-case text.
"""

from __future__ import annotations

import re

__all__ = ["document_wording", "yaml_block"]

#: One line of a parameter block: an optional list dash, a key, a colon, a value (maybe none).
_YAML_LINE = re.compile(r"^(?P<indent>\s*)(?:-\s+)?(?P<key>[a-z][a-z0-9_ .-]*?)\s*:\s*(?P<value>.*?)\s*$")
_TRUE = frozenset(("true", "yes", "y", "on", "1"))
_FALSE = frozenset(("false", "no", "n", "off", "0", "none"))
#: The words of a key that names a distance or speed limit ("max_distance_m", "speed_min_mps").
_LIMIT_WHAT = frozenset(("distance", "dist", "range", "radius", "gap", "within", "speed", "velocity"))
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
    "kph": "km/h", "km/h": "km/h",
}  # fmt: skip


def _limit_key(key: str) -> tuple[str, str, str] | None:
    """(what, bound, unit) of a key naming a limit ("speed max mps" -> ("speed", "max", "m/s"))."""
    words = key.split()
    what = [w for w in words if w in _LIMIT_WHAT]
    if len(what) != 1 or any(
        w not in _LIMIT_WHAT and w not in _LIMIT_BOUND and w not in _LIMIT_UNIT for w in words
    ):
        return None
    bound = next((_LIMIT_BOUND[w] for w in words if w in _LIMIT_BOUND), "")
    unit = next((_LIMIT_UNIT[w] for w in words if w in _LIMIT_UNIT), "")
    return what[0], bound, unit


_NUMBER = re.compile(r"^(?:[<>]=?\s*)?(\d+(?:\.\d+)?)\s*(m/s|mps|km/h|kmh|kph|m|metres|meters)?$")
#: "lane: same as ego", "lane: ego lane", "lane: same": the lane of another object.
_SAME_LANE = re.compile(r"^(?:same(?: lane)?(?: as (?P<other>.+))?|(?P<own>ego|the ego)(?:'s)? lane)$")
#: "position: ahead", "side: left of ego": a place relative to another object.
_PLACE = {
    "ahead": "in front of",
    "in front": "in front of",
    "front": "in front of",
    "forward": "in front of",
    "behind": "behind",
    "back": "behind",
    "rear": "behind",
    "left": "on the left of",
    "right": "on the right of",
}
_PLACE_VALUE = re.compile(
    rf"^(?P<place>{'|'.join(sorted(_PLACE, key=len, reverse=True))})(?: of (?P<other>.+))?$"
)


def _reference(other: str | None) -> str:
    """The object a relation refers to: "ego" (or nothing) -> "the ego vehicle"."""
    if other is None or other.strip() in ("ego", "the ego", "ego vehicle", "the ego vehicle", "av", "the av"):
        return "the ego vehicle"
    return other.strip()


def _yaml_part(key: str, value: str) -> str:
    """One ``key: value`` line of a parameter block as a part of a specification line."""
    if (limit := _limit_key(key)) is not None and (number := _NUMBER.match(value)) is not None:
        what, bound, key_unit = limit
        unit = _LIMIT_UNIT.get(number[2] or "", key_unit)
        if what in ("speed", "velocity"):
            return f"speed: {'faster' if bound == 'min' else 'slower'} than {number[1]} {unit or 'm/s'}"
        if bound == "min":
            return f"condition: at least {number[1]} {unit or 'm'} away"
        return f"range: {number[1]} {unit or 'm'}"
    if value in _TRUE:  # "stopped: true" -> a condition named by the key
        return f"condition: {key}"
    if value in _FALSE:
        return f"condition: not {key}"
    if re.match(r"^\w+ing\b", key) and value in ("left", "right"):  # "changing lanes: left"
        return f"motion: {key} {'to the ' if key.startswith('changing') else ''}{value}"
    if key == "lane" and (same := _SAME_LANE.match(value)) is not None:
        return f"condition: in the same lane as {_reference(same['other'])}"
    if key in ("position", "relative position", "side", "location") and (place := _PLACE_VALUE.match(value)):
        return f"condition: {_PLACE[place['place']]} {_reference(place['other'])}"
    return f"{key}: {value}"


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


def yaml_block(text: str) -> str:
    r"""A parameter block (two or more ``key: value`` lines, or a one-line "{...}") as one line.

    "actor: bus\nstate: stopped" -> "actor: bus; state: stopped"; "target:\n  category: truck\n
    motion: turning left" -> "category: truck; motion: turning left" (a key without a value only
    groups the lines under it; under "ego:" they describe the ego vehicle); "objects: [car, box
    truck]" -> "objects: car or box truck". A text that is not such a block is returned as it is.
    """
    stripped = text.strip()
    if stripped.startswith("{") and stripped.endswith("}") and ":" in stripped:
        lines = _flow_items(stripped)
    else:
        lines = [line for line in stripped.splitlines() if line.strip() and not line.strip().startswith("#")]
    if len(lines) < 2:
        return text
    parts: list[str] = []
    parent, parent_indent = "", -1
    for line in lines:
        found = _YAML_LINE.match(line)
        if found is None:
            return text
        indent = len(found["indent"])
        key = " ".join(found["key"].replace("_", " ").replace("-", " ").split())
        value = " ".join(found["value"].strip("'\"").replace("_", " ").split())
        if indent <= parent_indent:
            parent, parent_indent = "", -1
        if not value:  # a key that groups the lines under it
            parent, parent_indent = key, indent
            continue
        if value.startswith("[") and value.endswith("]"):
            value = " or ".join(v.strip().strip("'\"") for v in value[1:-1].split(",") if v.strip())
        if parent in ("ego", "ego vehicle", "av") and key in (
            "action",
            "motion",
            "manoeuvre",
            "maneuver",
            "state",
        ):
            parts.append(f"ego: {value}")
            continue
        parts.append(_yaml_part(key, value))
    return "; ".join(_referred(parts)) if len(parts) >= 2 else text


#: Keys that name the object the part before them refers to ("within_m: 10 / of: ego").
_REFERENCE_KEYS = frozenset(("of", "from", "to", "relative to", "reference", "wrt", "with respect to", "ref"))


def _referred(parts: list[str]) -> list[str]:
    """``parts`` with a reference key ("of: truck") folded into the part before it."""
    out: list[str] = []
    for part in parts:
        key, _, value = part.partition(": ")
        if key in _REFERENCE_KEYS and out:
            before_key, _, before = out[-1].partition(": ")
            if before_key == "range":  # "range: 10 m" of X -> "within 10 m of X"
                out[-1] = f"condition: within {before} of {_reference(value)}"
            else:
                out[-1] = out[-1].replace("the ego vehicle", _reference(value))
            continue
        out.append(part)
    return out


#: Wording of a ticket title and of a contract clause, dropped or put plainly.
_DOCUMENT: tuple[tuple[re.Pattern[str], str], ...] = (
    # a ticket title: "[LBL-1021] [ped] [crossing] Tag ..." / "MINE-301 [bus] Label ..." / "QA-7: Find ..."
    (re.compile(r"^\[?[a-z][a-z0-9]*-\d+\]?(?::\s*|\s+)(?=\[|[a-z])"), ""),
    (re.compile(r"^(?:\[[\w ./:&+-]{1,30}\]\s*)+(?::\s*|-\s+)?"), ""),
    # a contract clause: its number ("3.1", "4.2.1.", "R-12", "(a)")
    (
        re.compile(
            r"^(?:(?:clause|section|req(?:uirement)?|item)\s+)?(?:[a-z]{1,4}-\d+[.):]?|\d+(?:\.\d+)+[.)]?|\d+[.)])"
            r"\s+(?=\D)"
        ),
        "",
    ),
    (re.compile(r"^\([a-z0-9]{1,3}\)\s+"), ""),
    (
        re.compile(
            r"^the (?:supplier|contractor|vendor|provider|service provider|bidder|tenderer|consultant)"
            r" (?:shall|must|will|is required to|agrees to)(?: be required to)?"
            r"(?: (?:identify|deliver|provide|extract|supply|detect|annotate|report|list|tag|label|mine"
            r"|furnish|produce|return|submit|flag|locate|retrieve|mark)"
            r"(?: and (?:identify|deliver|provide|extract|supply|report|list|tag|label"
            r"|mark|flag))?)?(?: to the (?:client|authority|purchaser|buyer|contracting authority))?,?\s+"
        ),
        "",
    ),
    (re.compile(r"^(?:each|every) (?=\S)"), ""),
    # "ensure that all trucks turning right are identified" -> "all trucks turning right"
    (
        re.compile(
            r"^ensure that (.+?) (?:is|are) (?:identified|extracted|delivered|reported|detected|labelled"
            r"|labeled|tagged|flagged|provided)(?: in full)?\.?$"
        ),
        r"\1",
    ),
    (
        re.compile(
            r"^(?:all |every |each |any )?(?:(?:relevant|such) )?(?:instances?|occurrences?|cases?|examples?"
            r"|events?|situations?|scenarios?|episodes?|time (?:intervals?|periods?|spans?))"
            r" (?:of|wherein|where|in which|whereby|during which|when)\s+"
        ),
        "",
    ),
    # what the supplier delivers it with: "..., together with the timestamps", "in the agreed format"
    (
        re.compile(
            r"(?:^|,? )together with (?:the |their |its )?(?:timestamps?|track ids?|frame ids?)"
            r"(?: and (?:the |their |its )?(?:timestamps?|track ids?|frame ids?))?,?(?= |$)"
        ),
        "",
    ),
    (re.compile(r"^(?:and |, ?)"), ""),
    (re.compile(r",? (?:in|using) the (?:agreed|specified|prescribed) (?:format|schema|manner)\b.*$"), ""),
    (re.compile(r",? (?:as|which shall be|to be) delivered (?:to|in)\b.*$"), ""),
    # "in the same lane as and ahead of the ego vehicle": each relation with its object
    (
        re.compile(
            r"\b(in the same lane as|next to|behind|ahead of|in front of),? and (in the same lane as|next to"
            r"|behind|ahead of|in front of),? (the ego vehicle|the ego|(?:the|a|an) [a-z]+)\b"
        ),
        r"\1 \3 and \2 \3",
    ),
)


def document_wording(text: str) -> str:
    """``text`` (lower case, one line) without the ticket or clause wording around the request."""
    for pattern, replacement in _DOCUMENT:
        text = pattern.sub(replacement, text)
    return text
