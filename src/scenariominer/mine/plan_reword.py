"""The model puts a description in plain words; the phrase rules read those words.

The phrase rules (:mod:`scenariominer.mine.plan_reader`) read most descriptions in full, but a
register they have not met (a parameter block, a child's words, a set-builder formula) leaves
them reading it only in part or not at all, and the 1.5B model's own plans and programs are far
weaker than the rules' reading. Rewriting a sentence into plain words is a task a small model does
well, so when the rules cannot read a description in full, one short model call rewrites it
("actor: pedestrian / location: pedestrian_crossing" -> "pedestrians on a pedestrian crossing")
and the rules read the rewording. It is used only when they read it *in full* and it passes
checks against the original, so a rewording cannot silently change what is searched for:

* every number of the original is in the rewording and no other (a dropped "1.5 m/s^2" or an
  invented "10 m" would change the program), and a speed unit the original does not state is
  read as m/s, the tools' unit ("speed:>15" -> "faster than 15 km/h" is read as 15 m/s);
* the same sides (left, right) and a negation exactly when the original has one;
* the ego vehicle only when the original names it;
* its road user is one the original names, or a member of a group it names ("vehicles" may
  become "cars", not the other way round): a rewording that turns "skateboards" into "bicycles"
  or "cars in the bike lane" into "bicycles in a bike lane" is refused.

When the rules read a rewording only in part, a second request (:func:`reword_again`) shows the
model its rewording and asks for a simpler one without the words they left out
(``mining.generation.plan_reword_tries``); the same checks decide whether that one is used.

A refused or unreadable rewording changes nothing: the description goes on as before (read in
part by the rules, else by the model's plan), except that a description the rules cannot read even
in part gets their partial reading of the rewording when it passes the same checks
(``reworded_plan(..., partial=True)``). The plan keeps the rewording under ``reworded`` and
:func:`scenariominer.mine.plan.plan_text` shows it, so the user sees which words were read.
"""

from __future__ import annotations

import re
from typing import Any

from scenariominer.data.categories import EGO_CATEGORY, expand_categories
from scenariominer.llm.base import Message, assistant, system, user
from scenariominer.llm.client import ChatClient

__all__ = ["REWORD_GRAMMAR", "reword", "reword_again", "reword_messages", "reworded_plan"]

#: One line of plain text (no line break, no markup): the answer the rewording step may give.
REWORD_GRAMMAR = r"""root ::= [A-Za-z0-9] [A-Za-z0-9 ,.'/%()^*<>=+-]{0,160}"""

#: A number, with or without its unit run into it ("10m"); not the end of a word ("s3", "e4"), an
#: exponent ("m/s^2"), a compound ("2-wheeled", "4-way") or an ordinal ("3rd").
_NUMBER = re.compile(r"(?<![\w.^])\d+(?:\.\d+)?(?![\d.]|-[a-z]|(?:st|nd|rd|th)\b)")


def reword_messages(description: str) -> list[Message]:
    """The rewording request: the role, the worked examples as turns, then the description."""
    from scenariominer.mine.plan_documents import request_text
    from scenariominer.mine.plan_prompts import REWORD_EXAMPLES, reword_system_prompt

    messages = [system(reword_system_prompt())]
    for odd, plain in REWORD_EXAMPLES:
        messages += [user(odd), assistant(plain)]
    messages.append(user(request_text(description).strip()))
    return messages


def reword(client: ChatClient, description: str, *, max_tokens: int = 60) -> str:
    """One model call: ``description`` in plain words (one line; empty when the model gave none).

    Raises:
        BackendError: the model call failed.
    """
    messages = reword_messages(description)
    completion = client.completion(messages, grammar=REWORD_GRAMMAR, max_tokens=max_tokens)
    lines = completion.text.strip().splitlines()
    return " ".join(lines[0].split()) if lines else ""


#: What a rewording may say is done with the result ("... are returned", "..., flagged"): no part
#: of the scene, so left out before the rules read it (an original wording keeps its own rules).
_REPORTED = re.compile(
    r"(?:,?\s+(?:and\s+)?(?:(?:is|are|should be|must be|to be|gets?|will be)\s+)?"
    r"(?:returned|reported|flagged|listed|shown|found|selected|highlighted|detected|identified))+\.?$",
    re.IGNORECASE,
)

