"""The case base: one corpus table of the store, one row per case (section 3.2).

A case is ``<key: risk type, scene event caption; value: road context, other vehicle position,
other vehicle action, event context, ego evasive manoeuvre, manoeuvre justification>`` plus its
provenance. Each row keeps the caption's embedding as its binary payload (float32 bytes) with the
embedding model's name, so retrieval needs no re-embedding and a change of model is noticed.

Adding is checked: unknown risk types or manoeuvres are rejected with the reason; a caption whose
cosine similarity with a stored case (or an earlier case of the same batch) of the same risk type
reaches the duplicate threshold is reported as a near-duplicate and not stored. Rows of a batch
are independent: a bad one is reported and the rest are stored.
"""

from __future__ import annotations

import csv
import dataclasses
import hashlib
import io
import json
import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from scenariominer.cbr.vocab import CbrError, ManoeuvreSet, RiskTypeSet
from scenariominer.llm.embeddings import Embedder
from scenariominer.llm.errors import EmbeddingMismatchError
from scenariominer.retrieval import rank
from scenariominer.store import ScenarioStore
from scenariominer.store.corpus import CorpusTable

__all__ = [
    "CASE_FIELDS",
    "SCHEMA_VERSION",
    "AddReport",
    "Case",
    "CaseBase",
    "Duplicate",
    "read_case_file",
]

#: Layout version of the case rows (``data`` = the case fields + embedding model and dimension).
SCHEMA_VERSION = 1
#: The value fields of a case, in the chain-of-thought order of the prompt.
VALUE_FIELDS: tuple[str, ...] = (
    "road_context",
    "other_vehicle_position",
    "other_vehicle_action",
    "event_context",
    "manoeuvre",
    "justification",
)
#: Every field of an import row (``risk_type``, ``caption``, ``manoeuvre`` required).
CASE_FIELDS: tuple[str, ...] = (
    "case_id",
    "risk_type",
    "caption",
    *VALUE_FIELDS,
    "source",
    "log_id",
    "event_id",
    "time_s",
)


@dataclass(frozen=True)
class Case:
    """One case.

    Attributes:
        case_id: unique id (default: hash of risk type and caption).
        risk_type: risk type name (key).
        caption: scene event caption (key; embedded for retrieval).
        road_context, other_vehicle_position, other_vehicle_action, event_context: the analysis.
        manoeuvre: the evasive manoeuvre taken (a configured manoeuvre name).
        justification: why it resolves the risk.
        source: ``synthetic``, ``import:<file>``, ``event`` or another provenance tag.
        log_id, event_id: the log and event the case comes from (may be empty).
        time_s: time of the conflict in the log, seconds from its start (NaN if unknown).
    """

    case_id: str
    risk_type: str
    caption: str
    road_context: str = ""
    other_vehicle_position: str = ""
    other_vehicle_action: str = ""
    event_context: str = ""
    manoeuvre: str = ""
    justification: str = ""
    source: str = ""
    log_id: str = ""
    event_id: str = ""
    time_s: float = math.nan

    @staticmethod
    def make_id(risk_type: str, caption: str) -> str:
        """The default id: ``c`` + 12 hex digits of SHA-1 over risk type and caption."""
        digest = hashlib.sha1(f"{risk_type}\n{caption}".encode()).hexdigest()
        return f"c{digest[:12]}"

    def answer(self) -> dict[str, str]:
        """The value fields, in prompt order (what the model is asked to produce)."""
        return {f: str(getattr(self, f)) for f in VALUE_FIELDS}

    def to_json_dict(self) -> dict[str, Any]:
        """Every field (``time_s`` NaN as ``None``)."""
        d = dataclasses.asdict(self)
        d["time_s"] = None if not math.isfinite(self.time_s) else self.time_s
        return d

    @classmethod
    def from_mapping(cls, row: Mapping[str, Any]) -> Case:
        """Build a case from a mapping of field names (missing id: the default one).

        Raises:
            CbrError: ``risk_type`` or ``caption`` is missing or empty, or ``time_s`` is not a number.
        """
        risk = str(row.get("risk_type") or "").strip()
        caption = " ".join(str(row.get("caption") or "").split())
        if not risk or not caption:
            raise CbrError("a case needs a risk_type and a caption")
        values = {f: " ".join(str(row.get(f) or "").split()) for f in VALUE_FIELDS}
        raw_time = row.get("time_s")
        try:
            time_s = math.nan if raw_time in (None, "") else float(raw_time)  # type: ignore[arg-type]
        except (TypeError, ValueError):
            raise CbrError(f"time_s must be a number, got {raw_time!r}") from None
        return cls(
            case_id=str(row.get("case_id") or "").strip() or cls.make_id(risk, caption),
            risk_type=risk,
            caption=caption,
            source=str(row.get("source") or ""),
            log_id=str(row.get("log_id") or ""),
            event_id=str(row.get("event_id") or ""),
            time_s=time_s,
            **values,
        )


