"""Scenario-mining evaluation with the official Argoverse 2 evaluator, plus the paper's F1 scores.

:func:`evaluate_mining` runs ``av2.evaluation.scenario_mining.eval.evaluate`` (``av2==0.3.6``;
install with ``pip install 'scenariominer[av2eval]'``) on the (log, description) pairs present
in the prediction file and returns

* HOTA-Temporal (tracking of the referred objects at the timestamps the description holds),
* HOTA-Track (tracking of every referred track over its whole life),
* timestamp-level and log-level balanced accuracy, as av2 0.3.6 reports them, and
* timestamp-level and log-level F1, which the paper reports instead: every evaluation timestamp
  (or log) is a binary decision "some object is referred", compared between prediction and
  ground truth after the evaluator's own filters (boxes beyond ``max_range_m`` of the ego and
  outside the map's region of interest are dropped), with TP/FP/FN pooled over all pairs.

The evaluator matches frames by position, so every evaluated key must have the ground truth's
frames in the same order; :func:`evaluate_mining` checks that first and names the first
mismatch. Importing av2's evaluator patches ``numpy`` (it re-adds ``np.float``/``np.int``/
``np.bool`` for TrackEval) and selects matplotlib's ``Agg`` backend; this happens on the first
evaluation only, never on importing this module.
"""

from __future__ import annotations

import ast
import contextlib
import copy
import io
import math
import os
import warnings
from collections.abc import Iterator, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from scenariominer import errors as _errors
from scenariominer.mine.export import ObjectLabel, SubmissionFormatError, read_av2_submission

__all__ = [
    "INSTALL_AV2EVAL_HINT",
    "BinaryCounts",
    "MiningEvaluation",
    "MiningEvaluationError",
    "decision_counts",
    "evaluate_mining",
    "evaluate_mining_files",
]

INSTALL_AV2EVAL_HINT = "pip install 'scenariominer[av2eval]'"
_REFERRED = int(ObjectLabel.REFERRED)

Submission = Mapping[tuple[str, str], list[dict[str, Any]]]


class MiningEvaluationError(_errors.EvaluationError):
    """The prediction cannot be evaluated against the ground truth; the message says why."""


@dataclass(frozen=True)
class BinaryCounts:
    """Confusion counts of binary decisions (timestamps or logs containing the scenario).

    Attributes:
        tp: predicted and true.
        fp: predicted, not true.
        fn: true, not predicted.
        tn: neither.
    """

    tp: int
    fp: int
    fn: int
    tn: int

    @property
    def f1(self) -> float:
        """``2 tp / (2 tp + fp + fn)``; 1.0 when there is no positive on either side (nothing to find)."""
        denom = 2 * self.tp + self.fp + self.fn
        return 2 * self.tp / denom if denom else 1.0

    @property
    def balanced_accuracy(self) -> float:
        """Mean of true-positive and true-negative rate; an undefined rate counts as 1 (as av2 does)."""
        tpr = self.tp / (self.tp + self.fn) if self.tp + self.fn else 1.0
        tnr = self.tn / (self.tn + self.fp) if self.tn + self.fp else 1.0
        return (tpr + tnr) / 2

    def __add__(self, other: BinaryCounts) -> BinaryCounts:
        return BinaryCounts(self.tp + other.tp, self.fp + other.fp, self.fn + other.fn, self.tn + other.tn)


@dataclass(frozen=True)
class MiningEvaluation:
    """Scores of a scenario-mining prediction.

    Attributes:
        hota_temporal: HOTA of the referred objects at the timestamps the description holds.
        hota_track: HOTA of the referred objects over their whole tracks.
        timestamp_balanced_accuracy: official timestamp-level balanced accuracy (per-description mean).
        log_balanced_accuracy: official log-level balanced accuracy (per-description mean).
        timestamp_f1: F1 of the per-timestamp "scenario present" decisions, pooled over pairs.
        log_f1: F1 of the per-log decisions, pooled over pairs.
        timestamp_counts: the confusion counts behind ``timestamp_f1``.
        log_counts: the confusion counts behind ``log_f1``.
        pairs: the (log_id, description) pairs evaluated.
    """

    hota_temporal: float
    hota_track: float
    timestamp_balanced_accuracy: float
    log_balanced_accuracy: float
    timestamp_f1: float
    log_f1: float
    timestamp_counts: BinaryCounts
    log_counts: BinaryCounts
    pairs: tuple[tuple[str, str], ...]

    def as_dict(self) -> dict[str, Any]:
        """Plain-JSON form (counts as dicts)."""
        return {
            "hota_temporal": self.hota_temporal,
            "hota_track": self.hota_track,
            "timestamp_balanced_accuracy": self.timestamp_balanced_accuracy,
            "log_balanced_accuracy": self.log_balanced_accuracy,
            "timestamp_f1": self.timestamp_f1,
            "log_f1": self.log_f1,
            "timestamp_counts": self.timestamp_counts.__dict__,
            "log_counts": self.log_counts.__dict__,
            "pairs": [list(p) for p in self.pairs],
        }


