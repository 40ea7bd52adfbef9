"""Dual-path retrieval of braking events (braking paper, section III-E).

* **Category path**: events whose LLM category equals the requested one.
* **Free-text path**: the query is embedded with the same model as the stored descriptions and
  events are ranked by cosine similarity. Vectors of another model or dimension are refused with
  :class:`~scenariominer.store.EmbeddingMismatchError` instead of giving meaningless scores.

Both paths can filter by criticality (``min_decel_mps2``, ``max_ttc_s``) and sort by a measure
(:class:`SortKey`); a text query combined with a category searches inside that category.
"""

from __future__ import annotations

import math
from collections.abc import Collection, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import pyarrow as pa
import pyarrow.compute as pc

from scenariominer import errors as _errors
from scenariominer.explain.records import (
    EMBEDDINGS_TABLE,
    EVENTS_TABLE,
    EventRecord,
    json_number,
    records_from_table,
)
from scenariominer.llm.embeddings import Embedder
from scenariominer.retrieval import rank
from scenariominer.schema import SortKey
from scenariominer.store import ScenarioStore, UnknownTableError
from scenariominer.store.vectors import load_embeddings

__all__ = [
    "NoEventsError",
    "SearchHit",
    "InvalidSearchError",
    "SearchQuery",
    "SortKey",
    "load_events",
    "search_events",
]


class NoEventsError(_errors.ExplainError, LookupError):
    """The store holds no analysed events (run ``scenariominer analyze`` first)."""

    def __init__(self, root: str) -> None:
        super().__init__(f"store {root} holds no analysed braking events; run `scenariominer analyze` first")


class InvalidSearchError(_errors.ExplainError, ValueError):
    """A search that cannot mean anything: an empty text, ``k`` below 1, an unknown category."""


@dataclass(frozen=True)
class SearchQuery:
    """What to look for.

    Attributes:
        text: free-text scenario description (embedding path); ``None`` for the category path only.
        category: LLM category to match; ``None`` matches every category.
        k: maximum number of results.
        min_decel_mps2: keep events whose peak deceleration is at least this (m/s²).
        max_ttc_s: keep events whose minimum time-to-collision is at most this (s).
        sort: result order. A text query keeps the ``k`` most similar events and orders them by
            this key (``None``: by score); the category path orders every match by it and keeps
            the first ``k`` (``None``: by log and time).
    """

    text: str | None = None
    category: str | None = None
    k: int = 10
    min_decel_mps2: float | None = None
    max_ttc_s: float | None = None
    sort: SortKey | None = None

    def __post_init__(self) -> None:
        if self.k < 1:
            raise InvalidSearchError(f"k must be at least 1, got {self.k}")
        if self.text is not None and not self.text.strip():
            raise InvalidSearchError("the text query is empty: describe the scenario, or leave it out")
        if self.text is None and self.sort is SortKey.SCORE:
            raise InvalidSearchError("sorting by score needs a text query")


@dataclass(frozen=True)
class SearchHit:
    """One retrieved event.

    Attributes:
        event: the stored event (log id, guest id, window, category, explanation, criticality).
        score: cosine similarity to the text query; NaN on the category path.
    """

    event: EventRecord
    score: float

    def to_json_dict(self) -> dict[str, Any]:
        """The fields a user needs, JSON-safe (NaN and infinities become ``null``)."""
        e = self.event
        return {
            "event_id": e.event_id,
            "log_id": e.log_id,
            "guest_id": e.guest_id,
            "guest_category": e.guest_category,
            "start_ns": e.start_ns,
            "end_ns": e.end_ns,
            "duration_s": e.duration_s,
            "category": e.category,
            "explanation": e.explanation,
            "description": e.llm_description,
            "baseline_category": e.baseline_category,
            "score": json_number(self.score),
            "min_ttc_s": json_number(e.min_ttc_s),
            "pet_s": json_number(e.pet_s),
            "headway_s": json_number(e.headway_s),
            "peak_decel_mps2": json_number(e.peak_decel_mps2),
        }


