"""A graph-database pattern query, put in the plain words the phrase rules read.

Users of graph databases write a scenario as a Cypher-like pattern: road users are nodes labelled
by their category, what holds between them is a relationship, and a ``WHERE`` clause tests their
properties, e.g. ``MATCH (p:Pedestrian)-[:NEAR {max_m: 5}]->(e:Ego) WHERE p.speed > 1 RETURN p``.
:func:`graph_pattern` rewrites such a query into one English phrase about the returned node:
"pedestrian moving faster than 1 m/s and near the ego vehicle within 5 m". Map features are nodes
too (``(:Crosswalk)``, ``(:Intersection)``, ``(:DrivableArea)``; two road users ``IN`` the same
``(:Lane)`` node share a lane). Relationship and property names are the user's own, so they are
read as words (``CROSSING_IN_FRONT_OF`` -> "crossing in front of", ``FOLLOWS`` -> "following",
``is_parked = true`` -> "parked"); the returned node as the target of a relationship takes its
inverse ("being followed by", "behind"); ``HAS_AHEAD`` names where the other road user is ("with
a vehicle ahead of it"), and ``WITH v, count(p) AS n WHERE n >= 3`` asks for at least 3 of them
(``= 3`` is read as at least 3 too). A query that has alternatives (``OR``), a condition on a
road user other than the returned one, or a part this reading does not know comes back unchanged,
for the other readers (and the language model) to read.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field

from scenariominer.mine.plan_nouns import CATEGORY_RE

__all__ = [
    "GraphQuery",
    "Unreadable",
    "distance_test",
    "graph_pattern",
    "label_phrase",
    "node_label",
    "property_words",
    "query_words",
    "relationship_words",
    "top_level_split",
]

_QUERY = re.compile(
    r"^\s*match\s+(?P<pattern>.+?)(?:\s+where\s+(?P<where>.+?))?\s+return\s+(?:distinct\s+)?"
    r"(?P<ret>[a-z_]\w*)\b[^()]*?;?\s*$",
    re.IGNORECASE | re.DOTALL,
)
_NODE = re.compile(
    r"\(\s*(?P<var>[a-z_]\w*)?\s*(?::\s*(?P<label>[a-z_][\w]*))?\s*(?P<props>\{[^{}]*\})?\s*\)", re.IGNORECASE
)
_REL = re.compile(
    r"\s*(?P<left><)?-\s*(?:\[\s*(?P<var>[a-z_]\w*)?\s*(?::\s*(?P<type>[a-z_]\w*))?\s*(?P<props>\{[^{}]*\})?\s*\])?"
    r"\s*-(?P<right>>)?\s*",
    re.IGNORECASE,
)
_NUMBER = r"-?\d+(?:\.\d+)?"
_VALUE = rf"(?:{_NUMBER}|'[^']*'|\"[^\"]*\"|true|false)"
_COMPARISON = re.compile(
    rf"^(?P<var>[a-z_]\w*)\.(?P<prop>[a-z_]\w*)\s*(?P<op><>|!=|>=|<=|=~|==|=|<|>)\s*(?P<value>{_VALUE})$",
    re.IGNORECASE,
)
_COUNTED = re.compile(
    r"\s+with\s+(?P<kept>[a-z_]\w*)\s*,\s*count\(\s*(?:distinct\s+)?(?P<var>[a-z_]\w*)\s*\)\s+as\s+(?P<n>[a-z_]\w*)"
    r"\s+where\s+(?P=n)\s*(?P<op>>=|>|=)\s*(?P<number>\d+)(?=\s+return\b)",
    re.IGNORECASE,
)
_FLAG = re.compile(r"^(?P<var>[a-z_]\w*)\.(?P<prop>[a-z_]\w*)$", re.IGNORECASE)

#: Labels of the ego vehicle (lower case, without underscores).
_EGO = frozenset({"ego", "egovehicle", "av", "self", "sdc", "autonomousvehicle", "ourcar", "host"})
#: Map features as the phrase after a relationship; ``None`` for a lane (read with a second user).
_MAP: dict[str, str | None] = {
    "crosswalk": "a crosswalk",
    "pedestriancrossing": "a crosswalk",
    "crossing": "a crosswalk",
    "zebracrossing": "a crosswalk",
    "intersection": "an intersection",
    "junction": "an intersection",
    "drivablearea": "the drivable area",
    "road": "the road",
    "roadway": "the road",
    "lane": None,
}
#: Relationship verbs in the third person, as the -ing form ("FOLLOWS" -> "following").
_VERBS = {
    "follows": "following",
    "changes": "changing",
    "overtakes": "overtaking",
    "passes": "passing",
    "approaches": "approaching",
    "crosses": "crossing",
    "faces": "facing",
    "heads": "heading",
    "tailgates": "tailgating",
    "yields": "yielding",
    "turns": "turning",
    "moves": "moving",
    "drives": "driving",
    "travels": "travelling",
    "walks": "walking",
    "rides": "riding",
    "goes": "going",
    "runs": "running",
}
#: Relationship words as the returned node's phrase when it is the relationship's target ("{}":
#: the other road user).
_INVERSE = {
    "following": "being followed by {}",
    "tailgating": "being followed by {}",
    "overtaking": "being overtaken by {}",
    "passing": "being overtaken by {}",
    "near": "near {}",
    "close to": "near {}",
    "next to": "near {}",
    "within": "within {}",
    # "P in front of V", V returned: in V's own frame, so V has P in front of it
    "ahead of": "with {} ahead of it",
    "in front of": "with {} in front of it",
    "behind": "with {} behind it",
    "to the left of": "with {} to the left of it",
    "to the right of": "with {} to the right of it",
    "in the same lane as": "in the same lane as {}",
    "crossing in front of": "with {} crossing in front of it",
    "crossing": "being crossed by {}",
}
#: "HAS_AHEAD", "HAS_BEHIND": the other road user where it is, seen from the returned node.
_HAS = {
    "ahead": "ahead of it",
    "in front": "in front of it",
    "behind": "behind it",
    "left": "to the left of it",
    "right": "to the right of it",
    "on left": "to the left of it",
    "on right": "to the right of it",
    "nearby": "nearby",
    "near": "nearby",
}
#: Verbs of motion a relative direction qualifies ("TRAVELS {relative_direction: 'opposite'}").
_MOTION = frozenset({"travelling", "moving", "driving", "walking", "heading", "going", "riding"})
_RELATIVE = {
    "opposite": "in the opposite direction to",
    "same": "in the same direction as",
    "perpendicular": "perpendicular to",
}
#: Relationship types that mean one of the phrases above in other words.
_REL_WORDS = {
    "left of": "to the left of",
    "right of": "to the right of",
    "same lane": "in the same lane as",
    "same lane as": "in the same lane as",
    "in same lane as": "in the same lane as",
    "in same lane": "in the same lane as",
    "in lane of": "in the same lane as",
    "crosses in front of": "crossing in front of",
    "is in front of": "in front of",
}
_LOCATED = frozenset({"on", "in", "at", "inside", "within", "located in", "located on", "located at"})


class Unreadable(Exception):
    """A part of the query this reading does not put in words."""


@dataclass
class GraphQuery:
    """The road users, places, relationships and tests of one pattern, by variable name."""

    labels: dict[str, str] = field(default_factory=dict)  # variable -> label (lower case)
    #: (source, relationship words, stated distance in metres or None, target, negated)
    edges: list[tuple[str, str, str | None, str, bool]] = field(default_factory=list)
    #: (variable, phrase) conditions on a node's properties
    conditions: list[tuple[str, str]] = field(default_factory=list)
    #: relationship variable -> its index in ``edges``
    relationships: dict[str, int] = field(default_factory=dict)
    #: variable -> the least number of such road users ("WITH e, count(p) AS n WHERE n >= 3")
    counts: dict[str, int] = field(default_factory=dict)
    anonymous: int = 0


def graph_pattern(description: str) -> str:
    """``description`` as plain words when it is a graph pattern query, else unchanged."""
    query = GraphQuery()
    # "WITH e, count(p) AS n WHERE n >= 3": at least 3 of p
    counted = _COUNTED.search(description)
    if counted is not None:
        least = int(counted["number"]) + (1 if counted["op"] == ">" else 0)
        query.counts[counted["var"]] = least
        description_seen = description[: counted.start()] + " " + description[counted.end() :]
    else:
        description_seen = description
    found = _QUERY.match(description_seen)
    if found is None:
        return description
    try:
        # a second MATCH is another part of the same pattern
        pattern = re.sub(r"\s+match\s+", ", ", found.group("pattern"), flags=re.IGNORECASE)
        for path in top_level_split(pattern, ","):
            _read_path(path.strip(), query, negated=False)
        if found.group("where"):
            for test in top_level_split(found.group("where"), " and "):
                _read_test(test.strip(), query)
        return query_words(query, found.group("ret"))
    except Unreadable:
        return description


def top_level_split(text: str, separator: str) -> list[str]:
    """``text`` split at ``separator`` (case-insensitive) outside brackets and quotes."""
    parts, depth, quote, start, i = [], 0, "", 0, 0
    lowered = text.lower()
    while i < len(text):
        ch = text[i]
        if quote:
            quote = "" if ch == quote else quote
        elif ch in "'\"":
            quote = ch
        elif ch in "([{":
            depth += 1
        elif ch in ")]}":
            depth -= 1
        elif depth == 0 and lowered.startswith(separator, i):
            parts.append(text[start:i])
            start = i + len(separator)
            i = start
            continue
        i += 1
    parts.append(text[start:])
    return [p for p in parts if p.strip()]


def _read_path(path: str, query: GraphQuery, *, negated: bool) -> None:
    """The nodes and relationships of one path ``(a:A)-[:R]->(b:B)...`` into ``query``."""
    node = _NODE.match(path)
    if node is None:
        raise Unreadable(path)
    previous, at = _add_node(node, query), node.end()
    while at < len(path):
        rel = _REL.match(path, at)
        if rel is None:
            raise Unreadable(path[at:])
        node = _NODE.match(path, rel.end())
        if node is None or not rel.group("type"):
            raise Unreadable(path[at:])
        current = _add_node(node, query)
        words, distance = relationship_words(rel.group("type"), rel.group("props"))
        if rel.group("var"):
            query.relationships[rel.group("var")] = len(query.edges)
        if rel.group("left") and not rel.group("right"):
            query.edges.append((current, words, distance, previous, negated))
        else:
            query.edges.append((previous, words, distance, current, negated))
        previous, at = current, node.end()


def _add_node(node: re.Match[str], query: GraphQuery) -> str:
    var = node.group("var")
    if not var:
        query.anonymous += 1
        var = f"_{query.anonymous}"
    label = node.group("label")
    if label:
        query.labels[var] = label.lower().replace("_", "")
    elif var not in query.labels:
        raise Unreadable(f"node {var} has no label")
    for prop, value in _properties(node.group("props")):
        query.conditions.append((var, property_words(prop, "=", value)))
    return var


def _properties(props: str | None) -> list[tuple[str, str]]:
    """The ``{key: value, ...}`` map of a node or relationship as (key, value) pairs."""
    if not props:
        return []
    pairs = []
    for item in top_level_split(props.strip("{} "), ","):
        key, colon, value = item.partition(":")
        if not colon or not re.fullmatch(_VALUE, value.strip(), re.IGNORECASE):
            raise Unreadable(item)
        pairs.append((key.strip().lower(), value.strip().strip("'\"").lower()))
    return pairs


def relationship_words(kind: str, props: str | None) -> tuple[str, str | None]:
    """A relationship type as words, and the distance in metres its properties state.

    ``HAS_AHEAD`` stays "has ahead" (the other road user is ahead of this one); a direction
    property qualifies a turn or a lane change ("TURNING {direction: 'right'}" -> "turning right")
    and a relative direction a motion ("TRAVELS {relative_direction: 'opposite'}" -> "travelling in
    the opposite direction to"). An angle, or any other property, is not read.
    """
    words = kind.lower().replace("_", " ").strip()
    words = re.sub(r"^(?:is|are|was) ", "", words)
    first, _, rest = words.partition(" ")
    words = " ".join([_VERBS.get(first, first), *([rest] if rest else [])])
    words = _REL_WORDS.get(words, words)
    distance = None
    for key, value in _properties(props):
        if re.search(r"angle|deg|heading|yaw", key):
            raise Unreadable(f"{key}: {value}")
        if re.fullmatch(_NUMBER, value) and re.search(
            r"dist|max|within|range|radius|(?:^|_)m$|meters|metres", key
        ):
            distance = value
        elif (
            re.search(r"(?:^|_)(?:dir|direction|side|way)$", key) and value in _RELATIVE and words in _MOTION
        ):
            words = f"{words} {_RELATIVE[value]}"
        elif re.search(r"(?:^|_)(?:dir|direction|side|way)$", key) and value in ("left", "right"):
            if words in ("turning", "turn"):
                words = f"turning {value}"
            elif re.fullmatch(r"chang(?:es|ing) lanes?(?: to)?|lane change", words):
                words = f"changing lanes to the {value}"
            else:
                raise Unreadable(f"{key}: {value}")
        else:
            raise Unreadable(f"{key}: {value}")
    return words, distance


def _read_test(test: str, query: GraphQuery) -> None:
    """One conjunct of the ``WHERE`` clause into ``query``."""
    if re.search(r"\bor\b|\bxor\b", test, re.IGNORECASE):
        raise Unreadable("or")
    negated = False
    while (inner := re.match(r"^not\s*(?P<rest>.+)$|^\((?P<paren>.+)\)$", test, re.IGNORECASE)) is not None:
        if inner.group("rest") is not None:
            negated, test = not negated, inner.group("rest").strip()
        elif _NODE.fullmatch(test) or "-" in test and _NODE.match(test):
            break  # a pattern in brackets: the node's own brackets
        else:
            test = inner.group("paren").strip()
    test = re.sub(r"^exists\s*[({]\s*(?P<p>.+?)\s*[)}]$", r"\g<p>", test, flags=re.IGNORECASE)
    if _NODE.match(test) and _REL.search(test):
        _read_path(test, query, negated=negated)
        return
    if (cmp := _COMPARISON.match(test)) is not None:
        op = cmp.group("op")
        if negated:
            op = {"=": "<>", "==": "<>", "<>": "=", "!=": "="}.get(op, "")
            if not op:
                raise Unreadable(test)
        value = cmp.group("value").strip("'\"").lower()
        if cmp.group("var") in query.relationships:
            distance_test(query, cmp.group("var"), cmp.group("prop").lower(), op, value)
            return
        query.conditions.append((cmp.group("var"), property_words(cmp.group("prop").lower(), op, value)))
        return
    if (flag := _FLAG.match(test)) is not None:
        value = "false" if negated else "true"
        query.conditions.append((flag.group("var"), property_words(flag.group("prop").lower(), "=", value)))
        return
    raise Unreadable(test)


def distance_test(query: GraphQuery, var: str, prop: str, op: str, value: str) -> None:
    """A distance bound on a relationship variable (``r.distance < 5``) as that relationship's."""
    if not (op in ("<", "<=") and re.fullmatch(_NUMBER, value) and re.search(r"dist|range|(?:^|_)m$", prop)):
        raise Unreadable(f"{var}.{prop} {op} {value}")
    index = query.relationships[var]
    source, words, _, target, negated = query.edges[index]
    query.edges[index] = (source, words, value, target, negated)


def property_words(prop: str, op: str, value: str) -> str:
    """A property test as words: ``speed > 10`` -> "moving faster than 10 m/s"."""
    prop = re.sub(r"^(?:is|has)_", "", prop)
    prop = re.sub(r"^(?:long|lon|longitudinal|forward|fwd)_(?=acc)", "", prop)  # "longitudinal_accel"
    unit = "km/h" if re.search(r"kmh|kph", prop) else "mph" if "mph" in prop else "m/s"
    number = re.fullmatch(_NUMBER, value) is not None
    if (
        re.match(r"(?:abs_?)?(?:speed|velocity|vel)\b|(?:speed|velocity)_", prop)
        and number
        and op in ("<", "<=", ">", ">=")
    ):
        if op in (">", ">="):
            return f"moving faster than {value} {unit}"
        if op in ("<", "<="):
            return f"moving slower than {value} {unit}"
    if re.match(r"(?:accel|acceleration|acc)(?:_|$)", prop) and number and op in ("<", "<=", ">", ">="):
        return f"with acceleration {'below' if op[0] == '<' else 'above'} {value} m/s^2"
    if op in ("=", "==", "<>", "!="):
        positive = op in ("=", "==")
        if value in ("true", "false"):
            words = prop.replace("_", " ")
            return words if positive == (value == "true") else f"not {words}"
        if not number and positive:
            if re.fullmatch(r"turn(?:ing)?(?:_dir(?:ection)?)?|turn_?type|manoeuvre|maneuver", prop):
                return f"turning {value}"
            if re.fullmatch(r"lane_?change(?:_dir(?:ection)?)?|changing_lanes|lane_change_side", prop):
                return f"changing lanes to the {value}"
            if re.fullmatch(r"state|status|motion|activity|action", prop):
                return value.replace("_", " ")
    raise Unreadable(f"{prop} {op} {value}")


def _noun(label: str) -> str:
    """A road-user label as words ("boxtruck" -> "box truck"); not a road user: :class:`Unreadable`."""
    if label in _EGO:
        return "the ego vehicle"
    if label in _MAP:
        raise Unreadable(f"a map feature is no road user: {label}")
    noun = {
        "regularvehicle": "regular vehicle",
        "boxtruck": "box truck",
        "wheeleddevice": "wheeled device",
    }.get(label, label)
    if re.fullmatch(CATEGORY_RE, noun) is not None:
        return noun
    # two words run together ("schoolbus", "constructioncone")
    for at in range(2, len(noun) - 1):
        if re.fullmatch(CATEGORY_RE, spaced := f"{noun[:at]} {noun[at:]}") is not None:
            return spaced
    raise Unreadable(f"not a road user: {label}")


def node_label(name: str) -> str | None:
    """``name`` as a node label when it names a road user, the ego vehicle or a map feature.

    ``"Box_Truck"`` -> ``"boxtruck"``, ``"crosswalk"`` -> ``"crosswalk"``; ``None`` for other words.
    """
    label = re.sub(r"[\s_-]+", "", name.lower())
    if label in _EGO or label in _MAP:
        return label
    for candidate in (re.sub(r"[\s_-]+", " ", name.lower()).strip(), label):
        try:
            _noun(candidate)
        except Unreadable:
            continue
        return candidate
    return None


def label_phrase(label: str) -> str:
    """A node label with its article ("crosswalk" -> "a crosswalk", "ego" -> "the ego vehicle")."""
    if label in _MAP:
        if _MAP[label] is None:
            raise Unreadable("lane")
        return str(_MAP[label])
    return _with_article(_noun(label))


def _with_article(noun: str) -> str:
    return noun if noun.startswith("the ") else f"{'an' if noun[0] in 'aeiou' else 'a'} {noun}"


def query_words(query: GraphQuery, returned: str) -> str:
    """The phrase of the returned node: its noun, its property tests, its relationships."""
    if returned not in query.labels:
        raise Unreadable(returned)
    _merge_distances(query)
    phrases = [phrase for var, phrase in query.conditions if var == returned]
    # a test another one narrows says nothing more ("turning" beside "turning left")
    phrases = [p for p in dict.fromkeys(phrases) if not any(q.startswith(f"{p} ") for q in phrases)]
    adjectives: dict[str, list[str]] = {}
    for var, phrase in query.conditions:
        if var != returned:
            # another road user's test: a one-word state only ("a parked car")
            if not re.fullmatch(r"moving|stationary|parked|stopped", phrase):
                raise Unreadable(phrase)
            adjectives.setdefault(var, []).append(phrase)

    def other(var: str) -> str:
        if var not in query.labels:
            raise Unreadable(f"{var} is of no kind")
        label = query.labels[var]
        if label in _MAP:
            if _MAP[label] is None:
                raise Unreadable("lane")
            return str(_MAP[label])
        return _with_article(" ".join([*adjectives.get(var, []), _noun(label)]))

    lane_edges, lane_mates = _shared_lanes(query, returned)
    for source, words, distance, target, negated in query.edges:
        if (source, target) in lane_edges:
            continue
        if returned not in (source, target):
            raise Unreadable("a relationship between two other nodes")
        mate = target if source == returned else source
        counted = query.counts.get(mate)
        if counted is not None and query.labels[mate] not in _MAP and query.labels[mate] not in _EGO:
            named = f"at least {counted} {_plural(_noun(query.labels[mate]))}"
        elif counted is not None:
            raise Unreadable("a count of a map feature or of the ego vehicle")
        else:
            named = other(mate)
        if counted is not None and words in ("within", "close to"):
            words = "near"
        phrase = _edge_phrase(words, named, query.labels[mate], outgoing=source == returned, negated=negated)
        if counted is not None and words == "near" and distance is not None:
            phrase = f"with {named} within {distance} m"  # "with at least 3 pedestrians within 20 m"
        elif distance is not None:
            phrase = (
                f"within {distance} m of {named}"
                if words in ("within", "near", "close to") and not negated
                else f"{phrase} within {distance} m"
            )
        phrases.append(f"not {phrase}" if negated and not words.startswith("has ") else phrase)
    phrases += [f"in the same lane as {other(mate)}" for mate in lane_mates]
    return " ".join([_noun(query.labels[returned]), " and ".join(phrases)]).strip()


#: Relationships that say where one road user is from another, which a distance can bound.
_POSITIONAL = frozenset({"ahead of", "in front of", "behind", "to the left of", "to the right of"})


def _merge_distances(query: GraphQuery) -> None:
    """A distance between two road users and where one is from the other, as one relationship.

    "in_front_of(P, V), distance(V, P, D), D < 15": P in front of V within 15 m.
    """
    for index, (source, words, distance, target, negated) in enumerate(query.edges):
        if words != "within" or distance is None or negated:
            continue
        for other, (o_source, o_words, o_distance, o_target, o_negated) in enumerate(query.edges):
            same_pair = {o_source, o_target} == {source, target}
            if (
                other != index
                and same_pair
                and o_distance is None
                and not o_negated
                and o_words in _POSITIONAL
            ):
                query.edges[other] = (o_source, o_words, distance, o_target, False)
                del query.edges[index]
                return


def _edge_phrase(words: str, named: str, label: str, *, outgoing: bool, negated: bool) -> str:
    """The phrase of one relationship of the returned node with the road user or place ``named``."""
    if not outgoing:
        if words not in _INVERSE:
            raise Unreadable(words)
        return _INVERSE[words].format(named)
    if words.startswith("has "):
        where = _HAS.get(words[4:])
        if where is None:
            raise Unreadable(words)
        if negated:
            return f"with no {re.sub(r'^(?:an?|the) ', '', named)} {where}"
        return f"with {named} {where}"
    if label in _MAP and words in _LOCATED:
        return f"{'in' if label in ('intersection', 'junction') else 'on'} {named}"
    if label in _MAP and words.split()[0] in _MOTION | {"turning", "changing"}:
        return f"{words} on {named}"
    return f"{words} {named}"


def _plural(noun: str) -> str:
    """``noun`` in the plural ("bus" -> "buses", "box truck" -> "box trucks")."""
    return noun + ("es" if noun.endswith(("s", "x", "ch", "sh")) else "s")


def _shared_lanes(query: GraphQuery, returned: str) -> tuple[set[tuple[str, str]], list[str]]:
    """The lane nodes that the returned node shares with one other road user.

    Returns the (road user, lane) edges of those lane nodes and the other road users; a lane node
    used otherwise is not read (:class:`Unreadable`).
    """
    edges: set[tuple[str, str]] = set()
    mates: list[str] = []
    for lane in sorted(var for var, label in query.labels.items() if label == "lane"):
        users = sorted({s for s, w, _, t, neg in query.edges if t == lane and not neg and w in _LOCATED})
        if returned not in users or len(users) != 2:
            raise Unreadable("a lane node")
        edges |= {(user, lane) for user in users}
        mates += [user for user in users if user != returned]
    return edges, mates
