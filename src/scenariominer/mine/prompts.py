"""Prompts of mining-program synthesis (RefAV-style code generation with repair), versioned.

A request to the model has three parts, in this order:

1. the **system message**, identical for every description: the role, the predicate library
   (signatures and docstrings, :func:`library_text`), the object categories, the rules of the
   mining language and the argument-role guidance for spatial-relational functions (the paper's
   "enhanced prompting");
2. the **user message**: few-shot example programs chosen for this description, then the
   description itself, LAST;
3. on a repair round, the faulty program as the assistant's answer and a user message with the
   error (:func:`repair_message`).

Everything fixed comes first so a backend that keeps the key-value cache of the previous prompt
(llama-cpp-python compares each new prompt with the tokens it evaluated last and only evaluates
the part after the longest common prefix) pays for the library text once per process rather
than once per call; a repair round reuses the whole first request as its prefix.

Changing any text here changes the programs: bump :data:`PROMPT_VERSION`, which keys the program
cache, so cached programs are regenerated.
"""

from __future__ import annotations

import inspect
import re
from collections.abc import Sequence
from functools import cache

from scenariominer.config.mining import ReferenceStyle
from scenariominer.data.categories import AV2_CATEGORIES, CATEGORY_GROUPS
from scenariominer.llm.base import Message, assistant, system, user
from scenariominer.mine.dsl import DSL_FUNCTIONS, library_reference
from scenariominer.mine.programs import ExampleProgram

__all__ = [
    "PROMPT_VERSION",
    "build_messages",
    "categories_text",
    "compact_reference",
    "library_text",
    "repair_message",
    "repair_messages",
    "system_prompt",
    "user_prompt",
]

#: Version of the prompt texts below; part of every program-cache key.
PROMPT_VERSION = "mining-program/5"

_ROLE = (
    "You write short Python programs that find driving scenarios in a recorded log. A program "
    "composes the mining functions documented below: each function takes and returns a scenario "
    "(a set of objects and the timestamps at which something holds for them)."
)

_RULES = """Rules for the program:
- Use only the functions documented above, plus the variables log_dir (the log), description \
and output_dir, which are already defined. Do not import anything.
- Write straight-line code: assignments and function calls. No def, class, lambda, while, try \
or with; no attribute access except np.inf; no names starting with an underscore.
- Pass scenarios returned by the functions to other functions; never build them yourself.
- Call each function with the parameters its signature lists, and no others.
- Name variables after what they hold, never after a function: write \
vehicles_in_intersection = on_intersection(vehicles, log_dir), not on_intersection = ....
- Categories are kinds of objects. Places (intersections, crosswalks, lanes, the road) are \
tested with the map functions such as on_intersection, at_pedestrian_crossing, on_lane_type, on_road.
- Keep the program short: a few lines and no loops.
- Negate a predicate with scenario_not(function)(scenario, log_dir, ...), combine scenarios with \
scenario_and([a, b]) and scenario_or([a, b]).
- The last line must be output_scenario(final_scenario, description, log_dir, output_dir).
- Answer with the program only, in one ```python code block, with no explanation."""

_ROLES_GUIDE = """Who is the subject of a relation:
- In has_objects_in_relative_direction, get_objects_in_relative_direction, being_crossed_by \
and heading_in_relative_direction_to, the direction is seen from the track_candidates (first \
argument): "a vehicle with a bicycle to its right" is has_objects_in_relative_direction(\
vehicles, bicycles, log_dir, direction='right').
- In facing_toward and heading_toward, the track_candidates do the facing or moving, toward \
the related_candidates (second argument).
- Relational functions return the track_candidates; use get_objects_in_relative_direction or \
reverse_relationship(function)(...) when the description refers to the other object."""

_EXAMPLES_HEADER = "Example programs for similar descriptions:"
_TASK = "Write the program for this description."
_PLAN_HEADER = (
    "A first reading of the description (use its categories, functions and numbers unless they "
    "contradict the description):"
)
_REPAIR = (
    "That program failed: {error}\n"
    "Write the corrected complete program for the same description, again in one ```python "
    "code block. Keep what was right and fix the cause of the error."
)
_REPEATED = (
    "You wrote this program before and it failed the same way. Do not write it again: check the "
    "signature of the function named in the error and use only the arguments it documents, or "
    "use other functions."
)

