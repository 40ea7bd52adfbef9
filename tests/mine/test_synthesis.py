"""Program synthesis: code extraction from answers, few-shot choice, one model call."""

from __future__ import annotations

import pytest

from scenariominer.config.mining import GenerationConfig
from scenariominer.llm import ChatClient, HashingEmbedder
from scenariominer.llm.base import Role
from scenariominer.mine.programs import ExampleProgram, load_examples
from scenariominer.mine.synthesis import (
    ExampleSelector,
    ProgramSynthesizer,
    extract_program,
    normalize_description,
)
from scenariominer.testing import ScriptedBackend

PROGRAM = (
    "vehicles = get_objects_of_category(log_dir, category='VEHICLE')\n"
    "output_scenario(vehicles, description, log_dir, output_dir)\n"
)


# ---------------------------------------------------------------------- extraction


@pytest.mark.parametrize(
    "reply",
    [
        f"```python\n{PROGRAM}```",
        f"Here is the program:\n\n```python\n{PROGRAM}```\n\nIt selects the vehicles.",
        f"```py\n{PROGRAM}```",
        f"```\n{PROGRAM}```",
        f"```python\n{PROGRAM}",  # answer cut off before the closing fence
        PROGRAM,  # bare code
        f"Sure! The program is:\n{PROGRAM}This returns every vehicle.",  # bare code inside prose
    ],
)
def test_the_program_is_extracted_from_common_answer_shapes(reply: str) -> None:
    assert extract_program(reply) == PROGRAM


def test_the_block_that_outputs_a_scenario_wins_over_other_blocks() -> None:
    reply = f"First the categories:\n```python\nprint('VEHICLE')\n```\nThen:\n```python\n{PROGRAM}```"
    assert extract_program(reply) == PROGRAM
    two_partial = "```python\na = 1\n```\n```python\nb = get_objects_of_category(log_dir, 'BUS')\n```"
    assert extract_program(two_partial) == "b = get_objects_of_category(log_dir, 'BUS')\n"


def test_non_python_fences_are_ignored_and_unparseable_text_is_returned_as_is() -> None:
    assert extract_program(f"```json\n{{}}\n```\n```python\n{PROGRAM}```") == PROGRAM
    assert extract_program("I cannot do that (") == "I cannot do that (\n"
    assert extract_program("") == ""


def test_descriptions_are_normalised_for_identity() -> None:
    assert normalize_description("  Vehicle  with a Bicycle to its right. ") == (
        "vehicle with a bicycle to its right"
    )


# ---------------------------------------------------------------------- few-shot choice

BANK = (
    ExampleProgram("vehicle with a bicycle to its right", PROGRAM),
    ExampleProgram("pedestrian crossing in front of a vehicle", PROGRAM),
    ExampleProgram("bus in the bike lane", PROGRAM),
    ExampleProgram("vehicle turning left", PROGRAM),
)


def test_examples_are_chosen_by_similarity_most_similar_first() -> None:
    selector = ExampleSelector(BANK, HashingEmbedder(256))
    chosen = selector.select("bus in a bike lane", 2)
    assert chosen[0].description == "bus in the bike lane"
    sims = selector.similarities("bus in a bike lane")
    assert sims.shape == (4,)
    assert sims.argmax() == 2


def test_leave_one_out_never_shows_the_query_itself() -> None:
    selector = ExampleSelector(BANK, HashingEmbedder(256))
    query = "Vehicle with a bicycle to its right."
    assert all(
        normalize_description(e.description) != normalize_description(query)
        for e in selector.select(query, 3)
    )
    assert selector.select(query, 1, leave_one_out=False)[0].description == BANK[0].description
    assert len(selector.select(query, 10)) == 3
    assert selector.select(query, 0) == []
    assert ExampleSelector((), HashingEmbedder(8)).select(query, 3) == []


def test_the_bank_is_embedded_once() -> None:
    embedder = HashingEmbedder(64)
    selector = ExampleSelector(load_examples(), embedder)
    selector.select("a", 2)
    selector.select("b", 2)
    report = embedder.usage.report()
    assert sum(row.requests for row in report.rows) == len(load_examples()) + 2
    assert report.calls == 3


# ---------------------------------------------------------------------- one model call


def test_synthesizer_prompts_with_examples_and_extracts_the_program() -> None:
    backend = ScriptedBackend([f"Program:\n```python\n{PROGRAM}```"])
    synth = ProgramSynthesizer(
        ChatClient(backend),
        ExampleSelector(BANK, HashingEmbedder(256)),
        GenerationConfig(plan=False, few_shot_k=2, max_tokens=123),
    )
    messages = synth.first_messages("vehicle with a bicycle to its left")
    generation = synth.generate(messages)
    assert generation.program == PROGRAM
    assert generation.reply.startswith("Program:")
    assert not generation.cached and generation.latency_s >= 0
    request = backend.requests[0]
    assert request.params.max_tokens == 123
    assert [m.role for m in request.messages] == [Role.SYSTEM, Role.USER]
    assert "Description: vehicle with a bicycle to its right" in request.messages[1].content
    assert synth.model == "scripted:scripted-model"


def test_zero_shot_without_selector() -> None:
    synth = ProgramSynthesizer(
        ChatClient(ScriptedBackend([])), None, GenerationConfig(plan=False, few_shot_k=3)
    )
    assert synth.examples_for("anything") == []
    assert "Example programs" not in synth.first_messages("anything")[1].content
