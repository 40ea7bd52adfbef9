"""Evaluation of the braking pipeline against scenario labels (braking paper, section V).

Labels follow the paper's annotation scheme: one row per ``(log_id, guest_id, scenario_category)``
(the synthetic generator's ``labels.csv`` works as is; extra columns are ignored). Only labelled
logs that the store has analysed are evaluated. The unit of evaluation is the ego–guest *pair*
``(log_id, guest_id)``; a pair with several events is predicted as every category of its events.

* **KeyIdent** (Table IV): a labelled pair whose category is not ``not_relevant`` is *found* when
  some event names its guest; recall per label category and overall. Precision is over every
  pair detected in the evaluated logs: the share that is a relevant labelled pair.
* **Known categories** (Table V): per category of the category set (the fallbacks excluded),
  precision, recall and F1 of the rule-based baseline and of the LLM side by side, plus the
  micro average. Recall is end to end: a pair KeyIdent missed is a miss of both.
* **Free-text retrieval** (Table VI): for each out-of-distribution category with a query sentence,
  events are ranked by cosine similarity of the query to the stored description embeddings (a
  pair counts at its best-ranked event); P@10 and R@50 against the pairs labelled with it.
"""

from __future__ import annotations

import csv
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import pyarrow as pa

from scenariominer import errors as _errors
from scenariominer.eval.metrics import PRF, category_prf, micro_prf, precision_at_k, recall_at_k
from scenariominer.explain.categories import NOT_RELEVANT, CategorySet
from scenariominer.explain.records import EMBEDDINGS_TABLE, RUNS_TABLE
from scenariominer.explain.search import NoEventsError, load_events
from scenariominer.llm.embeddings import Embedder
from scenariominer.retrieval import rank
from scenariominer.store import ScenarioStore, UnknownTableError
from scenariominer.store.vectors import load_embeddings
from scenariominer.tags.stitch import aliases_from_notes

__all__ = [
    "OOD_QUERIES",
    "REQUIRED_LABEL_COLUMNS",
    "BrakingEvaluation",
    "CategoryScores",
    "KeyIdentRow",
    "Label",
    "LabelFileError",
    "MethodScores",
    "Pair",
    "RetrievalRow",
    "classification_scores",
    "evaluate_braking",
    "pedestrian_confusion",
    "keyident_scores",
    "read_labels",
    "resolve_aliases",
    "retrieval_row",
]

#: Columns a labels file must have (others are ignored).
REQUIRED_LABEL_COLUMNS: tuple[str, ...] = ("log_id", "guest_id", "scenario_category")

#: Free-text queries of the out-of-distribution categories (the braking paper's Table VI).
OOD_QUERIES: dict[str, str] = {
    "approach_stop": "The ego vehicle approaches a stopped or slow-moving vehicle ahead, requiring careful "
    "deceleration to maintain a safe distance.",
    "lead_brake": "The lead vehicle suddenly brakes, requiring the ego vehicle to brake in order to avoid "
    "a collision.",
    "ped_crossing": "A pedestrian crosses in front of the ego vehicle, requiring the ego vehicle to brake or "
    "yield to avoid a collision.",
}

#: A labelled or detected ego–guest pair: ``(log_id, guest_id)``.
Pair = tuple[str, str]


class LabelFileError(_errors.EvaluationError):
    """A labels file cannot be read; the message names the file (and line) and the problem."""

    def __init__(self, path: str | Path, problem: str) -> None:
        self.path = str(path)
        self.problem = problem
        super().__init__(f"{self.path}: {problem}")


@dataclass(frozen=True)
class Label:
    """One annotation.

    Attributes:
        log_id: the log.
        guest_id: the labelled guest's track id.
        category: what the guest does to the ego (``not_relevant`` when it is not why the ego brakes).
    """

    log_id: str
    guest_id: str
    category: str

    @property
    def pair(self) -> Pair:
        """``(log_id, guest_id)``."""
        return (self.log_id, self.guest_id)