_SUBJECT_PARAGRAPH = re.compile(r"^(SUBJECT|SUBJECTS)\b")
_SECTION = re.compile(r"^(Args|Returns|Raises|Example|Examples):\s*$")
_ROLE_ARGS = frozenset({"log_dir", "track_candidates", "related_candidates"})
_COMPAT_ARGS = frozenset({"output_dir", "visualize"})


_ABBREVIATIONS = ("e.g", "i.e", "incl", "etc", "vs", "approx")


def _first_sentence(text: str) -> str:
    """The text up to and including the first full stop that ends a sentence (or all of it)."""
    flat = " ".join(text.split())
    for match in re.finditer(r"\.(\s|$)", flat):
        head = flat[: match.start()]
        if not head.lower().endswith(_ABBREVIATIONS):
            return head + "."
    return flat


def _plain(text: str) -> str:
    """Docstring markup removed: ``:func:`x``` becomes ``x``, double backquotes are dropped."""
    return re.sub(r":\w+:`([^`]+)`", r"\1", text).replace("``", "")


def _sections(doc: str) -> tuple[list[str], dict[str, list[str]]]:
    """Split a Google-style docstring into body paragraphs and named sections (raw lines)."""
    body: list[str] = []
    sections: dict[str, list[str]] = {}
    current: list[str] | None = None
    paragraph: list[str] = []
    for line in doc.splitlines():
        match = _SECTION.match(line.strip()) if not line.startswith(" ") else None
        if match:
            if paragraph:
                body.append(" ".join(paragraph))
                paragraph = []
            current = sections.setdefault(match.group(1), [])
            continue
        if current is not None:
            current.append(line)
        elif line.strip():
            paragraph.append(line.strip())
        elif paragraph:
            body.append(" ".join(paragraph))
            paragraph = []
    if paragraph:
        body.append(" ".join(paragraph))
    return body, sections


def _args(lines: list[str]) -> list[tuple[str, str]]:
    """``(name, description)`` pairs of an ``Args:`` section (continuation lines joined)."""
    out: list[tuple[str, str]] = []
    for line in lines:
        stripped = line.strip()
        if not stripped:
            continue
        indent = len(line) - len(line.lstrip())
        match = re.match(r"^(\*{0,2}\w+):\s*(.*)$", stripped)
        if match and (not out or indent <= 4):
            out.append((match.group(1), match.group(2)))
        elif out:
            out[-1] = (out[-1][0], f"{out[-1][1]} {stripped}")
    return out


def _signature(name: str) -> str:
    sig = str(inspect.signature(DSL_FUNCTIONS[name])).replace("'", "")
    return f"{name}{sig}"


def _compact_entry(name: str) -> str:
    doc = inspect.getdoc(DSL_FUNCTIONS[name]) or ""
    body, sections = _sections(doc)
    lines = [_signature(name)]
    if body:
        lines.append(f"    {body[0]}")
    roles = next((p for p in body[1:] if _SUBJECT_PARAGRAPH.match(p)), None)
    if roles is not None:
        lines.append(f"    {roles}")
    for arg, text in _args(sections.get("Args", [])):
        if arg in _ROLE_ARGS or arg in _COMPAT_ARGS or arg.startswith("*"):
            continue
        lines.append(f"    {arg}: {_first_sentence(text)}")
    examples = [
        ln.strip()
        for ln in sections.get("Example", []) + sections.get("Examples", [])
        if ln.strip() and not ln.strip().startswith("#")
    ]
    if examples:
        joined: list[str] = []
        for ln in examples:  # re-join examples continued over several lines
            if joined and (joined[-1].endswith(("(", ",")) or ln.startswith(")")):
                joined[-1] = f"{joined[-1]} {ln}" if not joined[-1].endswith("(") else joined[-1] + ln
            else:
                joined.append(ln)
        lines.append(f"    e.g. {joined[0]}")
    return _plain("\n".join(lines))


