"""Mining outputs: matches, store tables, the Argoverse 2 submission frames, the query API and CLI."""

from __future__ import annotations

import pickle
from pathlib import Path

import numpy as np
import pyarrow as pa
import pytest
import typer
from mining_scenes import DT_S, T_S, Obj, const, make_log, street_scene
from typer.testing import CliRunner

from scenariominer.api.mining import store_report
from scenariominer.cli import app as root_app
from scenariominer.config.mining import GenerationConfig, MiningConfig
from scenariominer.data.log import Log
from scenariominer.llm import ChatClient, HashingEmbedder
from scenariominer.mine.context import LogContext
from scenariominer.mine.export import (
    MATCHES_TABLE,
    RUNS_TABLE,
    LogMatches,
    ObjectLabel,
    SubmissionFormatError,
    av2_frames,
    evaluation_timestamps,
    matches_table,
    program_sha256,
    read_av2_submission,
    runs_table,
    write_av2_submission,
)
from scenariominer.mine.loop import GenerationStatus
from scenariominer.mine.programs import load_examples
from scenariominer.mine.query import (
    ProgramSource,
    av2_submission,
    bank_program,
    mine_logs,
)
from scenariominer.mine.sandbox import ProgramResult, run_trusted_program
from scenariominer.mine.scenario import Scenario
from scenariominer.mine.synthesis import ExampleSelector, ProgramSynthesizer
from scenariominer.store import ScenarioStore
from scenariominer.testing import ScriptedBackend

KEY = "vehicle with a bicycle to its right"
PROGRAM = """
vehicles = get_objects_of_category(log_dir, category='VEHICLE')
bicycles = get_objects_of_category(log_dir, category='BICYCLE')
result = has_objects_in_relative_direction(
    vehicles, bicycles, log_dir, direction='right', within_distance=4, lateral_thresh=1)
output_scenario(result, description, log_dir, output_dir)
"""


def trusted(program: str, context: LogContext, description: str) -> ProgramResult:
    return run_trusted_program(program, context, description=description)


def pass_log() -> Log:
    """6 s at 10 Hz: the ego (4.5 m long) drives east at 10 m/s; a parked bicycle 3 m to its right
    at x = 30 is "to its right" (centre at most 1 m beyond the ego's front or rear) for t in
    [2.7, 3.3] s; a car drives 7 m left of the ego (the bicycle is 10 m to its right, too far);
    a pedestrian is seen only in the first 2 s."""
    zero = const(0.0)
    present = T_S < 2.0 - 1e-9
    objs = [
        Obj("ego", "EGO_VEHICLE", 10 * T_S, zero, zero),
        Obj("bike", "BICYCLE", const(30.0), const(-3.0), zero, length_m=1.8, width_m=0.6),
        Obj("car", "REGULAR_VEHICLE", 20 + 10 * T_S, const(7.0), zero),
        Obj("ped", "PEDESTRIAN", const(5.0), const(8.0), zero, 0.5, 0.5, present=present),
    ]
    return make_log(objs, log_id="pass")


@pytest.fixture(scope="module")
def passing() -> LogContext:
    return LogContext(pass_log())


@pytest.fixture(scope="module")
def result(passing: LogContext) -> Scenario:
    out = run_trusted_program(PROGRAM, passing, description=KEY)
    assert out.ok and out.scenario is not None
    return out.scenario


# ---------------------------------------------------------------------- matches and tables


def test_matches_record_the_referred_cells_by_id_and_time(passing: LogContext, result: Scenario) -> None:
    m = LogMatches.from_scenario(result, KEY, PROGRAM, execution_s=0.5)
    assert m.referred_track_ids == ["ego"]
    ts = m.timestamps_of("ego")
    # the bicycle's centre (x = 30) is within [x_ego - 3.25, x_ego + 3.25] for 10 t in [26.75, 33.25]
    t_s = (ts - passing.log.timestamps_ns[0]) * 1e-9
    assert np.allclose(t_s, [2.7, 2.8, 2.9, 3.0, 3.1, 3.2, 3.3])
    assert m.n_referred_timestamps == ts.size
    bike = passing.log.track_index("bike")
    assert m.related[bike].sum() == ts.size
    assert m.program_sha256 == program_sha256(PROGRAM) == program_sha256("  " + PROGRAM + "\n")
    assert m.timestamps_of("nobody").size == 0


