"""Prompts of mining-program synthesis: fixed prefix first, description last, exact repair prefix."""

from __future__ import annotations

import inspect

import pytest

from scenariominer.config.mining import ReferenceStyle
from scenariominer.data.categories import AV2_CATEGORIES
from scenariominer.llm.base import Message, Role
from scenariominer.mine.dsl import DSL_FUNCTIONS, library_reference
from scenariominer.mine.programs import ExampleProgram, load_examples
from scenariominer.mine.prompts import (
    PROMPT_VERSION,
    build_messages,
    compact_reference,
    library_text,
    repair_message,
    repair_messages,
    system_prompt,
    user_prompt,
)

EX_A = ExampleProgram("bus in the bike lane", "x = 1\noutput_scenario(x, description)\n")
EX_B = ExampleProgram("accelerating vehicle", "y = 2\noutput_scenario(y, description)\n")


def test_a_new_prompt_version_invalidates_cached_programs(monkeypatch: pytest.MonkeyPatch) -> None:
    import scenariominer.mine.loop as loop
    from scenariominer.config.mining import GenerationConfig

    messages = [Message(Role.USER, "find buses")]
    before = loop.program_cache_key("bus", "m", messages, GenerationConfig())
    assert loop.program_cache_key("Bus ", "m", messages, GenerationConfig()) == before  # normalised
    monkeypatch.setattr(loop, "PROMPT_VERSION", PROMPT_VERSION + "-next")
    assert loop.program_cache_key("bus", "m", messages, GenerationConfig()) != before


@pytest.mark.parametrize("style", list(ReferenceStyle))
def test_system_prompt_documents_every_function_and_category(style: ReferenceStyle) -> None:
    text = system_prompt(style)
    for name in DSL_FUNCTIONS:
        assert f"\n{name}(" in text or f"def {name}(" in text, name
    for category in AV2_CATEGORIES:
        assert category in text
    assert "VULNERABLE_ROAD_USER" in text
    assert "output_scenario(final_scenario, description, log_dir, output_dir)" in text
    # the spatial-relation guidance names who the subject is
    assert "seen from the track_candidates" in text
    assert "has_objects_in_relative_direction(vehicles, bicycles, log_dir, direction='right')" in text


def test_compact_reference_keeps_signatures_roles_and_examples_in_half_the_text() -> None:
    compact = compact_reference()
    full = library_reference()
    assert len(compact) < 0.55 * len(full)
    for name, func in DSL_FUNCTIONS.items():
        sig = str(inspect.signature(func)).replace("'", "")
        assert f"{name}{sig}" in compact, name
    # the subject/reference paragraph of a relational predicate survives
    assert "SUBJECT = track_candidates (returned): the object being crossed" in compact
    # one example per function, re-joined when the docstring wraps it over lines
    assert (
        "e.g. peds_in_front_of_vehicles = get_objects_in_relative_direction(vehicles, peds, log_dir, "
        "direction='forward', within_distance=15, lateral_thresh=1)" in compact
    )
    # sentences are not cut at abbreviations, markup is gone
    assert "(every motor vehicle incl. the ego:" in compact
    assert "``" not in compact and ":func:" not in compact
    assert library_text(ReferenceStyle.FULL) == full
    assert library_text("compact") == compact


def test_fixed_text_comes_first_and_the_description_last() -> None:
    a = build_messages("vehicle with a bicycle to its right", [EX_A, EX_B])
    b = build_messages("pedestrian near a bus", [EX_B])
    assert [m.role for m in a] == [Role.SYSTEM, Role.USER]
    assert a[0] == b[0]  # identical system message for every description
    assert a[1].content.rstrip().endswith("Description: vehicle with a bicycle to its right")
    # the most similar example (first in the list) is shown last, next to the description
    body = a[1].content
    assert (
        body.index("accelerating vehicle")
        < body.index("bus in the bike lane")
        < body.index("vehicle with a bicycle")
    )
    assert "```python\nx = 1\noutput_scenario(x, description)\n```" in body


def test_zero_shot_user_prompt_is_just_the_task() -> None:
    assert (
        user_prompt("  accelerating bus ")
        == "Write the program for this description.\nDescription: accelerating bus"
    )


def test_repair_request_extends_the_first_request_with_code_and_error() -> None:
    first = build_messages("accelerating vehicle", load_examples()[:2])
    feedback = "runtime error: line 2: NameError: name 'vehicle' is not defined"
    msgs = repair_messages(first, "v = vehicle\n", feedback)
    assert msgs[: len(first)] == first  # exact prefix: the key-value cache is reused
    assert msgs[-2].role is Role.ASSISTANT and msgs[-2].content == "```python\nv = vehicle\n```"
    assert msgs[-1].role is Role.USER and feedback in msgs[-1].content
    assert repair_message(feedback).startswith("That program failed: " + feedback)
    again = repair_messages(first, "v = vehicle\n", feedback, repeated=True)
    assert again[:-1] == msgs[:-1] and "You wrote this program before" in again[-1].content
