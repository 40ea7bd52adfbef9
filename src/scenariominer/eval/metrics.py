"""Retrieval metrics: precision, recall and F1 over sets, precision at k and recall at k.

Every function is pure and generic in the item type (here ``(log_id, guest_id)`` pairs). An
undefined ratio (no retrieved item for precision, no relevant item for recall) is NaN, so a
table can print "-" instead of a misleading 0.
"""

from __future__ import annotations

import math
from collections.abc import Collection, Hashable, Iterable, Mapping, Sequence
from dataclasses import dataclass
from typing import TypeVar

__all__ = ["PRF", "category_prf", "micro_prf", "precision_at_k", "prf", "recall_at_k"]

K = TypeVar("K", bound=Hashable)


@dataclass(frozen=True)
class PRF:
    """Counts and scores of one retrieval.

    Attributes:
        tp: retrieved and relevant.
        fp: retrieved, not relevant.
        fn: relevant, not retrieved.
    """

    tp: int
    fp: int
    fn: int

    @property
    def precision(self) -> float:
        """``tp / (tp + fp)``; NaN when nothing was retrieved."""
        return self.tp / (self.tp + self.fp) if self.tp + self.fp else math.nan

    @property
    def recall(self) -> float:
        """``tp / (tp + fn)``; NaN when nothing is relevant."""
        return self.tp / (self.tp + self.fn) if self.tp + self.fn else math.nan

    @property
    def f1(self) -> float:
        """Harmonic mean of precision and recall; NaN when either is undefined, 0 when both are 0."""
        p, r = self.precision, self.recall
        if math.isnan(p) or math.isnan(r):
            return math.nan
        return 2 * p * r / (p + r) if p + r > 0 else 0.0


def prf(retrieved: Collection[K], relevant: Collection[K]) -> PRF:
    """Precision/recall counts of a retrieved set against a relevant set."""
    got, want = set(retrieved), set(relevant)
    return PRF(tp=len(got & want), fp=len(got - want), fn=len(want - got))


def category_prf(truth: Mapping[K, str], predicted: Mapping[K, Collection[str]], category: str) -> PRF:
    """Scores of retrieving ``category``: items predicted as it against items labelled as it.

    Args:
        truth: the labelled category of each labelled item.
        predicted: the categories predicted for each item (an item with several events may
            have several); items missing from ``truth`` are not of any category.
        category: the category to score.
    """
    relevant = [k for k, c in truth.items() if c == category]
    retrieved = [k for k, cats in predicted.items() if category in cats]
    return prf(retrieved, relevant)


def micro_prf(parts: Iterable[PRF]) -> PRF:
    """Micro average: the sums of the counts."""
    tp = fp = fn = 0
    for p in parts:
        tp, fp, fn = tp + p.tp, fp + p.fp, fn + p.fn
    return PRF(tp, fp, fn)


def precision_at_k(ranked: Sequence[K], relevant: Collection[K], k: int) -> float:
    """Fraction of the first ``k`` ranked items that are relevant (divided by ``k``).

    Raises:
        ValueError: ``k < 1``.
    """
    if k < 1:
        raise ValueError(f"k must be at least 1, got {k}")
    want = set(relevant)
    return sum(1 for item in ranked[:k] if item in want) / k


def recall_at_k(ranked: Sequence[K], relevant: Collection[K], k: int) -> float:
    """Fraction of the relevant items found among the first ``k`` ranked items; NaN if none is relevant.

    Raises:
        ValueError: ``k < 1``.
    """
    if k < 1:
        raise ValueError(f"k must be at least 1, got {k}")
    want = set(relevant)
    if not want:
        return math.nan
    return len(want & set(ranked[:k])) / len(want)
