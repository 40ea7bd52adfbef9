"""The hand-written example bank: every program is valid, runs on a hand-built log (with known
answers) and on the real Argoverse 2 log, and the key case agrees with the published ground truth."""

from __future__ import annotations

import ast
import pickle
from pathlib import Path

import numpy as np
import pytest
from mining_scenes import street_scene

from scenariominer.data.adapters.av2 import read_av2_log
from scenariominer.data.preprocess import preprocess
from scenariominer.mine.context import LogContext
from scenariominer.mine.programs import ExampleBankError, load_examples, parse_examples
from scenariominer.mine.sandbox import ErrorKind, check_program, run_program, run_trusted_program

EXAMPLES = load_examples()
BY_DESCRIPTION = {e.description: e for e in EXAMPLES}
MAP_PREDICATES = {
    "changing_lanes",
    "at_pedestrian_crossing",
    "on_lane_type",
    "near_intersection",
    "on_intersection",
    "at_stop_sign",
    "in_drivable_area",
    "on_road",
    "in_same_lane",
    "on_relative_side_of_road",
}
KEY = "vehicle with a bicycle to its right"


def _called(program: str) -> set[str]:
    return {n.id for n in ast.walk(ast.parse(program)) if isinstance(n, ast.Name)}


def test_the_bank_has_at_least_twenty_distinct_valid_programs() -> None:
    assert len(EXAMPLES) >= 20
    assert len({e.description.lower() for e in EXAMPLES}) == len(EXAMPLES)
    for e in EXAMPLES:
        assert check_program(e.program) is None, (e.description, check_program(e.program))
        assert e.tags, e.description
        assert e.needs_map == bool(_called(e.program) & MAP_PREDICATES), e.description
    assert KEY in BY_DESCRIPTION


# ---------------------------------------------------------------------- the hand-built log

EXPECTED_ON_STREET: dict[str, set[str]] = {
    "vehicle with a bicycle to its right": {"ego"},
    "bus in the bike lane": {"bus"},
    "pedestrian crossing in front of a vehicle": {"ped"},
    "vehicle changing lanes to the left": {"changer"},
    "accelerating vehicle": {"bus"},
    "ego vehicle turning left": set(),
    "vehicle following another vehicle": {"ego", "changer"},
    "stationary vehicle in the drivable area": {"parked"},
    "pedestrian near a stop sign": {"ped"},
    "vehicle in an intersection": {"turner"},
    "two pedestrians near each other": {"pedA", "pedB"},
    "vehicle heading toward the ego vehicle": {"oncoming", "overtaker"},
    "bicycle in the bike lane": {"bike"},
    "vehicle being crossed by a pedestrian": {"lead"},
    "car turning right with a pedestrian nearby": {"turner"},
    "vehicle braking hard": set(),
    "jaywalking pedestrian": set(),
    "active vehicle at a stop sign": {"ego", "lead"},
    "bicycle sharing a lane with a vehicle": {"bike"},
    "oncoming vehicle passing the ego vehicle": {"oncoming"},
    "vehicle overtaking the ego vehicle on the left": {"overtaker"},
    "pedestrian on a crosswalk": {"ped"},
    "pedestrian facing the ego vehicle": {"pedA"},
    "pedestrian in front of the ego vehicle": {"ped"},
    "fast vehicle on the opposite side of the road from the ego vehicle": {"oncoming"},
    "ego vehicle changing lanes": set(),
    "vehicle swerving with high lateral acceleration while not turning": {"changer"},
}


@pytest.fixture(scope="module")
def street() -> LogContext:
    return street_scene()


@pytest.mark.parametrize("description", [e.description for e in EXAMPLES])
def test_every_program_runs_on_the_hand_built_log(street: LogContext, description: str) -> None:
    result = run_trusted_program(BY_DESCRIPTION[description].program, street, description=description)
    assert result.ok, result.error
    assert result.description == description
    if description in EXPECTED_ON_STREET:
        assert result.scenario is not None
        assert set(result.scenario) == EXPECTED_ON_STREET[description]


def test_known_answers_cover_most_of_the_bank() -> None:
    assert set(EXPECTED_ON_STREET) <= set(BY_DESCRIPTION)
    assert sum(bool(v) for v in EXPECTED_ON_STREET.values()) >= 20


def test_map_programs_fail_clearly_on_a_log_without_map() -> None:
    ctx = street_scene(with_map=False)
    for e in EXAMPLES:
        result = run_trusted_program(e.program, ctx, description=e.description)
        if e.needs_map:
            assert result.error is not None and result.error.kind is ErrorKind.RUNTIME
            assert "needs an HD map" in result.error.message
        else:
            assert result.ok, (e.description, result.error)


# ---------------------------------------------------------------------- the real log


@pytest.fixture(scope="module")
def real(av2_log_dir: Path) -> LogContext:
    return LogContext(preprocess(read_av2_log(av2_log_dir)))


def test_every_program_runs_on_the_real_log(real: LogContext) -> None:
    assert real.has_map
    for e in EXAMPLES:
        result = run_trusted_program(e.program, real, description=e.description)
        assert result.ok, (e.description, result.error)


