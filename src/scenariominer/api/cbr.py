"""Use cases of case-based reasoning for evasive manoeuvres (seed 002).

``cbr add/list/show/remove/build``, ``recommend`` and ``eval cbr``. Each function takes a store,
a typed request and the configuration; nothing here prints.
"""

from __future__ import annotations

import dataclasses
import time
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from scenariominer.cbr.build import BuildReport, build_case_set, read_holdout
from scenariominer.cbr.cases import AddReport, Case, CaseBase, read_case_file
from scenariominer.cbr.plot import plot_rollout
from scenariominer.cbr.query import find_event, query_from_event, scene_of_event
from scenariominer.cbr.recommend import Query, Recommendation, RecommendSettings
from scenariominer.cbr.recommend import recommend as _recommend
from scenariominer.cbr.rollout import RECORDED, RolloutOutcome, rollout
from scenariominer.cbr.vocab import CbrError, load_manoeuvres, load_risk_types
from scenariominer.config import Config
from scenariominer.eval.cbr import (
    EVAL_SCHEMA_VERSION,
    CbrEvaluation,
    default_grid,
    evaluate_cbr_grid,
    plot_evaluation,
)
from scenariominer.llm.factory import make_chat_client, make_embedder
from scenariominer.llm.usage import UsageCounter
from scenariominer.progress import Progress
from scenariominer.store import ScenarioStore

__all__ = [
    "CbrAddRequest",
    "CbrBuildRequest",
    "CbrEvalRequest",
    "RecommendRequest",
    "RecommendResult",
    "cbr_add",
    "cbr_build",
    "cbr_list",
    "cbr_remove",
    "cbr_show",
    "evaluate_cbr",
    "open_case_base",
    "recommend",
]


def open_case_base(store: ScenarioStore, config: Config) -> CaseBase:
    """The case base of ``store`` with the configured vocabularies.

    Raises:
        CbrError: a vocabulary file is unusable.
    """
    cfg = config.cbr
    return CaseBase(
        store, cfg.table, load_risk_types(cfg.risk_types_file), load_manoeuvres(cfg.manoeuvres_file)
    )


@dataclass(frozen=True)
class CbrAddRequest:
    """What to add: cases from a CSV/JSONL file, or one analysed event confirmed with a manoeuvre.

    Attributes:
        file: CSV or JSONL file of cases (docs/cbr.md).
        log_id, event_id: an analysed braking event (``event_id`` as ``scenariominer show`` takes).
        manoeuvre: the confirmed manoeuvre of the event (a configured name or label).
        justification: why it resolves the risk (optional).
        risk_type: override the mapped risk type of the event.
    """

    file: Path | None = None
    log_id: str | None = None
    event_id: str | None = None
    manoeuvre: str | None = None
    justification: str = ""
    risk_type: str | None = None


def _event_case(store: ScenarioStore, request: CbrAddRequest, config: Config, base: CaseBase) -> Case:
    if not request.manoeuvre:
        raise CbrError("adding an event needs the confirmed manoeuvre (--manoeuvre)")
    record = find_event(store, str(request.log_id), request.event_id)
    query = query_from_event(record, config.cbr)
    risk = request.risk_type or query.risk_type
    manoeuvre = request.manoeuvre
    for m in base.manoeuvres.manoeuvres:
        if manoeuvre.lower() == m.label.lower():
            manoeuvre = m.name
    return Case(
        case_id=Case.make_id(risk, query.caption),
        risk_type=risk,
        caption=query.caption,
        road_context="",
        other_vehicle_position="",
        other_vehicle_action=f"{record.guest_category.lower()} ({record.category})",
        event_context=record.explanation or record.llm_description or record.tag_description,
        manoeuvre=manoeuvre,
        justification=request.justification,
        source="event",
        log_id=record.log_id,
        event_id=record.event_id,
        time_s=round((record.closest_ns - record.start_ns) * 1e-9 + record.start_s, 3),
    )


def cbr_add(store: ScenarioStore, request: CbrAddRequest, config: Config) -> AddReport:
    """Store confirmed cases; near-duplicates and bad rows are reported, the rest stored.

    Raises:
        CbrError: neither a file nor an event given, an unreadable file, or an event without manoeuvre.
        ExplainError: the event is not found.
    """
    base = open_case_base(store, config)
    if request.file is not None:
        cases, rejected = read_case_file(request.file, base.manoeuvres)
    elif request.log_id is not None:
        cases, rejected = [_event_case(store, request, config, base)], []
    else:
        raise CbrError("give a case file or an analysed event (--log/--event) to add")
    report = base.add(cases, make_embedder(config), config.cbr.duplicate_threshold)
    return dataclasses.replace(report, rejected=tuple(rejected) + report.rejected)


