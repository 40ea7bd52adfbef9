"""From a description's plan to a mining program, without the model writing code.

The plan step (:mod:`scenariominer.mine.plan`) reads a description into its subject, the other
objects, the relations and the conditions, each named by an enum of what exists. This module
turns such a plan into a program by fixed rules:

* the subject is ``get_objects_of_category(log_dir, category=...)``;
* each condition filters the subject (``scenario_not(f)(...)`` when negated), with the keyword
  settings of its ``argument`` text that the function accepts;
* each relation filters the subject by its related objects; when the plan names the other
  object as the relation's subject (``being_crossed_by(ego, pedestrian)`` for "pedestrians
  crossing in front of the ego"), the relation is reversed (``reverse_relationship``);
* the result goes to ``output_scenario``.

Before that, the plan is normalised, because the small model often reads map context or a
direction as an object (rules in :func:`_normalised`, each leaving a note):

* a "related object" or relation target that is a part of the map ("a bike lane", "the
  crosswalk", "an intersection") becomes the map condition that tests it (``on_lane_type``,
  ``at_pedestrian_crossing``, ``on_intersection``, ``at_stop_sign``, ``on_road``);
* a relation whose other object is a bare direction ("facing toward *left*") or the subject
  itself ("vehicles ... *vehicles*") is a misreading: it is dropped when its direction is already
  given to a condition or can be given to one that takes it (``turning``, ``changing_lanes``);
* adjectives of the subject that name a state ("parked", "stopped") add its condition
  (``stationary``; "stopped" also takes the momentarily stopped, :data:`COMPOSITE_CONDITIONS`),
  and the subject's words decide its categories as the phrase rules read them
  (:func:`~scenariominer.mine.plan_reader.subject_categories`: "vehicles" the VEHICLE group,
  "regular vehicles" REGULAR_VEHICLE, "buses" every bus category), whatever was planned.

A plan the rules cannot use faithfully (a relation whose other object is not among the planned
objects, a required setting missing, a value outside its choices) gives no program but a
:class:`PlanCompileError` naming the part at fault, and the model writes the program instead.
Settings that are not arguments of the function are left out and listed in the result's notes.
"""

from __future__ import annotations

import inspect
import re
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

from scenariominer.mine.plan_nouns import singular
from scenariominer.mine.plan_reader import one_or_many, subject_categories

__all__ = ["PLAN_PROGRAM_VERSION", "CompiledPlan", "PlanCompileError", "compile_plan"]

#: Version of the rules below; part of the program-cache key when they are used.
PLAN_PROGRAM_VERSION = "plan-program/12"