def read_labels(path: str | Path) -> tuple[Label, ...]:
    """Read a labels CSV with at least the columns :data:`REQUIRED_LABEL_COLUMNS`.

    Raises:
        LabelFileError: the file is missing, a column is missing, a row has an empty field, or a
            pair is labelled twice with different categories.
    """
    p = Path(path)
    try:
        with p.open(newline="", encoding="utf-8") as fh:
            reader = csv.DictReader(fh)
            missing = [c for c in REQUIRED_LABEL_COLUMNS if c not in (reader.fieldnames or [])]
            if missing:
                raise LabelFileError(p, f"missing column(s) {missing}; need {list(REQUIRED_LABEL_COLUMNS)}")
            labels: dict[Pair, Label] = {}
            for line, row in enumerate(reader, start=2):
                values = [(row.get(c) or "").strip() for c in REQUIRED_LABEL_COLUMNS]
                if not all(values):
                    raise LabelFileError(p, f"line {line}: empty {REQUIRED_LABEL_COLUMNS[values.index('')]}")
                label = Label(*values)
                old = labels.get(label.pair)
                if old is not None and old.category != label.category:
                    raise LabelFileError(
                        p,
                        f"line {line}: pair {label.pair} is labelled {old.category!r} and {label.category!r}",
                    )
                labels[label.pair] = label
    except FileNotFoundError:
        raise LabelFileError(p, "labels file does not exist") from None
    except UnicodeDecodeError as exc:
        raise LabelFileError(p, f"not a UTF-8 text file ({exc})") from None
    return tuple(labels.values())


# ---------------------------------------------------------------------- pure scoring


@dataclass(frozen=True)
class KeyIdentRow:
    """KeyIdent recall of one label category.

    Attributes:
        category: the label category (``overall`` for all relevant labels).
        n_labels: labelled pairs of the category.
        n_found: of which KeyIdent detected.
    """

    category: str
    n_labels: int
    n_found: int

    @property
    def recall(self) -> float:
        """``n_found / n_labels``; NaN without labels."""
        return self.n_found / self.n_labels if self.n_labels else math.nan


@dataclass(frozen=True)
class CategoryScores:
    """Scores of one known category by each judge, side by side (a row of Table V).

    Attributes:
        category: the category (``overall`` for the micro average).
        scores: ``judge → scores``, in column order (``rules`` first, then e.g. ``llm``, ``hybrid``).
    """

    category: str
    scores: Mapping[str, PRF]

    @property
    def baseline(self) -> PRF:
        """Scores of the rule-based baseline (the ``rules`` column)."""
        return self.scores["rules"]


@dataclass(frozen=True)
class RetrievalRow:
    """Free-text retrieval of one category (a row of Table VI).

    Attributes:
        category: the labelled category the query describes.
        query: the query sentence.
        n_relevant: labelled pairs of the category in the evaluated logs.
        precision_at_k: share of relevant pairs among the first ``k_precision`` results.
        recall_at_k: share of the relevant pairs found among the first ``k_recall`` results.
        k_precision: the cut-off of the precision (10 in the paper).
        k_recall: the cut-off of the recall (50 in the paper).
    """

    category: str
    query: str
    n_relevant: int
    precision_at_k: float
    recall_at_k: float
    k_precision: int = 10
    k_recall: int = 50


def keyident_scores(labels: Sequence[Label], detected: Sequence[Pair]) -> tuple[list[KeyIdentRow], PRF]:
    """KeyIdent recall per label category and overall precision/recall (Table IV).

    Args:
        labels: the labels of the evaluated logs.
        detected: pairs with at least one event in the evaluated logs.

    Returns:
        One row per relevant label category (sorted, ``overall`` last) and the overall scores.
    """
    found = set(detected)
    relevant = [lab for lab in labels if lab.category != NOT_RELEVANT]
    rows = []
    for cat in sorted({lab.category for lab in relevant}):
        pairs = {lab.pair for lab in relevant if lab.category == cat}
        rows.append(KeyIdentRow(cat, len(pairs), len(pairs & found)))
    overall = PRF(
        tp=len({lab.pair for lab in relevant} & found),
        fp=len(found - {lab.pair for lab in relevant}),
        fn=len({lab.pair for lab in relevant} - found),
    )
    rows.append(KeyIdentRow("overall", overall.tp + overall.fn, overall.tp))
    return rows, overall


def classification_scores(
    labels: Sequence[Label],
    predictions: Mapping[str, Mapping[Pair, Sequence[str]]],
    categories: Sequence[str],
) -> list[CategoryScores]:
    """Per-category scores of each judge, plus the micro average (Table V).

    Args:
        labels: the labels of the evaluated logs.
        predictions: ``judge → (pair → categories of its events)``, in column order.
        categories: the known categories to score.
    """
    truth = {lab.pair: lab.category for lab in labels}
    rows = [
        CategoryScores(c, {j: category_prf(truth, pred, c) for j, pred in predictions.items()})
        for c in categories
    ]
    rows.append(CategoryScores("overall", {j: micro_prf(r.scores[j] for r in rows) for j in predictions}))
    return rows


