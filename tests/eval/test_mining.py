"""Scenario-mining evaluation: the official Argoverse 2 scores plus the paper's F1 scores."""

from __future__ import annotations

import copy
import pickle
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import typer
from typer.testing import CliRunner

from scenariominer.cli import app as root_app
from scenariominer.eval.mining import (
    BinaryCounts,
    MiningEvaluationError,
    decision_counts,
    evaluate_mining,
    evaluate_mining_files,
)

LOG = "3b3570b4-7b0b-3268-a571-b0889dbf40b6"
PROMPT = "vehicle with a bicycle to its right"


def frame(t_ns: int, labels: list[int]) -> dict[str, Any]:
    n = len(labels)
    return {
        "timestamp_ns": t_ns,
        "label": np.array(labels, dtype=np.int32),
        "name": np.array(["REFERRED_OBJECT" if x == 0 else "OTHER_OBJECT" for x in labels]),
        "track_id": np.arange(n, dtype=np.int32),
        "translation_m": np.zeros((n, 3)),
        "size": np.ones((n, 3), dtype=np.float32),
        "yaw": np.zeros(n, dtype=np.float32),
        "score": np.ones(n, dtype=np.float32),
        "ego_translation_m": [0.0, 0.0, 0.0],
    }


def seq(pattern: str) -> list[dict[str, Any]]:
    """Frames from a string: '1' = a referred object present, '0' = none."""
    return [frame(i, [0, 2] if c == "1" else [2, 2]) for i, c in enumerate(pattern)]


# ---------------------------------------------------------------------- F1 and balanced accuracy


def test_binary_counts_scores() -> None:
    c = BinaryCounts(tp=3, fp=1, fn=2, tn=4)
    assert c.f1 == pytest.approx(6 / 9)
    assert c.balanced_accuracy == pytest.approx((3 / 5 + 4 / 5) / 2)
    assert BinaryCounts(0, 0, 0, 5).f1 == 1.0  # nothing to find, nothing found
    assert BinaryCounts(0, 0, 4, 5).f1 == 0.0  # an empty answer finds nothing
    assert BinaryCounts(0, 0, 4, 5).balanced_accuracy == 0.5
    assert BinaryCounts(1, 2, 3, 4) + BinaryCounts(1, 1, 1, 1) == BinaryCounts(2, 3, 4, 5)


def test_decisions_are_counted_per_timestamp_and_per_log_over_the_predicted_pairs() -> None:
    gt = {("a", "p"): seq("0110"), ("b", "p"): seq("0000"), ("c", "p"): seq("1111")}
    pred = {("a", "p"): seq("0011"), ("b", "p"): seq("0100")}  # ("c", "p") is not evaluated
    ts, logs = decision_counts(pred, gt)
    assert ts == BinaryCounts(tp=1, fp=2, fn=1, tn=4)
    assert logs == BinaryCounts(tp=1, fp=1, fn=0, tn=0)
    assert ts.f1 == pytest.approx(2 / 5)


def test_ambiguous_ground_truth_frames_are_skipped() -> None:
    gt = {("a", "p"): seq("011")}
    gt[("a", "p")][0]["is_positive"] = None
    ts, _ = decision_counts({("a", "p"): seq("111")}, gt)
    assert ts == BinaryCounts(tp=2, fp=0, fn=0, tn=0)


# ---------------------------------------------------------------------- refused before evaluating


@pytest.mark.parametrize(
    ("pred", "message"),
    [
        ({}, "holds no"),
        ({("x", "p"): seq("01")}, "not in the ground truth"),
        ({("a", "p"): seq("0")}, "has 1 frames but the ground truth 2"),
        ({("a", "p"): [frame(5, [2]), frame(1, [2])]}, "frame 0 is at 5 ns"),
    ],
)
def test_misaligned_predictions_are_refused_with_the_cause(pred: dict[Any, Any], message: str) -> None:
    with pytest.raises(MiningEvaluationError, match=message):
        evaluate_mining(pred, {("a", "p"): seq("01")}, None)


def test_a_frame_without_scores_is_refused() -> None:
    pred = {("a", "p"): seq("01")}
    del pred[("a", "p")][1]["score"]
    with pytest.raises(MiningEvaluationError, match="frame 1 has no 'score'"):
        evaluate_mining(pred, {("a", "p"): seq("01")}, None)


def test_missing_map_folder_is_named(tmp_path: Path) -> None:
    with pytest.raises(MiningEvaluationError, match="has no a/map"):
        evaluate_mining({("a", "p"): seq("01")}, {("a", "p"): seq("01")}, tmp_path)


