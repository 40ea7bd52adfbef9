"""The analyze / search / show commands and ``eval braking`` through Typer's test runner."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
import typer
from braking_builders import answer
from typer.testing import CliRunner

from scenariominer import api
from scenariominer.api import braking as braking_api
from scenariominer.cli import app as root_app
from scenariominer.config import Config
from scenariominer.llm import ChatClient
from scenariominer.store import ScenarioStore
from scenariominer.testing import ScriptedBackend

runner = CliRunner()


def _app() -> typer.Typer:
    return root_app


@pytest.fixture(scope="module")
def workspace(tmp_path_factory: pytest.TempPathFactory) -> Path:
    root = tmp_path_factory.mktemp("cli")
    api.synth(root / "synth", 2, seed=5, categories=["right_ped", "cut_in"])
    api.ingest([root / "synth"], ScenarioStore.open(root / "store"), Config())
    (root / "cfg.toml").write_text('[embedding]\nbackend = "hashing"\nhashing_dim = 48\n')
    return root


def _flat(text: str) -> str:
    """Output with Rich's line wrapping undone."""
    return " ".join(text.split())


def _args(root: Path, *args: str) -> list[str]:
    return [*args, "--store", str(root / "store"), "--config", str(root / "cfg.toml")]


@pytest.fixture(scope="module")
def analysed(workspace: Path) -> Path:
    """The workspace after ``analyze --limit 0`` then ``analyze`` with a scripted LLM."""
    app = _app()
    pending = runner.invoke(app, _args(workspace, "analyze", "--limit", "0"))
    assert pending.exit_code == 0, pending.output
    assert "pending" in pending.output
    backend = ScriptedBackend(
        [answer("right_ped", "A pedestrian crosses while the ego turns right.", "why")] * 50
    )
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(braking_api, "make_chat_client", lambda cfg, **_: ChatClient(backend))
        done = runner.invoke(app, _args(workspace, "analyze", "--json"))
    assert done.exit_code == 0, done.output
    report = json.loads(done.output)
    assert report["n_llm_calls"] == len(backend.requests) > 0 and report["n_pending"] == 0
    return workspace


def test_search_by_category_as_json(analysed: Path) -> None:
    res = runner.invoke(_app(), _args(analysed, "search", "--category", "right_ped", "--json"))
    assert res.exit_code == 0, res.output
    hits = json.loads(res.output)
    assert hits and {h["category"] for h in hits} == {"right_ped"}
    assert {"log_id", "guest_id", "start_ns", "end_ns", "explanation", "min_ttc_s", "peak_decel_mps2"} <= set(
        hits[0]
    )


def test_search_by_text(analysed: Path) -> None:
    res = runner.invoke(
        _app(), _args(analysed, "search", "a pedestrian crosses", "--k", "1", "--sort", "decel")
    )
    assert res.exit_code == 0, res.output
    assert "1 event(s)" in res.output and "score" in res.output


def test_show_writes_a_png(analysed: Path) -> None:
    log_id = ScenarioStore.open(analysed / "store").log_ids()[0]
    out = analysed / "event.png"
    res = runner.invoke(_app(), _args(analysed, "show", log_id, "--out", str(out)))
    assert res.exit_code == 0, res.output
    assert out.read_bytes().startswith(b"\x89PNG")


def test_eval_braking(analysed: Path) -> None:
    labels = analysed / "synth" / "labels.csv"
    res = runner.invoke(_app(), _args(analysed, "eval", "braking", "--labels", str(labels), "--json"))
    assert res.exit_code == 0, res.output
    result = json.loads(res.output)
    assert result["n_logs"] == 2 and result["keyident"]["recall"] == 1.0
    assert [r["category"] for r in result["classification"]][-1] == "overall"
    by_method = {m["method"]: m for m in result["keyident_by_method"]}
    assert set(by_method) == {"tags", "counterfactual", "combined"}
    assert by_method["tags"]["recall"] == result["keyident"]["recall"]  # synthetic key objects raise tags
    table = runner.invoke(
        _app(), _args(analysed, "eval", "braking", "--labels", str(labels), "--no-retrieval")
    )
    assert table.exit_code == 0 and "Table V" in table.output
    assert "KeyIdent recall by method" in table.output


