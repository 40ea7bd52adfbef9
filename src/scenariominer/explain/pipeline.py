"""The braking-explanation pipeline over a store (braking paper, Fig. 2).

For each log: load → tracker-noise repair (:func:`~scenariominer.tags.stitch.stitch_tracks`) →
:func:`~scenariominer.tags.tag_log` → store the ``tags`` table → key objects by the configured
method (:func:`~scenariominer.events.counterfactual.identify_key_objects`: the paper's tags, the
counterfactual conflict search, or both) → per event: analysis window, criticality,
structured description, rule-based baseline, LLM understanding → embed the rephrased
descriptions → store ``events``, ``event_embeddings`` and the per-log ``braking_runs`` row in one
atomic write.

:func:`analyze_log` is the pure stage (a log in, records out); :func:`analyze_store` is the I/O
shell: incremental (a log whose ``braking_runs`` row has the same fingerprint and is complete is
skipped unless ``force``), bounded (``limit`` caps the fresh LLM calls of a run; the remaining
events are stored as ``pending`` and a later run finishes them, cached answers being free), and
robust (a log that cannot be analysed is recorded as ``failed`` with the reason, an invalid LLM
answer as category ``invalid``; neither stops the batch).
"""

from __future__ import annotations

import contextlib
import dataclasses
import hashlib
import json
import math
import time
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass
from datetime import UTC, datetime
from enum import StrEnum
from typing import TYPE_CHECKING, Any, cast

import numpy as np
import pyarrow as pa

from scenariominer.config import Config
from scenariominer.data.log import Log
from scenariominer.events.counterfactual import identify_key_objects
from scenariominer.events.criticality import event_criticality
from scenariominer.events.describe import DESCRIPTION_VERSION, describe_segments
from scenariominer.events.keyident import KeyEvent
from scenariominer.events.segments import pair_tags, segment_pair
from scenariominer.explain.baseline import BASELINE_VERSION, rule_candidates
from scenariominer.explain.categories import NOT_RELEVANT, CategorySet, load_categories
from scenariominer.explain.classify import Classification, ClassificationStatus
from scenariominer.explain.facts import event_facts
from scenariominer.explain.judge import Judge, allowed_categories, judge_event, rules_only
from scenariominer.explain.prompts import JUDGE_PROMPT_VERSION
from scenariominer.explain.records import (
    EMBEDDINGS_TABLE,
    EVENTS_TABLE,
    RUNS_SCHEMA,
    RUNS_TABLE,
    TAGS_TABLE,
    EventRecord,
    events_table,
)
from scenariominer.llm.client import ChatClient
from scenariominer.llm.embeddings import Embedder
from scenariominer.progress import NullProgress, Progress, step
from scenariominer.store import ScenarioStore, StoreRef, UnknownLogError, UnknownTableError

if TYPE_CHECKING:
    from scenariominer.exec import Executor, ItemOutcome
from scenariominer.store.vectors import embeddings_table
from scenariominer.tags.engine import LogTags, tag_log
from scenariominer.tags.stitch import ALIAS_NOTE_PREFIX, stitch_tracks

__all__ = [
    "AnalyzeReport",
    "LogAnalysis",
    "LogOutcome",
    "LogStatus",
    "analysis_fingerprint",
    "analyze_log",
    "analyze_store",
]


class LogStatus(StrEnum):
    """What a run did with a log.

    Attributes:
        ANALYZED: events found (possibly none), described, classified and stored.
        UNCHANGED: skipped; stored results have the same fingerprint and are complete.
        NO_EGO_MOTION: the ego never moves, so there is no braking to explain (tags stored, no events).
        FAILED: the log could not be analysed; the error is recorded.
    """

    ANALYZED = "analyzed"
    UNCHANGED = "unchanged"
    NO_EGO_MOTION = "no_ego_motion"
    FAILED = "failed"


@dataclass(frozen=True, eq=False)
class LogOutcome:
    """Result of the pure stage on one log.

    Attributes:
        tags: the log's tags.
        records: one record per KeyIdent event, embedding fields still empty.
        texts: the text to embed for each record (rephrased description, else the tag description).
        status: ``ANALYZED`` or ``NO_EGO_MOTION``.
        notes: data problems met (``; ``-joined into the runs table).
        classifications: the LLM outcome of each record.
    """

    tags: LogTags
    records: tuple[EventRecord, ...]
    texts: tuple[str, ...]
    status: LogStatus
    notes: tuple[str, ...]
    classifications: tuple[Classification, ...]