def test_mining_results_table_has_one_row_per_referred_cell(result: Scenario) -> None:
    m = LogMatches.from_scenario(result, KEY, PROGRAM)
    table = matches_table(m)
    assert table.num_rows == int(result.referred.sum())
    assert set(table.column("track_id").to_pylist()) == {"ego"}
    assert set(table.column("category").to_pylist()) == {"EGO_VEHICLE"}
    assert all(r == ["bike"] for r in table.column("related_track_ids").to_pylist())
    assert table.column("description").to_pylist()[0] == KEY
    runs = runs_table(m)
    assert runs.column("n_referred_tracks").to_pylist() == [1]
    assert runs.column("n_referred_cells").to_pylist() == [table.num_rows]


def test_related_objects_are_listed_per_cell(passing: LogContext) -> None:
    log = passing.log
    ego, bike, car = (log.track_index(t) for t in ("ego", "bike", "car"))
    mask = np.zeros((log.n_tracks, log.n_timestamps), dtype=bool)
    mask[ego, :3] = True
    mask[car, 1] = True
    relations = np.array([[ego, 0, bike], [ego, 0, car], [ego, 2, bike]])
    table = matches_table(
        LogMatches.from_scenario(Scenario.from_mask(passing, mask, relations), KEY, PROGRAM)
    )
    got = {
        (tid, t): sorted(rel)
        for tid, t, rel in zip(
            table.column("track_id").to_pylist(),
            table.column("timestamp_ns").to_pylist(),
            table.column("related_track_ids").to_pylist(),
            strict=True,
        )
    }
    ts = log.timestamps_ns
    assert got == {
        ("ego", ts[0]): ["bike", "car"],
        ("ego", ts[1]): [],
        ("ego", ts[2]): ["bike"],
        ("car", ts[1]): [],
    }
    assert matches_table(LogMatches.from_scenario(Scenario.empty(passing), KEY, PROGRAM)).num_rows == 0


# ---------------------------------------------------------------------- Argoverse 2 frames


def test_evaluation_timestamps_are_every_fifth_at_ten_hertz() -> None:
    log = pass_log()
    ts = evaluation_timestamps(log)
    assert np.array_equal(ts, log.timestamps_ns[::5])
    assert ts.size == 13  # 0.0, 0.5, ..., 6.0 s
    assert np.array_equal(evaluation_timestamps(log, rate_hz=10.0), log.timestamps_ns)
    with pytest.raises(ValueError, match="rate_hz"):
        evaluation_timestamps(log, rate_hz=0)


def test_every_evaluation_timestamp_gets_a_frame_with_every_observed_object(
    passing: LogContext, result: Scenario
) -> None:
    log = passing.log
    frames = av2_frames(LogMatches.from_scenario(result, KEY, PROGRAM), log)
    assert [int(f["timestamp_ns"]) for f in frames] == log.timestamps_ns[::5].tolist()
    for f, col in zip(frames, range(0, log.n_timestamps, 5), strict=True):
        n = int(log.valid[:, col].sum())
        assert f["translation_m"].shape == (n, 3) and f["size"].shape == (n, 3)
        assert f["yaw"].shape == f["label"].shape == f["track_id"].shape == f["score"].shape == (n,)
        assert f["velocity_m_per_s"].shape == (n, 3)
        assert f["size"].dtype == np.float32 and f["yaw"].dtype == np.float32
        assert f["label"].dtype == np.int32 and f["track_id"].dtype == np.int32
        assert f["ego_translation_m"] == [10 * col * DT_S, 0.0, 0.0]
        assert f["description"] == KEY and f["seq_id"] == ("pass", KEY)
        assert np.all(f["score"] == 1.0)
    # the pedestrian is only in the frames of the first 2 s (t = 0, 0.5, 1.0, 1.5)
    ped = log.track_index("ped")
    assert [ped in f["track_id"] for f in frames] == [True] * 4 + [False] * 9


