"""Query by example: the stored windows nearest to one agent's window in embedding space.

The query window is the stored window of the agent that contains the given moment and is best
centred on it; when the agent has no stored window there (it was not a chosen agent, say), one is
cut on the fly with the window settings the model was trained on. It is embedded with the model and ranked
against every stored embedding of that model by cosine similarity through
:class:`scenariominer.retrieval.ExactCosineIndex` (the project's one ranking).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from scenariominer.config.represent import WindowConfig
from scenariominer.represent.errors import NoWindowsError
from scenariominer.represent.lanes import log_lane_ids
from scenariominer.represent.model_table import load_embeddings, load_model
from scenariominer.represent.stages import current_window_logs
from scenariominer.represent.window_table import load_windows, log_window_records
from scenariominer.represent.windows import WindowSet, extract_agent_window
from scenariominer.retrieval import ExactCosineIndex
from scenariominer.store import ScenarioStore

__all__ = ["SimilarHit", "SimilarResult", "parse_window_id", "similar_windows"]


@dataclass(frozen=True)
class SimilarHit:
    """One window found similar to the query.

    Attributes:
        window_id: its id.
        log_id: its log.
        track_id: its chosen agent.
        start_s: start, seconds since the log's first timestamp.
        end_s: end, seconds since the log's first timestamp.
        distance: cosine distance ``1 - cos`` of the embeddings, in ``[0, 2]``.
    """

    window_id: str
    log_id: str
    track_id: str
    start_s: float
    end_s: float
    distance: float


@dataclass(frozen=True)
class SimilarResult:
    """Result of :func:`similar_windows`: the query window, the model and the hits, nearest first."""

    query: SimilarHit
    model_id: str
    hits: tuple[SimilarHit, ...]
    searched: int


def parse_window_id(window_id: str, distance: float = 0.0) -> SimilarHit:
    """Log, track and time range encoded in a window id (``log|track|start ms|length ms``)."""
    log_id, track_id, start_ms, length_ms = window_id.rsplit("|", 3)
    start = int(start_ms) / 1000.0
    return SimilarHit(window_id, log_id, track_id, start, start + int(length_ms) / 1000.0, distance)


def _query_window(
    store: ScenarioStore, config: WindowConfig, log_id: str, track_id: str, t_s: float
) -> WindowSet:
    """The agent's stored window containing ``t_s`` (best centred), else one cut now."""
    if log_window_records(store, [log_id]):
        try:
            ws = load_windows(store, log_ids=[log_id])
        except NoWindowsError:
            ws = None
        if ws is not None:
            inside = (ws.agent_ids == track_id) & (ws.start_s <= t_s) & (t_s <= ws.start_s + ws.length_s)
            if inside.any():
                idx = np.flatnonzero(inside)
                centre_gap = np.abs(ws.start_s[idx] + 0.5 * ws.length_s[idx] - t_s)
                return ws.select([int(idx[np.argmin(centre_gap)])])
    log = store.load_log(log_id)
    if not 0.0 <= t_s <= log.duration_s:  # it was moved silently to the nearest window that fits
        raise NoWindowsError(f"t = {t_s:g} s is outside log {log_id}, which lasts {log.duration_s:.1f} s")
    length = config.lengths_s[0]
    start = float(np.clip(t_s - 0.5 * length, 0.0, max(0.0, log.duration_s - length)))
    try:
        ws = extract_agent_window(log, config, track_id, start, length, log_lane_ids(log))
    except KeyError:
        raise NoWindowsError(f"track {track_id!r} is not in log {log_id}") from None
    if len(ws) == 0:
        raise NoWindowsError(
            f"track {track_id!r} of log {log_id} is not observed over a whole {length:g} s window around "
            f"t = {t_s:g} s"
        )
    return ws


def similar_windows(
    store: ScenarioStore,
    log_id: str,
    track_id: str,
    t_s: float,
    *,
    k: int = 10,
    model_id: str | None = None,
) -> SimilarResult:
    """The ``k`` stored windows nearest to the agent's window at ``t_s`` (the query itself excluded).

    Args:
        store: the store.
        log_id: the query's log.
        track_id: the query's agent.
        t_s: the moment, seconds since the log's first timestamp.
        k: number of hits.
        model_id: the embedder (default: the most recently trained).

    Raises:
        UnknownModelError: no model.
        NoWindowsError: no query window, or nothing embedded to search.
        UnknownLogError: the log is not in the store.
    """
    record, embedder = load_model(store, model_id)
    query = _query_window(store, record.windows(), log_id, track_id, t_s)
    zq = embedder.transform(query)[0]
    wids, _lids, z = load_embeddings(store, record.model_id, current_window_logs(store, record.window_config))
    if wids.size == 0:
        raise NoWindowsError(f"no embeddings of model {record.model_id}; run scenariominer embed apply")
    index = ExactCosineIndex(z.shape[1])
    index.add(wids.tolist(), z)
    qid = str(query.window_ids[0])
    hits = [h for h in index.search(zq, k + 1) if h.id != qid][:k]
    return SimilarResult(
        query=parse_window_id(qid),
        model_id=record.model_id,
        hits=tuple(parse_window_id(h.id, 1.0 - h.score) for h in hits),
        searched=int(wids.size),
    )