@dataclass(frozen=True)
class LogAnalysis:
    """What :func:`analyze_store` did with one log.

    Attributes:
        log_id: the log.
        status: see :class:`LogStatus`.
        n_events: events stored for the log.
        n_llm_calls: events sent to the LLM that were not answered from the cache.
        n_cached: events answered from the LLM cache.
        n_invalid: events whose answer stayed invalid after the repair round.
        n_errors: events whose LLM call failed.
        n_pending: events not classified because the run's limit was reached.
        llm_seconds: seconds spent in the LLM for this log.
        seconds: wall time for the log.
        error: the failure, for failed logs.
        notes: data problems met.
    """

    log_id: str
    status: LogStatus
    n_events: int = 0
    n_llm_calls: int = 0
    n_cached: int = 0
    n_invalid: int = 0
    n_errors: int = 0
    n_pending: int = 0
    llm_seconds: float = 0.0
    seconds: float = 0.0
    error: str = ""
    notes: tuple[str, ...] = ()


@dataclass(frozen=True)
class AnalyzeReport:
    """Result of :func:`analyze_store`.

    Attributes:
        logs: one entry per log considered, in order.
        fingerprint: the run's analysis fingerprint.
        seconds: wall time of the run.
    """

    logs: tuple[LogAnalysis, ...]
    fingerprint: str
    seconds: float

    def _count(self, status: LogStatus) -> int:
        return sum(1 for r in self.logs if r.status is status)

    @property
    def n_analyzed(self) -> int:
        """Logs analysed in this run."""
        return self._count(LogStatus.ANALYZED)

    @property
    def n_unchanged(self) -> int:
        """Logs skipped because their stored results are current."""
        return self._count(LogStatus.UNCHANGED)

    @property
    def n_failed(self) -> int:
        """Logs that could not be analysed."""
        return self._count(LogStatus.FAILED)

    @property
    def n_events(self) -> int:
        """Events stored in this run."""
        return sum(r.n_events for r in self.logs)

    @property
    def n_llm_calls(self) -> int:
        """Events classified by fresh (non-cached) LLM calls."""
        return sum(r.n_llm_calls for r in self.logs)

    @property
    def n_pending(self) -> int:
        """Events left unclassified because of the limit."""
        return sum(r.n_pending for r in self.logs)

    @property
    def n_invalid(self) -> int:
        """Events whose LLM answer stayed invalid."""
        return sum(r.n_invalid for r in self.logs)

    @property
    def llm_seconds(self) -> float:
        """Seconds spent in the LLM."""
        return sum(r.llm_seconds for r in self.logs)

    @property
    def mean_llm_latency_s(self) -> float:
        """Mean seconds per fresh LLM classification (NaN when there was none)."""
        return self.llm_seconds / self.n_llm_calls if self.n_llm_calls else math.nan

    def to_json(self) -> str:
        """The report as JSON (for scripts)."""
        data = asdict(self)
        data.update(
            n_analyzed=self.n_analyzed,
            n_unchanged=self.n_unchanged,
            n_failed=self.n_failed,
            n_events=self.n_events,
            n_llm_calls=self.n_llm_calls,
            n_pending=self.n_pending,
            n_invalid=self.n_invalid,
            llm_seconds=self.llm_seconds,
            mean_llm_latency_s=None if math.isnan(self.mean_llm_latency_s) else self.mean_llm_latency_s,
        )
        return json.dumps(data, default=str, indent=2)