def test_labels_mark_referred_related_and_other_objects(passing: LogContext, result: Scenario) -> None:
    log = passing.log
    frames = av2_frames(LogMatches.from_scenario(result, KEY, PROGRAM), log)
    ego, bike, car = (log.track_index(t) for t in ("ego", "bike", "car"))
    by_time = {round(float(f["timestamp_ns"] - log.timestamps_ns[0]) * 1e-9, 1): f for f in frames}

    def label_of(frame: dict[str, np.ndarray], row: int) -> int:
        return int(frame["label"][list(frame["track_id"]).index(row)])

    for t, f in by_time.items():
        beside = t == 3.0  # the only evaluation timestamp (2 Hz) inside [2.7, 3.3] s
        assert label_of(f, ego) == (ObjectLabel.REFERRED if beside else ObjectLabel.OTHER), t
        assert label_of(f, bike) == (ObjectLabel.RELATED if beside else ObjectLabel.OTHER), t
        assert label_of(f, car) == ObjectLabel.OTHER
        names = dict(zip(f["track_id"].tolist(), f["name"].tolist(), strict=True))
        assert names[ego] == ("REFERRED_OBJECT" if beside else "OTHER_OBJECT")
    # raw positions, not smoothed: the bicycle is exactly where the log has it
    f = by_time[3.0]
    assert f["translation_m"][list(f["track_id"]).index(bike)].tolist() == [30.0, -3.0, 0.0]


def test_matches_found_on_a_reordered_copy_map_by_track_id(passing: LogContext) -> None:
    log = passing.log
    reordered = log.select_tracks(np.array([0, 3, 2, 1]))  # same ids and cells, other rows
    ctx = LogContext(reordered)
    scenario = run_trusted_program(PROGRAM, ctx, description=KEY).scenario
    assert scenario is not None
    direct = av2_frames(
        LogMatches.from_scenario(
            run_trusted_program(PROGRAM, passing, description=KEY).scenario, KEY, PROGRAM
        ),  # type: ignore[arg-type]
        log,
    )
    via_copy = av2_frames(LogMatches.from_scenario(scenario, KEY, PROGRAM), log)
    for a, b in zip(direct, via_copy, strict=True):
        assert np.array_equal(a["label"], b["label"]) and np.array_equal(a["track_id"], b["track_id"])


def test_explicit_timestamps_and_empty_scenarios(passing: LogContext) -> None:
    log = passing.log
    empty = LogMatches.from_scenario(Scenario.empty(passing), KEY, PROGRAM)
    frames = av2_frames(empty, log, timestamps_ns=log.timestamps_ns[[0, 7, 60]])
    assert len(frames) == 3 and all(np.all(f["label"] == ObjectLabel.OTHER) for f in frames)
    with pytest.raises(ValueError, match="has no timestamp"):
        av2_frames(empty, log, timestamps_ns=[int(log.timestamps_ns[0]) + 1])
    other = LogMatches.from_scenario(Scenario.empty(street_scene(with_map=False)), KEY, PROGRAM)
    with pytest.raises(ValueError, match="matches are for log street"):
        av2_frames(other, log)


def test_submission_round_trip_and_format_errors(
    passing: LogContext, result: Scenario, tmp_path: Path
) -> None:
    frames = av2_frames(LogMatches.from_scenario(result, KEY, PROGRAM), passing.log)
    path = write_av2_submission({("pass", KEY): frames}, tmp_path / "sub" / "pred.pkl")
    back = read_av2_submission(path)
    assert list(back) == [("pass", KEY)] and len(back[("pass", KEY)]) == 13
    assert np.array_equal(back[("pass", KEY)][6]["label"], frames[6]["label"])
    bad = {
        "not_dict": [1, 2],
        "bad_key": {"pass": []},
        "no_list": {("pass", KEY): {}},
        "no_label": {("pass", KEY): [{"timestamp_ns": 1}]},
    }
    for name, data in bad.items():
        p = tmp_path / f"{name}.pkl"
        p.write_bytes(pickle.dumps(data))
        with pytest.raises(SubmissionFormatError):
            read_av2_submission(p)
    (tmp_path / "junk.pkl").write_bytes(b"not a pickle")
    with pytest.raises(SubmissionFormatError, match="cannot read"):
        read_av2_submission(tmp_path / "junk.pkl")


# ---------------------------------------------------------------------- the query API