@dataclass(frozen=True)
class Duplicate:
    """A case not stored because a stored one has nearly the same caption (same risk type)."""

    case_id: str
    existing_id: str
    similarity: float


@dataclass(frozen=True)
class AddReport:
    """What an add did: ids stored, near-duplicates skipped, rows rejected with the reason."""

    added: tuple[str, ...]
    duplicates: tuple[Duplicate, ...]
    rejected: tuple[tuple[str, str], ...]

    def to_json_dict(self) -> dict[str, Any]:
        """JSON-ready form."""
        return {
            "added": list(self.added),
            "duplicates": [dataclasses.asdict(d) for d in self.duplicates],
            "rejected": [{"row": r, "reason": why} for r, why in self.rejected],
        }


def _case_from_row(data: Mapping[str, Any]) -> Case:
    kwargs = {f.name: data.get(f.name, f.default) for f in dataclasses.fields(Case)}
    t = kwargs.get("time_s")
    kwargs["time_s"] = math.nan if t is None else float(t)
    return Case(**kwargs)


class CaseBase:
    """The case base held in the store's corpus table ``table``.

    Args:
        store: the scenario store.
        table: corpus table name (``cbr.table``).
        risk_types, manoeuvres: the configured vocabularies (cases are checked against them).
    """

    def __init__(
        self, store: ScenarioStore, table: str, risk_types: RiskTypeSet, manoeuvres: ManoeuvreSet
    ) -> None:
        self.table: CorpusTable = store.corpus(table, SCHEMA_VERSION)
        self.risk_types = risk_types
        self.manoeuvres = manoeuvres

    def __len__(self) -> int:
        return self.table.info().n_rows

    # ------------------------------------------------------------------ reading
    def cases(self, risk_type: str | None = None) -> list[Case]:
        """Every case (of one risk type), in id order."""
        out = [_case_from_row(r.data) for r in self.table.rows()]
        return [c for c in out if risk_type is None or c.risk_type == risk_type]

    def get(self, case_id: str) -> Case:
        """The case ``case_id``.

        Raises:
            CbrError: no such case.
        """
        row = self.table.get(case_id)
        if row is None:
            raise CbrError(f"no case {case_id!r} in the case base ({self.table.name})")
        return _case_from_row(row.data)

    def vectors(
        self, embedder_model: str, risk_type: str | None = None
    ) -> tuple[list[Case], NDArray[np.float32]]:
        """Cases (of one risk type) and their caption vectors ``(K, D)``.

        Raises:
            EmbeddingMismatchError: stored vectors come from another embedding model.
        """
        cases: list[Case] = []
        vecs: list[NDArray[np.float32]] = []
        for r in self.table.rows(with_blobs=True):
            case = _case_from_row(r.data)
            if risk_type is not None and case.risk_type != risk_type:
                continue
            model, dim = str(r.data.get("embedding_model", "")), int(r.data.get("embedding_dim", 0))
            if model != embedder_model:
                raise EmbeddingMismatchError(
                    (embedder_model, dim), (model, dim), f"case base {self.table.name!r} (rebuild it)"
                )
            cases.append(case)
            vecs.append(np.frombuffer(r.blob or b"", dtype=np.float32))
        if not vecs:
            return [], np.zeros((0, 0), np.float32)
        return cases, np.vstack(vecs)

    # ------------------------------------------------------------------ writing
    def check(self, case: Case) -> None:
        """Raise :class:`CbrError` unless the case's risk type and manoeuvre are configured."""
        self.risk_types.get(case.risk_type)
        if case.manoeuvre:
            self.manoeuvres.get(case.manoeuvre)
        else:
            raise CbrError(f"case {case.case_id}: no manoeuvre")

    def add(self, cases: Sequence[Case], embedder: Embedder, threshold: float) -> AddReport:
        """Store ``cases`` unless invalid or near-duplicates (see the module docstring)."""
        rejected: list[tuple[str, str]] = []
        good: list[Case] = []
        for c in cases:
            try:
                self.check(c)
            except CbrError as exc:
                rejected.append((c.case_id, str(exc)))
                continue
            good.append(c)
        if not good:
            return AddReport((), (), tuple(rejected))
        emb = embedder.embed([c.caption for c in good])
        stored_cases, stored = self.vectors(emb.model) if len(self) else ([], np.zeros((0, 0), np.float32))
        by_type: dict[str, tuple[list[str], list[NDArray[np.float32]]]] = {}
        for c, v in zip(stored_cases, stored, strict=True):
            ids, vs = by_type.setdefault(c.risk_type, ([], []))
            ids.append(c.case_id)
            vs.append(v)
        rows: dict[str, dict[str, Any]] = {}
        blobs: dict[str, bytes] = {}
        duplicates: list[Duplicate] = []
        for c, v in zip(good, emb.vectors, strict=True):
            ids, vs = by_type.setdefault(c.risk_type, ([], []))
            if c.case_id in ids:
                duplicates.append(Duplicate(c.case_id, c.case_id, 1.0))
                continue
            if vs and np.any(v):
                best = rank(np.vstack(vs), v, ids)[0]
                if best.score >= threshold:
                    duplicates.append(Duplicate(c.case_id, best.id, round(float(best.score), 4)))
                    continue
            ids.append(c.case_id)
            vs.append(np.asarray(v, np.float32))
            rows[c.case_id] = {**c.to_json_dict(), "embedding_model": emb.model, "embedding_dim": emb.dim}
            blobs[c.case_id] = np.asarray(v, np.float32).tobytes()
        if rows:
            self.table.upsert(rows, blobs)
        return AddReport(tuple(rows), tuple(duplicates), tuple(rejected))

    def remove(self, case_ids: Iterable[str]) -> int:
        """Delete cases; returns how many existed."""
        return self.table.delete(list(case_ids))

    def clear(self) -> None:
        """Delete every case."""
        self.table.clear()