def analysis_fingerprint(
    config: Config, categories: CategorySet, chat_client: ChatClient | None, embedder: Embedder
) -> str:
    """Hash of every setting that determines the stored results (a change forces re-analysis).

    Covers the tag and KeyIdent thresholds, the explanation settings that shape descriptions and
    measures, the categories, the versions of the prompt, description template and baseline rules,
    the chat model and decoding parameters, and the embedding model.
    """
    explain = dataclasses.replace(
        config.explain, categories_file="", show_past_s=0.0, show_future_s=0.0, search_k=1
    )
    payload = {
        "tags": asdict(config.tags),
        "explain": asdict(explain),
        "categories": categories.fingerprint,
        "prompt": JUDGE_PROMPT_VERSION,
        "description": DESCRIPTION_VERSION,
        "baseline": BASELINE_VERSION,
        "chat": None
        if chat_client is None
        else [chat_client.backend.name, chat_client.backend.model, chat_client.params.to_dict()],
        "embedding": [embedder.backend, embedder.model],
    }
    blob = json.dumps(payload, sort_keys=True, default=str)
    return hashlib.sha256(blob.encode()).hexdigest()[:16]


def _fresh_call(outcome: Classification) -> bool:
    """Whether the outcome cost a model call (asked, and not answered from the cache)."""
    asked = outcome.status not in (ClassificationStatus.PENDING, ClassificationStatus.RULES)
    return asked and not outcome.cached


def _pending(rules: Classification) -> Classification:
    """The rules' result, marked as waiting for the LLM."""
    return dataclasses.replace(rules, status=ClassificationStatus.PENDING)


def analyze_log(
    log: Log,
    config: Config,
    categories: CategorySet,
    chat_client: ChatClient | None,
    *,
    llm_budget: int | None = None,
    fingerprint: str = "",
    on_event: Callable[[Classification], None] | None = None,
) -> LogOutcome:
    """Tag one log, find its braking events and describe, measure and classify each.

    Args:
        log: a preprocessed log (as stored).
        config: tag, KeyIdent and explanation settings.
        categories: the LLM's categories.
        chat_client: the LLM; ``None`` leaves every event ``pending``.
        llm_budget: at most this many fresh (non-cached) LLM calls; ``None`` = unbounded. Once
            it is spent, the remaining events are ``pending``.
        fingerprint: stored on every record.
        on_event: called after each event that was sent to the LLM (progress).

    Returns:
        The tags and records (embedding fields empty; :func:`analyze_store` fills them).
    """
    cfg = config.explain
    notes: list[str] = list(log.notes)
    stitched = stitch_tracks(log, config.tags.stitch)
    log = stitched.log
    notes.extend(stitched.notes)
    tags = tag_log(log, config.tags)
    ego_speed = log.speed_mps[log.ego_index]
    top_speed = float(np.nanmax(ego_speed)) if np.isfinite(ego_speed).any() else 0.0
    if top_speed < cfg.min_ego_speed_mps:
        notes.append(
            f"the ego never reaches {cfg.min_ego_speed_mps:g} m/s (top speed {top_speed:.2f} m/s): "
            "no braking to explain"
        )
        return LogOutcome(tags, (), (), LogStatus.NO_EGO_MOTION, tuple(notes), ())
    events = identify_key_objects(log, tags, config.tags.keyident, aliases=stitched.aliases)
    records: list[EventRecord] = []
    texts: list[str] = []
    outcomes: list[Classification] = []
    fresh_calls = 0
    llm_model = "" if chat_client is None else chat_client.backend.model
    for event in events:
        record, text, outcome = _analyze_event(
            log,
            tags,
            event,
            config,
            categories,
            chat_client if llm_budget is None or fresh_calls < llm_budget else None,
            llm_model,
            fingerprint,
        )
        if _fresh_call(outcome):
            fresh_calls += 1
        if on_event is not None and outcome.status is not ClassificationStatus.PENDING:
            on_event(outcome)
        records.append(record)
        texts.append(text)
        outcomes.append(outcome)
    return LogOutcome(tags, tuple(records), tuple(texts), LogStatus.ANALYZED, tuple(notes), tuple(outcomes))