#: "one" as a pronoun ("each one", "one of them", "one that stops"), not a number.
_PRONOUN_ONE = re.compile(
    r"\b(?:each|every|any|no|this|that|the|which|a|some) one\b|\bone (?=of|that|who|which|another)\b",
    re.IGNORECASE,
)


def _numbers(text: str) -> set[float]:
    """The numbers in the normalised text ("five metres" counts as 5, "each one" as none)."""
    from scenariominer.mine.plan_wording import normalised_text

    return {float(n) for n in _NUMBER.findall(normalised_text(_PRONOUN_ONE.sub(" ", text)))}


#: A word that negates or excludes; "no more than" and its kind only bound a number.
_NEGATION = re.compile(
    r"\b(?:not|no|non|never|without|except|false|none|nowhere|neither|nor|other than|apart from|"
    r"aside from)\b|n't\b|\bexclu|\b(?:not|non|no)_|_not\b|\bun(?:moving|parked|marked)\b|!="
)
_BOUND = re.compile(r"\bno (?:more|less|fewer|further|farther|faster|slower|closer|later|sooner) than\b")

#: Words for the ego vehicle that are no road-user phrase of the rules.
_EGO_WORDS = re.compile(r"\b(?:ego|we|us|our|ours|me|my|av|sdv|adv)\b")


#: A speed unit other than the tools' own (m/s).
_SPEED_UNIT = re.compile(
    r"\b(?:km/h|km/hr|kmh|kph|kilomet(?:re|er)s? (?:per|an|a) hour|mph|miles? (?:per|an|a) hour)(?![\w/])",
    re.IGNORECASE,
)


def _units_as_stated(description: str, rewording: str) -> str:
    """``rewording`` with a speed unit the description does not state put back as m/s.

    A bare "speed:>15" means 15 m/s (the tools' unit); the model tends to add "km/h" to it.
    """
    if _SPEED_UNIT.search(description) is not None:
        return rewording
    return _SPEED_UNIT.sub("m/s", rewording)


#: "right" as an intensifier ("sitting right on the road", "right next to", "rolls right over the
#: crosswalk"), no side.
_RIGHT_AS_INTENSIFIER = re.compile(
    r"(?<!turn )(?<!turns )(?<!turning )(?<!turned )(?<!the )(?<!go )(?<!going )(?<!veer )(?<!veering )"
    r"(?<!swerve )(?<!swerving )(?<!lanes )(?<!lane )(?<!keep )(?<!keeping )(?<!far )"
    r"\bright (?=(?:on|in|at|into|onto|next|beside|by|there|here|now|away|up|behind|before|after|over"
    r"|across|through|past|out|down|along|off)\b)"
)


def _sides(text: str) -> set[str]:
    """The sides the text names ("left", "right"; also inside a field name, "left_side")."""
    text = _RIGHT_AS_INTENSIFIER.sub(" ", text.lower())
    return set(re.findall(r"(?<![a-z])(left|right)(?:wards?)?(?![a-z])", text))


def _negated(text: str) -> bool:
    """Whether the text negates or excludes anything."""
    return _NEGATION.search(_BOUND.sub(" ", text.lower())) is not None


def _named_categories(text: str) -> set[str]:
    """Every category of the road users the normalised text names anywhere."""
    from scenariominer.mine.plan_reader import subject_categories
    from scenariominer.mine.plan_wording import CATEGORY_RE, normalised_text

    named: set[str] = set()
    # also with hyphens as spaces: a flag's or a field's value names one too ("regular-vehicle")
    for variant in (text, re.sub(r"(?<=[a-z])[-_](?=[a-z])", " ", text.lower())):
        for found in re.finditer(rf"(?<![\w-])(?:{CATEGORY_RE})(?![\w-])", normalised_text(variant)):
            named.update(subject_categories(found.group(0)) or ())
    return named


def reworded_plan(
    description: str, rewording: str, *, partial: bool = False
) -> tuple[dict[str, Any] | None, str]:
    """The phrase rules' full reading of ``rewording`` if it passes the checks against ``description``.

    Args:
        description: the request as written.
        rewording: the model's plain rewording of it.
        partial: accept the rules' partial reading of the rewording (the words they left out
            listed under ``unread``), for a description they cannot read even in part; the checks
            are the same.

    Returns:
        (plan, reason): the plan (with ``reworded`` set) and ``""``; or ``None`` and why the
        rewording was not used.
    """
    plan, reason, _ = _judged(description, rewording, partial=partial)
    return plan, reason


