"""The labelled synthetic case set: balanced over the risk types, split into case base and hold-out.

For each risk type, scenes are drawn (:mod:`.scenes`) until ``per_type`` labelled ones exist
(discarded draws are counted); their texts come from :mod:`.captions`. The first
``holdout_per_type`` of each risk type form the hold-out split, stored in its own corpus table
(``<table>_holdout``) with every manoeuvre's rollout outcome, and are never added to the case
base; the rest go through :meth:`CaseBase.add` (so near-duplicates are reported and skipped).
"""

from __future__ import annotations

import time
from collections import Counter
from dataclasses import dataclass
from typing import Any

import numpy as np

from scenariominer.cbr.captions import case_from_scene
from scenariominer.cbr.cases import AddReport, Case, CaseBase
from scenariominer.cbr.scenes import LabelledScene, draw_scene, label_scene
from scenariominer.cbr.vocab import CbrError, ManoeuvreSet
from scenariominer.store import ScenarioStore
from scenariominer.store.corpus import CorpusTable

__all__ = [
    "HOLDOUT_SCHEMA_VERSION",
    "BuildReport",
    "HoldoutCase",
    "draw_labelled",
    "holdout_table",
    "read_holdout",
]

HOLDOUT_SCHEMA_VERSION = 1
_MAX_DRAWS_PER_CASE = 50
_TOP_UP_ROUNDS = 8


@dataclass(frozen=True)
class HoldoutCase:
    """A hold-out case and the rollout outcome of every manoeuvre on its scene (``avoided`` by name)."""

    case: Case
    avoided: dict[str, bool]
    min_distance_m: dict[str, float]


@dataclass(frozen=True)
class BuildReport:
    """What ``cbr build`` wrote.

    Attributes:
        n_case_base: cases stored in the case base.
        n_holdout: cases stored in the hold-out split.
        n_drawn: scenes drawn (labelled + discarded).
        labels: ground-truth manoeuvre counts per risk type (both splits).
        add: the case-base add report (near-duplicates, rejected rows).
        seconds: wall-clock time.
    """

    n_case_base: int
    n_holdout: int
    n_drawn: int
    labels: dict[str, dict[str, int]]
    add: AddReport
    seconds: float

    def to_json_dict(self) -> dict[str, Any]:
        """JSON-ready form."""
        return {
            "n_case_base": self.n_case_base,
            "n_holdout": self.n_holdout,
            "n_drawn": self.n_drawn,
            "labels": self.labels,
            "duplicates": len(self.add.duplicates),
            "rejected": len(self.add.rejected),
            "seconds": self.seconds,
        }


def draw_labelled(
    rng: np.random.Generator,
    risk_type: str,
    n: int,
    manoeuvres: ManoeuvreSet,
    first_index: int,
    max_speed_mps: float,
) -> tuple[list[LabelledScene], int]:
    """``n`` labelled scenes of ``risk_type`` (ids numbered from ``first_index``) and the draws used.

    Raises:
        CbrError: the risk type yields too few labelled scenes within the draw budget.
    """
    got: list[LabelledScene] = []
    drawn = 0
    while len(got) < n:
        if drawn >= max(n, 1) * _MAX_DRAWS_PER_CASE:
            raise CbrError(f"risk type {risk_type}: only {len(got)} of {n} scenes could be labelled")
        drawn += 1
        scene = draw_scene(rng, risk_type, f"{risk_type}-{first_index + len(got):04d}")
        labelled = label_scene(scene, manoeuvres, max_speed_mps=max_speed_mps)
        if labelled is not None:
            got.append(labelled)
    return got, drawn


def holdout_table(store: ScenarioStore, table: str) -> CorpusTable:
    """The corpus table of the hold-out split of case table ``table``."""
    return store.corpus(f"{table}_holdout", HOLDOUT_SCHEMA_VERSION)


def read_holdout(store: ScenarioStore, table: str) -> list[HoldoutCase]:
    """Every hold-out case, in id order."""
    out = []
    for r in holdout_table(store, table).rows():
        d = dict(r.data)
        outcomes = d.pop("outcomes")
        case = Case.from_mapping(d)
        out.append(
            HoldoutCase(
                case,
                {k: bool(v["avoided"]) for k, v in outcomes.items()},
                {
                    k: float(v["min_distance_m"]) if v["min_distance_m"] is not None else float("inf")
                    for k, v in outcomes.items()
                },
            )
        )
    return out


def build_case_set(
    base: CaseBase,
    store: ScenarioStore,
    embedder: Any,
    *,
    per_type: int,
    holdout_per_type: int,
    seed: int,
    threshold: float,
    max_speed_mps: float,
) -> BuildReport:
    """Draw, label and store the synthetic case set, replacing the old one (module docstring).

    Near-duplicates of stored captions are skipped and replaced by fresh draws (at most
    ``_TOP_UP_ROUNDS`` rounds per risk type), so the case base reaches ``per_type -
    holdout_per_type`` cases per risk type unless the scenes run out of variety.

    Raises:
        CbrError: ``holdout_per_type >= per_type`` or a risk type cannot be labelled.
    """
    if not 0 <= holdout_per_type < per_type:
        raise CbrError("holdout_per_type must be >= 0 and smaller than per_type")
    start = time.perf_counter()
    rng = np.random.default_rng(seed)
    text_rng = np.random.default_rng(seed + 1)
    base.clear()
    holdout_table(store, base.table.name).clear()
    base.table = store.corpus(base.table.name, base.table.schema_version)
    hold = holdout_table(store, base.table.name)
    labels: dict[str, Counter[str]] = {}
    drawn_total = 0
    added: list[str] = []
    duplicates: list[Any] = []
    rejected: list[tuple[str, str]] = []
    hold_rows: dict[str, dict[str, Any]] = {}
    for rt in base.risk_types.names:
        labels[rt] = Counter()
        held, drawn = draw_labelled(rng, rt, holdout_per_type, base.manoeuvres, 0, max_speed_mps)
        drawn_total += drawn
        for item in held:
            case = case_from_scene(item, base.manoeuvres, text_rng)
            outcomes = {k: {**o.to_json_dict(), "avoided": o.avoided} for k, o in item.outcomes.items()}
            hold_rows[case.case_id] = {**case.to_json_dict(), "outcomes": outcomes}
            labels[rt][item.manoeuvre] += 1
        need, index = per_type - holdout_per_type, holdout_per_type
        for _round in range(_TOP_UP_ROUNDS):
            if need <= 0:
                break
            batch, drawn = draw_labelled(rng, rt, need, base.manoeuvres, index, max_speed_mps)
            drawn_total += drawn
            index += len(batch)
            report = base.add(
                [case_from_scene(x, base.manoeuvres, text_rng) for x in batch], embedder, threshold
            )
            kept = set(report.added)
            for x in batch:
                if f"syn-{x.scene.scene_id}" in kept:
                    labels[rt][x.manoeuvre] += 1
            added += report.added
            duplicates += report.duplicates
            rejected += report.rejected
            need -= len(report.added)
    if hold_rows:
        hold.upsert(hold_rows)
    return BuildReport(
        len(added),
        len(hold_rows),
        drawn_total,
        {rt: dict(c) for rt, c in labels.items()},
        AddReport(tuple(added), tuple(duplicates), tuple(rejected)),
        time.perf_counter() - start,
    )