def _analyze_event(
    log: Log,
    tags: LogTags,
    event: KeyEvent,
    config: Config,
    categories: CategorySet,
    chat_client: ChatClient | None,
    llm_model: str,
    fingerprint: str,
) -> tuple[EventRecord, str, Classification]:
    cfg = config.explain
    notes: list[str] = []
    pair = pair_tags(
        tags,
        event.track_id,
        event.start_ns,
        event.end_ns,
        context_before_s=cfg.context_before_s,
        context_after_s=cfg.context_after_s,
        log=log,
        turn_lookahead_s=cfg.turn_lookahead_s,
    )
    if pair.guest_frames < 3:
        notes.append(f"the guest is observed in only {pair.guest_frames} frame(s) of the window")
    if event.method == "counterfactual":
        notes.append(
            f"key object by counterfactual conflict ({event.conflict_s:.1f} s after the braking onset)"
        )
    if event.aliases:
        notes.append(f"{ALIAS_NOTE_PREFIX}{','.join(event.aliases)}")
    description = describe_segments(segment_pair(pair, cfg.min_segment_s))
    crit = event_criticality(log, tags, event.track_id, event.start_ns, event.end_ns, cfg)
    candidates = rule_candidates(pair)
    facts = event_facts(log, pair, crit, event.start_ns, event.min_distance_m)
    judge = Judge(cfg.judge)
    allowed = allowed_categories(judge, candidates, categories)
    if judge is Judge.RULES:
        outcome = rules_only(candidates, categories, facts)
    elif chat_client is None:
        outcome = _pending(rules_only(candidates, categories, facts))
    else:
        outcome = judge_event(
            chat_client, facts, candidates, categories, judge, max_tokens=cfg.llm_max_tokens
        )
    if outcome.status is ClassificationStatus.INVALID:
        notes.append("the LLM answer was invalid after the repair round")
    notes.extend(outcome.notes)
    use_llm_text = outcome.is_valid and bool(outcome.description)
    record = EventRecord(
        event_id=event.event_id,
        log_id=log.log_id,
        guest_id=event.track_id,
        guest_category=event.category,
        start_ns=event.start_ns,
        end_ns=event.end_ns,
        start_s=(event.start_ns - int(log.timestamps_ns[0])) * 1e-9,
        end_s=(event.end_ns - int(log.timestamps_ns[0])) * 1e-9,
        window_start_ns=int(pair.timestamps_ns[0]),
        window_end_ns=int(pair.timestamps_ns[-1]),
        closest_ns=crit.closest_ns,
        n_frames=event.n_frames,
        peak_collision=event.peak_collision.value,
        peak_traj_overlap=event.peak_traj_overlap.value,
        min_ttc_s=crit.min_ttc_s,
        min_distance_m=event.min_distance_m,
        pet_s=crit.pet_s,
        headway_s=crit.headway_s,
        peak_decel_mps2=crit.peak_decel_mps2,
        tag_description=description,
        baseline_category=candidates[0] if candidates else NOT_RELEVANT,
        rule_candidates=",".join(candidates),
        facts=facts.text(),
        judge=judge.value,
        llm_category=outcome.category if outcome.is_valid and len(allowed) > 1 else "",
        category=outcome.category,
        llm_status=outcome.status.value,
        llm_description=outcome.description,
        explanation=outcome.explanation,
        llm_raw_answer=outcome.raw_answer,
        llm_error=outcome.error,
        llm_attempts=outcome.attempts,
        llm_latency_s=outcome.latency_s,
        llm_model=llm_model if outcome.attempts else "",
        prompt_version=JUDGE_PROMPT_VERSION,
        categories_source=categories.source,
        embedded_text="llm" if use_llm_text else "tags",
        embedding_model="",
        embedding_dim=0,
        notes="; ".join(notes),
        fingerprint=fingerprint,
    )
    return record, (outcome.description if use_llm_text else description), outcome


def _runs_row(
    fingerprint: str,
    status: LogStatus,
    records: Sequence[EventRecord],
    error: str,
    notes: Sequence[str],
    s: float,
) -> pa.Table:
    n_pending = sum(1 for r in records if r.llm_status == ClassificationStatus.PENDING.value)
    row = {
        "fingerprint": [fingerprint],
        "status": [status.value],
        "complete": [status is not LogStatus.FAILED and n_pending == 0],
        "n_events": [len(records)],
        "n_classified": [len(records) - n_pending],
        "n_pending": [n_pending],
        "error": [error],
        "notes": ["; ".join(notes)],
        "seconds": [s],
        "analyzed_at": [datetime.now(UTC).isoformat()],
    }
    return pa.table(row, schema=RUNS_SCHEMA)