def cbr_list(store: ScenarioStore, config: Config, risk_type: str | None = None) -> list[Case]:
    """Every stored case (of one risk type), in id order."""
    base = open_case_base(store, config)
    if risk_type is not None:
        base.risk_types.get(risk_type)
    return base.cases(risk_type)


def cbr_show(store: ScenarioStore, config: Config, case_id: str) -> Case:
    """One stored case.

    Raises:
        CbrError: no such case.
    """
    return open_case_base(store, config).get(case_id)


def cbr_remove(store: ScenarioStore, config: Config, case_ids: Sequence[str]) -> int:
    """Delete cases; returns how many existed."""
    return open_case_base(store, config).remove(case_ids)


@dataclass(frozen=True)
class CbrBuildRequest:
    """The synthetic case set: ``per_type`` cases per risk type, ``holdout_per_type`` held out."""

    per_type: int = 110
    holdout_per_type: int = 10
    seed: int = 0


def cbr_build(store: ScenarioStore, request: CbrBuildRequest, config: Config) -> BuildReport:
    """Build the labelled synthetic case set (replaces the case base and its hold-out split).

    Raises:
        CbrError: bad sizes, or a risk type without a scene generator.
    """
    base = open_case_base(store, config)
    return build_case_set(
        base,
        store,
        make_embedder(config),
        per_type=request.per_type,
        holdout_per_type=request.holdout_per_type,
        seed=request.seed,
        threshold=config.cbr.duplicate_threshold,
        max_speed_mps=config.cbr.rollout.max_speed_mps,
    )


@dataclass(frozen=True)
class RecommendRequest:
    """An analysed event to recommend for (``None`` fields keep ``[cbr]``).

    Attributes:
        log_id: the log.
        event_id: the event (default: the hardest braking of the log).
        out: PNG of the rollout check (default ``<log>_<event>_cbr.png``).
        k, selection, risk_aware: prompt configuration.
        risk_type: override the mapped risk type.
    """

    log_id: str
    event_id: str | None = None
    out: Path | None = None
    k: int | None = None
    selection: str | None = None
    risk_aware: bool | None = None
    risk_type: str | None = None


@dataclass(frozen=True)
class RecommendResult:
    """A recommendation with its rollout check and picture."""

    query: Query
    recommendation: Recommendation
    outcomes: dict[str, RolloutOutcome]
    picture: Path
    seconds: float
    notes: tuple[str, ...] = ()

    def to_json_dict(self) -> dict[str, Any]:
        """JSON-ready form."""
        return {
            "notes": list(self.notes),
            "query": dataclasses.asdict(self.query),
            "recommendation": self.recommendation.to_json_dict(),
            "rollout": {
                "recommended": self.outcomes[self.recommendation.manoeuvre].to_json_dict(),
                "recorded": self.outcomes[RECORDED].to_json_dict(),
                "all": [o.to_json_dict() for o in self.outcomes.values()],
            },
            "picture": str(self.picture),
            "seconds": self.seconds,
        }


def _settings(config: Config, k: int | None, selection: str | None, aware: bool | None) -> RecommendSettings:
    c = config.cbr
    return RecommendSettings(
        k=c.k if k is None else k,
        selection=selection or c.selection,
        risk_aware=c.risk_aware if aware is None else aware,
        seed=c.seed,
        max_field_chars=c.max_field_chars,
        max_tokens=c.max_tokens,
    )