@pytest.mark.slow  # starts the sandbox's process server and reads the map in each child
def test_sandboxed_and_trusted_runs_agree_on_the_real_log(real: LogContext) -> None:
    for description in (KEY, "vehicle changing lanes to the left"):
        program = BY_DESCRIPTION[description].program
        child = run_program(program, real, description=description)
        local = run_trusted_program(program, real, description=description)
        assert child.ok and local.ok, (child.error, local.error)
        assert child.scenario is not None and local.scenario is not None
        assert np.array_equal(child.scenario.referred, local.scenario.referred)


def _gt_referred(real: LogContext, gt_pkl: Path) -> list[tuple[int, set[int]]]:
    """Per ground-truth frame: timestamp index and the log rows of the referred boxes (< 1 m)."""
    frames = next(iter(pickle.loads(gt_pkl.read_bytes()).values()))
    log = real.log
    raw_x, raw_y = log.x_m, log.y_m
    out = []
    for frame in frames:
        t = int(np.searchsorted(log.timestamps_ns, frame["timestamp_ns"]))
        assert log.timestamps_ns[t] == frame["timestamp_ns"]
        rows = set()
        for k in np.flatnonzero(frame["label"] == 0):
            d = np.hypot(
                raw_x[:, t] - frame["translation_m"][k, 0], raw_y[:, t] - frame["translation_m"][k, 1]
            )
            j = int(np.nanargmin(d))
            assert d[j] < 1.0
            rows.add(j)
        out.append((t, rows))
    return out


def test_vehicle_with_a_bicycle_to_its_right_matches_the_ground_truth(
    av2_log_dir: Path, av2_gt_pkl: Path
) -> None:
    # positions for matching must be the raw boxes (the GT is in the raw city frame)
    real = LogContext(preprocess(read_av2_log(av2_log_dir)))
    raw = read_av2_log(av2_log_dir)
    gt = _gt_referred(LogContext(raw), av2_gt_pkl)
    result = run_trusted_program(BY_DESCRIPTION[KEY].program, real, description=KEY)
    assert result.ok and result.scenario is not None
    pred = result.scenario.referred
    vehicle_rows = set(np.flatnonzero(real.category_mask("VEHICLE")).tolist())
    tp = fp = fn = tp_vehicle = 0
    for t, rows in gt:
        predicted = set(np.flatnonzero(pred[:, t]).tolist())
        tp += len(predicted & rows)
        fp += len(predicted - rows)
        fn += len(rows - predicted)
        tp_vehicle += len(predicted & rows & vehicle_rows)
    # the ground truth refers to two cars passing a bicycle rack (21 boxes) and to five parked
    # BICYCLEs with another bicycle to their right: it counts bicycles as vehicles (the Argoverse 2
    # taxonomy defines BICYCLE as a non-motorized vehicle), and so does the bank's program
    gt_categories = {str(real.log.categories[j]) for _, rows in gt for j in rows}
    assert gt_categories == {"BICYCLE", "REGULAR_VEHICLE"}
    assert tp_vehicle == 21
    assert fp == 0 and fn == 0 and tp == sum(len(rows) for _, rows in gt)


# ---------------------------------------------------------------------- bank files


def test_user_bank_files_extend_and_override(tmp_path: Path) -> None:
    extra = tmp_path / "mine.toml"
    extra.write_text(
        "[[example]]\n"
        f"description = '{KEY}'\n"
        "tags = ['custom']\n"
        "program = '''\nx = get_objects_of_category(log_dir, 'ANY')\noutput_scenario(x, description)\n'''\n"
        "[[example]]\n"
        "description = 'any object'\n"
        "program = '''\noutput_scenario(get_objects_of_category(log_dir, 'ANY'), description)\n'''\n",
        encoding="utf-8",
    )
    merged = {e.description: e for e in load_examples([extra])}
    assert merged[KEY].tags == ("custom",) and merged[KEY].source == str(extra)
    assert "any object" in merged and len(merged) == len(EXAMPLES) + 1
    assert {e.description for e in load_examples([extra], builtin=False)} == {KEY, "any object"}


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("[[example]\n", "not valid TOML"),
        ("x = 1\n", r"\[\[example\]\] tables"),
        ("[[example]]\nprogram = 'output_scenario(x)'\n", "non-empty string 'description'"),
        ("[[example]]\ndescription = 'd'\nprogram = 'x = 1'\n", "calls output_scenario"),
        ("[[example]]\ndescription = 'd'\nprogram = 'output_scenario(x)'\ncolour = 1\n", "unknown key"),
        ("[[example]]\ndescription = 'd'\nprogram = 'output_scenario(x)'\ntags = 'a'\n", "list of strings"),
    ],
)
def test_malformed_bank_files_are_rejected_with_the_entry_named(text: str, message: str) -> None:
    with pytest.raises(ExampleBankError, match=message):
        parse_examples(text, "bad.toml")


def test_missing_bank_file_is_reported(tmp_path: Path) -> None:
    with pytest.raises(ExampleBankError, match="cannot read"):
        load_examples([tmp_path / "nope.toml"])