def _current_runs(store: ScenarioStore) -> dict[str, tuple[str, bool]]:
    """``log_id → (fingerprint, complete)`` of the stored runs table (empty when absent)."""
    try:
        table = store.read_table(RUNS_TABLE)
    except UnknownTableError:
        return {}
    ids = table.column("log_id").to_pylist()
    fps = table.column("fingerprint").to_pylist()
    done = table.column("complete").to_pylist()
    return {str(i): (str(f), bool(c)) for i, f, c in zip(ids, fps, done, strict=True)}


def analyze_store(
    store: ScenarioStore,
    config: Config,
    chat_client: ChatClient | None,
    embedder: Embedder,
    log_ids: Sequence[str] | None = None,
    progress: Progress | None = None,
    *,
    force: bool = False,
    limit: int | None = None,
    categories: CategorySet | None = None,
    executor: Executor | None = None,
) -> AnalyzeReport:
    """Explain the braking events of every log in a store (see the module docstring).

    Args:
        store: the store; logs are read from it and results written back.
        config: settings (``tags``, ``explain``).
        chat_client: the LLM (``None``: events are stored as ``pending``).
        embedder: embeds the rephrased descriptions (its model is recorded with every vector).
        log_ids: the logs to analyse; ``None`` means every log in the store.
        progress: progress sink.
        force: re-analyse logs whose stored results are current.
        limit: at most this many fresh LLM calls in this run (``None`` = no limit).
        categories: the LLM's categories; defaults to ``config.explain.categories_file`` or the
            paper's.
        executor: runs the rules stage of each log (tags, events, facts, embeddings and their
            commit) in its workers; each worker builds the configured embedder, which must be
            the model ``embedder`` names. The LLM stage goes to the workers too when the model
            is served (a concurrent backend) and there is no ``limit``, with at most
            ``llm.max_concurrency`` logs in flight; an embedded model answers here, one log
            after the other (it lives in one process). ``None``: everything runs here.

    Returns:
        What happened to each log.

    Raises:
        CategoryFileError: the configured category file is unusable.
        UnknownLogError: a requested log is not in the store.
    """
    t_run = time.perf_counter()
    progress = progress or NullProgress()
    categories = categories or load_categories(config.explain.categories_file)
    fingerprint = analysis_fingerprint(config, categories, chat_client, embedder)
    ids = list(store.log_ids() if log_ids is None else log_ids)
    known = set(store.log_ids())
    missing = [i for i in ids if i not in known]
    if missing:
        raise UnknownLogError(missing[0])
    runs = {} if force else _current_runs(store)
    todo = [i for i in ids if runs.get(i, ("", False))[:2] != (fingerprint, True)]
    uses_llm = chat_client is not None and config.explain.judge != "rules"
    results: dict[str, LogAnalysis] = {i: LogAnalysis(i, LogStatus.UNCHANGED) for i in ids if i not in todo}
    fresh = [i for i in todo if runs.get(i, ("", False))[0] != fingerprint]
    rule_ids = fresh if uses_llm else todo  # rule results of every log first, each stored at once
    with step(progress, "rules" if uses_llm else "analyze", len(rule_ids)):
        if executor is not None and executor.name != "local":
            _MODELS[_embedder_key(config)] = embedder  # items run in this process reuse it
            task = RulesTask(StoreRef.of(store), config, categories, fingerprint, embedder.model)
            outcomes = executor.map(
                task, rule_ids, keys=rule_ids, on_outcome=lambda o: _rules_done(progress, o)
            )
            results.update({o.key: _analysis_of(o) for o in outcomes})
        else:
            for log_id in rule_ids:
                result = _analyze_and_store(store, log_id, config, categories, None, embedder, 0, fingerprint)
                results[log_id] = result
                progress.advance(1, _rules_message(result))
    if uses_llm:
        waiting = _pending_counts(store, todo, fingerprint)
        budget = limit
        with step(progress, "LLM", sum(waiting.values())):
            llm_ids = [i for i in todo if waiting.get(i)]
            if _fan_out_llm(chat_client, executor, limit):
                assert executor is not None
                assert chat_client is not None
                _MODELS[_chat_key(config)] = chat_client  # items run in this process reuse them
                _MODELS[_embedder_key(config)] = embedder
                llm_task = LLMTask(StoreRef.of(store), config, categories, fingerprint)
                outcomes = executor.map(
                    llm_task,
                    llm_ids,
                    keys=llm_ids,
                    max_in_flight=min(executor.workers, config.llm.max_concurrency),
                    on_outcome=lambda o: progress.advance(waiting[o.key], _llm_message(o)),
                )
                results.update({o.key: _analysis_of(o) for o in outcomes})
                llm_ids = []
            for log_id in llm_ids:
                if budget == 0:
                    break
                result = _analyze_and_store(
                    store,
                    log_id,
                    config,
                    categories,
                    chat_client,
                    embedder,
                    budget,
                    fingerprint,
                    on_event=lambda c: progress.advance(1, _event_message(c)),
                )
                if budget is not None:
                    budget = max(0, budget - result.n_llm_calls)
                results[log_id] = result
    return AnalyzeReport(tuple(results[i] for i in ids), fingerprint, time.perf_counter() - t_run)


