"""The description -> program evaluation set, its scorer and ``eval nl2prog`` (issue 18, item 5).

No language model runs here: candidate programs come from scripted providers.
"""

from __future__ import annotations

import ast
import itertools
import json
import re
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest
from typer.testing import CliRunner

from scenariominer.api import evaluation as evaluation_api
from scenariominer.cli import app
from scenariominer.config import Config
from scenariominer.errors import LLMError
from scenariominer.eval.nl2prog import (
    FAMILIES,
    HELD_OUT_SPLITS,
    SPLITS,
    BankOnlySelector,
    EvalEntry,
    EvalSetError,
    description_key,
    evaluate_nl2prog,
    family_counts,
    jaccard,
    load_eval_set,
    nearest_bank_provider,
    parse_eval_set,
    reference_provider,
    similar_bank_entries,
)
from scenariominer.mine.context import LogContext
from scenariominer.mine.programs import ExampleProgram, load_examples
from scenariominer.mine.sandbox import ProgramResult, run_trusted_program
from scenariominer.mine.synthesis import normalize_description
from scenariominer.testing import HashingEmbedder

runner = CliRunner()

ENTRIES = load_eval_set()

#: The dev material of the phrase rules (tests/mine/data): other people's descriptions outside
#: the held-out ``published`` and ``challenge`` samples.
DEV_MATERIAL = Path(__file__).resolve().parents[1] / "mine" / "data"
REAL_LOGS = Path(__file__).resolve().parents[1] / "real_data" / "av2"
SECOND_LOG = REAL_LOGS / "adcf7d18-0510-35b0-a2fa-b4cea13a6d76"
THIRD_LOG = REAL_LOGS / "3bffdcff-c3a7-38b6-a0f2-64196d130958"


def _trusted(program: str, ctx: LogContext, description: str) -> ProgramResult:
    return run_trusted_program(program, ctx, description=description)


@pytest.fixture(scope="module")
def shared_log(av2_log_dir: Path) -> LogContext:
    from scenariominer.api.mining import load_logs

    cfg = Config()
    (log,) = load_logs([av2_log_dir], None, cfg)
    return LogContext(log, cfg.mining)


# ---------------------------------------------------------------------------------- the set


def test_the_set_loads_with_enough_entries_in_every_split() -> None:
    dev, holdout = load_eval_set("dev"), load_eval_set("holdout")
    published, challenge = load_eval_set("published"), load_eval_set("challenge")
    assert len(dev) + len(holdout) >= 60
    fresh_splits = [split for split in SPLITS if split.startswith("fresh")]
    assert len(fresh_splits) >= 10  # fresh ... fresh10, each written by a separate pass
    fresh = [load_eval_set(split) for split in fresh_splits]
    ours, theirs = len(dev) + len(holdout), len(published) + len(challenge)
    assert ours + theirs + sum(len(split) for split in fresh) == len(ENTRIES)
    assert 0.28 <= len(holdout) / (len(dev) + len(holdout)) <= 0.4  # about a third of our own wording
    assert len(published) >= 30 and len(challenge) >= 30
    assert all(len(split) >= 15 for split in fresh)
    assert set(HELD_OUT_SPLITS) == set(SPLITS) - {"dev"}
    assert all(e.program.rstrip().splitlines()[-1].startswith("output_scenario(") for e in ENTRIES)
    assert load_eval_set("all") == ENTRIES


def test_every_family_is_covered_by_several_entries() -> None:
    counts = family_counts(ENTRIES)
    assert set(counts) == set(FAMILIES)
    assert {f: n for f, n in counts.items() if n < 2} == {}
    # the holdout alone still spans the main families
    held = family_counts(load_eval_set("holdout"))
    core = ("category", "category_group", "motion", "relation", "map", "composition", "direction")
    assert all(held[f] >= 1 for f in (*core, "crossing", "turning", "pedestrian", "cyclist", "bus", "ego"))


def test_the_category_groups_and_many_categories_are_asked_for() -> None:
    used = {c for e in ENTRIES for c in re.findall(r"category='([A-Z_]+)'", e.program)}
    assert {"VEHICLE", "VULNERABLE_ROAD_USER", "ANY"} <= used
    assert len(used - {"VEHICLE", "VULNERABLE_ROAD_USER", "ANY"}) >= 25


