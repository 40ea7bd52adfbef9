"""The ``embed`` commands and ``similar`` on a tiny store, through the real command line."""

from __future__ import annotations

import json
from pathlib import Path

from typer.testing import CliRunner

from scenariominer.cli import app
from scenariominer.store import ScenarioStore

runner = CliRunner()

TINY_TOML = """
[represent.windows]
lengths_s = [4.0]
overlap = 0.5
n_steps = 8
k_neighbours = 3
agents = "vehicles"

[represent.embedder]
latent_dim = 4
hidden_dim = 8
attention_heads = 2
epochs = 3
batch_size = 16
threads = 1

[represent.cluster]
min_cluster_size = 4
tsne_perplexity = 5.0
"""


def _run(*args: str) -> str:
    """Run a command; its output with line wrapping undone (Rich wraps at the terminal width)."""
    result = runner.invoke(app, list(args))
    assert result.exit_code == 0, result.output
    return result.output if "--json" in args else " ".join(result.output.split())


def test_windows_train_cluster_apply_plot_similar(tiny_store: ScenarioStore, tmp_path: Path) -> None:
    cfg = tmp_path / "tiny.toml"
    cfg.write_text(TINY_TOML, encoding="utf-8")
    common = ("--store", str(tiny_store.root), "--config", str(cfg))
    out = _run("embed", "windows", *common, "--log", "cruise-a")
    assert "36 windows from 1 logs: 1 cut now" in out
    out = _run("embed", "train", *common, "--loss", "mse", "--epochs", "2")
    assert "mse loss, 36 windows of 1 logs (4 agents x 8 steps), 2 epochs" in out
    report = json.loads(_run("embed", "cluster", *common, "--json"))
    assert report["n_windows"] == 36
    assert report["n_clusters"] + 0 == len(report["sizes"])
    assert "1 cut now" in _run("embed", "windows", *common)  # weave-a only: cruise-a is current
    out = _run("embed", "apply", *common)
    assert "embedded 36 windows of 1 new or changed logs" in out
    assert "assigned 36 windows to clustering" in out
    out = _run("embed", "plot", *common, "--out", str(tmp_path / "plots"))
    assert "72 windows" in out and (tmp_path / "plots" / "mean_speed_mps.png").is_file()
    hits = json.loads(_run("similar", "weave-a", "--track", "ego", "--t", "3", "-k", "3", *common, "--json"))
    assert hits["query"]["window_id"].startswith("weave-a|ego|")
    assert len(hits["hits"]) == 3
    assert all(h["window_id"] != hits["query"]["window_id"] for h in hits["hits"])
    distances = [h["distance"] for h in hits["hits"]]
    assert distances == sorted(distances)
    table = _run("similar", "weave-a", "--track", "ego", "--t", "3", "-k", "2", *common)
    assert "distance" in table


def test_similar_names_a_missing_track(tiny_store: ScenarioStore, tmp_path: Path) -> None:
    cfg = tmp_path / "tiny.toml"
    cfg.write_text(TINY_TOML, encoding="utf-8")
    common = ("--store", str(tiny_store.root), "--config", str(cfg))
    _run("embed", "windows", *common)
    _run("embed", "train", *common, "--epochs", "1")
    result = runner.invoke(app, ["similar", "weave-a", "--track", "nobody", "--t", "3", *common])
    assert result.exit_code == 2
    assert "track 'nobody' is not in log weave-a" in " ".join(result.output.split())
    for t in ("99", "-1"):
        result = runner.invoke(app, ["similar", "weave-a", "--track", "ego", "--t", t, *common])
        assert result.exit_code == 2, result.output
        assert f"t = {t} s is outside log weave-a, which lasts" in " ".join(result.output.split())


def test_train_without_windows_says_what_to_run(tiny_store: ScenarioStore) -> None:
    result = runner.invoke(app, ["embed", "train", "--store", str(tiny_store.root)])
    assert result.exit_code == 2
    assert "scenariominer embed windows" in " ".join(result.output.split())


def test_training_on_too_few_windows_to_cluster_says_so(tiny_store: ScenarioStore, tmp_path: Path) -> None:
    # a model trained on the 3 windows of three AV2 logs was reported like any other
    cfg = tmp_path / "few.toml"
    cfg.write_text(TINY_TOML.replace("min_cluster_size = 4", "min_cluster_size = 40"), encoding="utf-8")
    common = ("--store", str(tiny_store.root), "--config", str(cfg))
    _run("embed", "windows", *common, "--log", "cruise-a")
    out = _run("embed", "train", *common, "--epochs", "1")
    assert "note: only 36 windows: too few for the model to generalise" in out
    assert "min_cluster_size (40)" in out
    cfg.write_text(TINY_TOML, encoding="utf-8")  # 36 windows against 4
    assert "note:" not in _run("embed", "train", *common, "--epochs", "1")
