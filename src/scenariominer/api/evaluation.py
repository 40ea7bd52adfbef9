"""Use cases ``eval braking`` and ``eval mining``: score stored results against labels."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from scenariominer.config import Config
from scenariominer.errors import ConfigError
from scenariominer.eval.braking import BrakingEvaluation, read_labels
from scenariominer.eval.braking import evaluate_braking as _evaluate_braking
from scenariominer.eval.mining import MiningEvaluation, evaluate_mining_files
from scenariominer.explain.categories import CategorySet, load_categories
from scenariominer.explain.judge import Judge, rejudge_events
from scenariominer.explain.search import load_events
from scenariominer.llm.factory import make_chat_client, make_embedder
from scenariominer.llm.usage import UsageCounter
from scenariominer.progress import NullProgress, Progress, step
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
        judges: further judges to score side by side with the stored one (``llm``, ``hybrid``):
            each re-judges the stored events from their stored facts with the configured model
            (answers the response cache holds are free).
    """

    labels: Path
    categories_file: Path | None = None
    retrieval: bool = True
    complete_only: bool = False
    judges: tuple[str, ...] = ()


def evaluate_braking(
    store: ScenarioStore,
    request: BrakingEvalRequest,
    config: Config,
    progress: Progress | None = None,
    usage: UsageCounter | None = None,
) -> BrakingEvaluation:
    """KeyIdent recall, baseline vs LLM per category, text retrieval (the paper's Tables IV-VI).

    Raises:
        EvaluationError: an unusable label file.
        ExplainError: unusable category file, or no analysed events.
        LLMError, EmbeddingMismatchError: embedder problems.
    """
    rows = read_labels(request.labels)
    categories = load_categories(request.categories_file or config.explain.categories_file)
    embedder = make_embedder(config) if request.retrieval else None
    extra = _rejudge(store, request, config, categories, progress, usage) if request.judges else {}
    return _evaluate_braking(
        store,
        rows,
        embedder,
        categories=categories,
        only_complete=request.complete_only,
        extra_judges=extra,
    )


def _rejudge(
    store: ScenarioStore,
    request: BrakingEvalRequest,
    config: Config,
    categories: CategorySet,
    progress: Progress | None,
    usage: UsageCounter | None,
) -> dict[str, dict[str, str]]:
    try:
        judges = [Judge(j) for j in request.judges]
    except ValueError:
        raise ConfigError(
            f"judges must be among {[j.value for j in Judge]}, got {list(request.judges)}"
        ) from None
    events = load_events(store)
    stored = set(events.column("judge").to_pylist()) if "judge" in events.column_names else set()
    todo = [j for j in judges if j is not Judge.RULES and j.value not in stored]
    if not todo:
        return {}
    progress = progress or NullProgress()
    client = make_chat_client(config, usage=usage)
    out: dict[str, dict[str, str]] = {}
    try:
        for judge in todo:
            with step(progress, f"judge ({judge.value})", events.num_rows):
                out[judge.value] = rejudge_events(
                    events,
                    client,
                    categories,
                    judge,
                    max_tokens=config.explain.llm_max_tokens,
                    on_event=lambda _c: progress.advance(1),
                )
    finally:
        client.close()
    return out


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