@pytest.mark.parametrize(("one", "other"), list(itertools.combinations(SPLITS, 2)))
def test_the_splits_are_disjoint(one: str, other: str) -> None:
    first, second = load_eval_set(one), load_eval_set(other)
    assert not {normalize_description(e.description) for e in first} & {
        normalize_description(e.description) for e in second
    }
    assert not {description_key(e.description) for e in first} & {
        description_key(e.description) for e in second
    }


def test_no_holdout_description_is_in_the_bank_or_near_one() -> None:
    bank = load_examples()
    bank_text = {normalize_description(e.description) for e in bank}
    bank_keys = {description_key(e.description) for e in bank}
    for e in (e for e in ENTRIES if e.split in HELD_OUT_SPLITS):
        assert normalize_description(e.description) not in bank_text, e.description
        assert description_key(e.description) not in bank_keys, e.description
        assert similar_bank_entries(e.description, bank) == [], e.description
    # nor is any description of the set copied into the bank
    assert not {normalize_description(e.description) for e in ENTRIES} & bank_text


def _dev_material(name: str) -> list[str]:
    lines = (DEV_MATERIAL / name).read_text(encoding="utf-8").splitlines()
    return [line.strip() for line in lines if line.strip() and not line.startswith("#")]


@pytest.mark.parametrize("dev_file", ["refav_published_dev.txt", "challenge_dev.txt"])
def test_no_challenge_description_is_near_the_dev_material(dev_file: str) -> None:
    dev = _dev_material(dev_file)
    assert len(dev) >= 25
    dev_keys = [set(description_key(d).split()) for d in dev]
    for e in load_eval_set("challenge"):
        mine = set(description_key(e.description).split())
        near = [
            d
            for d, theirs in zip(dev, dev_keys, strict=True)
            if len(mine & theirs) / len(mine | theirs) >= 0.6
        ]
        assert near == [], (e.description, near)


def test_the_selector_never_shows_hidden_descriptions_and_can_drop_the_most_similar() -> None:
    holdout = load_eval_set("holdout")
    leaked = ExampleProgram(holdout[0].description, holdout[0].program)
    bank = (*load_examples(), leaked)
    selector = BankOnlySelector(bank, HashingEmbedder(64), hidden=[e.description for e in holdout])
    assert leaked not in selector.examples
    assert leaked.description not in [x.description for x in selector.select(leaked.description, 5)]
    query = "vehicle with a bicycle to its right"
    full = BankOnlySelector(load_examples(), HashingEmbedder(64))
    assert query not in [x.description for x in full.select(query, 5)]  # leave-one-out
    assert full.select(query, 1, leave_one_out=False)[0].description == query
    without = BankOnlySelector(load_examples(), HashingEmbedder(64), exclude_most_similar=2)
    sims = dict(
        zip([x.description for x in without.examples], without.similarities(query).tolist(), strict=True)
    )
    others = sorted((d for d in sims if d != query), key=lambda d: -sims[d])
    chosen = [x.description for x in without.select(query, 3)]
    assert len(chosen) == 3 and query not in chosen and not set(chosen) & set(others[:2])
    assert max(sims[d] for d in chosen) <= sims[others[1]]


def test_malformed_sets_are_refused_with_the_entry_named() -> None:
    ok = 'description = "x"\nsplit = "dev"\nfamily = ["motion"]\nprogram = "output_scenario(s)"\n'
    assert parse_eval_set("[[entry]]\n" + ok)[0] == EvalEntry("x", "output_scenario(s)\n", "dev", ("motion",))
    with pytest.raises(EvalSetError, match="unknown family"):
        parse_eval_set("[[entry]]\n" + ok.replace('"motion"', '"flying"'))
    with pytest.raises(EvalSetError, match="split"):
        parse_eval_set("[[entry]]\n" + ok.replace('"dev"', '"test"'))
    with pytest.raises(EvalSetError, match="twice"):
        parse_eval_set(f"[[entry]]\n{ok}[[entry]]\n{ok.replace('x', 'X.')}")
    with pytest.raises(EvalSetError, match="unknown split"):
        load_eval_set("train")