_EGO_WORDS = re.compile(r"\b(ego|self[- ]driving|our (car|vehicle)|the av)\b", re.IGNORECASE)
_OTHER_WORDS = re.compile(r"\b(another|other|others|each other|one another)\b", re.IGNORECASE)
_SETTING = re.compile(r"^\s*([A-Za-z_][A-Za-z0-9_]*)\s*[=:]\s*(.+?)\s*$")
#: Relation functions whose result is their second object set (the related candidates).
_RETURNS_RELATED = frozenset({"get_objects_in_relative_direction"})
_SCENARIO_PARAMS = ("track_candidates", "related_candidates", "log_dir")
#: Words that name a part of the map rather than an object.
_MAP_WORDS = re.compile(
    r"\b(lanes?|crosswalks?|crossings?|intersections?|junctions?|roads?|streets?|sidewalks?|"
    r"drivable|stop signs?)\b",
    re.IGNORECASE,
)
#: Map parts the rules turn into a condition: (words, function, argument).
_MAP_CONDITIONS: tuple[tuple[re.Pattern[str], str, str | None], ...] = (
    (re.compile(r"\b(bike|bicycle|cycle|cycling)\s+lanes?\b", re.I), "on_lane_type", "lane_type='BIKE'"),
    (re.compile(r"\bbus\s+lanes?\b", re.I), "on_lane_type", "lane_type='BUS'"),
    (re.compile(r"\b(crosswalks?|(pedestrian|zebra) crossings?)\b", re.I), "at_pedestrian_crossing", None),
    (re.compile(r"\b(intersections?|junctions?)\b", re.I), "on_intersection", None),
    (re.compile(r"\bstop signs?\b", re.I), "at_stop_sign", None),
    (re.compile(r"\b(drivable area|roads?|streets?)\b", re.I), "on_road", None),
)
#: Adjectives of the subject that name a condition.
_STATE_WORDS: tuple[tuple[re.Pattern[str], str], ...] = (
    (re.compile(r"\b(parked|stationary)\b", re.I), "stationary"),
    (re.compile(r"\b(stopped|halted)\b", re.I), "stopped"),
)
#: Conditions that are no single mining function, as the expression testing them (``{t}``: the
#: object set). "stopped": at rest at the timestamp, parked objects included, as the Argoverse 2
#: scenario-mining ground truth of "stopped car" has it (``has_velocity`` alone leaves out the
#: objects that never move, ``stationary`` alone the momentarily stopped ones).
#: A composite may take numbers (``{accel}``), given as the condition's ``argument`` ("accel=2");
#: "a lateral acceleration above 2 m/s^2 either way" is 2 m/s^2 or more toward the left or the right.
COMPOSITE_CONDITIONS: dict[str, str] = {
    "stopped": "scenario_or([stationary({t}, log_dir), "
    "has_velocity({t}, log_dir, min_velocity=0, max_velocity=0.5)])",
    "lateral_acceleration_either_way": "scenario_or([has_lateral_acceleration({t}, log_dir, "
    "min_accel={accel}), has_lateral_acceleration({t}, log_dir, max_accel=-{accel})])",
    # another road user's "oncoming" (phrase rules only): heading against the subject
    "oncoming": "heading_in_relative_direction_to({t}, subject, log_dir, direction='opposite')",
}


#: A condition holding when any of its alternatives does (``any_of``: lists of conditions).
ANY_OF = "any_of"


class PlanCompileError(ValueError):
    """The plan cannot be turned into a program by the rules (the message names the part)."""


@dataclass(frozen=True)
class CompiledPlan:
    """A program built from a plan.

    Attributes:
        program: the mining program text.
        notes: settings of the plan left out, with the reason (empty when all were used).
    """

    program: str
    notes: tuple[str, ...] = ()


def compile_plan(plan: Mapping[str, Any]) -> CompiledPlan:
    """Build the program of ``plan`` (as :func:`scenariominer.mine.plan.extract_plan` returns it).

    Raises:
        PlanCompileError: the plan names something the rules cannot express (the message says what).
    """
    if "error" in plan:
        raise PlanCompileError(f"no plan: {plan['error']}")
    notes: list[str] = []
    if plan.get("read_by") != "rules":  # the phrase rules' plans are normal already
        plan = _normalised(plan, notes)
    subject_category = _category(plan.get("subject_words"), plan.get("subject_category"))
    if not subject_category:
        raise PlanCompileError("the plan names no subject category")
    lines = [f"subject = {_objects_of(subject_category)}"]
    current = "subject"
    step = 0
    for cond in plan.get("conditions", []):
        step += 1
        lines.append(f"step_{step} = {_condition_call(cond, current, notes)}")
        current = f"step_{step}"

    objects = _related_objects(plan, lines)
    for rel in _lane_of_related(plan, objects, lines):
        step += 1
        if rel.get("function") == IN_LINE:
            call = _in_line_call(rel, current, objects, plan, lines, step)
        else:
            call = _relation_call(rel, current, objects, plan, notes)
        lines.append(f"step_{step} = {call}")
        current = f"step_{step}"
    lines.append(f"output_scenario({current}, description, log_dir, output_dir)")
    return CompiledPlan("\n".join(lines) + "\n", tuple(notes))


