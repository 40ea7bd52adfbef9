"""Fault-tolerant iterative code generation (Algorithm 1): repair from errors, K tries, cache."""

from __future__ import annotations

import os
from pathlib import Path

import pytest
from mining_scenes import street_scene

from scenariominer.config.mining import GenerationConfig, MiningConfig
from scenariominer.llm import ChatClient, HashingEmbedder
from scenariominer.llm.base import Role
from scenariominer.mine.context import LogContext
from scenariominer.mine.loop import (
    GenerationReport,
    GenerationStatus,
    ProgramCache,
    generate_program,
    validate_program,
)
from scenariominer.mine.programs import load_examples
from scenariominer.mine.sandbox import ErrorKind, ProgramResult, run_trusted_program
from scenariominer.mine.synthesis import ExampleSelector, ProgramSynthesizer
from scenariominer.testing import ScriptedBackend

DESCRIPTION = "vehicle with a bicycle to its right"

SYNTAX_ERROR = "```python\nvehicles = get_objects_of_category(log_dir, category='VEHICLE'\n```"
FORBIDDEN = "```python\nimport os\nvehicles = get_objects_of_category(log_dir, category='VEHICLE')\n```"
RUNTIME_ERROR = (
    "```python\n"
    "vehicles = get_objects_of_category(log_dir, category='VEHICLE')\n"
    "bicycles = get_objects_of_category(log_dir, category='BICYCLE')\n"
    "side = 'diagonal'\n"  # through a variable: only running it can tell
    "result = has_objects_in_relative_direction(vehicles, bicycles, log_dir, direction=side)\n"
    "output_scenario(result, description, log_dir, output_dir)\n"
    "```"
)
VALID = RUNTIME_ERROR.replace("'diagonal'", "'right'")


def trusted(program: str, context: LogContext, description: str) -> ProgramResult:
    """In-process runner: the tests need the loop's logic, not the child process."""
    return run_trusted_program(program, context, description=description)


@pytest.fixture(scope="module")
def street() -> LogContext:
    return street_scene()


def _synth(replies: list[str], k: int = 5) -> tuple[ProgramSynthesizer, ScriptedBackend]:
    backend = ScriptedBackend(replies)
    selector = ExampleSelector(load_examples(), HashingEmbedder(128))
    return ProgramSynthesizer(
        ChatClient(backend), selector, GenerationConfig(plan=False, max_attempts=k)
    ), backend


def _config(k: int = 5) -> MiningConfig:
    return MiningConfig(generation=GenerationConfig(plan=False, max_attempts=k))


def test_errors_are_fed_back_until_a_valid_program_in_four_attempts(street: LogContext) -> None:
    synth, backend = _synth([SYNTAX_ERROR, FORBIDDEN, RUNTIME_ERROR, VALID])
    report = generate_program(DESCRIPTION, synth, [street], config=_config(), runner=trusted)

    assert report.status is GenerationStatus.OK and report.ok
    assert report.attempts_used == 4
    kinds = [a.error.kind if a.error else None for a in report.attempts]
    assert kinds == [ErrorKind.SYNTAX, ErrorKind.FORBIDDEN, ErrorKind.RUNTIME, None]
    assert report.program is not None and "side = 'right'" in report.program
    assert report.validation_log_ids == (street.log_id,)

    requests = backend.requests
    assert len(requests) == 4
    first = requests[0].messages
    assert [m.role for m in first] == [Role.SYSTEM, Role.USER]
    for i in range(1, 4):
        previous = report.attempts[i - 1]
        assert previous.error is not None
        msgs = requests[i].messages
        assert msgs[: len(first)] == first  # the repair prompt extends the first request
        assert msgs[-2].role is Role.ASSISTANT and previous.program.strip() in msgs[-2].content
        assert previous.error.message in msgs[-1].content  # the previous error is shown to the model
    assert "'(' was never closed" in requests[1].messages[-1].content
    assert "imports are not allowed" in requests[2].messages[-1].content
    assert "direction must be one of" in requests[3].messages[-1].content
    assert report.generation_s >= 0 and report.validation_s > 0


def test_after_k_failures_the_description_goes_to_manual_review_with_every_attempt(
    street: LogContext,
) -> None:
    synth, backend = _synth([SYNTAX_ERROR, FORBIDDEN, RUNTIME_ERROR], k=3)
    report = generate_program(DESCRIPTION, synth, [street], config=_config(3), runner=trusted)
    assert report.status is GenerationStatus.MANUAL_REVIEW and not report.ok
    assert report.program is None
    assert report.attempts_used == 3 and report.max_attempts == 3
    assert [a.index for a in report.attempts] == [1, 2, 3]
    assert all(a.error is not None for a in report.attempts)
    assert report.last_error is not None and report.last_error.kind is ErrorKind.RUNTIME
    assert backend.remaining == 0


def test_a_repeated_failing_program_makes_the_next_request_sample(street: LogContext) -> None:
    commented = RUNTIME_ERROR.replace("output_scenario(", "# same program, new comment\noutput_scenario(")
    synth, backend = _synth([RUNTIME_ERROR, commented, VALID])
    report = generate_program(DESCRIPTION, synth, [street], config=_config(), runner=trusted)
    assert report.ok and report.attempts_used == 3
    first, second, third = (r.params for r in backend.requests)
    assert first.temperature == second.temperature == 0.0  # greedy while the answers differ
    assert third.temperature == 0.7 and third.seed == 3 and third.top_k == 0  # sampled after a repeat
    assert "You wrote this program before" in backend.requests[2].messages[-1].content
    assert "You wrote this program before" not in backend.requests[1].messages[-1].content
    # retry_temperature = 0 keeps every request greedy
    synth, backend = _synth([RUNTIME_ERROR, RUNTIME_ERROR, VALID])
    greedy = MiningConfig(generation=GenerationConfig(plan=False, retry_temperature=0.0))
    assert generate_program(DESCRIPTION, synth, [street], config=greedy, runner=trusted).ok
    assert all(r.params.temperature == 0.0 for r in backend.requests)


