"""The program grammar (mine/grammar.py), checked with llama.cpp's own grammar sampler.

`GbnfMatcher` feeds a text's tokens through the grammar exactly as constrained decoding would, so
these tests say what the embedded model can and cannot write under the grammar.
"""

from __future__ import annotations

import ast
import importlib.util

import pytest

from scenariominer.llm.client import ChatClient
from scenariominer.llm.factory import resolve_cache_dir
from scenariominer.llm.gbnf import GbnfMatcher, GrammarSyntaxError
from scenariominer.llm.llamacpp import LlamaCppBackend
from scenariominer.llm.model_files import ModelNotAvailableError, ensure_model_file
from scenariominer.mine.dsl import get_objects_of_category, stationary
from scenariominer.mine.grammar import program_grammar
from scenariominer.mine.programs import load_examples
from scenariominer.mine.prompts import build_messages
from scenariominer.mine.sandbox import check_program
from scenariominer.mine.synthesis import extract_program

OUTPUT = "output_scenario({}, description, log_dir, output_dir)"
GOOD = """vehicles = get_objects_of_category(log_dir, category='VEHICLE')
peds = get_objects_of_category(log_dir, category='PEDESTRIAN')
near = has_objects_in_relative_direction(vehicles, peds, log_dir, direction='forward', within_distance=20)
moving = scenario_not(stationary)(near, log_dir)
output_scenario(moving, description, log_dir, output_dir)
"""


@pytest.fixture(scope="module")
def matcher() -> GbnfMatcher:
    if importlib.util.find_spec("llama_cpp") is None:
        pytest.skip("llama-cpp-python is not installed (pip install 'scenariominer[llm]')")
    try:
        return GbnfMatcher(ensure_model_file(resolve_cache_dir()).path)
    except ModelNotAvailableError as exc:
        pytest.skip(f"bundled model not available: {exc}")


def test_every_bank_program_is_admitted(matcher: GbnfMatcher) -> None:
    grammar = program_grammar()
    for example in load_examples():
        # the bank's layout (comments, calls over several lines) normalised as the model writes it
        source = ast.unparse(ast.parse(example.program)) + "\n"
        assert matcher.match(grammar, source).accepted, example.description


def test_a_fenced_program_and_comments_are_admitted(matcher: GbnfMatcher) -> None:
    text = "```python\n# pedestrians ahead\n" + GOOD + "```"
    assert matcher.match(program_grammar(), text).accepted


@pytest.mark.parametrize(
    ("wrong", "where"),
    [
        # log_dir where the second object set belongs
        (GOOD.replace("(vehicles, peds, log_dir,", "(vehicles, log_dir, log_dir,"), "log_dir, log_dir"),
        # the log rebound as a variable
        ("log_dir = log_dir\n" + GOOD, "log_dir = "),
        # a direction the predicate does not know
        (GOOD.replace("'forward'", "'upward'"), "'upward'"),
        # a category that is not an Argoverse 2 name or group
        (GOOD.replace("'PEDESTRIAN'", "'PERSON'"), "'PERSON'"),
        # a keyword argument the function does not have
        (GOOD.replace("within_distance=20", "distance_thresh=20"), "distance_thresh"),
        # a function that does not exist
        (GOOD.replace("scenario_not(stationary)", "is_parked"), "is_parked"),
        # prose after the program
        (GOOD + "This program finds vehicles.", "This program"),
        # no output_scenario line
        (GOOD.replace("output_scenario(moving, description, log_dir, output_dir)\n", ""), None),
        # Python the sandbox refuses anyway: imports, attribute access, loops
        ("import os\n" + GOOD, "import"),
        (GOOD.replace("peds = get", "peds = log_dir.get"), "log_dir.get"),
    ],
)
def test_programs_outside_the_grammar_are_refused_where_they_leave_it(
    matcher: GbnfMatcher, wrong: str, where: str | None
) -> None:
    result = matcher.match(program_grammar(), wrong)
    assert not result.accepted
    assert result.rejected_at is not None
    if where is None:
        assert result.rejected_at >= len(wrong) - 60  # a valid prefix that may not end there
    else:
        # the first forbidden token starts inside the faulty part (tokens may begin a few characters early)
        start = wrong.index(where)
        assert start - 8 <= result.rejected_at <= start + len(where)


def test_names_exclude_the_log_and_the_output_call(matcher: GbnfMatcher) -> None:
    grammar = program_grammar()
    for name, ok in (("log_dirs", True), ("log_di", True), ("logs", True), ("output", True),
                     ("log_dir", False), ("output_scenario_buses", False)):  # fmt: skip
        text = f"{name} = get_objects_of_category(log_dir, category='BUS')\n{OUTPUT.format(name)}"
        assert matcher.match(grammar, text).accepted is ok, name


def test_the_output_call_may_take_a_nested_call_and_fewer_arguments(matcher: GbnfMatcher) -> None:
    grammar = program_grammar()
    for text in (
        "output_scenario(stationary(get_objects_of_category(log_dir, category='BUS'), log_dir))",
        "output_scenario(stationary(get_objects_of_category(log_dir, category='BUS'), log_dir), description)",
    ):
        assert matcher.match(grammar, text).accepted, text


def test_choices_follow_the_predicates(matcher: GbnfMatcher) -> None:
    """The grammar offers exactly what the predicates accept: a value they refuse is not offered."""
    grammar = program_grammar()
    for lane_type, ok in (("BIKE", True), ("SIDEWALK", False)):
        text = f"x = on_lane_type(vehicles, log_dir, lane_type='{lane_type}')\n{OUTPUT.format('x')}"
        assert matcher.match(grammar, text).accepted is ok


def test_a_grammar_over_some_functions_offers_only_those(matcher: GbnfMatcher) -> None:
    small = program_grammar(
        (("get_objects_of_category", get_objects_of_category), ("stationary", stationary))
    )
    ok = "a = get_objects_of_category(log_dir, category='BUS')\nb = stationary(a, log_dir)\n"
    ok += OUTPUT.format("b")
    assert matcher.match(small, ok).accepted
    assert not matcher.match(small, ok.replace("stationary(a, log_dir)", "turning(a, log_dir)")).accepted
    assert matcher.match(
        program_grammar(), ok.replace("stationary(a, log_dir)", "turning(a, log_dir)")
    ).accepted


def test_a_broken_grammar_is_a_clear_error(matcher: GbnfMatcher) -> None:
    with pytest.raises(GrammarSyntaxError, match="could not parse"):
        matcher.match("root ::= undefined-rule", "x")


@pytest.mark.slow
def test_the_embedded_model_writes_a_checkable_program_under_the_grammar() -> None:
    """Real model, real grammar: the answer is a program the sandbox's static check accepts."""
    try:
        model = ensure_model_file(resolve_cache_dir())
    except ModelNotAvailableError as exc:
        pytest.skip(f"bundled model not available: {exc}")
    backend = LlamaCppBackend(model, model_name="qwen2.5-coder-1.5b", n_ctx=8192)
    client = ChatClient(backend)
    try:
        bank = load_examples()
        for description in ("parked bus", "pedestrian crossing in front of a moving vehicle"):
            reply = client.completion(
                build_messages(description, bank[:3], "compact"), grammar=program_grammar(), max_tokens=300
            )
            program = extract_program(reply.text)
            assert check_program(program) is None, (description, reply.text)
            assert "output_scenario(" in program
    finally:
        backend.close()