def _frame_positive(frame: Mapping[str, Any]) -> bool | None:
    """Whether a frame contains the scenario; ``None`` for a frame the GT marks ambiguous."""
    if "is_positive" in frame:
        value = frame["is_positive"]
        return None if value is None else bool(value)
    labels = np.asarray(frame.get("label", ()))
    return bool(labels.size and np.any(labels == _REFERRED))


def decision_counts(predictions: Submission, ground_truth: Submission) -> tuple[BinaryCounts, BinaryCounts]:
    """Timestamp-level and log-level confusion counts, pooled over the prediction's keys.

    A frame (timestamp) is positive when it has a referred box (or ``is_positive``); a log is
    positive when any of its frames is. Frames the ground truth marks ambiguous
    (``is_positive = None``) are skipped, as the official evaluator does.

    Raises:
        MiningEvaluationError: a key is missing from the ground truth or frame counts differ.
    """
    ts = BinaryCounts(0, 0, 0, 0)
    logs = BinaryCounts(0, 0, 0, 0)
    for key, pred_frames in predictions.items():
        if key not in ground_truth:
            raise MiningEvaluationError(f"{key!r} is not in the ground truth")
        gt_frames = ground_truth[key]
        if len(gt_frames) != len(pred_frames):
            raise MiningEvaluationError(
                f"{key!r}: the prediction has {len(pred_frames)} frames, the ground truth {len(gt_frames)}"
            )
        truth = [_frame_positive(f) for f in gt_frames]
        pred = [bool(_frame_positive(f)) for f in pred_frames]
        keep = [t is not None for t in truth]
        if not any(keep):
            continue
        t_arr = np.array([bool(t) for t, k in zip(truth, keep, strict=True) if k])
        p_arr = np.array([p for p, k in zip(pred, keep, strict=True) if k])
        ts = ts + BinaryCounts(
            int(np.sum(t_arr & p_arr)),
            int(np.sum(~t_arr & p_arr)),
            int(np.sum(t_arr & ~p_arr)),
            int(np.sum(~t_arr & ~p_arr)),
        )
        t_log, p_log = bool(t_arr.any()), bool(any(pred))
        logs = logs + BinaryCounts(
            int(t_log and p_log),
            int(p_log and not t_log),
            int(t_log and not p_log),
            int(not t_log and not p_log),
        )
    return ts, logs


def _check_alignment(predictions: Submission, ground_truth: Submission) -> None:
    for key, frames in predictions.items():
        if key not in ground_truth:
            raise MiningEvaluationError(
                f"the prediction's pair {key!r} is not in the ground truth; evaluate only pairs the ground "
                "truth covers"
            )
        gt_frames = ground_truth[key]
        if len(frames) != len(gt_frames):
            raise MiningEvaluationError(
                f"{key!r}: the prediction has {len(frames)} frames but the ground truth {len(gt_frames)}; "
                "export one frame per evaluation timestamp (see scenariominer.mine.export)"
            )
        for i, (p, g) in enumerate(zip(frames, gt_frames, strict=True)):
            if int(p["timestamp_ns"]) != int(g["timestamp_ns"]):
                raise MiningEvaluationError(
                    f"{key!r}: frame {i} is at {int(p['timestamp_ns'])} ns, the ground truth's at "
                    f"{int(g['timestamp_ns'])} ns; frames must be in the ground truth's order"
                )
            for name in ("score", "name", "track_id", "label", "translation_m"):
                if name not in p:
                    raise MiningEvaluationError(
                        f"{key!r}: frame {i} has no '{name}' (the evaluator needs it)"
                    )


@contextlib.contextmanager
def _quiet_evaluator() -> Iterator[None]:
    """Silence the evaluator's progress bars and third-party warnings for the duration.

    ``TQDM_DISABLE`` only counts when tqdm is first imported (another library may have imported it
    already: the embedder does), so the bars, which tqdm writes to ``sys.stderr``, are also sent
    to a discarded buffer. The evaluator reports failures by raising, never on stderr alone.
    """
    previous = os.environ.get("TQDM_DISABLE")
    os.environ["TQDM_DISABLE"] = "1"
    try:
        with warnings.catch_warnings(), contextlib.redirect_stderr(io.StringIO()):
            warnings.simplefilter("ignore")
            yield
    finally:
        if previous is None:
            os.environ.pop("TQDM_DISABLE", None)
        else:
            os.environ["TQDM_DISABLE"] = previous


def _import_av2_eval() -> Any:
    try:
        with _quiet_evaluator():
            from av2.evaluation.scenario_mining import eval as av2_eval
    except ImportError as exc:
        raise MiningEvaluationError(
            f"the official Argoverse 2 evaluator is not installed ({exc}); run: {INSTALL_AV2EVAL_HINT}"
        ) from None
    return av2_eval