def test_unreadable_files_are_reported(tmp_path: Path) -> None:
    bad = tmp_path / "bad.pkl"
    bad.write_bytes(pickle.dumps([1]))
    with pytest.raises(MiningEvaluationError, match="expected a dict"):
        evaluate_mining_files(bad, bad, None)


# ---------------------------------------------------------------------- the official evaluator


@pytest.fixture(scope="module")
def gt(av2_gt_pkl: Path) -> dict[tuple[str, str], list[dict[str, Any]]]:
    data: dict[tuple[str, str], list[dict[str, Any]]] = pickle.loads(av2_gt_pkl.read_bytes())
    return data


def with_scores(frames: list[dict[str, Any]]) -> list[dict[str, Any]]:
    out = copy.deepcopy(frames)
    for f in out:
        f["score"] = np.ones(len(f["label"]), dtype=np.float32)
    return out


@pytest.mark.slow  # imports av2's evaluator (torch) and runs TrackEval twice (~10-20 s)
def test_a_perfect_prediction_scores_one_everywhere(
    gt: dict[Any, Any], av2_log_dir: Path, capfd: pytest.CaptureFixture[str]
) -> None:
    import tqdm  # noqa: F401 - imported first (as the embedder does), TQDM_DISABLE no longer counts

    pred = {k: with_scores(v) for k, v in gt.items()}
    # a ground-truth pair the prediction does not contain is not evaluated
    gt_more = {**gt, (LOG, "bus in the bike lane"): with_scores(gt[(LOG, PROMPT)])}
    capfd.readouterr()
    ev = evaluate_mining(pred, gt_more, av2_log_dir.parent)
    assert "track score thresholds" not in capfd.readouterr().err  # the evaluator's progress bars
    assert (ev.hota_temporal, ev.hota_track) == pytest.approx((1.0, 1.0))
    assert (ev.timestamp_balanced_accuracy, ev.log_balanced_accuracy) == pytest.approx((1.0, 1.0))
    assert (ev.timestamp_f1, ev.log_f1) == (1.0, 1.0)
    assert ev.pairs == ((LOG, PROMPT),)
    assert ev.timestamp_counts.fp == ev.timestamp_counts.fn == 0 and ev.timestamp_counts.tp > 0


@pytest.mark.slow
def test_an_empty_prediction_scores_zero_and_one_half(gt: dict[Any, Any], av2_log_dir: Path) -> None:
    pred = {k: with_scores(v) for k, v in gt.items()}
    for frames in pred.values():
        for f in frames:
            f["label"] = np.full(len(f["label"]), 2, dtype=np.int32)
            f["name"] = np.full(len(f["label"]), "OTHER_OBJECT")
    ev = evaluate_mining(pred, gt, av2_log_dir.parent)
    assert (ev.hota_temporal, ev.hota_track) == pytest.approx((0.0, 0.0))
    assert (ev.timestamp_balanced_accuracy, ev.log_balanced_accuracy) == pytest.approx((0.5, 0.5))
    assert (ev.timestamp_f1, ev.log_f1) == (0.0, 0.0)
    assert ev.timestamp_counts.tp == 0 and ev.timestamp_counts.fn > 0


# ---------------------------------------------------------------------- the eval mining command


@pytest.fixture(scope="module")
def cli() -> typer.Typer:
    return root_app


def test_eval_mining_command_reports_bad_input(cli: typer.Typer, tmp_path: Path) -> None:
    res = CliRunner().invoke(
        cli, ["eval", "mining", "--pred", str(tmp_path / "p.pkl"), "--gt", str(tmp_path / "g.pkl")]
    )
    assert res.exit_code == 2 and "cannot read the pickle" in res.output


@pytest.mark.slow
def test_eval_mining_command_prints_the_scores(
    cli: typer.Typer, gt: dict[Any, Any], av2_gt_pkl: Path, av2_log_dir: Path, tmp_path: Path
) -> None:
    pred_path = tmp_path / "pred.pkl"
    pred_path.write_bytes(pickle.dumps({k: with_scores(v) for k, v in gt.items()}))
    args = [
        "eval",
        "mining",
        "--pred",
        str(pred_path),
        "--gt",
        str(av2_gt_pkl),
        "--dataset-dir",
        str(av2_log_dir.parent),
    ]
    res = CliRunner().invoke(cli, args)
    assert res.exit_code == 0, res.output
    for name in ("HOTA-Temporal", "HOTA-Track", "timestamp balanced accuracy", "log F1"):
        assert name in res.output
    assert "1.000" in res.output