def test_user_errors_exit_2_with_one_line(workspace: Path, tmp_path: Path) -> None:
    app = _app()
    missing = runner.invoke(app, ["search", "--category", "cut_in", "--store", str(tmp_path / "nope")])
    assert missing.exit_code == 2 and "no store here" in _flat(missing.output)
    bad_cats = tmp_path / "cats.toml"
    bad_cats.write_text('invalid = "x"\n')
    res = runner.invoke(app, _args(workspace, "analyze", "--limit", "0", "--categories", str(bad_cats)))
    assert res.exit_code == 2 and "reserved" in _flat(res.output)
    labels = workspace / "synth" / "labels.csv"
    res = runner.invoke(
        app, _args(workspace, "eval", "braking", "--labels", str(labels), "--categories", str(bad_cats))
    )
    assert res.exit_code == 2 and "reserved" in _flat(res.output)
    res = runner.invoke(app, _args(workspace, "show", "no-such-log"))
    assert res.exit_code == 2
    res = runner.invoke(app, _args(workspace, "eval", "braking", "--labels", str(tmp_path / "none.csv")))
    assert res.exit_code == 2 and "does not exist" in _flat(res.output)


def test_eval_braking_sets_side_by_side(analysed: Path, tmp_path: Path) -> None:
    labels = analysed / "synth" / "labels.csv"
    # A second set: the same store scored against labels that name another guest for one log.
    rows = labels.read_text().splitlines()
    header, first = rows[0].split(","), rows[1].split(",")
    first[header.index("guest_id")] = "someone-else"
    other = tmp_path / "labels.csv"
    other.write_text("\n".join([rows[0], ",".join(first), *rows[2:]]) + "\n")
    spec = f"shifted={analysed / 'store'},{other}"
    res = runner.invoke(
        _app(),
        _args(
            analysed, "eval", "braking", "--labels", str(labels), "--no-retrieval", "--also", spec, "--json"
        ),
    )
    assert res.exit_code == 0, res.output
    sets = json.loads(res.output)["sets"]
    assert list(sets) == ["synth", "shifted"]
    assert sets["synth"]["keyident"]["recall"] == 1.0
    assert sets["shifted"]["keyident"]["recall"] == 0.5  # one of the two labelled guests is not found
    table = runner.invoke(
        _app(), _args(analysed, "eval", "braking", "--labels", str(labels), "--no-retrieval", "--also", spec)
    )
    assert table.exit_code == 0, table.output
    recall_row = next(ln for ln in table.output.splitlines() if "KeyIdent recall " in ln and "│" in ln)
    assert "synth" in table.output and "shifted" in table.output and "1.00" in recall_row
    bad = runner.invoke(_app(), _args(analysed, "eval", "braking", "--labels", str(labels), "--also", "oops"))
    assert bad.exit_code == 2 and "NAME=STORE,LABELS" in _flat(bad.output)
    same = runner.invoke(
        _app(),
        _args(
            analysed,
            "eval",
            "braking",
            "--labels",
            str(labels),
            "--no-retrieval",
            "--also",
            f"synth={spec[8:]}",
        ),
    )
    assert same.exit_code == 2 and "unique" in _flat(same.output)


def test_show_names_its_png_after_the_event_once() -> None:
    from scenariominer.api.braking import ShowRequest

    log, event = "e63bc8f8", "e63bc8f8:e9154a48:316412025793275471"
    assert ShowRequest(log, event_id=event).out_path() == Path("e63bc8f8_e9154a48_316412025793275471.png")
    assert ShowRequest(log, event_id="guest:1").out_path() == Path("e63bc8f8_guest_1.png")
    assert ShowRequest(log).out_path() == Path("e63bc8f8_event.png")
    assert ShowRequest(log, out=Path("x.png"), event_id=event).out_path() == Path("x.png")