def _same_program(program: str) -> str:
    """``program`` with the names it assigns numbered in order: references that differ only in their
    variable names ("cars = ...", "vehicles = ...") run once (the set repeats many programs)."""
    tree = ast.parse(program)
    names: dict[str, str] = {}
    for node in ast.walk(tree):
        if isinstance(node, ast.Name) and isinstance(node.ctx, ast.Store):
            names.setdefault(node.id, f"v{len(names)}")
    for node in ast.walk(tree):
        if isinstance(node, ast.Name) and node.id in names:
            node.id = names[node.id]
    return ast.unparse(tree)


def _finds_something(ctx: LogContext) -> dict[str, bool]:
    """Whether each reference finds something on the log, asserting every one runs."""
    found_by_program: dict[str, bool] = {}
    found = {}
    for e in ENTRIES:
        key = _same_program(e.program)
        if key not in found_by_program:
            result = run_trusted_program(e.program, ctx, description=e.description)
            assert result.error is None and result.scenario is not None, (e.description, result.error)
            found_by_program[key] = result.scenario.n_referred_cells > 0
        found[e.description] = found_by_program[key]
    return found


def test_same_program_numbers_only_the_assigned_names() -> None:
    a = (
        "cars = get_objects_of_category(log_dir, category='BUS')\n"
        "output_scenario(cars, description, log_dir, output_dir)"
    )
    b = a.replace("cars", "buses")
    assert _same_program(a) == _same_program(b)
    assert "log_dir" in _same_program(a) and "v0" in _same_program(a)
    assert _same_program(a) != _same_program(a.replace("'BUS'", "'TRUCK'"))


def test_every_reference_runs_on_the_shared_log_and_most_find_something(shared_log: LogContext) -> None:
    found = _finds_something(shared_log)
    ours = [e.description for e in ENTRIES if e.split in ("dev", "holdout")]
    assert sum(found[d] for d in ours) >= len(ours) / 2
    holdout = [e.description for e in load_eval_set("holdout")]
    assert sum(found[d] for d in holdout) >= len(holdout) / 2
    # the published sample was drawn blind to our logs: a 15 s log holds a part of its scenes only
    published = [e.description for e in load_eval_set("published")]
    assert sum(found[d] for d in published) >= len(published) / 4
    # so was the challenge sample, picked from a list of rare scenes: most name road users or
    # objects the shared log does not have
    challenge = [e.description for e in load_eval_set("challenge")]
    assert sum(found[d] for d in challenge) >= 1


@pytest.mark.parametrize("log_dir", [SECOND_LOG, THIRD_LOG], ids=["adcf7d18", "3bffdcff"])
def test_every_reference_runs_on_the_other_real_logs(log_dir: Path) -> None:
    from scenariominer.api.mining import load_logs

    cfg = Config()
    (log,) = load_logs([log_dir], None, cfg)
    ctx = LogContext(log, cfg.mining)
    found = _finds_something(ctx)
    assert sum(found.values()) >= len(ENTRIES) / 4


# ---------------------------------------------------------------------------------- scoring


def test_jaccard_of_cell_sets() -> None:
    a = frozenset({("t1", 1), ("t1", 2)})
    assert jaccard(a, a) == 1.0 and jaccard(frozenset(), frozenset()) == 1.0
    assert jaccard(a, frozenset({("t2", 1)})) == 0.0
    assert jaccard(a, frozenset({("t1", 2), ("t1", 3)})) == pytest.approx(1 / 3)


def _entry(description: str) -> EvalEntry:
    return next(e for e in ENTRIES if e.description == description)


SPEEDING = "vehicles speeding up"  # finds something on the shared log
SCHOOL_BUSES = "school buses"  # finds nothing there

_BOLLARDS = """
bollards = get_objects_of_category(log_dir, category='BOLLARD')
output_scenario(bollards, description, log_dir, output_dir)
"""