def recommend(
    store: ScenarioStore, request: RecommendRequest, config: Config, usage: UsageCounter | None = None
) -> RecommendResult:
    """Recommend an evasive manoeuvre for an analysed event, roll it out and draw both ego paths.

    Raises:
        ExplainError: no analysed events, or no such event.
        CbrError: unknown risk type or an answer that violates the schema.
        LLMError: the model cannot be loaded or fails.
    """
    start = time.perf_counter()
    base = open_case_base(store, config)
    record = find_event(store, request.log_id, request.event_id)
    query = query_from_event(record, config.cbr)
    if request.risk_type:
        query = dataclasses.replace(query, risk_type=request.risk_type)
    settings = _settings(config, request.k, request.selection, request.risk_aware)
    client = make_chat_client(config, usage=usage)
    try:
        rec = _recommend(query, base, client, make_embedder(config, usage=usage), settings)
    finally:
        client.close()
    scene = scene_of_event(store, record, config.cbr)
    r = config.cbr.rollout
    outcomes = rollout(scene, base.manoeuvres.manoeuvres, max_speed_mps=r.max_speed_mps, margin_m=r.margin_m)
    out = request.out or Path(
        f"{record.log_id}_{record.event_id.split(':', 1)[-1].replace(':', '_')}_cbr.png"
    )
    short_id = f"{record.log_id[:8]}:{record.guest_id[:8]}:{record.start_ns}"
    title = f"event {short_id} ({query.risk_type}): recommended {rec.manoeuvre}"
    picture = plot_rollout(scene, outcomes, rec.manoeuvre, out, title)
    notes = _recommend_notes(len(base), settings.k, outcomes[rec.manoeuvre], outcomes[RECORDED])
    return RecommendResult(query, rec, outcomes, picture, time.perf_counter() - start, notes)


def _recommend_notes(
    n_cases: int, k: int, recommended: RolloutOutcome, recorded: RolloutOutcome
) -> tuple[str, ...]:
    """What a user must know before trusting a recommendation (an empty case base, a failed check)."""
    notes = []
    if k > 0 and n_cases == 0:
        notes.append(
            "the store has no case base, so no case was retrieved (zero-shot): "
            "`scenariominer cbr build` makes one, `cbr add` adds confirmed events"
        )
    if recommended.collision and not recorded.collision:
        notes.append(
            f"the recommended {recommended.manoeuvre} collides in the rollout check at "
            f"{recommended.first_collision_s:.1f} s while the recorded driving does not: review it before use"
        )
    return tuple(notes)


@dataclass(frozen=True)
class CbrEvalRequest:
    """The evaluation grid.

    Attributes:
        per_type: hold-out cases per risk type to use (``None``: all), the first ones in id order.
        ks: shots to compare (0 = zero-shot).
        configs: only these configuration labels (e.g. ``aware/similarity/k3``); ``None``: all.
        time_budget_s: stop asking the model after this long; what is stored is scored.
        text_metrics: compute BLEU/ROUGE/METEOR/CIDEr.
        picture: write a PNG of the grid here (accuracy and rollout success per configuration).
    """

    per_type: int | None = None
    ks: tuple[int, ...] = (0, 1, 3, 5)
    configs: tuple[str, ...] | None = None
    time_budget_s: float | None = None
    text_metrics: bool = True
    picture: Path | None = None


def evaluate_cbr(
    store: ScenarioStore,
    request: CbrEvalRequest,
    config: Config,
    progress: Progress | None = None,
    usage: UsageCounter | None = None,
) -> CbrEvaluation:
    """Run (or continue) the CBR evaluation grid on the hold-out split and score it.

    Raises:
        CbrError: no hold-out split, a leak into the case base, or an unknown configuration label.
        LLMError: the model or the embedder cannot be loaded.
    """
    base = open_case_base(store, config)
    holdout = read_holdout(store, config.cbr.table)
    if request.per_type is not None:
        seen: dict[str, int] = {}
        kept = []
        for hc in holdout:
            if seen.get(hc.case.risk_type, 0) < request.per_type:
                kept.append(hc)
                seen[hc.case.risk_type] = seen.get(hc.case.risk_type, 0) + 1
        holdout = kept
    c = config.cbr
    grid = default_grid(request.ks, c.seed, c.max_field_chars, c.max_tokens)
    if request.configs is not None:
        known = {g.label for g in grid}
        unknown = [x for x in request.configs if x not in known]
        if unknown:
            raise CbrError(f"unknown configuration(s) {unknown}; known: {sorted(known)}")
        grid = [g for g in grid if g.label in request.configs]
    results = store.corpus(f"{c.table}_eval", EVAL_SCHEMA_VERSION)
    client = make_chat_client(config, usage=usage)
    try:
        ev = evaluate_cbr_grid(
            base,
            holdout,
            results,
            client,
            make_embedder(config, usage=usage),
            grid,
            time_budget_s=request.time_budget_s,
            with_text=request.text_metrics,
            progress=progress,
        )
    finally:
        client.close()
    if request.picture is not None:
        ev = dataclasses.replace(ev, picture=plot_evaluation(ev, request.picture))
    return ev
