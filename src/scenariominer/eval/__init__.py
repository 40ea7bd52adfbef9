"""Evaluation of the pipelines against labelled data (braking paper, section V)."""

from scenariominer.eval.braking import (
    OOD_QUERIES,
    BrakingEvaluation,
    Label,
    LabelFileError,
    evaluate_braking,
    read_labels,
)
from scenariominer.eval.metrics import PRF, category_prf, micro_prf, precision_at_k, prf, recall_at_k

__all__ = [
    "OOD_QUERIES",
    "PRF",
    "BrakingEvaluation",
    "Label",
    "LabelFileError",
    "category_prf",
    "evaluate_braking",
    "micro_prf",
    "precision_at_k",
    "prf",
    "read_labels",
    "recall_at_k",
]