def _normalised(plan: Mapping[str, Any], notes: list[str]) -> dict[str, Any]:
    """``plan`` with map parts as conditions, misread relations dropped and state words applied.

    Raises:
        PlanCompileError: a map part no rule turns into a condition, or a misread relation whose
            direction no condition can take.
    """
    subject_words = str(plan.get("subject_words", ""))
    conditions = [dict(c) for c in plan.get("conditions", [])]
    related, relations = [], []
    for obj in plan.get("related", []):
        words = str(obj.get("words", ""))
        if _MAP_WORDS.search(words):
            _add_map_condition(words, conditions, notes)
        else:
            related.append(obj)
    for rel in plan.get("relations", []):
        other = str(rel.get("other_words", ""))
        if _MAP_WORDS.search(other):
            _add_map_condition(other, conditions, notes)
        elif _norm(other) in _direction_words() or _relates_subject_to_itself(rel, subject_words, plan):
            _drop_misread_relation(rel, conditions, notes)
        else:
            relations.append(rel)
    for pattern, function in _STATE_WORDS:
        found = pattern.search(subject_words)
        if found and all(c.get("function") != function for c in conditions):
            conditions.insert(0, {"function": function, "negated": False, "argument": None})
            notes.append(f"{function}: added for {found.group(0)!r}")
    category = plan.get("subject_category")
    read = subject_categories(subject_words)
    if read and not _EGO_WORDS.search(subject_words):
        # the subject's words name its categories the way the phrase rules read them ("vehicles":
        # the VEHICLE group, "regular vehicles": REGULAR_VEHICLE, "buses": every bus category)
        chosen = one_or_many(read)
        if chosen != category:
            notes.append(f"subject: {', '.join(read)} for {subject_words!r}, not {category}")
        category = chosen
    return {
        **plan,
        "subject_category": category,
        "related": related,
        "relations": relations,
        "conditions": conditions,
    }


def _direction_words() -> frozenset[str]:
    """The relative directions the predicates accept, and their aliases ("front", "behind")."""
    from scenariominer.mine.dsl._common import _DIRECTION_ALIASES, ARGUMENT_CHOICES

    relative = ARGUMENT_CHOICES["has_objects_in_relative_direction"]["direction"]
    return frozenset({*(d for d in relative if d), *_DIRECTION_ALIASES})


def _relates_subject_to_itself(rel: Mapping[str, Any], subject_words: str, plan: Mapping[str, Any]) -> bool:
    """Both sides of ``rel`` are the subject's own words (not "another ..." nor a planned object)."""
    other, own = _norm(str(rel.get("other_words", ""))), _norm(str(rel.get("subject_words", "")))
    subject = _norm(subject_words)
    planned = {_norm(str(obj.get("words", ""))) for obj in plan.get("related", [])}
    return (
        other == subject
        and own in ("", subject)
        and other not in planned
        and not _OTHER_WORDS.search(str(rel.get("other_words", "")))
    )


def _add_map_condition(words: str, conditions: list[dict[str, Any]], notes: list[str]) -> None:
    """Append the condition that tests the map part ``words`` (once)."""
    for pattern, function, argument in _MAP_CONDITIONS:
        if pattern.search(words):
            if not any(c.get("function") == function and c.get("argument") == argument for c in conditions):
                conditions.append({"function": function, "negated": False, "argument": argument})
                notes.append(f"{function}: {words!r} is a part of the map, tested as a condition")
            return
    raise PlanCompileError(f"{words!r} is a part of the map, not an object, and no rule tests it")


def _drop_misread_relation(
    rel: Mapping[str, Any], conditions: list[dict[str, Any]], notes: list[str]
) -> None:
    """Drop a relation to a bare direction or to the subject itself, keeping its direction.

    Raises:
        PlanCompileError: the relation names a direction that no condition already has or can take.
    """
    from scenariominer.mine.dsl._common import _DIRECTION_ALIASES, ARGUMENT_CHOICES

    name, other = rel.get("function"), str(rel.get("other_words", ""))
    word = str(rel.get("direction") or (other if _norm(other) in _direction_words() else "")).lower()
    direction = _DIRECTION_ALIASES.get(word, word)
    for cond in conditions:
        accepts = ARGUMENT_CHOICES.get(str(cond.get("function")), {}).get("direction", ())
        if direction and direction in accepts:
            argument = str(cond.get("argument") or "")
            if direction not in argument:
                if "direction" in argument:
                    continue  # another direction is already given: not this condition
                cond["argument"] = ", ".join(a for a in (argument, f"direction={direction!r}") if a)
            notes.append(f"{name}: {other!r} is not an object; its direction goes to {cond['function']}")
            return
    raise PlanCompileError(f"relation {name}: {other!r} is not an object the plan names")