def load_events(store: ScenarioStore, log_ids: Sequence[str] | None = None) -> pa.Table:
    """The ``events`` table of the store (or of some logs).

    Raises:
        NoEventsError: no log has been analysed.
    """
    try:
        return store.read_table(EVENTS_TABLE, log_ids)
    except UnknownTableError:
        raise NoEventsError(str(store.root)) from None


def _filter(table: pa.Table, query: SearchQuery) -> pa.Table:
    mask = pa.array(np.ones(table.num_rows, dtype=bool))
    if query.category is not None:
        mask = pc.and_(mask, pc.equal(table.column("category"), query.category))
    if query.min_decel_mps2 is not None:
        mask = pc.and_(mask, pc.greater_equal(table.column("peak_decel_mps2"), query.min_decel_mps2))
    if query.max_ttc_s is not None:
        mask = pc.and_(mask, pc.less_equal(table.column("min_ttc_s"), query.max_ttc_s))
    return table.filter(pc.fill_null(mask, False))


def _sort_value(hit: SearchHit, key: SortKey) -> float:
    """Ascending sort value; NaN sorts last."""
    e = hit.event
    value = {
        SortKey.SCORE: -hit.score,
        SortKey.TTC: e.min_ttc_s,
        SortKey.DECEL: -e.peak_decel_mps2,
        SortKey.PET: e.pet_s,
        SortKey.HEADWAY: e.headway_s,
    }[key]
    return math.inf if math.isnan(value) else value


def search_events(
    store: ScenarioStore,
    query: SearchQuery,
    embedder: Embedder | None = None,
    log_ids: Sequence[str] | None = None,
    known_categories: Collection[str] | None = None,
) -> list[SearchHit]:
    """Retrieve events by category and/or free text, filtered and sorted by criticality.

    Args:
        store: the store.
        query: what to look for.
        embedder: embeds ``query.text``; must be the model the descriptions were embedded with.
        log_ids: restrict the search to these logs.
        known_categories: the configured category names; a ``query.category`` that is neither one
            of them nor on a stored event is an error (a typo matched nothing without a word).
            ``None`` checks nothing.

    Returns:
        At most ``query.k`` hits.

    Raises:
        NoEventsError: the store holds no analysed events.
        InvalidSearchError: an unknown category.
        ValueError: a text query without an embedder.
        EmbeddingMismatchError: the stored vectors come from another model or dimension.
    """
    events = load_events(store, log_ids)
    if query.category is not None and known_categories is not None:
        stored = set(events.column("category").to_pylist())
        if query.category not in stored and query.category not in set(known_categories):
            raise InvalidSearchError(
                f"unknown category {query.category!r}; the events' categories: {', '.join(sorted(stored))}"
            )
    table = _filter(events, query)
    records = records_from_table(table)
    scores = np.full(len(records), np.nan)
    if query.text is not None:
        if embedder is None:
            raise ValueError("a text query needs an embedder")
        q = embedder.embed([query.text])
        keys, matrix = load_embeddings(store, EMBEDDINGS_TABLE, q.model, dim=q.dim, log_ids=log_ids)
        ranked = rank(matrix, q.vectors[0], keys.column("item_id").to_pylist())
        by_event = {h.id: h.score for h in ranked}
        scores = np.array([by_event.get(r.event_id, np.nan) for r in records], dtype=np.float64)
        keep = np.isfinite(scores)
        records = [r for r, ok in zip(records, keep, strict=True) if ok]
        scores = scores[keep]
    hits = [SearchHit(r, float(s)) for r, s in zip(records, scores, strict=True)]
    if query.text is not None:
        # The k most similar events, then (optionally) ordered by a criticality measure.
        hits.sort(key=lambda h: (_sort_value(h, SortKey.SCORE), h.event.log_id, h.event.start_ns))
        hits = hits[: query.k]
        if query.sort is not None and query.sort is not SortKey.SCORE:
            hits.sort(key=lambda h: (_sort_value(h, query.sort or SortKey.SCORE), -h.score))
        return hits
    if query.sort is None:
        hits.sort(key=lambda h: (h.event.log_id, h.event.start_ns, h.event.guest_id))
    else:
        hits.sort(
            key=lambda h: (_sort_value(h, query.sort or SortKey.SCORE), h.event.log_id, h.event.start_ns)
        )
    return hits[: query.k]