def evaluate_mining(
    predictions: Submission,
    ground_truth: Submission,
    dataset_dir: str | Path | None,
    *,
    max_range_m: int = 50,
    objective_metric: str = "HOTA",
    out_dir: str | Path | None = None,
) -> MiningEvaluation:
    """Score a prediction with the official evaluator on the pairs it contains.

    Args:
        predictions: ``{(log_id, description): [frame, ...]}`` (see :mod:`scenariominer.mine.export`).
        ground_truth: the same layout with the true labels; pairs absent from ``predictions``
            are ignored.
        dataset_dir: folder holding ``<log_id>/map`` and ``<log_id>/city_SE3_egovehicle.feather``
            for the region-of-interest filter; ``None`` skips that filter.
        max_range_m: boxes farther than this from the ego are not evaluated (the benchmark uses 50).
        objective_metric: ``"HOTA"`` (or ``"MOTA"``) for the evaluator's score-threshold tuning.
        out_dir: where the evaluator writes its JSON metrics and confusion plots; ``None`` writes nothing.

    Raises:
        MiningEvaluationError: no pairs, a pair missing from the ground truth, misaligned frames,
            a missing per-box key, a missing dataset folder, or av2 not installed.
    """
    if not predictions:
        raise MiningEvaluationError("the prediction holds no (log_id, description) pair")
    _check_alignment(predictions, ground_truth)
    if dataset_dir is not None:
        root = Path(dataset_dir)
        for log_id, _ in predictions:
            if not (root / log_id / "map").is_dir():
                raise MiningEvaluationError(
                    f"dataset folder {root} has no {log_id}/map (needed for the region-of-interest filter)"
                )
    av2_eval = _import_av2_eval()
    pred = copy.deepcopy({k: list(v) for k, v in predictions.items()})
    gt = copy.deepcopy({k: list(ground_truth[k]) for k in predictions})
    data_dir = None if dataset_dir is None else str(dataset_dir)
    out = None if out_dir is None else str(out_dir)
    with _quiet_evaluator():
        hota_t, hota, ts_ba, log_ba = av2_eval.evaluate(
            copy.deepcopy(pred), copy.deepcopy(gt), objective_metric, max_range_m, data_dir, out
        )
        # the paper's F1 scores, on the boxes the evaluator itself keeps
        pred_f = av2_eval.filter_max_dist(av2_eval.relabel_sequence_ids(pred), max_range_m)
        gt_f = av2_eval.filter_max_dist(av2_eval.relabel_sequence_ids(gt), max_range_m)
        if data_dir is not None:
            pred_f = av2_eval.filter_drivable_area(pred_f, data_dir)
            gt_f = av2_eval.filter_drivable_area(gt_f, data_dir)
    ts_counts, log_counts = decision_counts(_as_tuple_keys(pred_f), _as_tuple_keys(gt_f))
    return MiningEvaluation(
        hota_temporal=float(hota_t),
        hota_track=float(hota),
        timestamp_balanced_accuracy=float(ts_ba),
        log_balanced_accuracy=float(log_ba),
        timestamp_f1=ts_counts.f1,
        log_f1=log_counts.f1,
        timestamp_counts=ts_counts,
        log_counts=log_counts,
        pairs=tuple(predictions),
    )


def _as_tuple_keys(
    sequences: Mapping[Any, list[dict[str, Any]]],
) -> dict[tuple[str, str], list[dict[str, Any]]]:
    """Undo av2's ``str((log_id, prompt))`` keys (its frames keep the original ``seq_id`` strings)."""
    out: dict[tuple[str, str], list[dict[str, Any]]] = {}
    for key, frames in sequences.items():
        if isinstance(key, tuple):
            out[key] = frames
            continue
        try:
            parsed = ast.literal_eval(str(key))  # av2 keys are str((log_id, prompt))
        except (ValueError, SyntaxError):
            parsed = None
        if not (isinstance(parsed, tuple) and len(parsed) == 2):
            raise MiningEvaluationError(f"unexpected sequence id {key!r} from the evaluator")
        out[(str(parsed[0]), str(parsed[1]))] = frames
    return out


def evaluate_mining_files(
    pred_path: str | Path,
    gt_path: str | Path,
    dataset_dir: str | Path | None,
    *,
    max_range_m: int = 50,
    out_dir: str | Path | None = None,
) -> MiningEvaluation:
    """:func:`evaluate_mining` on two pickles (prediction, ground truth).

    Raises:
        MiningEvaluationError: as :func:`evaluate_mining`, or a pickle with the wrong layout.
    """
    try:
        pred = read_av2_submission(pred_path)
        gt = read_av2_submission(gt_path)
    except SubmissionFormatError as exc:
        raise MiningEvaluationError(str(exc)) from None
    if math.isnan(float(max_range_m)) or max_range_m <= 0:
        raise MiningEvaluationError(f"max_range_m must be > 0, got {max_range_m}")
    return evaluate_mining(pred, gt, dataset_dir, max_range_m=max_range_m, out_dir=out_dir)
