"""The evaluation grid: scoring, per-risk-type accuracy, rollout success, resuming, no leaks."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from scenariominer.cbr.build import HoldoutCase
from scenariominer.cbr.cases import Case
from scenariominer.cbr.recommend import RecommendSettings
from scenariominer.cbr.vocab import CbrError
from scenariominer.eval.cbr import (
    baseline_rows,
    default_grid,
    evaluate_cbr_grid,
    interleaved,
    text_metrics,
)
from scenariominer.llm.client import ChatClient
from scenariominer.store import ScenarioStore
from scenariominer.testing import ScriptedBackend

from .helpers import EMBEDDER, answer, case_base


def _holdout() -> list[HoldoutCase]:
    def hc(cid: str, risk: str, truth: str, avoided: dict[str, bool]) -> HoldoutCase:
        case = Case(
            cid,
            risk,
            f"caption of {cid}",
            event_context="the ego nears a stopped car",
            manoeuvre=truth,
            justification="braking stops the car before the obstacle",
        )
        return HoldoutCase(case, avoided, {k: 1.0 for k in avoided})

    return [
        hc(
            "q1",
            "vehicle_ahead",
            "emergency_braking",
            {"emergency_braking": True, "evasive_steering_left": True},
        ),
        hc(
            "q2",
            "vehicle_ahead",
            "evasive_steering_left",
            {"emergency_braking": False, "evasive_steering_left": True},
        ),
        hc("q3", "pedestrian", "emergency_braking", {"emergency_braking": True}),
    ]


def test_grid_scores_accuracy_per_type_and_rollout_success(tmp_path: Path) -> None:
    base = case_base(tmp_path)
    results = ScenarioStore.open(tmp_path / "store").corpus("cbr_eval_test", 1)
    backend = ScriptedBackend([answer("emergency_braking")] * 3)
    grid = [RecommendSettings(k=0)]
    ev = evaluate_cbr_grid(base, _holdout(), results, ChatClient(backend), EMBEDDER, grid, with_text=False)
    (c,) = ev.configs
    assert c.n_answered == 3 and c.complete
    assert c.accuracy == pytest.approx(2 / 3)
    assert c.per_type == {"pedestrian": 1.0, "vehicle_ahead": 0.5}
    assert c.rollout_success == pytest.approx(2 / 3)  # braking does not avoid q2's conflict
    assert ev.fresh_calls == 3
    # Resumed: every answer is stored, so no model call is made (the script is empty).
    again = evaluate_cbr_grid(
        base, _holdout(), results, ChatClient(ScriptedBackend([])), EMBEDDER, grid, with_text=False
    )
    assert again.configs[0].accuracy == c.accuracy and again.fresh_calls == 0


def test_invalid_answer_counts_as_wrong_and_the_grid_goes_on(tmp_path: Path) -> None:
    base = case_base(tmp_path)
    results = ScenarioStore.open(tmp_path / "store").corpus("cbr_eval_test", 1)
    # Order q3, q1, q2 (rounds over risk types): q3's answer is garbage twice, the others are right.
    replies = ["garbage", "garbage", answer("emergency_braking"), answer("evasive_steering_left")]
    ev = evaluate_cbr_grid(
        base,
        _holdout(),
        results,
        ChatClient(ScriptedBackend(replies)),
        EMBEDDER,
        [RecommendSettings(k=0)],
        with_text=False,
    )
    c = ev.configs[0]
    assert c.n_invalid == 1 and c.n_answered == 3
    assert c.accuracy == pytest.approx(2 / 3)


def test_time_budget_stops_and_leaves_the_rest_for_later(tmp_path: Path) -> None:
    base = case_base(tmp_path)
    results = ScenarioStore.open(tmp_path / "store").corpus("cbr_eval_test", 1)
    ticks = iter([0.0, 0.0, 0.0, 100.0, 100.0, 100.0, 100.0, 100.0])
    ev = evaluate_cbr_grid(
        base,
        _holdout(),
        results,
        ChatClient(ScriptedBackend([answer()] * 3)),
        EMBEDDER,
        [RecommendSettings(k=0)],
        time_budget_s=10.0,
        with_text=False,
        clock=lambda: next(ticks),
    )
    c = ev.configs[0]
    assert 0 < c.n_answered < 3 and not c.complete


def test_a_stopped_run_leaves_every_configuration_on_the_same_cases(tmp_path: Path) -> None:
    """Cases go in rounds over risk types, all configurations per case before the next one."""
    assert [hc.case.case_id for hc in interleaved(_holdout())] == ["q3", "q1", "q2"]
    base = case_base(tmp_path)
    results = ScenarioStore.open(tmp_path / "store").corpus("cbr_eval_test", 1)
    grid = [RecommendSettings(k=0), RecommendSettings(k=0, risk_aware=False)]
    ticks = iter([0.0] * 5 + [100.0] * 20)  # start, then four answers within the budget
    ev = evaluate_cbr_grid(
        base,
        _holdout(),
        results,
        ChatClient(ScriptedBackend([answer("emergency_braking")] * 4)),
        EMBEDDER,
        grid,
        time_budget_s=10.0,
        with_text=False,
        clock=lambda: next(ticks),
    )
    assert [c.n_answered for c in ev.configs] == [2, 2]  # q3 (pedestrian) and q1 (vehicle_ahead)
    assert set(ev.configs[0].per_type) == {"pedestrian", "vehicle_ahead"}


def test_holdout_case_in_the_case_base_is_refused(tmp_path: Path) -> None:
    base = case_base(tmp_path)
    leaked = [HoldoutCase(base.get("a1"), {}, {})]
    results = ScenarioStore.open(tmp_path / "store").corpus("cbr_eval_test", 1)
    with pytest.raises(CbrError, match="are in the case base"):
        evaluate_cbr_grid(
            base, leaked, results, ChatClient(ScriptedBackend([])), EMBEDDER, [RecommendSettings()]
        )


def test_default_grid_is_the_papers_comparison() -> None:
    labels = [g.label for g in default_grid()]
    assert len(labels) == 14 and len(set(labels)) == 14
    assert labels[:4] == ["aware/k0", "aware/similarity/k3", "aware/random/k3", "unaware/k0"]


@pytest.mark.skipif(shutil.which("java") is None, reason="METEOR's jar needs Java")
def test_text_metrics_score_meteor_and_leave_no_noise_on_stderr() -> None:
    """METEOR's jar is started, scored and shut down; nothing is printed when Python exits."""
    pytest.importorskip("pycocoevalcap")
    script = (
        "from scenariominer.eval.cbr import text_metrics\n"
        "s, notes = text_metrics(['the car brakes hard', 'a truck cuts in'],"
        " ['the car brakes', 'a van cuts in from the left'])\n"
        "print(sorted(s), notes)\n"
        "import gc; gc.collect()\n"
    )
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert "METEOR" in done.stdout and "unavailable" not in done.stdout
    assert "Exception ignored" not in done.stderr and "Traceback" not in done.stderr, done.stderr