def _relation_call(
    rel: Mapping[str, Any],
    current: str,
    objects: Mapping[str, str],
    plan: Mapping[str, Any],
    notes: list[str],
) -> str:
    """The call that filters ``current`` (the subject so far) by one planned relation.

    A relation in any of several directions ("on either side", phrase rules only) is the
    ``scenario_or`` of the relation in each.
    """
    from scenariominer.mine.dsl import DSL_FUNCTIONS

    sides = rel.get("any_direction")
    if sides:
        one = {k: v for k, v in rel.items() if k != "any_direction"}
        calls = [_relation_call({**one, "direction": side}, current, objects, plan, notes) for side in sides]
        return f"scenario_or([{', '.join(calls)}])"
    name = str(rel.get("function", ""))
    func = DSL_FUNCTIONS.get(name)
    if func is None:
        raise PlanCompileError(f"relation {name!r} is not a mining function")
    subject_words, category = _subject(plan)
    other = _match_object(str(rel.get("other_words", "")), objects, subject_words, category)
    rel_words = str(rel.get("subject_words", ""))
    rel_subject = (
        "subject"
        if not _norm(rel_words) or _norm(rel_words) == _norm(subject_words)
        else _match_object(rel_words, objects, subject_words, category)
    )
    # the direction is a bare word: it goes to the text argument that accepts it (side=... too)
    settings = ", ".join(str(v) for v in (rel.get("direction"), rel.get("argument")) if v)
    kwargs = _kwargs_text(_settings(name, func, settings or None, notes))
    if name in _RETURNS_RELATED:
        # the function returns its second set: the subject goes there, the other object first
        anchor = rel_subject if rel_subject not in (None, "subject") else other
        if anchor in (None, "subject"):
            raise PlanCompileError(f"relation {name}: no object other than the subject to look from")
        return f"{name}({anchor}, {current}, log_dir{kwargs})"
    if rel.get("negated"):
        # "with no vehicle ahead" (phrase rules only): the subject's timestamps where it does not hold
        if other in (None, "subject") or rel_subject not in (None, "subject") or name in _RETURNS_RELATED:
            raise PlanCompileError(
                f"relation {name}: only a relation of the subject to another object can be negated"
            )
        return f"scenario_not({name})({current}, {other}, log_dir{kwargs})"
    if rel_subject not in (None, "subject") and other in (None, "subject"):
        # the plan reads the relation from the other object's side: the subject is its target
        return f"reverse_relationship({name})({rel_subject}, {current}, log_dir{kwargs})"
    if other is None:
        raise PlanCompileError(
            f"relation {name}: {rel.get('other_words')!r} is not one of the planned objects"
        )
    return f"{name}({current}, {other}, log_dir{kwargs})"


def _lane_of_related(plan: Mapping[str, Any], objects: Mapping[str, str], lines: list[str]) -> list[Any]:
    """The plan's relations, with "X ahead ... in the same lane" read as one object X.

    "with a vehicle ahead in the same lane" asks for a vehicle that is both ahead and in the
    subject's lane; read as two relations, any vehicle ahead and any vehicle sharing the lane
    would do, and "with *no* vehicle ahead in the same lane" would mean no vehicle ahead at all.
    So when an object the subject has in a direction is the one an ``in_same_lane`` relation of
    the subject names (and no other relation uses it), that object's set is narrowed to the
    objects sharing a lane with the subject and the ``in_same_lane`` relation is dropped.
    """
    relations = list(plan.get("relations", []))
    subject_words = _norm(str(plan.get("subject_words", "")))

    def of_subject(rel: Mapping[str, Any]) -> bool:
        return _norm(str(rel.get("subject_words", ""))) in ("", subject_words)

    for lane in [r for r in relations if r.get("function") == "in_same_lane" and not r.get("negated")]:
        other = _norm(str(lane.get("other_words", "")))
        users = [r for r in relations if _norm(str(r.get("other_words", ""))) == other]
        var = objects.get(str(lane.get("other_words", "")).strip().lower())
        directed = [r for r in users if r.get("function") == "has_objects_in_relative_direction"]
        if var is None or len(users) != 2 or len(directed) != 1 or not all(map(of_subject, users)):
            continue
        lines.append(f"{var} = in_same_lane({var}, subject, log_dir)")
        relations.remove(lane)
    return relations