@dataclass(frozen=True)
class RulesTask:
    """The worker side of the rules stage: analyse one stored log without the LLM (picklable)."""

    store: StoreRef
    config: Config
    categories: CategorySet
    fingerprint: str
    embedding_model: str

    def __call__(self, log_id: str) -> LogAnalysis:
        """Analyse ``log_id`` and commit its tags, events, embeddings and runs row."""
        embedder = _worker_embedder(self.config)
        if embedder.model != self.embedding_model:
            raise ValueError(
                f"the worker's embedder is {embedder.model!r}, the run's {self.embedding_model!r}: "
                "workers build the embedder from the configuration"
            )
        return _analyze_and_store(
            self.store.open(), log_id, self.config, self.categories, None, embedder, 0, self.fingerprint
        )


@dataclass(frozen=True)
class LLMTask:
    """The worker side of the LLM stage against a served model: finish one log's events (picklable).

    The worker builds its own chat client and embedder from the configuration; a fingerprint that
    differs from the run's (another model or decoding settings) is refused, so every worker answers
    with the model the run was started with.
    """

    store: StoreRef
    config: Config
    categories: CategorySet
    fingerprint: str

    def __call__(self, log_id: str) -> LogAnalysis:
        """Ask the served model about ``log_id``'s pending events and commit the log's results."""
        client, embedder = _worker_chat_client(self.config), _worker_embedder(self.config)
        mine = analysis_fingerprint(self.config, self.categories, client, embedder)
        if mine != self.fingerprint:
            raise ValueError(
                f"the worker's model settings give fingerprint {mine}, the run's {self.fingerprint}"
            )
        return _analyze_and_store(
            self.store.open(), log_id, self.config, self.categories, client, embedder, None, self.fingerprint
        )


def _fan_out_llm(client: ChatClient | None, executor: Executor | None, limit: int | None) -> bool:
    """Whether the LLM stage goes to the executor: a served (concurrent) model, workers, no call budget."""
    return (
        client is not None
        and client.backend.concurrent
        and executor is not None
        and executor.name != "local"
        and limit is None
    )


def _llm_message(outcome: ItemOutcome[LogAnalysis]) -> str:
    a = _analysis_of(outcome)
    return f"{a.status.value} {a.log_id[:8]} ({a.n_llm_calls} calls, {a.n_cached} cached)"


#: Models built by this process's tasks, by kind and settings: a worker builds each once.
_MODELS: dict[str, Any] = {}


def _chat_key(config: Config) -> str:
    return f"chat:{config.llm!r}"


def _embedder_key(config: Config) -> str:
    return f"embedder:{config.embedding!r}"


def _worker_chat_client(config: Config) -> ChatClient:
    """The chat client of this process for ``config.llm`` (built once per worker)."""
    from scenariominer.llm.factory import make_chat_client

    return cast(ChatClient, _per_process(_chat_key(config), lambda: make_chat_client(config)))


def _worker_embedder(config: Config) -> Embedder:
    """The embedder of this process for ``config.embedding`` (built once per worker)."""
    from scenariominer.llm.factory import make_embedder

    return cast(Embedder, _per_process(_embedder_key(config), lambda: make_embedder(config)))