def test_a_bank_description_runs_the_trusted_bank_program_on_every_log(passing: LogContext) -> None:
    street = street_scene()
    report = mine_logs(KEY, [passing, street])
    assert report.source is ProgramSource.BANK and report.status is GenerationStatus.OK
    assert report.attempts_used == 0 and report.generation_s == 0
    assert report.n_logs == 2 and [m.log_id for m in report.matches] == ["pass", "street"]
    assert report.matches[0].referred_track_ids == ["ego"]
    assert report.program == bank_program(KEY, load_examples()).program  # type: ignore[union-attr]
    assert report.summary()["n_matching_logs"] == report.n_matching_logs == 2


def test_a_failing_log_is_reported_and_the_others_still_run(passing: LogContext) -> None:
    program = (
        "v = get_objects_of_category(log_dir, category='VEHICLE')\n"
        "output_scenario(on_intersection(v, log_dir), description, log_dir, output_dir)\n"
    )
    report = mine_logs(
        "vehicle in an intersection", [passing, street_scene()], program=program, runner=trusted
    )
    assert report.source is ProgramSource.GIVEN
    assert [f.log_id for f in report.failures] == ["pass"]
    assert "needs an HD map" in report.failures[0].error.message
    assert [m.log_id for m in report.matches] == ["street"]


def test_unknown_descriptions_go_through_the_model_loop(passing: LogContext) -> None:
    backend = ScriptedBackend(
        [f"```python\n{PROGRAM.replace('BICYCLE', 'TANK')}```", f"```python{PROGRAM}```"]
    )
    built: list[int] = []

    def factory() -> ProgramSynthesizer:
        built.append(1)
        return ProgramSynthesizer(
            ChatClient(backend),
            ExampleSelector(load_examples(), HashingEmbedder(64)),
            GenerationConfig(plan=False),
        )

    cfg = MiningConfig(generation=GenerationConfig(plan=False, max_attempts=3))
    report = mine_logs(
        "car with a bike on its right", [passing], config=cfg, synthesizer=factory, runner=trusted
    )
    assert built == [1]
    assert report.source is ProgramSource.GENERATED and report.attempts_used == 2
    assert report.generation is not None and report.generation.attempts[0].error is not None
    assert report.matches[0].referred_track_ids == ["ego"]
    # the bank program is used without building the model
    mine_logs(KEY, [passing], synthesizer=factory, runner=trusted)
    assert built == [1]
    with pytest.raises(ValueError, match="no language model"):
        mine_logs("car with a bike on its right", [passing])


def test_manual_review_exports_empty_frames(passing: LogContext) -> None:
    backend = ScriptedBackend(["import os"])
    synth = ProgramSynthesizer(ChatClient(backend), None, GenerationConfig(plan=False, max_attempts=1))
    cfg = MiningConfig(generation=GenerationConfig(plan=False, max_attempts=1))
    report = mine_logs("something odd", [passing], config=cfg, synthesizer=synth, runner=trusted)
    assert report.status is GenerationStatus.MANUAL_REVIEW and report.program is None and not report.matches
    sub = av2_submission(report, {"pass": passing.log})
    assert len(sub[("pass", "something odd")]) == 13
    assert all(np.all(f["label"] == ObjectLabel.OTHER) for f in sub[("pass", "something odd")])


def test_results_are_stored_and_replace_only_the_same_description(
    passing: LogContext, tmp_path: Path
) -> None:
    store = ScenarioStore.open(tmp_path / "store")
    store.replace_source("src", "h1", [passing.log])
    first = mine_logs(KEY, [passing])
    assert store_report(store, first) == ["pass"]
    rows = store.read_table(MATCHES_TABLE)
    assert rows.num_rows == int(first.matches[0].referred.sum())
    other = mine_logs(
        "any pedestrian",
        [passing],
        program="output_scenario(get_objects_of_category(log_dir, 'PEDESTRIAN'), description)\n",
        runner=trusted,
    )
    store_report(store, other)
    store_report(store, first)  # again: replaces its own rows, keeps the pedestrian rows
    rows = store.read_table(MATCHES_TABLE)
    counts = {d: rows.column("description").to_pylist().count(d) for d in {KEY, "any pedestrian"}}
    assert counts == {KEY: int(first.matches[0].referred.sum()), "any pedestrian": 20}
    runs = store.read_table(RUNS_TABLE)
    assert sorted(runs.column("description").to_pylist()) == ["any pedestrian", KEY]
    assert (
        store.sql(f"SELECT count(*) AS n FROM {MATCHES_TABLE} WHERE track_id = 'ego'").column("n")[0].as_py()
        > 0
    )
    # logs the store does not hold are skipped
    assert store_report(store, mine_logs(KEY, [street_scene()])) == []
    assert isinstance(rows, pa.Table)


