"""Programs built from a description's plan by rules (mine/plan_program.py), and their place in the loop."""

from __future__ import annotations

import json
from typing import Any

import pytest
from mining_scenes import idx, street_scene

from scenariominer.config.mining import GenerationConfig, MiningConfig
from scenariominer.llm.client import ChatClient
from scenariominer.llm.embeddings import HashingEmbedder
from scenariominer.mine.loop import generate_program
from scenariominer.mine.plan_program import PlanCompileError, compile_plan
from scenariominer.mine.programs import load_examples
from scenariominer.mine.sandbox import ErrorKind, ProgramResult, run_trusted_program
from scenariominer.mine.synthesis import ExampleSelector, ProgramSynthesizer
from scenariominer.testing import ScriptedBackend

SCENE = street_scene()


def _plan(category: str, *, related: Any = (), relations: Any = (), conditions: Any = ()) -> dict[str, Any]:
    return {
        "subject_words": category.lower(),
        "subject_category": category,
        "related": list(related),
        "relations": list(relations),
        "conditions": list(conditions),
        "numbers": [],
    }


def _cond(function: str, argument: str | None = None, negated: bool = False) -> dict[str, Any]:
    return {"function": function, "negated": negated, "argument": argument}


def _referred(plan: dict[str, Any]) -> set[int]:
    result = run_trusted_program(compile_plan(plan).program, SCENE, description="d")
    assert result.ok, result.error
    assert result.scenario is not None
    return {int(i) for i in result.scenario.referred_tracks}


def test_conditions_filter_the_subject_and_a_negated_one_is_wrapped_in_scenario_not() -> None:
    moving = _referred(_plan("PEDESTRIAN", conditions=[_cond("stationary", negated=True)]))
    assert moving == {idx(SCENE, "ped")}  # the only pedestrian that walks
    left = _referred(_plan("VEHICLE", conditions=[_cond("changing_lanes", "direction='left'")]))
    assert left == {idx(SCENE, "changer")}
    # a bare word goes to the one text argument that accepts it
    assert _referred(_plan("BUS", conditions=[_cond("on_lane_type", "BIKE")])) == {idx(SCENE, "bus")}


def test_a_relation_read_from_the_other_objects_side_is_reversed() -> None:
    plan = _plan(
        "PEDESTRIAN",
        related=[{"words": "ego", "category": "EGO_VEHICLE"}],
        relations=[{"subject_words": "the ego", "function": "near_objects", "other_words": "pedestrians"}],
    )
    program = compile_plan(plan).program
    assert "reverse_relationship(near_objects)(related_1, subject, log_dir)" in program
    # the ego passes within 10 m of ped (x = 50), pedA and pedB (x = 20, 8 m off); ped2 stays 38 m away
    assert _referred(plan) == {idx(SCENE, "ped"), idx(SCENE, "pedA"), idx(SCENE, "pedB")}


def test_another_member_of_the_subjects_category_is_the_related_set() -> None:
    plan = _plan(
        "VEHICLE",
        relations=[{"subject_words": "vehicle", "function": "following", "other_words": "another vehicle"}],
    )
    assert "following(subject, get_objects_of_category(log_dir, category='VEHICLE'), log_dir)" in (
        compile_plan(plan).program
    )
    assert idx(SCENE, "changer") in _referred(plan)  # 20 m behind the ego... and behind the lead


def test_settings_the_function_does_not_take_are_left_out_with_a_note() -> None:
    compiled = compile_plan(_plan("VEHICLE", conditions=[_cond("stationary", "speed=3")]))
    assert "speed" not in compiled.program
    assert compiled.notes == ("stationary: left out 'speed=3' (speed is not an argument of stationary)",)
    near = compile_plan(_plan("BOX_TRUCK", conditions=[_cond("near_intersection", "threshold=15")]))
    assert "near_intersection(subject, log_dir, threshold=15)" in near.program and not near.notes


@pytest.mark.parametrize(
    ("words", "planned", "expected"),
    [
        (
            "regular vehicles",
            "VEHICLE",
            "subject = get_objects_of_category(log_dir, category='REGULAR_VEHICLE')",
        ),
        ("vehicles", "REGULAR_VEHICLE", "subject = get_objects_of_category(log_dir, category='VEHICLE')"),
        ("buses", "BUS", "category='ARTICULATED_BUS'"),
        ("the ego car", "VEHICLE", "subject = get_objects_of_category(log_dir, category='EGO_VEHICLE')"),
    ],
)
def test_the_subjects_words_decide_its_categories_as_the_phrase_rules_read_them(
    words: str, planned: str, expected: str
) -> None:
    plan = {**_plan(planned), "subject_words": words}
    assert expected in compile_plan(plan).program