def test_rendered_grid_has_one_row_per_configuration_and_marks_unfinished_ones(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """At 100 columns every configuration's label, accuracy and rollout rate are printed whole."""
    import io

    from rich.console import Console

    from scenariominer.cli import _common
    from scenariominer.cli.cbr import render_eval

    base = case_base(tmp_path)
    results = ScenarioStore.open(tmp_path / "store").corpus("cbr_eval_test", 1)
    grid = [RecommendSettings(k=0), RecommendSettings(k=1, risk_aware=False, selection="random")]
    ticks = iter([0.0] * 6 + [100.0] * 20)
    ev = evaluate_cbr_grid(
        base,
        _holdout(),
        results,
        ChatClient(ScriptedBackend([answer("emergency_braking")] * 5)),
        EMBEDDER,
        grid,
        time_budget_s=10.0,
        with_text=False,
        clock=lambda: next(ticks),
    )
    assert ev.configs[0].complete and not ev.configs[1].complete
    buf = io.StringIO()
    monkeypatch.setitem(_common._consoles, "out", Console(file=buf, width=100))
    render_eval(ev)
    out = buf.getvalue()
    lines: dict[str, str] = {}  # label -> its row in the first (accuracy) table
    for ln in out.splitlines():
        if ln.count("│") > 2:
            lines.setdefault(ln.split("│")[1].strip(), ln)
    first, second = ev.configs[0].label, ev.configs[1].label + " *"
    assert first in lines and second in lines
    assert "0.67" in lines[first]  # overall accuracy 2/3 of the first configuration
    assert "not every hold-out case answered yet" in out


def test_model_free_baselines_answer_the_majority_and_the_neighbours_vote(tmp_path: Path) -> None:
    base = case_base(tmp_path)  # vehicle_ahead: braking x2, steering left x1; pedestrian: braking x2

    def hc(cid: str, risk: str, caption: str, truth: str) -> HoldoutCase:
        return HoldoutCase(Case(cid, risk, caption, manoeuvre=truth), {truth: True}, {truth: 1.0})

    holdout = [
        hc(
            "v1",
            "vehicle_ahead",
            "a stopped truck very close ahead with the left lane free",
            "evasive_steering_left",
        ),
        hc("v2", "vehicle_ahead", "the car in front brakes suddenly in dense traffic", "emergency_braking"),
        hc("w1", "pedestrian", "a child runs across the road from the right", "evasive_steering_right"),
    ]
    rows = baseline_rows(base, holdout, EMBEDDER, k=1)
    assert {cid: r["manoeuvre"] for cid, r in rows["baseline/majority"].items()} == {
        "v1": "emergency_braking",
        "v2": "emergency_braking",
        "w1": "emergency_braking",
    }
    # k=1: the answer of the nearest case (the same caption) of the same risk type
    assert rows["baseline/vote/k1"]["v1"]["manoeuvre"] == "evasive_steering_left"
    assert rows["baseline/vote/k1"]["v2"]["manoeuvre"] == "emergency_braking"
    # The grid scores them beside the model's configurations, with no model call.
    results = ScenarioStore.open(tmp_path / "store").corpus("cbr_eval_test", 1)
    ev = evaluate_cbr_grid(
        base,
        holdout,
        results,
        ChatClient(ScriptedBackend([answer()] * 3)),
        EMBEDDER,
        [RecommendSettings(k=0)],
        with_text=False,
    )
    by_label = {b.label: b for b in ev.baselines}
    assert by_label["baseline/majority"].accuracy == pytest.approx(1 / 3)
    assert by_label["baseline/majority"].rollout_success == pytest.approx(1 / 3)
    assert (
        "baseline/vote/k5" in by_label and ev.to_json_dict()["baselines"][0]["label"] == "baseline/majority"
    )


def _java_children() -> list[int]:
    """Pids of this process's children running java (from /proc; Linux)."""
    me = str(os.getpid())
    kids = []
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            fields = stat.read_text().rsplit(")", 1)[1].split()
            cmd = (stat.parent / "cmdline").read_bytes()
        except OSError:
            continue
        if fields[1] == me and b"java" in cmd:
            kids.append(int(stat.parent.name))
    return kids


@pytest.mark.skipif(shutil.which("java") is None, reason="METEOR's jar needs Java")
def test_one_text_scorer_serves_many_calls_with_one_jar_and_stops_it() -> None:
    pytest.importorskip("pycocoevalcap")
    from scenariominer.eval.cbr import TextScorer

    pairs = [
        (["the car brakes hard", "a truck cuts in"], ["the car brakes", "a van cuts in from the left"]),
        (["steer right to pass the cyclist"], ["brake and let the cyclist cross"]),
    ]
    with TextScorer() as scorer:
        shared = [scorer.score(h, r) for h, r in pairs]
        assert len(_java_children()) == 1  # started once, kept for the second call
    assert _java_children() == []
    assert shared == [text_metrics(h, r) for h, r in pairs]  # the same scores as one-off scoring
    assert all("METEOR" in s for s, _ in shared)


def test_grid_picture_is_a_png_with_one_bar_per_configuration(tmp_path: Path) -> None:
    from PIL import Image

    from scenariominer.eval.cbr import plot_evaluation

    base = case_base(tmp_path)
    results = ScenarioStore.open(tmp_path / "store").corpus("cbr_eval_test", 1)
    grid = [RecommendSettings(k=0), RecommendSettings(k=1), RecommendSettings(k=1, selection="random")]
    ev = evaluate_cbr_grid(
        base,
        _holdout(),
        results,
        ChatClient(ScriptedBackend([answer("emergency_braking")] * 9)),
        EMBEDDER,
        grid,
        with_text=False,
    )
    small = plot_evaluation(ev, tmp_path / "pics" / "grid.png")
    assert small == tmp_path / "pics" / "grid.png"
    with Image.open(small) as img:
        assert img.format == "PNG"
        h3 = img.size[1]
    # The figure grows with the number of configurations (one bar each).
    more = evaluate_cbr_grid(
        base,
        _holdout(),
        results,
        ChatClient(ScriptedBackend([answer("emergency_braking")] * 30)),
        EMBEDDER,
        default_grid(ks=(0, 1, 3)),
        with_text=False,
    )
    with Image.open(plot_evaluation(more, tmp_path / "grid10.png")) as img:
        assert img.size[1] > h3
    assert ev.to_json_dict()["picture"] is None