def _scripted(programs: dict[str, str | None | Exception]) -> Callable[[str], str | None]:
    def provide(description: str) -> str | None:
        answer = programs[description]
        if isinstance(answer, Exception):
            raise answer
        return answer

    return provide


def test_the_reference_scores_one_and_a_disjoint_candidate_zero(shared_log: LogContext) -> None:
    entries = [_entry(SPEEDING), _entry(SCHOOL_BUSES)]
    same = evaluate_nl2prog(entries, [shared_log], reference_provider(entries), candidate_runner=_trusted)
    assert same.runnable_share == 1.0 and same.mean_jaccard == 1.0 and same.n_scored_cells == 1
    assert same.empty_cells == (1, 1)
    speeding, buses = same.descriptions
    assert speeding.mean_jaccard == 1.0 and speeding.cells[0].reference_cells > 0
    assert buses.mean_jaccard is None and buses.cells[0].jaccard == 1.0  # both find nothing
    disjoint = evaluate_nl2prog(
        entries,
        [shared_log],
        _scripted({SPEEDING: _BOLLARDS, SCHOOL_BUSES: _BOLLARDS}),
        candidate_runner=_trusted,
    )
    assert disjoint.runnable_share == 1.0 and disjoint.mean_jaccard == 0.0
    assert disjoint.empty_cells == (0, 1)  # the bollards are found where the reference finds nothing
    assert disjoint.descriptions[0].cells[0].shared_cells == 0


def test_descriptions_the_phrase_rules_read_are_aggregated_apart(shared_log: LogContext) -> None:
    entries = [_entry(SPEEDING), _entry(SCHOOL_BUSES), _entry("bollards")]
    scripted = _scripted({SPEEDING: _BOLLARDS, SCHOOL_BUSES: _BOLLARDS, "bollards": _BOLLARDS})
    readers = {SPEEDING: "rules", SCHOOL_BUSES: "model", "bollards": "partial"}
    ev = evaluate_nl2prog(
        entries, [shared_log], scripted, candidate_runner=_trusted, reader=readers.__getitem__
    )
    assert [s.read_by_rules for s in ev.descriptions] == [True, False, False]
    by = ev.by_reader()
    rules, partial, model = by["rules"], by["partial"], by["model"]
    assert (rules.n_descriptions, rules.n_scored_cells, rules.mean_jaccard) == (1, 1, 0.0)
    assert (model.n_descriptions, model.n_scored_cells, model.mean_jaccard) == (1, 0, None)
    assert (partial.n_descriptions, partial.n_scored_cells, partial.mean_jaccard) == (1, 1, 1.0)
    doc = ev.to_json_dict()
    assert doc["read_by"]["rules"]["n_descriptions"] == 1 and doc["descriptions"][0]["read_by_rules"] is True
    assert [d["reader"] for d in doc["descriptions"]] == ["rules", "model", "partial"]
    # no reader given: the model read everything
    plain = evaluate_nl2prog(entries[:1], [shared_log], scripted, candidate_runner=_trusted)
    assert plain.descriptions[0].reader == "model" and plain.by_reader()["rules"].n_descriptions == 0


def test_failing_candidates_are_not_runnable_and_score_zero(shared_log: LogContext) -> None:
    entries = [_entry(d) for d in (SPEEDING, "vehicles inside an intersection", "bollards", "a box truck")]
    raising = "x = get_objects_of_category(log_dir, category='FLYING_CAR')\noutput_scenario(x, description)\n"
    provider = _scripted(
        {
            SPEEDING: raising,  # raises when run
            "vehicles inside an intersection": None,  # no program
            "bollards": RuntimeError("boom"),  # the provider itself fails
            "a box truck": "import os\n",  # refused by the checker
        }
    )
    ev = evaluate_nl2prog(entries, [shared_log], provider, candidate_runner=_trusted)
    assert ev.n_runnable == 0 and ev.mean_jaccard == 0.0 and ev.n_scored_cells == 4
    errors = [s.error or "" for s in ev.descriptions]
    assert "FLYING_CAR" in errors[0]
    assert "no program" in errors[1]
    assert "provider failed" in errors[2] and "boom" in errors[2]
    assert "import" in errors[3]
    assert all(s.cells[0].jaccard == 0.0 for s in ev.descriptions)