# ---------------------------------------------------------------------- the mine command


@pytest.fixture(scope="module")
def cli() -> typer.Typer:
    return root_app


def test_mine_command_needs_logs_or_a_store(cli: typer.Typer) -> None:
    res = CliRunner().invoke(cli, ["mine", KEY])
    assert res.exit_code == 2 and "--logs" in res.output
    res = CliRunner().invoke(cli, ["mine", KEY, "--logs", "x", "--export", "av2"])
    assert res.exit_code == 2 and "--out" in res.output


@pytest.mark.slow  # reads, preprocesses and mines the real log, then reads it raw again (~5 s)
def test_mine_command_exports_the_shared_log_aligned_to_the_ground_truth(
    cli: typer.Typer, av2_log_dir: Path, av2_gt_pkl: Path, tmp_path: Path
) -> None:
    out = tmp_path / "pred.pkl"
    res = CliRunner().invoke(
        cli,
        [
            "mine",
            KEY,
            "--logs",
            str(av2_log_dir),
            "--export",
            "av2",
            "--out",
            str(out),
            "--store",
            str(tmp_path / "st"),
        ],
    )
    assert res.exit_code == 0, res.output
    assert "program ok (bank, no model call)" in res.output and f"wrote {out}" in res.output
    pred = read_av2_submission(out)
    gt = read_av2_submission(av2_gt_pkl)
    assert list(pred) == list(gt)
    key = next(iter(gt))
    assert [int(f["timestamp_ns"]) for f in pred[key]] == [int(f["timestamp_ns"]) for f in gt[key]]
    store = ScenarioStore.open(tmp_path / "st")
    assert store.read_table(MATCHES_TABLE).num_rows > 0
    # aligned to the ground truth's own timestamps (mined from the store this time)
    aligned = tmp_path / "aligned.pkl"
    args = ["mine", KEY, "--store", str(tmp_path / "st"), "--export", "av2", "--out", str(aligned)]
    res = CliRunner().invoke(cli, [*args, "--align-to", str(av2_gt_pkl)])
    assert res.exit_code == 0, res.output
    got = read_av2_submission(aligned)[key]
    assert [int(f["timestamp_ns"]) for f in got] == [int(f["timestamp_ns"]) for f in gt[key]]
    assert [np.flatnonzero(f["label"] == 0).size for f in got] == [
        np.flatnonzero(f["label"] == 0).size for f in pred[key]
    ]
    # program files run too (in the sandbox), results print as JSON
    prog = tmp_path / "p.py"
    prog.write_text(PROGRAM, encoding="utf-8")
    res = CliRunner().invoke(
        cli, ["mine", "custom", "--logs", str(av2_log_dir), "--program", str(prog), "--json"]
    )
    assert res.exit_code == 0, res.output
    assert '"source": "given"' in res.output


def test_the_configured_synthesizer_uses_the_bank_files_and_the_generation_settings(tmp_path: Path) -> None:
    from scenariominer.config import Config
    from scenariominer.config.llm import EmbeddingConfig, LLMConfig
    from scenariominer.mine.query import make_synthesizer

    extra = tmp_path / "bank.toml"
    extra.write_text(
        "[[example]]\ndescription = 'two buses side by side'\n"
        "program = '''\noutput_scenario(get_objects_of_category(log_dir, 'BUS'), description)\n'''\n",
        encoding="utf-8",
    )
    cfg = Config(
        llm=LLMConfig(backend="openai", cache=False),  # no request is made by building it
        embedding=EmbeddingConfig(backend="hashing", cache=False),
        mining=MiningConfig(
            generation=GenerationConfig(plan=False, few_shot_k=2, examples_files=(str(extra),))
        ),
    )
    synth = make_synthesizer(cfg)
    assert synth.config.few_shot_k == 2 and synth.leave_one_out
    assert synth.model.startswith("openai:")
    shown = synth.examples_for("two buses side by side with a car")
    assert len(shown) == 2 and shown[0].description == "two buses side by side"