@cache
def compact_reference(names: tuple[str, ...] | None = None) -> str:
    """A short form of the predicate library for small context windows and slow CPUs.

    Per function: the signature, the one-line summary, the paragraph stating which argument is
    the subject and which the reference (when the function has one), the first sentence of each
    argument's description and the first example. About half the tokens of
    :func:`~scenariominer.mine.dsl.library_reference`.

    Args:
        names: functions to include, in this order; default every DSL function.
    """
    chosen = names if names is not None else tuple(DSL_FUNCTIONS)
    return "\n\n".join(_compact_entry(n) for n in chosen)


def library_text(style: ReferenceStyle | str = ReferenceStyle.COMPACT) -> str:
    """The predicate library as documented in the prompt, in the given style."""
    style = ReferenceStyle(style)
    if style is ReferenceStyle.FULL:
        return library_reference()
    return compact_reference()


def categories_text() -> str:
    """The object categories and category groups a program may name."""
    cats = ", ".join(c for c in AV2_CATEGORIES)
    groups = "; ".join(
        f"{g} ({', '.join(sorted(members))})" if g != "ANY" else "ANY (every category)"
        for g, members in CATEGORY_GROUPS.items()
    )
    return f"Object categories: {cats}.\nCategory groups: {groups}."


@cache
def system_prompt(style: ReferenceStyle | str = ReferenceStyle.COMPACT) -> str:
    """The system message shared by every request (role, library, categories, rules)."""
    style = ReferenceStyle(style)
    return (
        f"{_ROLE}\n\nMining functions:\n\n{library_text(style)}\n\n{categories_text()}\n\n"
        f"{_ROLES_GUIDE}\n\n{_RULES}"
    )


def _fenced(program: str) -> str:
    return f"```python\n{program.strip()}\n```"


def user_prompt(description: str, examples: Sequence[ExampleProgram] = (), plan: str | None = None) -> str:
    """The user message: the few-shot examples, then the description (last).

    Args:
        description: the scenario description to write a program for.
        examples: example programs, most similar first; they are listed most similar LAST so the
            closest example sits next to the description.
        plan: the description's plan (:func:`scenariominer.mine.plan.plan_text`), shown after it.
    """
    parts: list[str] = []
    if examples:
        parts.append(_EXAMPLES_HEADER)
        for ex in reversed(list(examples)):
            parts.append(f"Description: {ex.description}\n{_fenced(ex.program)}")
    parts.append(f"{_TASK}\nDescription: {description.strip()}")
    if plan:
        parts.append(f"{_PLAN_HEADER}\n{plan}")
    return "\n\n".join(parts)


def build_messages(
    description: str,
    examples: Sequence[ExampleProgram] = (),
    style: ReferenceStyle | str = ReferenceStyle.COMPACT,
    plan: str | None = None,
) -> list[Message]:
    """The first request for a description: system message, then the user message."""
    return [system(system_prompt(style)), user(user_prompt(description, examples, plan))]


def repair_message(error_feedback: str, *, repeated: bool = False) -> str:
    """The user message of a repair round, quoting the error of the previous program.

    Args:
        error_feedback: the error in words.
        repeated: the faulty program had already failed in an earlier attempt; the message then
            asks for a different program.
    """
    text = _REPAIR.format(error=error_feedback.strip())
    return f"{text}\n{_REPEATED}" if repeated else text


def repair_messages(
    first: Sequence[Message], faulty_program: str, error_feedback: str, *, repeated: bool = False
) -> list[Message]:
    """A repair request: the first request, the faulty program as the answer, then the error.

    Only the latest failure is shown (as in the paper's algorithm, each round composes the
    description with the last code and its error), which keeps the prompt short; the first
    request stays an exact prefix so its key-value cache is reused.

    Args:
        first: the messages of the first request (:func:`build_messages`).
        faulty_program: the program that failed (as extracted from the answer).
        error_feedback: the error in words (:meth:`ProgramError.feedback`).
        repeated: the faulty program had already failed before (see :func:`repair_message`).
    """
    return [
        *first,
        assistant(_fenced(faulty_program or "# (no code)")),
        user(repair_message(error_feedback, repeated=repeated)),
    ]
