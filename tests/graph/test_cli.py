"""``graph build``, ``ask`` and ``eval retrieval`` through the real command line on a tiny highway store."""

from __future__ import annotations

import json
from pathlib import Path

from PIL import Image
from typer.testing import CliRunner

from scenariominer.cli import app

from .helpers import write_highway

runner = CliRunner()

CONFIG_TOML = """
[embedding]
backend = "hashing"
cache = false

[represent.windows]
lengths_s = [15.0]
overlap = 0.0
"""


def _run(*args: str) -> str:
    result = runner.invoke(app, list(args))
    assert result.exit_code == 0, result.output
    return " ".join(result.output.split())


def test_build_ask_and_evaluate_from_the_command_line(tmp_path: Path) -> None:
    write_highway(tmp_path / "rec")
    cfg = tmp_path / "config.toml"
    cfg.write_text(CONFIG_TOML)
    common = ("--store", str(tmp_path / "store"), "--config", str(cfg))
    _run("ingest", str(tmp_path / "rec"), *common)
    _run("embed", "windows", *common)
    out = _run("graph", "build", "--no-summaries", *common)
    assert "24 samples of 24 logs (24 described now)" in out
    # a second build describes nothing again
    assert "(0 described now)" in _run("graph", "build", "--no-summaries", *common)

    picture = tmp_path / "top.png"
    reply = json.loads(
        _run(
            "ask",
            "lane change to the left",
            "-k",
            "3",
            "--no-answer",
            "--picture",
            str(picture),
            "--json",
            *common,
        )
    )
    samples = reply["result"]["samples"]
    assert [s["rank"] for s in samples] == [1, 2, 3]
    assert all(s["start_frame"] is not None and s["log_id"].startswith("highd-01-") for s in samples)
    assert reply["result"]["llm_status"] == "no model" and reply["result"]["answer"] == ""
    with Image.open(picture) as im:
        assert im.size[1] > im.size[0] / 2  # three stacked panels
    table = runner.invoke(app, ["ask", "lane change to the left", "-k", "1", "--no-answer", *common]).output
    first = samples[0]
    others = [t for t in first["track_ids"] if t != first["agent_id"]]
    assert f"{len(others)}: {others[0][:8]}" in table  # the count of the others, not every id folded

    out = _run("eval", "retrieval", "--k-max", "24", *common)
    # 6 vehicles on a 3-lane carriageway: two-lane queries have no relevant window and are skipped
    assert "windows/graph" in out and "windows/vector" in out
    assert "not scored (no relevant window): " in out and "gen-l1-two-lane" in out


def test_ask_without_a_graph_says_what_to_run(tmp_path: Path) -> None:
    write_highway(tmp_path / "rec")
    cfg = tmp_path / "config.toml"
    cfg.write_text(CONFIG_TOML)
    common = ("--store", str(tmp_path / "store"), "--config", str(cfg))
    _run("ingest", str(tmp_path / "rec"), *common)
    result = runner.invoke(app, ["ask", "any lane change", "--no-answer", *common])
    assert result.exit_code != 0
    assert "graph build" in " ".join(result.output.split())
    # and `graph build` before any windows says to cut them first, not to run itself
    result = runner.invoke(app, ["graph", "build", "--no-summaries", *common])
    assert result.exit_code != 0
    shown = " ".join(result.output.split())
    assert "run scenariominer embed windows first" in shown and "graph build" not in shown