def _per_process(key: str, build: Callable[[], Any]) -> Any:
    if key not in _MODELS:
        _MODELS[key] = build()
    return _MODELS[key]


def _analysis_of(outcome: ItemOutcome[LogAnalysis]) -> LogAnalysis:
    """The worker's analysis, or a failed one naming why the worker gave none."""
    if outcome.value is not None:
        return outcome.value
    return LogAnalysis(outcome.key, LogStatus.FAILED, seconds=outcome.seconds, error=outcome.error)


def _rules_message(result: LogAnalysis) -> str:
    return f"{result.status.value} {result.log_id[:8]} ({result.n_events} events)"


def _rules_done(progress: Progress, outcome: ItemOutcome[LogAnalysis]) -> None:
    progress.advance(1, _rules_message(_analysis_of(outcome)))


def _event_message(outcome: Classification) -> str:
    """Progress text after one LLM answer."""
    how = "cached" if outcome.cached else f"{outcome.latency_s:.1f} s"
    return f"{outcome.category} ({how})"


def _pending_counts(store: ScenarioStore, log_ids: Sequence[str], fingerprint: str) -> dict[str, int]:
    """``log_id → events still waiting for the LLM`` of the given logs' current runs rows."""
    try:
        table = store.read_table(RUNS_TABLE, list(log_ids))
    except UnknownTableError:
        return {}
    out: dict[str, int] = {}
    for row in table.select(["log_id", "fingerprint", "status", "n_pending"]).to_pylist():
        if row["fingerprint"] == fingerprint and row["status"] == LogStatus.ANALYZED.value:
            out[str(row["log_id"])] = int(row["n_pending"] or 0)
    return out


def _analyze_and_store(
    store: ScenarioStore,
    log_id: str,
    config: Config,
    categories: CategorySet,
    chat_client: ChatClient | None,
    embedder: Embedder,
    budget: int | None,
    fingerprint: str,
    on_event: Callable[[Classification], None] | None = None,
) -> LogAnalysis:
    t0 = time.perf_counter()
    try:
        log = store.load_log(log_id)
        outcome = analyze_log(
            log,
            config,
            categories,
            chat_client,
            llm_budget=budget,
            fingerprint=fingerprint,
            on_event=on_event,
        )
        records = list(outcome.records)
        if records:
            emb = embedder.embed(list(outcome.texts))
            records = [
                dataclasses.replace(r, embedding_model=emb.model, embedding_dim=emb.dim) for r in records
            ]
            emb_table = embeddings_table([r.event_id for r in records], emb.vectors, emb.model)
        else:
            emb_table = embeddings_table([], np.zeros((0, 1), dtype=np.float32), embedder.model)
        seconds = time.perf_counter() - t0
        store.write_tables(
            log_id,
            {
                TAGS_TABLE: outcome.tags.to_arrow(),
                EVENTS_TABLE: events_table(records),
                EMBEDDINGS_TABLE: emb_table,
                RUNS_TABLE: _runs_row(fingerprint, outcome.status, records, "", outcome.notes, seconds),
            },
        )
    except Exception as exc:  # noqa: BLE001 - one bad log must not stop the batch; the cause is recorded
        error = f"{type(exc).__name__}: {exc}"
        seconds = time.perf_counter() - t0
        with contextlib.suppress(Exception):  # recording the failure is best effort
            store.write_table(
                log_id, RUNS_TABLE, _runs_row(fingerprint, LogStatus.FAILED, [], error, [], seconds)
            )
        return LogAnalysis(log_id, LogStatus.FAILED, seconds=seconds, error=error)
    cls = outcome.classifications
    return LogAnalysis(
        log_id=log_id,
        status=outcome.status,
        n_events=len(records),
        n_llm_calls=sum(1 for c in cls if _fresh_call(c)),
        n_cached=sum(1 for c in cls if c.cached),
        n_invalid=sum(1 for c in cls if c.status is ClassificationStatus.INVALID),
        n_errors=sum(1 for c in cls if c.status is ClassificationStatus.ERROR),
        n_pending=sum(1 for c in cls if c.status is ClassificationStatus.PENDING),
        llm_seconds=sum(c.latency_s for c in cls),
        seconds=seconds,
        notes=outcome.notes,
    )
