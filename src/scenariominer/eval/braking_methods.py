"""KeyIdent recall per identification method, recomputed from the stored logs.

The store holds the events of one configuration. To compare the key-object methods
(``tags``, ``counterfactual``, ``combined``, see :mod:`scenariominer.events.counterfactual`) on the
same logs, each labelled log is loaded again, cleaned (:func:`~scenariominer.tags.stitch.stitch_tracks`
when ``tags.stitch.enabled``), tagged once and searched by every method; no LLM is involved. A
labelled pair is found when an event names its guest or has it among its aliases (stitched ids);
such an event counts once, as the labelled pair.
When the labels file has a ``noise_level`` column, recall is also given per noise level.
"""

from __future__ import annotations

import csv
import dataclasses
from collections.abc import Sequence
from pathlib import Path

from scenariominer.config import Config
from scenariominer.config.tags import KEYIDENT_METHODS
from scenariominer.eval.braking import Label, MethodScores, Pair, keyident_scores
from scenariominer.events.counterfactual import identify_key_objects
from scenariominer.store import ScenarioStore
from scenariominer.tags.engine import tag_log
from scenariominer.tags.stitch import stitch_tracks

__all__ = ["MethodScores", "keyident_by_method", "read_noise_levels"]


def read_noise_levels(path: str | Path) -> dict[str, str]:
    """``log_id → noise level`` from a labels CSV's optional ``noise_level`` column (empty if none)."""
    with Path(path).open(newline="", encoding="utf-8") as fh:
        reader = csv.DictReader(fh)
        if "noise_level" not in (reader.fieldnames or []):
            return {}
        return {str(r["log_id"]): str(r["noise_level"] or "") for r in reader if r.get("log_id")}


def _detected_pairs(
    store: ScenarioStore, log_ids: Sequence[str], config: Config, labelled: set[Pair]
) -> dict[str, list[Pair]]:
    """``method → pairs with an event``, every method on the same tagged logs.

    A stitched guest counts as the labelled one of its ids when there is one, else as its own id.
    """
    out: dict[str, list[Pair]] = {m: [] for m in KEYIDENT_METHODS}
    for log_id in log_ids:  # one iteration per log
        stitched = stitch_tracks(store.load_log(log_id), config.tags.stitch)
        tags = tag_log(stitched.log, config.tags)
        for method in KEYIDENT_METHODS:
            cfg = dataclasses.replace(config.tags.keyident, method=method)
            for ev in identify_key_objects(stitched.log, tags, cfg, aliases=stitched.aliases):
                ids = (ev.track_id, *ev.aliases)
                out[method].append(
                    next(((log_id, g) for g in ids if (log_id, g) in labelled), (log_id, ev.track_id))
                )
    return out


def keyident_by_method(
    store: ScenarioStore,
    labels: Sequence[Label],
    config: Config,
    noise_levels: dict[str, str] | None = None,
) -> list[MethodScores]:
    """KeyIdent recall of every method on the labelled logs of a store (see the module docstring).

    Args:
        store: the store holding the logs.
        labels: the labels; their logs absent from the store are skipped.
        config: tag, stitching and KeyIdent settings (the method is varied).
        noise_levels: ``log_id → noise level``; adds one block of rows per level.

    Returns:
        For each method, the ``all`` scores, then one entry per noise level (sorted).
    """
    known = set(store.log_ids())
    logs = sorted({lab.log_id for lab in labels} & known)
    evaluated = [lab for lab in labels if lab.log_id in known]
    detected = _detected_pairs(store, logs, config, {lab.pair for lab in evaluated})
    levels = sorted(set((noise_levels or {}).values()) - {""})
    out: list[MethodScores] = []
    for method in KEYIDENT_METHODS:
        rows, overall = keyident_scores(evaluated, detected[method])
        out.append(MethodScores(method, "all", tuple(rows), overall))
        for level in levels:
            ids = {lg for lg, lv in (noise_levels or {}).items() if lv == level}
            sub = [lab for lab in evaluated if lab.log_id in ids]
            rows, overall = keyident_scores(sub, [p for p in detected[method] if p[0] in ids])
            out.append(MethodScores(method, level, tuple(rows), overall))
    return out