def _subject(plan: Mapping[str, Any]) -> tuple[str, str | list[str]]:
    """The plan's subject words and its category (or categories), as relations match objects by them."""
    subject_words = str(plan.get("subject_words", ""))
    return subject_words, _category(subject_words, plan.get("subject_category"))


#: The relation "the N-th vehicle ahead of / behind X in its lane" (phrase rules only: "two cars
#: ahead"), built from the mining functions by :func:`_in_line_call`.
IN_LINE = "in_line"
#: The lane corridor of a line of vehicles: within 50 m, at most 1 m sideways past the box.
_LINE_CORRIDOR = "within_distance=50, lateral_thresh=1"


def _in_line_call(
    rel: Mapping[str, Any],
    current: str,
    objects: Mapping[str, str],
    plan: Mapping[str, Any],
    lines: list[str],
    step: int,
) -> str:
    """``current``'s members that are the ``rank``-th vehicle in ``direction`` of the other object.

    The line is the vehicles in that direction of the other object within its lane corridor
    (:data:`_LINE_CORRIDOR`); the N-th of them has exactly N - 1 of the line between the other
    object and itself, i.e. on its own opposite side. Defines ``line_<step>`` (and ``after_<step>``)
    in ``lines``.

    Raises:
        PlanCompileError: no rank, a direction other than forward/backward, or an unknown object.
    """
    found = re.fullmatch(r"rank=(\d+)", str(rel.get("argument") or ""))
    direction = rel.get("direction")
    if found is None or int(found.group(1)) < 1 or direction not in ("forward", "backward"):
        raise PlanCompileError(f"relation {IN_LINE}: needs rank=N >= 1 and direction forward or backward")
    rank = int(found.group(1))
    anchor = _match_object(str(rel.get("other_words", "")), objects, *_subject(plan))
    if anchor in (None, "subject"):
        raise PlanCompileError(
            f"relation {IN_LINE}: {rel.get('other_words')!r} is not one of the planned objects"
        )
    line = f"line_{step}"
    lines.append(f"# the vehicles in line {direction} of {anchor}, in its lane corridor")
    lines.append(
        f"{line} = get_objects_in_relative_direction({anchor}, get_objects_of_category(log_dir, "
        f"category='VEHICLE'), log_dir, direction='{direction}', {_LINE_CORRIDOR})"
    )
    back = "backward" if direction == "forward" else "forward"
    between = f"{line}, log_dir, direction='{back}', {_LINE_CORRIDOR}"
    members = f"scenario_and([{current}, {line}])"
    if rank > 1:  # at least rank - 1 of the line between the other object and it ...
        after = f"after_{step}"
        lines.append(
            f"{after} = has_objects_in_relative_direction({members}, {between}, min_number={rank - 1})"
        )
        members = after
    # ... and not rank of them
    return f"scenario_not(has_objects_in_relative_direction)({members}, {between}, min_number={rank})"