def pedestrian_confusion(
    predictions: Mapping[str, Mapping[Pair, Sequence[str]]], pedestrians: set[Pair], category: str
) -> dict[str, tuple[int, int]]:
    """Per judge: ``(pedestrian pairs predicted as category, pedestrian pairs it predicted)``.

    Args:
        predictions: ``judge → (pair → categories of its events)``.
        pedestrians: the detected pairs whose guest is a pedestrian.
        category: the category a pedestrian should never get (``obj_crossing``).
    """
    out: dict[str, tuple[int, int]] = {}
    for judge, pred in predictions.items():
        seen = [p for p in pedestrians if p in pred]
        out[judge] = (sum(1 for p in seen if category in pred[p]), len(seen))
    return out


def retrieval_row(
    labels: Sequence[Label],
    ranked: Sequence[Pair],
    category: str,
    query: str,
    k_precision: int = 10,
    k_recall: int = 50,
) -> RetrievalRow:
    """P@k and R@k of one query's ranking (pairs best first, each at most once)."""
    relevant = {lab.pair for lab in labels if lab.category == category}
    return RetrievalRow(
        category=category,
        query=query,
        n_relevant=len(relevant),
        precision_at_k=precision_at_k(ranked, relevant, k_precision),
        recall_at_k=recall_at_k(ranked, relevant, k_recall),
        k_precision=k_precision,
        k_recall=k_recall,
    )


# ---------------------------------------------------------------------- store evaluation


@dataclass(frozen=True)
class MethodScores:
    """KeyIdent scores of one key-object method (and one noise level), recomputed from the logs.

    Attributes:
        method: ``tags``, ``counterfactual`` or ``combined`` (see ``tags.keyident.method``).
        noise_level: the labels' noise level these rows cover (``all``: every evaluated log).
        rows: recall per label category, ``overall`` last.
        overall: precision / recall counts over every detected pair.
    """

    method: str
    noise_level: str
    rows: tuple[KeyIdentRow, ...]
    overall: PRF


@dataclass(frozen=True)
class BrakingEvaluation:
    """Every table of the braking evaluation.

    Attributes:
        n_logs: labelled logs evaluated (analysed in the store).
        n_logs_not_analyzed: labelled logs absent from the store or not analysed (ignored), or
            not completely classified when only complete logs are evaluated.
        n_labels: labels of the evaluated logs.
        n_events: events in the evaluated logs.
        llm_status: number of events per LLM status (``ok``, ``repaired``, ``invalid``, ``error``,
            ``pending``).
        keyident: Table IV rows.
        keyident_overall: KeyIdent precision/recall counts.
        classification: Table V rows (``overall`` last).
        retrieval: Table VI rows.
        embedding_model: model of the description embeddings ("" without retrieval).
        judges: the columns of Table V, in order (``rules`` first).
        pedestrians_as_obj_crossing: per judge, ``(pedestrian pairs classed obj_crossing,
            pedestrian pairs detected)``.
        by_method: KeyIdent recall of every key-object method on the same logs (empty unless
            asked for; see :mod:`scenariominer.eval.braking_methods`).
    """

    n_logs: int
    n_logs_not_analyzed: int
    n_labels: int
    n_events: int
    llm_status: Mapping[str, int]
    keyident: tuple[KeyIdentRow, ...]
    keyident_overall: PRF
    classification: tuple[CategoryScores, ...]
    retrieval: tuple[RetrievalRow, ...] = field(default_factory=tuple)
    embedding_model: str = ""
    judges: tuple[str, ...] = ("rules",)
    pedestrians_as_obj_crossing: Mapping[str, tuple[int, int]] = field(default_factory=dict)
    by_method: tuple[MethodScores, ...] = ()

    def to_json_dict(self) -> dict[str, Any]:
        """JSON-safe form (undefined scores are ``null``)."""

        def num(x: float) -> float | None:
            return None if math.isnan(x) else round(x, 4)

        def scores(p: PRF) -> dict[str, Any]:
            return {
                "precision": num(p.precision),
                "recall": num(p.recall),
                "f1": num(p.f1),
                "tp": p.tp,
                "fp": p.fp,
                "fn": p.fn,
            }

        return {
            "n_logs": self.n_logs,
            "n_logs_not_analyzed": self.n_logs_not_analyzed,
            "n_labels": self.n_labels,
            "n_events": self.n_events,
            "llm_status": dict(self.llm_status),
            "keyident": {
                "precision": num(self.keyident_overall.precision),
                "recall": num(self.keyident_overall.recall),
                "by_category": [
                    {
                        "category": r.category,
                        "n_labels": r.n_labels,
                        "n_found": r.n_found,
                        "recall": num(r.recall),
                    }
                    for r in self.keyident
                ],
            },
            "judges": list(self.judges),
            "classification": [
                {"category": r.category, **{j: scores(p) for j, p in r.scores.items()}}
                for r in self.classification
            ],
            "pedestrians_as_obj_crossing": {
                j: {"n": n, "of": of} for j, (n, of) in self.pedestrians_as_obj_crossing.items()
            },
            "retrieval": [
                {
                    "category": r.category,
                    "query": r.query,
                    "n_relevant": r.n_relevant,
                    f"p_at_{r.k_precision}": num(r.precision_at_k),
                    f"r_at_{r.k_recall}": num(r.recall_at_k),
                }
                for r in self.retrieval
            ],
            "embedding_model": self.embedding_model,
            "keyident_by_method": [
                {
                    "method": m.method,
                    "noise_level": m.noise_level,
                    "precision": num(m.overall.precision),
                    "recall": num(m.overall.recall),
                    "by_category": {r.category: num(r.recall) for r in m.rows},
                }
                for m in self.by_method
            ],
        }


