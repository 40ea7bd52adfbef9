"""The stored form of analysed braking events: one row per event in the ``events`` table.

:class:`EventRecord` is the typed record; :func:`events_table` and :func:`records_from_table`
are the matching save/load pair over :data:`EVENTS_SCHEMA` (the store adds the ``log_id``
column). Per-log bookkeeping of a run (fingerprint, status, counts) lives in the ``braking_runs``
table (:data:`RUNS_SCHEMA`), one row per analysed log, so logs without events, skipped logs and
failed logs are recorded too.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import pyarrow as pa

__all__ = [
    "EMBEDDINGS_TABLE",
    "EVENTS_SCHEMA",
    "EVENTS_TABLE",
    "RUNS_SCHEMA",
    "RUNS_TABLE",
    "TAGS_TABLE",
    "EventRecord",
    "events_table",
    "json_number",
    "records_from_table",
]

#: Derived table with the per-cell tags of each log (:meth:`LogTags.to_arrow`).
TAGS_TABLE = "tags"
#: Derived table with one row per braking event (:data:`EVENTS_SCHEMA`).
EVENTS_TABLE = "events"
#: Embeddings table of the events' rephrased descriptions (``item_id`` = ``event_id``).
EMBEDDINGS_TABLE = "event_embeddings"
#: Derived table with one row per analysed log (:data:`RUNS_SCHEMA`).
RUNS_TABLE = "braking_runs"


@dataclass(frozen=True)
class EventRecord:
    """One analysed braking event, as stored.

    Attributes:
        event_id: ``<log_id>:<guest_id>:<start_ns>`` (unique in the store).
        log_id: the log.
        guest_id: the guest object's track id.
        guest_category: the guest's Argoverse 2 category.
        start_ns: first KeyIdent timestamp of the event.
        end_ns: last KeyIdent timestamp (inclusive).
        start_s: ``start_ns`` in seconds from the log's first timestamp.
        end_s: ``end_ns`` in seconds from the log's first timestamp.
        window_start_ns: first timestamp of the analysis window (event plus context).
        window_end_ns: last timestamp of the analysis window.
        closest_ns: timestamp of the closest ego–guest approach inside the event (picture key time).
        n_frames: KeyIdent timestamps in the event.
        peak_collision: highest CollisionTag in the event.
        peak_traj_overlap: highest TrajOverlapTag in the event.
        min_ttc_s: minimum time-to-collision in the window, seconds (``inf`` if none).
        min_distance_m: smallest box distance in the event, metres.
        pet_s: post-encroachment time, seconds (NaN if the paths never share a region).
        headway_s: minimum time headway behind the guest, seconds (NaN if it never leads).
        peak_decel_mps2: the ego's peak deceleration in the window, m/s².
        tag_description: the structured description given to the LLM.
        baseline_category: the rule-based baseline's category (the first rule that holds).
        rule_candidates: every category whose rule holds, comma-separated.
        facts: the event's facts as given to the LLM (who, where, speeds, gap, TTC).
        judge: who decided the category (``hybrid``, ``llm`` or ``rules``).
        llm_category: the category the LLM chose ("" when it was not asked to choose).
        category: the final category, or ``invalid`` / ``error``; while the LLM's answer is
            pending, the rules' category.
        llm_status: how the LLM answer was obtained (see ``ClassificationStatus``).
        llm_description: the LLM's rephrased description.
        explanation: the LLM's reason for the category.
        llm_raw_answer: the raw answer of an invalid classification.
        llm_error: validation or backend error.
        llm_attempts: answers requested from the LLM.
        llm_latency_s: seconds spent in the LLM (0 for cached answers).
        llm_model: the chat model.
        prompt_version: version of the prompt texts.
        categories_source: ``builtin`` or the category file.
        embedded_text: which text was embedded: ``llm`` (rephrased) or ``tags`` (no valid answer).
        embedding_model: the embedding model.
        embedding_dim: the embedding dimension.
        notes: data problems met on the way (e.g. a guest seen in one frame), ``; ``-separated.
        fingerprint: hash of every setting that determined this row.
    """

    event_id: str
    log_id: str
    guest_id: str
    guest_category: str
    start_ns: int
    end_ns: int
    start_s: float
    end_s: float
    window_start_ns: int
    window_end_ns: int
    closest_ns: int
    n_frames: int
    peak_collision: str
    peak_traj_overlap: str
    min_ttc_s: float
    min_distance_m: float
    pet_s: float
    headway_s: float
    peak_decel_mps2: float
    tag_description: str
    baseline_category: str
    rule_candidates: str
    facts: str
    judge: str
    llm_category: str
    category: str
    llm_status: str
    llm_description: str
    explanation: str
    llm_raw_answer: str
    llm_error: str
    llm_attempts: int
    llm_latency_s: float
    llm_model: str
    prompt_version: str
    categories_source: str
    embedded_text: str
    embedding_model: str
    embedding_dim: int
    notes: str
    fingerprint: str

    @property
    def duration_s(self) -> float:
        """Seconds from the first to the last KeyIdent timestamp."""
        return (self.end_ns - self.start_ns) * 1e-9


# Field annotations are strings (``from __future__ import annotations``): map them to Arrow types
# and to the value a missing (null) cell is read back as.
_ARROW_TYPES: dict[str, pa.DataType] = {"str": pa.string(), "int": pa.int64(), "float": pa.float64()}
_NULL_VALUES: dict[str, Any] = {"str": "", "int": 0, "float": math.nan}
_FIELD_KINDS: dict[str, str] = {f.name: str(f.type) for f in dataclasses.fields(EventRecord)}

#: Arrow schema of the ``events`` table (without the store's ``log_id`` column).
EVENTS_SCHEMA = pa.schema(
    [pa.field(name, _ARROW_TYPES[kind]) for name, kind in _FIELD_KINDS.items() if name != "log_id"]
)

#: Arrow schema of the ``braking_runs`` table (one row per analysed log).
RUNS_SCHEMA = pa.schema(
    [
        pa.field("fingerprint", pa.string()),
        pa.field("status", pa.string()),
        pa.field("complete", pa.bool_()),
        pa.field("n_events", pa.int64()),
        pa.field("n_classified", pa.int64()),
        pa.field("n_pending", pa.int64()),
        pa.field("error", pa.string()),
        pa.field("notes", pa.string()),
        pa.field("seconds", pa.float64()),
        pa.field("analyzed_at", pa.string()),
    ]
)


def events_table(records: Sequence[EventRecord]) -> pa.Table:
    """Build the ``events`` table of one log's records (an empty table has the full schema)."""
    columns = {
        field.name: pa.array([getattr(r, field.name) for r in records], type=field.type)
        for field in EVENTS_SCHEMA
    }
    return pa.table(columns, schema=EVENTS_SCHEMA)


def records_from_table(table: pa.Table) -> list[EventRecord]:
    """Rebuild records from an ``events`` table read from the store (with its ``log_id`` column).

    Raises:
        ValueError: a column of :class:`EventRecord` is missing.
    """
    names = list(_FIELD_KINDS)
    missing = [n for n in names if n not in table.column_names]
    if missing:
        raise ValueError(f"events table lacks column(s) {missing}; re-run the analysis")
    return [
        EventRecord(**{k: _NULL_VALUES[_FIELD_KINDS[k]] if v is None else v for k, v in row.items()})
        for row in table.select(names).to_pylist()
    ]


def json_number(value: float) -> float | None:
    """``value`` for JSON output: ``None`` for NaN and infinities (JSON has no such numbers)."""
    return value if math.isfinite(value) else None