def _condition_call(cond: Mapping[str, Any], target: str, notes: list[str]) -> str:
    """The call that filters the object set ``target`` by one planned condition.

    Raises:
        PlanCompileError: the condition is not a mining function, or its settings do not fit.
    """
    from scenariominer.mine.dsl import DSL_FUNCTIONS

    name = str(cond.get("function", ""))
    if name == ANY_OF:  # "either A or B" (phrase rules only): each alternative a chain of conditions
        alternatives = []
        for chain in cond.get("any_of") or []:
            expression = target
            for part in chain:
                expression = _condition_call(part, expression, notes)
            alternatives.append(expression)
        if len(alternatives) < 2 or cond.get("negated"):
            raise PlanCompileError("an 'any_of' condition needs two alternatives and cannot be negated")
        return f"scenario_or([{', '.join(alternatives)}])"
    if name in COMPOSITE_CONDITIONS:
        return _composite_call(name, cond, target)
    func = DSL_FUNCTIONS.get(name)
    if func is None:
        raise PlanCompileError(f"condition {name!r} is not a mining function")
    kwargs = _kwargs_text(_settings(name, func, cond.get("argument"), notes))
    call = f"scenario_not({name})" if cond.get("negated") else name
    return f"{call}({target}, log_dir{kwargs})"


def _composite_call(name: str, cond: Mapping[str, Any], target: str) -> str:
    """The expression of a :data:`COMPOSITE_CONDITIONS` condition on ``target``.

    Raises:
        PlanCompileError: it is negated, or its numbers are missing, extra or not numbers.
    """
    template = COMPOSITE_CONDITIONS[name]
    wanted = set(re.findall(r"\{(\w+)\}", template)) - {"t"}
    values: dict[str, float] = {}
    for piece in str(cond.get("argument") or "").split(","):
        if (match := _SETTING.match(piece)) is not None:
            value = _literal(match.group(2))
            if match.group(1) not in wanted or not isinstance(value, int | float) or value < 0:
                raise PlanCompileError(f"condition {name!r}: {piece.strip()!r} is not one of its settings")
            values[match.group(1)] = value
        elif piece.strip():
            raise PlanCompileError(f"condition {name!r}: {piece.strip()!r} is not one of its settings")
    if cond.get("negated"):
        raise PlanCompileError(f"condition {name!r} cannot be negated")
    if missing := sorted(wanted - values.keys()):
        raise PlanCompileError(f"condition {name!r} needs {', '.join(missing)}")
    return template.format(t=target, **values)


def _related_objects(plan: Mapping[str, Any], lines: list[str]) -> dict[str, str]:
    """Define one object set per planned other object; its words (lower case) -> variable name.

    An object's own conditions ("a *moving* vehicle", from the phrase rules) filter its set.
    """
    objects: dict[str, str] = {}
    for index, obj in enumerate(plan.get("related", []), start=1):
        category = _category(obj.get("words"), obj.get("category"))
        if not category:
            raise PlanCompileError(f"other object {obj.get('words')!r} has no category")
        var = f"related_{index}"
        lines.append(f"{var} = {_objects_of(category)}")
        for cond in obj.get("conditions", []):
            lines.append(f"{var} = {_condition_call(cond, var, [])}")
        objects[str(obj.get("words", "")).strip().lower()] = var
    return objects


def _known_category(name: str, value: str) -> str:
    """``value`` as a category or category group name of ``name``'s ``category`` argument.

    Raises:
        PlanCompileError: it is neither.
    """
    from scenariominer.data.categories import CATEGORY_GROUPS, UnknownCategoryError, canonical_category

    if value.upper() in CATEGORY_GROUPS:
        return value.upper()
    try:
        return canonical_category(value)
    except UnknownCategoryError:
        raise PlanCompileError(f"{name}: category={value!r} is no Argoverse 2 category or group") from None


def _category(words: Any, category: Any) -> str | list[str]:
    """The planned category (or categories), or EGO_VEHICLE when the words name the ego.

    ("the ego vehicle" is often planned as VEHICLE.)
    """
    if _EGO_WORDS.search(str(words or "")):
        return "EGO_VEHICLE"
    if isinstance(category, list | tuple):
        return [str(c) for c in category if c]
    return str(category or "")


def _objects_of(category: str | list[str]) -> str:
    """The expression of the objects of one category, or of the union of several."""
    if isinstance(category, str):
        return _same_category(category)
    if len(category) == 1:
        return _same_category(category[0])
    return "scenario_or([" + ", ".join(_same_category(c) for c in category) + "])"