@pytest.mark.parametrize(
    ("plan", "message"),
    [
        (_plan("BUS", conditions=[_cond("on_lane_type")]), "on_lane_type: the plan gives no lane_type"),
        (_plan("BUS", conditions=[_cond("on_lane_type", "lane_type='TRAM'")]), "'TRAM' is not one of"),
        (_plan("BUS", conditions=[_cond("overtakes")]), "'overtakes' is not a mining function"),
        (
            _plan(
                "VEHICLE",
                related=[{"words": "bus", "category": "BUS"}, {"words": "truck", "category": "TRUCK"}],
                relations=[{"subject_words": "vehicle", "function": "near_objects", "other_words": "tram"}],
            ),
            "'tram' is not one of the planned objects",
        ),
        ({"error": "no valid answer"}, "no plan"),
        # a composite condition takes exactly its numbers and cannot be negated
        (_plan("VEHICLE", conditions=[_cond("lateral_acceleration_either_way")]), "needs accel"),
        (
            _plan("VEHICLE", conditions=[_cond("lateral_acceleration_either_way", "speed=2")]),
            "'speed=2' is not one of its settings",
        ),
        (
            _plan("VEHICLE", conditions=[_cond("lateral_acceleration_either_way", "accel=-2")]),
            "'accel=-2' is not one of its settings",
        ),
        (
            _plan("VEHICLE", conditions=[{**_cond("stopped"), "negated": True}]),
            "'stopped' cannot be negated",
        ),
        (
            _plan("VEHICLE", conditions=[{**_cond("any_of"), "any_of": [[_cond("turning")]]}]),
            "'any_of' condition needs two alternatives",
        ),
    ],
)
def test_a_plan_the_rules_cannot_express_names_the_part_at_fault(plan: dict[str, Any], message: str) -> None:
    with pytest.raises(PlanCompileError, match=message.replace("(", r"\(")):
        compile_plan(plan)


def _trusted(program: str, context, description: str) -> ProgramResult:  # type: ignore[no-untyped-def]
    return run_trusted_program(program, context, description=description)


def _synth(replies: list[str]) -> tuple[ProgramSynthesizer, ScriptedBackend]:
    backend = ScriptedBackend(replies)
    config = GenerationConfig(max_attempts=2, plan=True, plan_program=True, plan_rules=False)
    selector = ExampleSelector(load_examples(), HashingEmbedder(128))
    return ProgramSynthesizer(ChatClient(backend), selector, config), backend


BUSES = "buses in the bike lane"
WRITTEN = (
    "```python\n"
    "buses = get_objects_of_category(log_dir, category='BUS')\n"
    "output_scenario(on_lane_type(buses, log_dir, lane_type='BIKE'), description, log_dir, output_dir)\n"
    "```"
)


def test_the_loop_runs_the_plans_program_without_asking_the_model_to_write_one() -> None:
    plan = _plan("BUS", conditions=[_cond("on_lane_type", "lane_type='BIKE'")])
    synth, backend = _synth([json.dumps(plan)])
    report = generate_program(BUSES, synth, [SCENE], config=MiningConfig(), runner=_trusted)

    assert report.ok and len(backend.requests) == 1  # the plan call only
    assert report.program is not None and "on_lane_type(subject, log_dir, lane_type='BIKE')" in report.program
    assert [a.index for a in report.attempts] == [0] and report.attempts_used == 0


def test_when_the_rules_cannot_express_the_plan_the_model_writes_the_program() -> None:
    plan = _plan("BUS", conditions=[_cond("on_lane_type")])  # no lane type: no program by rules
    synth, backend = _synth([json.dumps(plan), WRITTEN])
    report = generate_program(BUSES, synth, [SCENE], config=MiningConfig(), runner=_trusted)

    assert report.ok and report.program is not None and "buses" in report.program
    first, written = report.attempts
    assert first.index == 0 and first.error is not None and first.error.kind is ErrorKind.PLAN
    assert "lane_type" in first.error.message
    assert written.index == 1 and written.error is None and report.attempts_used == 1
    assert len(backend.requests) == 2  # the plan, then one program