def test_an_empty_scenario_is_a_valid_answer(street: LogContext) -> None:
    program = (
        "```python\nx = get_objects_of_category(log_dir, category='DOG')\n"
        "output_scenario(x, description, log_dir, output_dir)\n```"
    )
    synth, _ = _synth([program])
    report = generate_program("dog on the road", synth, [street], config=_config(), runner=trusted)
    assert report.ok and report.attempts_used == 1


def test_a_program_must_run_on_every_validation_log(street: LogContext) -> None:
    needs_map = (
        "v = get_objects_of_category(log_dir, category='VEHICLE')\n"
        "output_scenario(on_intersection(v, log_dir), description, log_dir, output_dir)\n"
    )
    no_map = street_scene(with_map=False)
    assert validate_program(needs_map, [street], "vehicle in an intersection", runner=trusted) is None
    error = validate_program(needs_map, [street, no_map], "vehicle in an intersection", runner=trusted)
    assert error is not None and error.kind is ErrorKind.RUNTIME
    assert error.message.startswith(f"on log {no_map.log_id}: ") and "needs an HD map" in error.message
    with pytest.raises(ValueError, match="at least one validation log"):
        validate_program("x = 1", [], "d")


def test_the_outcome_is_cached_so_a_rerun_costs_no_model_call(street: LogContext, tmp_path: Path) -> None:
    cache = ProgramCache(tmp_path / "programs.sqlite3")
    synth, backend = _synth([RUNTIME_ERROR, VALID])
    first = generate_program(DESCRIPTION, synth, [street], config=_config(), cache=cache, runner=trusted)
    assert first.ok and not first.from_cache and len(cache) == 1

    again = generate_program(DESCRIPTION, synth, [street], config=_config(), cache=cache, runner=trusted)
    assert again.from_cache and backend.remaining == 0 and len(backend.requests) == 2
    assert again.program == first.program and again.attempts == first.attempts

    reopened = ProgramCache(tmp_path / "programs.sqlite3")
    assert isinstance(
        generate_program(DESCRIPTION, synth, [street], config=_config(), cache=reopened, runner=trusted),
        GenerationReport,
    )
    # another K (or description) is another key: the model is asked again
    synth2, backend2 = _synth([VALID], k=4)
    fresh = generate_program(DESCRIPTION, synth2, [street], config=_config(4), cache=cache, runner=trusted)
    assert not fresh.from_cache and len(backend2.requests) == 1
    # force ignores the cached outcome
    synth3, backend3 = _synth([VALID])
    forced = generate_program(
        DESCRIPTION, synth3, [street], config=_config(), cache=cache, runner=trusted, force=True
    )
    assert not forced.from_cache and forced.attempts_used == 1 and len(backend3.requests) == 1
    assert GenerationReport.from_json(forced.to_json(), from_cache=False) == forced


def test_generation_needs_a_validation_log() -> None:
    synth, _ = _synth([VALID])
    with pytest.raises(ValueError, match="validation log"):
        generate_program(DESCRIPTION, synth, [], config=_config())


@pytest.mark.slow  # starts the sandbox's process server
def test_runtime_errors_from_the_sandbox_child_are_fed_back(street: LogContext) -> None:
    synth, backend = _synth([RUNTIME_ERROR, VALID])
    report = generate_program(DESCRIPTION, synth, [street], config=_config())  # default: sandbox
    assert report.ok and report.attempts_used == 2
    assert report.attempts[0].error is not None
    assert "direction must be one of" in backend.requests[1].messages[-1].content


@pytest.mark.slow  # runs the embedded Qwen2.5-Coder-1.5B model (about a minute per call on 2 cores)
def test_the_embedded_model_writes_a_program_within_k_attempts(street: LogContext) -> None:
    from scenariominer.config import Config
    from scenariominer.config.llm import LLMConfig
    from scenariominer.llm.errors import ModelNotAvailableError
    from scenariominer.llm.factory import make_chat_client
    from scenariominer.mine.sandbox import check_program

    pytest.importorskip("llama_cpp")
    try:
        client = make_chat_client(Config(llm=LLMConfig(cache=False, n_threads=os.cpu_count() or 0)))
    except ModelNotAvailableError as exc:
        pytest.skip(f"embedded model not available: {exc}")
    k = 2
    synth = ProgramSynthesizer(
        client,
        ExampleSelector(load_examples(), HashingEmbedder(256)),
        GenerationConfig(plan=False, max_attempts=k),
    )
    report = generate_program("accelerating bus", synth, [street], config=_config(k), runner=trusted)
    client.close()
    assert 1 <= report.attempts_used <= k
    assert all(a.generation_s > 0 and not a.cached_reply for a in report.attempts)
    if report.ok:
        assert report.program is not None and check_program(report.program) is None
        assert report.attempts[-1].error is None
    else:
        assert report.status is GenerationStatus.MANUAL_REVIEW and report.attempts_used == k
        assert all(a.error is not None for a in report.attempts)