def _manoeuvre_name(value: str, manoeuvres: ManoeuvreSet) -> str:
    """Accept a manoeuvre by name or by its label (case-insensitive)."""
    v = value.strip()
    for m in manoeuvres.manoeuvres:
        if v == m.name or v.lower() == m.label.lower():
            return m.name
    return v


def read_case_file(path: Path, manoeuvres: ManoeuvreSet) -> tuple[list[Case], list[tuple[str, str]]]:
    """Read cases from a CSV (header row) or JSONL file (one object a line); see docs/cbr.md.

    Returns:
        ``(cases, rejected)``: rows that became cases, and ``(row label, reason)`` for the others.

    Raises:
        CbrError: the file cannot be read or has an unknown extension.
    """
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise CbrError(f"{path}: cannot read: {exc}") from None
    rows: list[tuple[str, Any]] = []
    if path.suffix.lower() == ".csv":
        reader = csv.DictReader(io.StringIO(text))
        rows = [(f"{path.name}:{i + 2}", r) for i, r in enumerate(reader)]
    elif path.suffix.lower() in (".jsonl", ".ndjson"):
        for i, line in enumerate(text.splitlines()):
            if line.strip():
                try:
                    rows.append((f"{path.name}:{i + 1}", json.loads(line)))
                except json.JSONDecodeError as exc:
                    rows.append((f"{path.name}:{i + 1}", f"not JSON: {exc.msg}"))
    else:
        raise CbrError(f"{path}: unknown case file type {path.suffix!r} (use .csv or .jsonl)")
    cases: list[Case] = []
    rejected: list[tuple[str, str]] = []
    for label, row in rows:
        if not isinstance(row, Mapping):
            rejected.append((label, row if isinstance(row, str) else "not a JSON object"))
            continue
        unknown = sorted(set(row) - set(CASE_FIELDS))
        if unknown:
            rejected.append((label, f"unknown field(s) {unknown}; known: {list(CASE_FIELDS)}"))
            continue
        try:
            case = Case.from_mapping({**row, "source": row.get("source") or f"import:{path.name}"})
        except CbrError as exc:
            rejected.append((label, str(exc)))
            continue
        cases.append(dataclasses.replace(case, manoeuvre=_manoeuvre_name(case.manoeuvre, manoeuvres)))
    return cases, rejected