def _judged(
    description: str, rewording: str, *, partial: bool = False
) -> tuple[dict[str, Any] | None, str, str]:
    """(plan, reason, hint): :func:`reworded_plan`'s answer and what to tell the model when refused.

    The hint is empty when the rewording passes, and when a second request is not worth asking:
    only a rewording with words the rules leave out gets one (told to keep a negation, the model
    negated the wrong word; told which numbers to keep, or shown plain phrases, it echoed them).
    """
    from scenariominer.mine.plan_reader import read_plan

    if not rewording:
        return None, "the model gave no rewording", ""
    rewording = _units_as_stated(description, rewording)
    plan = read_plan(_REPORTED.sub("", rewording), partial=partial)
    if plan is None:
        if partial:
            return None, f"the phrase rules cannot read the rewording even in part: {rewording!r}", ""
        return (
            None,
            f"the phrase rules cannot read the rewording in full: {rewording!r}",
            _unread_hint(rewording),
        )
    stated, kept = _numbers(description), _numbers(rewording)
    if stated != kept:
        return (
            None,
            (
                f"the rewording {rewording!r} changes the numbers stated "
                f"({sorted(stated) or 'none'} -> {sorted(kept) or 'none'})"
            ),
            "",
        )
    if _sides(description) != _sides(rewording):
        return None, f"the rewording {rewording!r} changes the sides stated (left, right)", ""
    negated = _negated(description)
    if negated != _negated(rewording):
        said = "drops the negation of" if negated else "adds a negation to"
        return None, f"the rewording {rewording!r} {said} the description", ""
    named = _named_categories(description)
    subject = plan["subject_category"]
    if not _categories_of(subject) <= expand_categories(named):
        return None, f"the rewording {rewording!r} is about a road user the description does not name", ""
    ego_in_plan = EGO_CATEGORY in [subject, *(o["category"] for o in plan.get("related", []))]
    if ego_in_plan and EGO_CATEGORY not in named and _EGO_WORDS.search(description.lower()) is None:
        return (
            None,
            f"the rewording {rewording!r} brings in the ego vehicle, which the description does not",
            "",
        )
    return {**plan, "reworded": rewording}, "", ""


def _unread_hint(rewording: str) -> str:
    """What to tell the model about a rewording the rules read only in part: the words left out.

    Empty when they cannot read even its subject (asked to start with the road users, the model
    answered "road users").
    """
    from scenariominer.mine.plan_reader import read_plan

    partial = read_plan(_REPORTED.sub("", rewording), partial=True)
    unread = list(dict.fromkeys((partial or {}).get("unread") or []))
    if not unread:
        return ""
    return "Simpler, please: without the words " + ", ".join(f"'{w}'" for w in unread) + "."


def reword_again(
    client: ChatClient, description: str, rewording: str, *, max_tokens: int = 60
) -> tuple[str, str]:
    """A second rewording after ``rewording`` was refused because the rules read it only in part.

    The model is shown its rewording and asked for a simpler one without the words the rules left
    out ("car changes lanes and returns to original lane" -> "car changes lanes"); the checks of
    :func:`reworded_plan` against ``description`` still decide whether it is used.

    Returns:
        (the new rewording, the hint that was given); ``("", "")`` when ``rewording`` passes or
        was refused for another reason (no second request is asked for then).

    Raises:
        BackendError: the model call failed.
    """
    _, _, hint = _judged(description, rewording)
    if not hint:
        return "", ""
    messages = [*reword_messages(description), assistant(rewording or "-"), user(hint)]
    completion = client.completion(messages, grammar=REWORD_GRAMMAR, max_tokens=max_tokens)
    lines = completion.text.strip().splitlines()
    return (" ".join(lines[0].split()) if lines else ""), hint


def _categories_of(category: str | list[str]) -> frozenset[str]:
    """The categories a plan's category (one, or a list of several) stands for."""
    return expand_categories(category if isinstance(category, list) else [category])