def _match_object(
    words: str, objects: Mapping[str, str], subject_words: str, subject_category: str | list[str]
) -> str | None:
    """The variable a relation's words refer to, or ``None`` when none fits."""
    text = _norm(words)
    if not text:
        return None
    for obj_words, var in objects.items():
        if _norm(obj_words) == text:
            return var
    if text == _norm(subject_words):
        return "subject"
    for obj_words, var in objects.items():
        norm = _norm(obj_words)
        if norm and (f" {norm} " in f" {text} " or f" {text} " in f" {norm} "):
            return var
    if _OTHER_WORDS.search(text):
        # "a vehicle behind another vehicle": the other is another member of the subject's category
        return _objects_of(subject_category)
    if _EGO_WORDS.search(text):
        return _same_category("EGO_VEHICLE")
    if len(objects) == 1:
        return next(iter(objects.values()))
    return None


def _norm(words: str) -> str:
    """Words compared without case, articles or a plural ``s`` ("the buses" ~ "bus")."""
    kept = [w for w in re.findall(r"[a-z0-9]+", words.lower()) if w not in ("the", "a", "an")]
    return " ".join(singular(w) for w in kept)


def _same_category(category: str) -> str:
    return f"get_objects_of_category(log_dir, category={category!r})"


def _settings(name: str, func: Callable[..., Any], text: Any, notes: list[str]) -> dict[str, Any]:
    """The keyword arguments of ``text`` (``"k=v, k2=v2"`` or a bare choice) that ``func`` accepts.

    Raises:
        PlanCompileError: a required setting is missing or a value is not one of its choices.
    """
    from scenariominer.mine.dsl._common import _DIRECTION_ALIASES, ARGUMENT_CHOICES

    params = {
        p.name: p
        for p in inspect.signature(func).parameters.values()
        if p.name not in _SCENARIO_PARAMS and p.kind is p.POSITIONAL_OR_KEYWORD
    }
    choices = ARGUMENT_CHOICES.get(name, {})
    kwargs: dict[str, Any] = {}
    for piece in str(text).split(",") if text else []:
        match = _SETTING.match(piece)
        key, raw = (match.group(1), match.group(2)) if match else (None, piece.strip())
        value = _literal(raw)
        if isinstance(value, str):
            value = _DIRECTION_ALIASES.get(value.lower(), value)
        if key is None:
            # a bare word: the one text argument that accepts it
            key = next((k for k, opts in choices.items() if _choice(value, opts) is not None), None)
            if key is None:
                notes.append(f"{name}: left out {piece.strip()!r} (not a setting of {name})")
                continue
        if key not in params:
            notes.append(f"{name}: left out {piece.strip()!r} ({key} is not an argument of {name})")
            continue
        if key in choices:
            chosen = _choice(value, choices[key])
            if chosen is None and value is not None:
                allowed = ", ".join(repr(o) for o in choices[key] if o is not None)
                raise PlanCompileError(f"{name}: {key}={value!r} is not one of {allowed}")
            value = chosen
        elif key == "category" and isinstance(value, str):
            value = _known_category(name, value)
        elif not isinstance(value, int | float) or isinstance(value, bool):
            notes.append(f"{name}: left out {piece.strip()!r} ({key} takes a number)")
            continue
        kwargs[key] = value
    missing = [k for k, p in params.items() if p.default is inspect.Parameter.empty and k not in kwargs]
    if missing:
        raise PlanCompileError(f"{name}: the plan gives no {', '.join(missing)}")
    return kwargs


def _choice(value: Any, options: tuple[str | None, ...]) -> str | None:
    for option in options:
        if option is not None and isinstance(value, str) and value.lower() == option.lower():
            return option
    return None


def _literal(raw: str) -> Any:
    """A setting's value: a number, or text without its quotes."""
    text = raw.strip().strip("'\"")
    try:
        number = float(text)
    except ValueError:
        return text
    return int(number) if number.is_integer() and "." not in text else number


def _kwargs_text(kwargs: Mapping[str, Any]) -> str:
    return "".join(f", {k}={v!r}" for k, v in kwargs.items())
