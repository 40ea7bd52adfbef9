"""Execution-based consensus over sampled programs, with a scripted model on a synthetic street."""

from __future__ import annotations

import math

import pytest
from mining_scenes import street_scene

from scenariominer.config.mining import GenerationConfig, MiningConfig
from scenariominer.llm import ChatClient, HashingEmbedder
from scenariominer.mine.consensus import Candidate, cell_jaccard, choose_by_consensus, consensus_program
from scenariominer.mine.context import LogContext
from scenariominer.mine.programs import load_examples
from scenariominer.mine.sandbox import ProgramResult, run_trusted_program
from scenariominer.mine.synthesis import ExampleSelector, ProgramSynthesizer
from scenariominer.testing import ScriptedBackend

BIKE_RIGHT = (
    "```python\n"
    "vehicles = get_objects_of_category(log_dir, category='VEHICLE')\n"
    "bicycles = get_objects_of_category(log_dir, category='BICYCLE')\n"
    "result = has_objects_in_relative_direction(vehicles, bicycles, log_dir, direction='{side}')\n"
    "output_scenario(result, description, log_dir, output_dir)\n"
    "```"
)
RIGHT, LEFT = BIKE_RIGHT.format(side="right"), BIKE_RIGHT.format(side="left")
BROKEN = "```python\nx = turning(log_dir)\n```"


def trusted(program: str, context: LogContext, description: str) -> ProgramResult:
    return run_trusted_program(program, context, description=description)


@pytest.fixture(scope="module")
def street() -> LogContext:
    return street_scene()


def _synth(replies: list[str]) -> tuple[ProgramSynthesizer, ScriptedBackend]:
    backend = ScriptedBackend(replies)
    selector = ExampleSelector(load_examples(), HashingEmbedder(128))
    return ProgramSynthesizer(
        ChatClient(backend), selector, GenerationConfig(plan=False, max_attempts=3)
    ), backend


def _cells(*cells: tuple[str, str, int]) -> frozenset[tuple[str, str, int]]:
    return frozenset(cells)


def test_jaccard_of_cells() -> None:
    a, b = _cells(("L", "t1", 0), ("L", "t1", 1)), _cells(("L", "t1", 1))
    assert cell_jaccard(a, b) == 0.5
    assert cell_jaccard(frozenset(), frozenset()) == 1.0  # both find nothing: they agree
    assert cell_jaccard(a, frozenset()) == 0.0


def test_the_candidate_the_others_agree_with_wins() -> None:
    x, y = _cells(("L", "a", 0), ("L", "a", 1)), _cells(("L", "b", 5))
    report = choose_by_consensus(
        [
            Candidate("greedy", y),
            Candidate("s1", x, seed=1),
            Candidate("s2", x, seed=2),
            Candidate("bad", None, "e"),
        ],
        min_agreement=0.5,
    )
    assert report.program == "s1"  # two of three valid candidates found x
    assert report.agreement[0] == 0.0 and report.agreement[1] == 0.5 and math.isnan(report.agreement[3])
    assert report.confidence == 0.5 and not report.needs_review


def test_a_lone_or_disputed_result_is_flagged_for_review() -> None:
    x = _cells(("L", "a", 0))
    lone = choose_by_consensus([Candidate("only", x), Candidate("bad", None, "e")])
    assert lone.program == "only" and lone.needs_review and math.isnan(lone.confidence)
    disputed = choose_by_consensus([Candidate("g", x), Candidate("s", _cells(("L", "b", 0)))], 0.5)
    assert disputed.program == "g" and disputed.confidence == 0.0 and disputed.needs_review  # tie: greedy
    none = choose_by_consensus([Candidate("bad", None, "e")])
    assert none.program is None and none.needs_review


def test_sampled_candidates_outvote_a_wrong_greedy_program(street: LogContext) -> None:
    # the greedy loop's program looks left; two of three samples look right, one does not run
    synth, backend = _synth([LEFT, RIGHT, BROKEN, RIGHT])
    config = MiningConfig(generation=GenerationConfig(plan=False, max_attempts=3))
    report = consensus_program(
        "vehicle with a bicycle to its right", synth, [street], samples=4, config=config, runner=trusted
    )
    assert report.program is not None and "direction='right'" in report.program
    assert [c.ok for c in report.candidates] == [True, True, False, True]
    assert report.candidates[2].error.startswith("forbidden error")
    assert (
        report.confidence == pytest.approx(report.agreement[1]) and report.agreement[1] > report.agreement[0]
    )
    # the samples come from the first request at a temperature, one seed each
    sampled = backend.requests[1:]
    assert [r.params.seed for r in sampled] == [1, 2, 3]
    assert all(r.params.temperature > 0 for r in sampled)


def test_one_sample_is_the_plain_loop(street: LogContext) -> None:
    synth, backend = _synth([RIGHT])
    report = consensus_program(
        "vehicle with a bicycle to its right", synth, [street], samples=1, runner=trusted
    )
    assert report.program is not None and len(report.candidates) == 1 and len(backend.requests) == 1
    assert report.needs_review  # nothing to compare with


def test_mining_with_consensus_reports_its_confidence(street: LogContext) -> None:
    from scenariominer.mine.query import mine_logs

    synth, _ = _synth([LEFT, RIGHT, RIGHT])
    config = MiningConfig(generation=GenerationConfig(plan=False, max_attempts=3, consensus_samples=3))
    report = mine_logs(
        "bikes to the right of vehicles", [street], config=config, synthesizer=synth, runner=trusted
    )
    assert report.program is not None and "direction='right'" in report.program
    summary = report.summary()
    assert summary["consensus_candidates"] == 3 and summary["consensus_valid"] == 3
    assert summary["consensus_confidence"] == pytest.approx(0.5) and summary["needs_review"] is False
