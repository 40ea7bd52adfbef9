"""Use cases ``eval braking``, ``eval mining`` and ``eval nl2prog``: score results against labels."""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from pathlib import Path

from scenariominer.config import Config
from scenariominer.errors import ConfigError, EvaluationError, ExplainError
from scenariominer.eval.braking import BrakingEvaluation, read_labels
from scenariominer.eval.braking import evaluate_braking as _evaluate_braking
from scenariominer.eval.mining import MiningEvaluation, evaluate_mining_files
from scenariominer.eval.nl2prog import CandidateProvider, Nl2ProgEvaluation, generator_provider, load_eval_set
from scenariominer.eval.nl2prog import evaluate_nl2prog as _evaluate_nl2prog
from scenariominer.explain.categories import CategorySet, load_categories
from scenariominer.explain.judge import Judge, rejudge_events
from scenariominer.explain.search import load_events
from scenariominer.llm.factory import make_chat_client, make_embedder
from scenariominer.llm.usage import UsageCounter
from scenariominer.progress import NullProgress, Progress, step
from scenariominer.store import ScenarioStore

__all__ = [
    "BrakingEvalRequest",
    "BrakingSet",
    "MiningEvalRequest",
    "Nl2ProgEvalRequest",
    "evaluate_braking",
    "evaluate_braking_sets",
    "evaluate_mining",
    "evaluate_nl2prog",
]


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
        methods: also give KeyIdent recall of every key-object method (``tags``,
            ``counterfactual``, ``combined``) on the same logs, and per ``noise_level`` when the
            labels have that column (the logs are tagged again; no LLM).
    """

    labels: Path
    categories_file: Path | None = None
    retrieval: bool = True
    complete_only: bool = False
    judges: tuple[str, ...] = ()
    methods: bool = True


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
    ev = _evaluate_braking(
        store,
        rows,
        embedder,
        categories=categories,
        only_complete=request.complete_only,
        extra_judges=extra,
    )
    if not request.methods:
        return ev
    from scenariominer.eval.braking_methods import keyident_by_method, read_noise_levels

    by_method = keyident_by_method(store, rows, config, read_noise_levels(request.labels))
    return dataclasses.replace(ev, by_method=tuple(by_method))


@dataclass(frozen=True)
class BrakingSet:
    """One labelled set of a side-by-side braking evaluation.

    Attributes:
        name: the set's name in the report (e.g. ``tune``, ``sumo``).
        store: the store its logs were ingested into and analysed in.
        labels: its labels CSV.
    """

    name: str
    store: ScenarioStore
    labels: Path


def evaluate_braking_sets(
    sets: list[BrakingSet],
    request: BrakingEvalRequest,
    config: Config,
    progress: Progress | None = None,
    usage: UsageCounter | None = None,
) -> list[tuple[str, BrakingEvaluation]]:
    """Evaluate several labelled sets with the same settings, for a side-by-side report.

    Each set is scored as by :func:`evaluate_braking` with ``request`` (its ``labels`` replaced
    by the set's), e.g. the tuning split beside a hold-out made by another generator.

    Raises:
        EvaluationError: two sets share a name, or a set's evaluation failed (the message names
            the set and the cause).
    """
    names = [s.name for s in sets]
    if len(set(names)) != len(names):
        raise EvaluationError(f"set names must be unique, got {names}")
    out = []
    for s in sets:
        try:
            ev = evaluate_braking(
                s.store, dataclasses.replace(request, labels=s.labels), config, progress, usage
            )
        except (EvaluationError, ExplainError) as exc:
            raise EvaluationError(f"set {s.name!r}: {exc}") from exc
        out.append((s.name, ev))
    return out


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


@dataclass(frozen=True)
class Nl2ProgEvalRequest:
    """Which descriptions of the description -> program evaluation set to score, on which logs.

    Attributes:
        split: ``holdout`` (default), ``published``, ``challenge``, ``dev`` or ``all``.
        limit: score at most this many descriptions (in set order); ``None`` for all.
        logs: log folders or files (any supported format); default the Argoverse 2 sample log
            beside a source checkout (``../shared/data/av2``).
        without_similar_bank: leave out of each description's few-shot examples the bank entries
            most similar to it (``mining.generation.few_shot_k`` of them), to compare generation
            with and without near-duplicate examples.
    """

    split: str = "holdout"
    limit: int | None = None
    logs: tuple[Path, ...] = ()
    without_similar_bank: bool = False


def evaluate_nl2prog(
    request: Nl2ProgEvalRequest,
    config: Config,
    progress: Progress | None = None,
    usage: UsageCounter | None = None,
    provider: CandidateProvider | None = None,
) -> Nl2ProgEvaluation:
    """Score generated programs against the evaluation set's references (Jaccard of referred cells).

    Args:
        request: split, limit, logs, few-shot variant.
        config: the configuration (model, embedder, mining thresholds, program cache).
        progress: advanced once per description.
        usage: counts model calls and tokens.
        provider: description -> program; default the language-model loop
            (:func:`~scenariominer.eval.nl2prog.generator_provider`: the shipped bank only,
            leave-one-out, holdout never shown), validated on the first
            ``mining.generation.validation_logs`` logs.

    Raises:
        EvaluationError: unknown split, bad limit, malformed set, or no logs to score on.
        DataError: unreadable logs.
        LLMError: the model is missing or failed.
    """
    from scenariominer.api.corpus import find_sample_av2
    from scenariominer.api.mining import load_logs
    from scenariominer.eval.nl2prog import GeneratorProvider
    from scenariominer.mine.context import LogContext
    from scenariominer.mine.loop import ProgramCache
    from scenariominer.mine.plan_reader import rules_plan

    if request.limit is not None and request.limit < 0:
        raise EvaluationError(f"limit must be >= 0, got {request.limit}")
    entries = load_eval_set(request.split)[: request.limit]
    paths = list(request.logs)
    if not paths:
        sample = find_sample_av2()
        if sample is None:
            raise EvaluationError(
                "no logs given and no Argoverse 2 sample log beside the checkout; pass --logs PATH"
            )
        paths = [sample]
    contexts = [LogContext(log, config.mining) for log in load_logs(paths, None, config)]
    if not contexts:
        raise EvaluationError(f"no logs found under {[str(p) for p in paths]}")
    gen = config.mining.generation
    provider_is_the_loop = provider is None
    if provider is None:
        cache = ProgramCache.in_dir(config.llm.cache_dir) if gen.cache_programs else None
        provider = generator_provider(
            contexts[: gen.validation_logs],
            config,
            exclude_most_similar=gen.few_shot_k if request.without_similar_bank else 0,
            cache=cache,
            usage=usage,
        )
    progress = progress or NullProgress()
    reads = gen.plan and gen.plan_rules and gen.plan_program and provider_is_the_loop

    def reader(description: str) -> str:
        # the plan the loop used; another provider (a test's): how the rules alone read it
        if isinstance(provider, GeneratorProvider):
            plan = provider.plan_of(description)
        else:
            plan = rules_plan(description, partial=gen.plan_partial)
        if plan is None or plan.get("read_by") != "rules":
            return "model"
        if plan.get("reworded"):
            return "reworded-partial" if plan.get("unread") else "reworded"
        return "partial" if plan.get("unread") else "rules"

    with step(progress, "descriptions", len(entries)):
        return _evaluate_nl2prog(
            entries,
            contexts,
            provider,
            on_description=lambda s: progress.advance(1, s.description[:48]),
            reader=reader if reads else None,
        )