def test_a_model_failure_stops_the_evaluation(shared_log: LogContext) -> None:
    provider = _scripted({SPEEDING: LLMError("no model")})
    with pytest.raises(LLMError):
        evaluate_nl2prog([_entry(SPEEDING)], [shared_log], provider, candidate_runner=_trusted)


def test_sandboxed_candidates_and_aggregates_per_family(shared_log: LogContext) -> None:
    entries = [_entry(SPEEDING), _entry("vehicles inside an intersection")]
    partial = _entry(SPEEDING).program.replace("min_accel=1.0", "min_accel=2.0")  # a subset of the cells
    provider = _scripted({SPEEDING: partial, "vehicles inside an intersection": None})
    ev = evaluate_nl2prog(entries, [shared_log], provider)  # default: the sandbox
    speeding = ev.descriptions[0]
    assert speeding.runnable and speeding.execution_s > 0
    j = speeding.mean_jaccard
    assert j is not None and 0 < j < 1
    assert ev.mean_jaccard == pytest.approx(j / 2)
    families = ev.per_family()
    assert families["motion"].mean_jaccard == pytest.approx(j) and families["motion"].n_runnable == 1
    assert families["intersection"].mean_jaccard == 0.0 and families["intersection"].n_runnable == 0
    doc = ev.to_json_dict()
    assert (
        doc["n_descriptions"] == 2
        and doc["n_runnable"] == 1
        and doc["families"]["motion"]["n_scored_cells"] == 1
    )
    json.dumps(doc)


def test_the_nearest_bank_baseline_copies_the_closest_bank_program() -> None:
    bank = load_examples()
    provide = nearest_bank_provider(bank)
    assert provide("vehicles changing lanes to the right") == next(
        e.program for e in bank if e.description == "vehicle changing lanes to the left"
    )
    assert provide("zzz") is None


# ---------------------------------------------------------------------------------- the command


def test_eval_nl2prog_command_with_a_scripted_provider(
    av2_log_dir: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    holdout = load_eval_set("holdout")[:3]
    answers: dict[str, str | None | Exception] = {
        holdout[0].description: holdout[0].program,
        holdout[1].description: None,
        holdout[2].description: _BOLLARDS,
    }
    calls: list[dict[str, Any]] = []

    def fake_generator(validation: Any, config: Any, **kwargs: Any) -> Callable[[str], str | None]:
        calls.append(kwargs)
        return _scripted(answers)

    monkeypatch.setattr(evaluation_api, "generator_provider", fake_generator)
    cfg = tmp_path / "cfg.toml"
    cfg.write_text(f'[llm]\ncache_dir = "{tmp_path / "cache"}"\n')
    args = [
        "eval",
        "nl2prog",
        "--split",
        "holdout",
        "--limit",
        "3",
        "--logs",
        str(av2_log_dir),
        "-c",
        str(cfg),
    ]
    res = runner.invoke(app, [*args, "--json"])
    assert res.exit_code == 0, res.output
    doc = json.loads(res.output)
    assert doc["split"] == "holdout" and doc["n_descriptions"] == 3 and doc["n_runnable"] == 2
    assert [d["description"] for d in doc["descriptions"]] == [e.description for e in holdout]
    assert (
        doc["descriptions"][0]["mean_jaccard"] in (1.0, None) and doc["descriptions"][1]["runnable"] is False
    )
    assert calls[-1]["exclude_most_similar"] == 0
    res = runner.invoke(app, [*args, "--no-bank-similar"])
    assert res.exit_code == 0, res.output
    assert calls[-1]["exclude_most_similar"] == Config().mining.generation.few_shot_k
    text = " ".join(res.output.split())
    assert "runnable 2/3" in text and "mean Jaccard" in text and "per family" in text
    assert "without the most similar bank entries" in text and "not runnable" in text
    bad = runner.invoke(
        app, ["eval", "nl2prog", "--split", "train", "--logs", str(av2_log_dir), "-c", str(cfg)]
    )
    assert bad.exit_code == 2 and "unknown split" in bad.output
