"""The plan step of program generation (mine/plan.py) with a scripted model and the real one."""

from __future__ import annotations

import json

import pytest
from mining_scenes import street_scene
from pydantic import ValidationError

from scenariominer.config.mining import GenerationConfig, MiningConfig
from scenariominer.llm.cache import resolve_cache_dir
from scenariominer.llm.client import ChatClient
from scenariominer.llm.embeddings import HashingEmbedder
from scenariominer.llm.llamacpp import LlamaCppBackend
from scenariominer.llm.model_files import ModelNotAvailableError, ensure_model_file
from scenariominer.mine.loop import GenerationReport, generate_program
from scenariominer.mine.plan import extract_plan, plan_model, plan_text
from scenariominer.mine.programs import load_examples
from scenariominer.mine.sandbox import ProgramResult, run_trusted_program
from scenariominer.mine.synthesis import ExampleSelector, ProgramSynthesizer
from scenariominer.testing import ScriptedBackend

DESCRIPTION = "vehicle with a bicycle to its right"
PLAN = {
    "subject_words": "vehicle",
    "subject_category": "VEHICLE",
    "related": [{"words": "bicycle", "category": "BICYCLE"}],
    "relations": [
        {
            "subject_words": "vehicle",
            "function": "has_objects_in_relative_direction",
            "other_words": "bicycle",
            "direction": "right",
            "argument": None,
        }
    ],
    "conditions": [],
    "numbers": [{"value": 4, "unit": "m", "meaning": "distance to the bicycle"}],
}
PROGRAM = (
    "```python\n"
    "vehicles = get_objects_of_category(log_dir, category='VEHICLE')\n"
    "bicycles = get_objects_of_category(log_dir, category='BICYCLE')\n"
    "result = has_objects_in_relative_direction(vehicles, bicycles, log_dir, direction='right')\n"
    "output_scenario(result, description, log_dir, output_dir)\n"
    "```"
)


def trusted(program: str, context, description: str) -> ProgramResult:  # type: ignore[no-untyped-def]
    return run_trusted_program(program, context, description=description)


def _synth(
    replies: list[str], plan: bool = True, plan_program: bool = False
) -> tuple[ProgramSynthesizer, ScriptedBackend]:
    backend = ScriptedBackend(replies)
    selector = ExampleSelector(load_examples(), HashingEmbedder(128))
    config = GenerationConfig(max_attempts=2, plan=plan, plan_program=plan_program, plan_rules=False)
    return ProgramSynthesizer(ChatClient(backend), selector, config), backend


def test_the_plan_schema_names_only_existing_categories_and_functions() -> None:
    model = plan_model()
    model.model_validate(PLAN)
    for field, bad in (
        ("subject_category", "CAR"),
        ("relations", [{**PLAN["relations"][0], "function": "overtakes"}]),
    ):
        with pytest.raises(ValidationError):
            model.model_validate({**PLAN, field: bad})
    schema = json.dumps(model.model_json_schema())
    assert "ARTICULATED_BUS" in schema and "being_crossed_by" in schema
    # the structural helpers are not planned: the program writer adds them itself
    assert "output_scenario" not in schema and "scenario_and" not in schema


def test_the_plan_is_shown_to_the_program_writer_and_stored_with_the_report() -> None:
    synth, backend = _synth([json.dumps(PLAN), PROGRAM])
    report = generate_program(DESCRIPTION, synth, [street_scene()], config=MiningConfig(), runner=trusted)

    assert report.ok and report.plan == PLAN
    plan_request, program_request = backend.requests
    assert plan_request.json_schema is not None  # constrained by the plan's schema
    shown = program_request.messages[-1].content
    assert shown.index("Description: vehicle with a bicycle") < shown.index(
        "has_objects_in_relative_direction(vehicle, bicycle, direction='right')"
    )
    assert "number stated: 4 m (distance to the bicycle)" in shown
    assert GenerationReport.from_json(report.to_json()).plan == PLAN


def test_a_plan_the_model_cannot_form_is_recorded_and_the_program_written_without_it() -> None:
    garbage = '{"subject_words": "vehicle", "subject_category": "SPACESHIP"}'
    synth, backend = _synth([garbage, garbage, garbage, PROGRAM])
    report = generate_program(DESCRIPTION, synth, [street_scene()], config=MiningConfig(), runner=trusted)

    assert report.ok
    assert (
        report.plan is not None
        and "SPACESHIP" in report.plan["error"]
        or "subject_category" in str(report.plan)
    )
    assert "first reading" not in backend.requests[-1].messages[-1].content


def test_planning_off_makes_no_plan_call() -> None:
    synth, backend = _synth([PROGRAM], plan=False)
    report = generate_program(DESCRIPTION, synth, [street_scene()], config=MiningConfig(), runner=trusted)
    assert report.ok and report.plan is None and len(backend.requests) == 1


def test_plan_text_lists_every_part() -> None:
    text = plan_text({**PLAN, "conditions": [{"function": "stationary", "negated": True, "argument": None}]})
    assert text.splitlines() == [
        "- subject: vehicle -> category VEHICLE",
        "- other objects: bicycle -> category BICYCLE",
        "- relation: has_objects_in_relative_direction(vehicle, bicycle, direction='right')",
        "- condition: scenario_not(...) of stationary(vehicle)",
        "- number stated: 4 m (distance to the bicycle)",
    ]


@pytest.mark.slow
def test_the_embedded_model_reads_a_description_into_a_valid_plan() -> None:
    try:
        model_file = ensure_model_file(resolve_cache_dir())
    except ModelNotAvailableError as exc:
        pytest.skip(f"bundled model not available: {exc}")
    backend = LlamaCppBackend(model_file, model_name="qwen2.5-coder-1.5b", n_ctx=8192)
    try:
        plan = extract_plan(ChatClient(backend), "pedestrians within 10 m of a bus")
    finally:
        backend.close()
    plan_model().model_validate(plan)  # the schema holds (the grammar enforced it)
    assert plan["subject_category"] == "PEDESTRIAN"
    assert any(n["value"] == 10 and n["unit"] == "m" for n in plan["numbers"])