def test_a_relations_direction_goes_to_the_argument_that_accepts_it_and_its_settings_are_kept() -> None:
    plan = _plan(
        "VEHICLE",
        related=[{"words": "ego", "category": "EGO_VEHICLE"}, {"words": "people", "category": "PEDESTRIAN"}],
        relations=[
            {"subject_words": "vehicles", "function": "on_relative_side_of_road", "other_words": "the ego",
             "direction": "opposite"},
            {"subject_words": "vehicles", "function": "near_objects", "other_words": "people",
             "argument": "distance_thresh=5, min_objects=3"},
        ],
    )  # fmt: skip
    program = compile_plan(plan).program
    assert "on_relative_side_of_road(subject, related_1, log_dir, side='opposite')" in program
    assert "near_objects(step_1, related_2, log_dir, distance_thresh=5, min_objects=3)" in program
    # "behind" is read as "backward"; this function returns its second set, so the subject goes there
    for subject_words, other_words in (("ego", "vehicles"), ("vehicles", "the ego")):
        behind = _plan(
            "VEHICLE",
            related=[{"words": "ego", "category": "EGO_VEHICLE"}],
            relations=[{"subject_words": subject_words, "function": "get_objects_in_relative_direction",
                        "other_words": other_words, "direction": "behind"}],
        )  # fmt: skip
        program = compile_plan(behind).program
        assert (
            "get_objects_in_relative_direction(related_1, subject, log_dir, direction='backward')" in program
        )


def test_words_that_name_the_ego_select_the_ego_whatever_category_was_planned() -> None:
    plan = _plan(
        "PEDESTRIAN",
        related=[{"words": "ego vehicle", "category": "VEHICLE"}],
        relations=[
            {"subject_words": "ego vehicle", "function": "near_objects", "other_words": "pedestrians"}
        ],
    )
    assert (
        "related_1 = get_objects_of_category(log_dir, category='EGO_VEHICLE')" in compile_plan(plan).program
    )
    ego = {**_plan("VEHICLE", conditions=[_cond("turning", "left")]), "subject_words": "the ego car"}
    assert compile_plan(ego).program.startswith(
        "subject = get_objects_of_category(log_dir, category='EGO_VEHICLE')"
    )


def test_a_part_of_the_map_planned_as_an_object_becomes_its_condition() -> None:
    plan = _plan(
        "BUS",
        related=[{"words": "bike lane", "category": "LARGE_VEHICLE"}],
        relations=[{"subject_words": "buses", "function": "has_objects_in_relative_direction",
                    "other_words": "bike lane", "direction": "left"}],
    )  # fmt: skip
    compiled = compile_plan(plan)
    assert "LARGE_VEHICLE" not in compiled.program and "has_objects" not in compiled.program
    assert "on_lane_type(subject, log_dir, lane_type='BIKE')" in compiled.program
    assert compiled.notes == (
        "on_lane_type: 'bike lane' is a part of the map, tested as a condition",
        "subject: BUS, ARTICULATED_BUS, SCHOOL_BUS for 'bus', not BUS",  # "bus": every bus category
    )
    assert _referred(plan) == {idx(SCENE, "bus")}
    sidewalk = _plan("PEDESTRIAN", related=[{"words": "the sidewalk", "category": "PEDESTRIAN"}])
    with pytest.raises(PlanCompileError, match="'the sidewalk' is a part of the map"):
        compile_plan(sidewalk)


def test_a_relation_to_a_bare_direction_or_to_the_subject_itself_gives_its_direction_to_a_condition() -> None:
    to_itself = _plan(
        "VEHICLE",
        relations=[{"subject_words": "vehicle", "function": "has_objects_in_relative_direction",
                    "other_words": "vehicles", "direction": "left"}],
        conditions=[_cond("changing_lanes")],
    )  # fmt: skip
    program = compile_plan(to_itself).program
    assert "has_objects" not in program and "changing_lanes(subject, log_dir, direction='left')" in program
    assert _referred(to_itself) == {idx(SCENE, "changer")}
    to_a_word = _plan(
        "VEHICLE",
        relations=[{"subject_words": "vehicle", "function": "facing_toward", "other_words": "left"}],
        conditions=[_cond("turning", "direction='left'")],
    )
    assert "facing_toward" not in compile_plan(to_a_word).program
    nowhere = _plan(
        "VEHICLE",
        relations=[{"subject_words": "vehicle", "function": "facing_toward", "other_words": "left"}],
    )
    with pytest.raises(PlanCompileError, match="facing_toward: 'left' is not an object"):
        compile_plan(nowhere)


def test_state_words_of_the_subject_add_their_condition_and_vehicles_means_the_group() -> None:
    plan = {
        **_plan("REGULAR_VEHICLE", conditions=[_cond("in_drivable_area")]),
        "subject_words": "parked vehicles",
    }
    program = compile_plan(plan).program
    assert program.splitlines()[:3] == [
        "subject = get_objects_of_category(log_dir, category='VEHICLE')",
        "step_1 = stationary(subject, log_dir)",
        "step_2 = in_drivable_area(step_1, log_dir)",
    ]