def _analyzed_logs(store: ScenarioStore, only_complete: bool) -> set[str]:
    try:
        table = store.read_table(RUNS_TABLE)
    except UnknownTableError:
        raise NoEventsError(str(store.root)) from None
    ids = [str(x) for x in table.column("log_id").to_pylist()]
    if not only_complete:
        return set(ids)
    complete = table.column("complete").to_pylist()
    return {i for i, done in zip(ids, complete, strict=True) if done}


def _pairs_by_category(events: pa.Table, column: str) -> dict[Pair, list[str]]:
    out: dict[Pair, list[str]] = {}
    for log_id, guest_id, cat in zip(
        events.column("log_id").to_pylist(),
        events.column("guest_id").to_pylist(),
        events.column(column).to_pylist(),
        strict=True,
    ):
        out.setdefault((str(log_id), str(guest_id)), []).append(str(cat))
    return out


def resolve_aliases(events: pa.Table, labelled: set[Pair]) -> pa.Table:
    """Events whose guest is a stitched object name the labelled one of its ids, if any.

    An event's notes list the other track ids of its guest (tracks stitched into it after an id
    switch, :data:`~scenariominer.tags.stitch.ALIAS_NOTE_PREFIX`). When the guest id itself is not
    labelled but one of those is, the event's ``guest_id`` becomes that id, so the event counts
    once, for the labelled object.
    """
    if "notes" not in events.column_names or events.num_rows == 0:
        return events
    guests = []
    for log_id, guest_id, note in zip(
        events.column("log_id").to_pylist(),
        events.column("guest_id").to_pylist(),
        events.column("notes").to_pylist(),
        strict=True,
    ):
        ids = (str(guest_id), *aliases_from_notes(str(note or "")))
        guests.append(next((g for g in ids if (str(log_id), g) in labelled), str(guest_id)))
    index = events.column_names.index("guest_id")
    return events.set_column(index, "guest_id", pa.array(guests, pa.string()))


def _pair_of_event(events: pa.Table) -> dict[str, Pair]:
    """``event_id → (log_id, guest_id)`` of the events table."""
    return {
        str(e): (str(lg), str(g))
        for e, lg, g in zip(
            events.column("event_id").to_pylist(),
            events.column("log_id").to_pylist(),
            events.column("guest_id").to_pylist(),
            strict=True,
        )
    }


def _ranked_pairs(
    store: ScenarioStore,
    events: pa.Table,
    log_ids: Sequence[str],
    embedder: Embedder,
    query: str,
) -> tuple[list[Pair], str]:
    q = embedder.embed([query])
    keys, matrix = load_embeddings(store, EMBEDDINGS_TABLE, q.model, dim=q.dim, log_ids=log_ids)
    if matrix.shape[0] == 0:
        return [], q.model
    ranked = rank(matrix, q.vectors[0])
    pair_of_event = _pair_of_event(events)
    item_ids = keys.column("item_id").to_pylist()
    pairs: list[Pair] = []
    seen: set[Pair] = set()
    for hit in ranked:
        pair = pair_of_event.get(str(item_ids[int(hit.id)]))
        if pair is not None and pair not in seen:
            seen.add(pair)
            pairs.append(pair)
    return pairs, q.model


