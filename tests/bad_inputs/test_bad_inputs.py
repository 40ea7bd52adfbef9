"""The bad-input corpus (``bad_registry``): each case is ingested next to a good log.

Every case must end as registered (rejected with its error, repaired with its note, or accepted),
without a traceback or a hang, and the good log beside it must still be stored.
"""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest
from bad_av2 import av2_folder
from bad_registry import BEGIN, DOC, END, Case, all_cases, doc_with_table
from typer.testing import CliRunner

from scenariominer import api
from scenariominer.config import Config, IngestConfig
from scenariominer.data.ingest import SourceResult

CASES = all_cases()
GOOD = "good-log"
# Short highD windows (the small recording lasts 20 s) and few egos keep each case fast.
CONFIG = Config(ingest=IngestConfig(highd_window_s=4.0, highd_max_egos_per_recording=2))


def test_the_corpus_has_more_than_51_classes_with_unique_names() -> None:
    names = [c.name for c in CASES]
    assert len(names) == len(set(names))
    assert len(CASES) > 51
    for fmt in ("av2", "map", "highd", "tabular", "path"):
        assert any(c.fmt == fmt for c in CASES), fmt


def test_docs_list_every_case_with_its_outcome() -> None:
    text = DOC.read_text(encoding="utf-8")
    assert BEGIN in text and END in text
    assert text == doc_with_table(text, CASES), (
        "docs/bad-input.md is out of date: run .venv/bin/python tests/bad_inputs/bad_registry.py --write-doc"
    )


def _bad_results(results: list[SourceResult], good_dir: Path) -> list[SourceResult]:
    return [r for r in results if r.key != str(good_dir.resolve())]


def _check_api(case: Case, paths: list[Path], good_dir: Path, tmp_path: Path) -> None:
    store = api.open_store(tmp_path / "store", CONFIG)
    report = api.ingest([*paths, good_dir], store, CONFIG)
    logs = store.log_ids()
    assert GOOD in logs, [r.error for r in report.failed]
    bad = _bad_results(list(report.sources), good_dir)
    assert bad, "the bad input produced no result"
    errors = [r.error for r in bad if r.status == "failed"]
    if case.outcome == "rejected":
        assert errors, f"expected a rejection, got {bad}"
        assert any(re.search(case.pattern, e) for e in errors), errors
        assert logs == [GOOD], logs
    else:
        assert not errors, errors
        assert len(logs) > 1
        notes = [n for r in bad for n in r.notes]
        stored = [n for log_id in logs if log_id != GOOD for n in store.log_meta(log_id).notes]
        if case.outcome == "repaired":
            assert any(re.search(case.pattern, n) for n in notes), notes
            assert any(re.search(case.pattern, n) for n in stored), stored
    if case.check is not None:
        case.check(store, report, tmp_path / "in")


def _check_cli(case: Case, paths: list[Path], good_dir: Path, tmp_path: Path) -> None:
    from scenariominer.cli import app

    store_dir = tmp_path / "store"
    args = ["ingest", *map(str, paths), str(good_dir), "--store", str(store_dir)]
    result = CliRunner().invoke(app, args)
    output = result.output
    assert result.exception is None or isinstance(result.exception, SystemExit), repr(result.exception)
    assert "Traceback" not in output
    assert result.exit_code == (1 if case.outcome == "rejected" else 0), output
    flat = " ".join(output.split())
    if case.pattern:
        assert re.search(case.pattern, flat), flat
    store = api.open_existing_store(store_dir, CONFIG)
    logs = store.log_ids()
    assert GOOD in logs
    assert (logs == [GOOD]) == (case.outcome == "rejected"), logs
    json_run = CliRunner().invoke(app, [*args, "--json", "--force"])
    report = json.loads(json_run.stdout)
    assert report["store"]["n_logs"] == len(logs)
    if case.check is not None:
        case.check(store, output, tmp_path / "in")


@pytest.mark.timeout(60)
@pytest.mark.parametrize("case", CASES, ids=[c.name for c in CASES])
def test_bad_input_is_rejected_or_repaired_and_the_good_log_lands(case: Case, tmp_path: Path) -> None:
    good_dir = av2_folder(tmp_path / "good", GOOD, with_map=False)
    paths = list(case.make(tmp_path / "in"))
    if case.via == "cli":
        _check_cli(case, paths, good_dir, tmp_path)
    else:
        _check_api(case, paths, good_dir, tmp_path)
