"""Retrieval metrics on small hand-made sets with known answers."""

from __future__ import annotations

import math

import pytest

from scenariominer.eval.metrics import PRF, category_prf, micro_prf, precision_at_k, prf, recall_at_k


def test_prf_counts_and_scores() -> None:
    s = prf(retrieved=["a", "b", "c", "d"], relevant=["b", "d", "e"])
    assert (s.tp, s.fp, s.fn) == (2, 2, 1)
    assert s.precision == pytest.approx(0.5)
    assert s.recall == pytest.approx(2 / 3)
    assert s.f1 == pytest.approx(2 * 0.5 * (2 / 3) / (0.5 + 2 / 3))


def test_undefined_scores_are_nan_and_zero_scores_zero() -> None:
    nothing_retrieved = PRF(tp=0, fp=0, fn=3)
    assert math.isnan(nothing_retrieved.precision) and nothing_retrieved.recall == 0.0
    assert math.isnan(nothing_retrieved.f1)
    nothing_relevant = PRF(tp=0, fp=2, fn=0)
    assert nothing_relevant.precision == 0.0 and math.isnan(nothing_relevant.recall)
    all_wrong = PRF(tp=0, fp=2, fn=2)
    assert all_wrong.f1 == 0.0


def test_category_prf_with_multi_category_predictions() -> None:
    truth = {"p1": "cut_in", "p2": "cut_in", "p3": "obj_crossing", "p4": "not_relevant"}
    predicted = {"p1": ["cut_in"], "p2": ["obj_crossing", "cut_in"], "p3": ["cut_in"], "x": ["cut_in"]}
    cut_in = category_prf(truth, predicted, "cut_in")
    assert (cut_in.tp, cut_in.fp, cut_in.fn) == (2, 2, 0)
    crossing = category_prf(truth, predicted, "obj_crossing")
    assert (crossing.tp, crossing.fp, crossing.fn) == (0, 1, 1)
    total = micro_prf([cut_in, crossing])
    assert (total.tp, total.fp, total.fn) == (2, 3, 1)
    assert total.precision == pytest.approx(0.4) and total.recall == pytest.approx(2 / 3)


def test_precision_and_recall_at_k() -> None:
    ranked = ["r1", "x1", "r2", "x2", "x3", "r3"]
    relevant = {"r1", "r2", "r3", "r4"}
    assert precision_at_k(ranked, relevant, 2) == pytest.approx(0.5)
    assert precision_at_k(ranked, relevant, 10) == pytest.approx(0.3)  # divided by k, not by 6
    assert recall_at_k(ranked, relevant, 3) == pytest.approx(0.5)
    assert recall_at_k(ranked, relevant, 50) == pytest.approx(0.75)
    assert math.isnan(recall_at_k(ranked, set(), 5))
    with pytest.raises(ValueError, match="k must"):
        precision_at_k(ranked, relevant, 0)