def evaluate_braking(
    store: ScenarioStore,
    labels: Sequence[Label],
    embedder: Embedder | None = None,
    *,
    categories: CategorySet | None = None,
    queries: Mapping[str, str] | None = None,
    k_precision: int = 10,
    k_recall: int = 50,
    only_complete: bool = False,
    extra_judges: Mapping[str, Mapping[str, str]] | None = None,
) -> BrakingEvaluation:
    """Evaluate the analysed events of a store against labels (see the module docstring).

    Args:
        store: a store analysed by :func:`scenariominer.explain.pipeline.analyze_store`.
        labels: the annotations.
        embedder: embeds the free-text queries (same model as the stored descriptions); ``None``
            skips Table VI.
        categories: the known categories to score (default: the paper's four).
        queries: free-text query per labelled category (default :data:`OOD_QUERIES`); only
            categories present in the labels are evaluated.
        k_precision: precision cut-off.
        k_recall: recall cut-off.
        only_complete: evaluate only logs whose every event has an LLM answer (skips logs left
            ``pending`` by ``--limit``, so a partial LLM run is scored on the logs it finished).
        extra_judges: further columns of Table V, ``judge → (event_id → category)`` (e.g. the
            LLM alone re-judging the stored events); the stored ``category`` is the column named
            after the store's own judge, the rules' ``baseline_category`` the ``rules`` column.

    Raises:
        NoEventsError: the store has not been analysed.
        EmbeddingMismatchError: the stored embeddings come from another model than ``embedder``.
    """
    categories = categories or CategorySet.default()
    queries = OOD_QUERIES if queries is None else queries
    analyzed = _analyzed_logs(store, only_complete)
    labelled_logs = sorted({lab.log_id for lab in labels})
    logs = [lg for lg in labelled_logs if lg in analyzed]
    evaluated = [lab for lab in labels if lab.log_id in set(logs)]
    try:
        events = load_events(store, logs) if logs else None
    except NoEventsError:
        events = None
    if events is None or events.num_rows == 0:
        events = pa.table(
            {
                name: pa.array([], pa.string())
                for name in (
                    "log_id",
                    "guest_id",
                    "guest_category",
                    "event_id",
                    "category",
                    "baseline_category",
                    "llm_status",
                    "judge",
                )
            }
        )
    events = resolve_aliases(events, {lab.pair for lab in evaluated})
    detected = list(_pairs_by_category(events, "category"))
    ki_rows, ki_overall = keyident_scores(evaluated, detected)
    predictions = _predictions(events, extra_judges or {})
    cls_rows = classification_scores(evaluated, predictions, categories.scenario_names)
    pedestrians = {
        p for p, cats in _pairs_by_category(events, "guest_category").items() if "PEDESTRIAN" in cats
    }
    confusion = pedestrian_confusion(predictions, pedestrians, "obj_crossing")
    status: dict[str, int] = {}
    for s in events.column("llm_status").to_pylist():
        status[str(s)] = status.get(str(s), 0) + 1
    retrieval: list[RetrievalRow] = []
    model = ""
    present = {lab.category for lab in evaluated}
    if embedder is not None and events.num_rows:
        for cat, text in queries.items():
            if cat not in present:
                continue
            ranked, model = _ranked_pairs(store, events, logs, embedder, text)
            retrieval.append(retrieval_row(evaluated, ranked, cat, text, k_precision, k_recall))
    return BrakingEvaluation(
        n_logs=len(logs),
        n_logs_not_analyzed=len(labelled_logs) - len(logs),
        n_labels=len(evaluated),
        n_events=events.num_rows,
        llm_status=status,
        keyident=tuple(ki_rows),
        keyident_overall=ki_overall,
        classification=tuple(cls_rows),
        retrieval=tuple(retrieval),
        embedding_model=model,
        judges=tuple(predictions),
        pedestrians_as_obj_crossing=confusion,
    )


def _predictions(
    events: pa.Table, extra_judges: Mapping[str, Mapping[str, str]]
) -> dict[str, dict[Pair, list[str]]]:
    """The Table V columns: ``rules``, the store's own judge, then the extra judges."""
    stored = {str(j) for j in events.column("judge").to_pylist()} if "judge" in events.column_names else set()
    own = (stored.pop() if len(stored) == 1 else "") or "llm"  # stores before judges: the LLM's
    out = {"rules": _pairs_by_category(events, "baseline_category")}
    if own != "rules":
        out[own] = _pairs_by_category(events, "category")
    pairs = _pair_of_event(events)
    for judge, by_event in extra_judges.items():
        col: dict[Pair, list[str]] = {}
        for event_id, category in by_event.items():
            if event_id in pairs:
                col.setdefault(pairs[event_id], []).append(category)
        out[judge] = col
    return out
