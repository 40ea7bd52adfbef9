"""Use cases ``eval braking`` and ``eval mining``: score stored results against labels."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from scenariominer.config import Config
from scenariominer.eval.braking import BrakingEvaluation, read_labels
from scenariominer.eval.braking import evaluate_braking as _evaluate_braking
from scenariominer.eval.mining import MiningEvaluation, evaluate_mining_files
from scenariominer.explain.categories import load_categories
from scenariominer.llm.factory import make_embedder
from scenariominer.store import ScenarioStore

__all__ = ["BrakingEvalRequest", "MiningEvalRequest", "evaluate_braking", "evaluate_mining"]


@dataclass(frozen=True)
class BrakingEvalRequest:
    """Labels to score the store's braking events against.

    Attributes:
        labels: CSV with ``log_id, guest_id, scenario_category``.
        categories_file: the categories the store was analysed with (default: the configured ones).
        retrieval: also evaluate free-text retrieval (loads the embedder).
        complete_only: score only logs whose events all have an LLM answer.
    """

    labels: Path
    categories_file: Path | None = None
    retrieval: bool = True
    complete_only: bool = False


def evaluate_braking(store: ScenarioStore, request: BrakingEvalRequest, config: Config) -> BrakingEvaluation:
    """KeyIdent recall, baseline vs LLM per category, text retrieval (the paper's Tables IV-VI).

    Raises:
        EvaluationError: an unusable label file.
        ExplainError: unusable category file, or no analysed events.
        LLMError, EmbeddingMismatchError: embedder problems.
    """
    rows = read_labels(request.labels)
    categories = load_categories(request.categories_file or config.explain.categories_file)
    embedder = make_embedder(config) if request.retrieval else None
    return _evaluate_braking(
        store, rows, embedder, categories=categories, only_complete=request.complete_only
    )


@dataclass(frozen=True)
class MiningEvalRequest:
    """A scenario-mining prediction pickle and its ground truth (Argoverse 2 layout)."""

    pred: Path
    gt: Path
    dataset_dir: Path | None = None
    max_range_m: int = 50
    out_dir: Path | None = None


def evaluate_mining(request: MiningEvalRequest) -> MiningEvaluation:
    """The official Argoverse 2 scores plus timestamp and log F1.

    Raises:
        EvaluationError: unreadable pickles, mismatched frames, or the evaluator is not installed.
    """
    return evaluate_mining_files(
        request.pred,
        request.gt,
        request.dataset_dir,
        max_range_m=request.max_range_m,
        out_dir=request.out_dir,
    )
