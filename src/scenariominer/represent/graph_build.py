"""Store stage: descriptions, graph, communities and LLM summaries of every windowed log, incrementally.

A graph belongs to one clustering of one embedder (``graph id`` = ``<model id>``), or to no
embedder (``graph id`` = ``windows``: descriptions and graph without clusters). A log is
(re)described only when its windows or its cluster labels changed since its rows were written
(its ``source`` stamp); other logs' rows are left as they are. Communities are recomputed over the
merged graph (no model call), and LLM summaries are asked only for clusters and communities whose
inputs changed (:mod:`.summaries`).
"""

from __future__ import annotations

import functools
import hashlib
import json
from collections.abc import Sequence
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from scenariominer.errors import ScenarioMinerError
from scenariominer.llm.client import ChatClient
from scenariominer.llm.embeddings import Embedder
from scenariominer.progress import NullProgress, Progress
from scenariominer.represent.cluster import latest_clustering, load_labels
from scenariominer.represent.describe import DescribeSettings, WindowDescription, describe_windows
from scenariominer.represent.errors import NoWindowsError
from scenariominer.represent.graph import (
    EMBEDDED_ENTITIES,
    EMBEDDED_RELATIONS,
    CommunityLevel,
    GraphElements,
    graph_elements,
    graph_logs,
    leiden_communities,
    load_graph,
    save_log_graph,
)
from scenariominer.represent.graph_store import GraphNotBuiltError
from scenariominer.represent.model_table import list_models, load_embeddings
from scenariominer.represent.summaries import SummarySettings, cluster_summaries, community_reports
from scenariominer.represent.window_table import load_windows, log_window_records
from scenariominer.store import ScenarioStore

__all__ = [
    "COMMUNITIES_TABLE",
    "GraphBuildReport",
    "GraphSettings",
    "build_store_graph",
    "load_communities",
    "resolve_graph_id",
]

COMMUNITIES_TABLE = "graph_communities"
_SCHEMA = 1
_BATCH_LOGS = 64

Float32Array = NDArray[np.float32]


@dataclass(frozen=True)
class GraphSettings:
    """Settings of the graph stage.

    Attributes:
        resolutions: Leiden resolution per community level, coarse to fine.
        describe: thresholds of the template descriptions.
        summaries: how many samples and communities the LLM sees.
        seed: Leiden seed.
    """

    # Chosen from the community sizes of a 2,435-window SUMO graph (not from retrieval scores): at
    # 0.05 and 0.3 everything is one community (the lane, manoeuvre and traffic hubs tie it
    # together); 0.5 splits it in two, 0.85 into a handful of large communities, 1.0 also isolates
    # each quiet sample with its vehicles.
    resolutions: tuple[float, ...] = (0.5, 0.85, 1.0)
    describe: DescribeSettings = DescribeSettings()
    summaries: SummarySettings = SummarySettings()
    seed: int = 0


@dataclass(frozen=True)
class GraphBuildReport:
    """Result of :func:`build_store_graph`.

    Attributes:
        graph_id: the graph.
        clustering_id: the clustering whose labels the samples carry (``""``: none).
        n_logs: logs in the graph.
        n_logs_built: logs (re)described now.
        n_samples: samples in the graph.
        n_entities: entities.
        n_relationships: relationships.
        communities_per_level: communities found at each level.
        n_summaries: cluster summaries, contrasts and community reports available.
        n_llm_calls: summaries asked now (the rest came from the store).
        failed: ``(log id, reason)`` of logs that could not be described.
        failed_summaries: ``(summary, reason)`` of summaries the model did not give (a garbled
            answer); asked again by the next build.
    """

    graph_id: str
    clustering_id: str
    n_logs: int
    n_logs_built: int
    n_samples: int
    n_entities: int
    n_relationships: int
    communities_per_level: tuple[int, ...]
    n_summaries: int
    n_llm_calls: int
    failed: tuple[tuple[str, str], ...]
    failed_summaries: tuple[tuple[str, str], ...] = ()


def resolve_graph_id(store: ScenarioStore, model_id: str | None, loss: str | None) -> str:
    """``model_id``, the latest model (with ``loss``), or ``windows`` when the store has no model."""
    if model_id:
        return model_id
    models = [m for m in list_models(store) if loss is None or m.loss == loss]
    if models:
        return models[0].model_id
    return "windows"


#: Bumped when descriptions change for the same windows, so stored logs are described again.
DESCRIPTION_VERSION = 2


def _source(window_config: str, clustering_id: str, labels: Sequence[int]) -> str:
    text = json.dumps([DESCRIPTION_VERSION, window_config, clustering_id, list(labels)])
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def _embed_batch(
    described: dict[str, tuple[list[WindowDescription], GraphElements]],
    embedder: Embedder,
    failed: list[tuple[str, str]],
) -> dict[str, tuple[list[WindowDescription], GraphElements, dict[str, Float32Array]]]:
    """Vectors of each log's descriptions, entities and relationships, each distinct text embedded once.

    Lanes, manoeuvres and traffic states repeat across the logs of a batch, so one call over the
    distinct texts replaces one per log (about a third of the texts are distinct).
    """
    texts: dict[str, tuple[list[str], list[str], list[str]]] = {}
    for lid, (descs, els) in described.items():
        texts[lid] = (
            [d.text for d in descs],
            [e.text for e in els.entities if e.kind in EMBEDDED_ENTITIES],
            [r.text for r in els.relationships if r.kind in EMBEDDED_RELATIONS],
        )
    unique = sorted({t for parts in texts.values() for part in parts for t in part})
    try:
        vectors = embedder.embed(unique).vectors if unique else np.zeros((0, 0), np.float32)
    except Exception as exc:  # noqa: BLE001 -- the batch's logs are reported, later batches go on
        failed.extend((lid, f"{type(exc).__name__}: {exc}") for lid in described)
        return {}
    row = {t: i for i, t in enumerate(unique)}
    out = {}
    for lid, (descs, els) in described.items():
        d_t, e_t, r_t = texts[lid]
        out[lid] = (
            descs,
            els,
            {
                "samples": vectors[[row[t] for t in d_t]],
                "entities": vectors[[row[t] for t in e_t]],
                "relationships": vectors[[row[t] for t in r_t]],
            },
        )
    return out


@functools.lru_cache(maxsize=64)
def _meta_frame_rate(path: str) -> float | None:
    from scenariominer.data.adapters.highd import HighDFiles
    from scenariominer.data.adapters.highd.format import read_recording_meta

    files = HighDFiles.from_path(Path(path))
    return None if files is None else float(read_recording_meta(files.recording_meta).frame_rate_hz)


def _recording_frame_rate(store: ScenarioStore, log_id: str) -> float | None:
    """Frame rate of the highD-format recording a log came from (``None``: not one, or unreadable).

    Frames cited in descriptions must be the recording's own (SUMO-made recordings run at 10 Hz,
    real highD at 25 Hz).
    """
    try:
        meta = store.log_meta(log_id)
        if meta.dataset != "highd" or not meta.source_path:
            return None
        return _meta_frame_rate(str(meta.source_path))
    except (OSError, LookupError, ValueError, ScenarioMinerError):  # no such log or no readable meta
        return None


def build_store_graph(
    store: ScenarioStore,
    graph_id: str,
    embedder: Embedder,
    client: ChatClient | None = None,
    settings: GraphSettings | None = None,
    progress: Progress | None = None,
) -> GraphBuildReport:
    """Describe new or changed logs, store the graph, recompute communities, summarise (if ``client``)."""
    s = settings or GraphSettings()
    bar = progress or NullProgress()
    records = log_window_records(store)
    clustering = latest_clustering(store, graph_id) if graph_id != "windows" else None
    cid = clustering.clustering_id if clustering else ""
    logs = sorted(lid for lid, rec in records.items() if rec.window_ids)
    if not logs:  # it said "no graph ...; build it first (scenariominer graph build)", its own command
        raise NoWindowsError(
            "no trajectory windows in the store to describe; run scenariominer embed windows first"
        )
    labels = load_labels(store, cid, logs) if cid else None
    label_of = dict(zip(labels.window_ids.tolist(), labels.labels.tolist(), strict=True)) if labels else {}
    stored = graph_logs(store, graph_id)
    wanted = {
        lid: _source(records[lid].config, cid, [label_of.get(w, -2) for w in records[lid].window_ids])
        for lid in logs
    }
    todo = [lid for lid in logs if stored.get(lid) != wanted[lid]]
    failed: list[tuple[str, str]] = []
    bar.start("describing logs", total=len(todo))
    for b in range(0, len(todo), _BATCH_LOGS):
        batch = todo[b : b + _BATCH_LOGS]
        described = {}
        for lid in batch:
            try:
                ws = load_windows(store, log_ids=[lid])
                clusters = (
                    np.asarray([label_of.get(w, -1) for w in ws.window_ids.tolist()], np.int64)
                    if cid
                    else None
                )
                rate = _recording_frame_rate(store, lid)
                describe = s.describe if rate is None else replace(s.describe, highd_frame_rate_hz=rate)
                descs = describe_windows(ws, clusters, describe)
                described[lid] = (descs, graph_elements(descs, graph_id))
            except Exception as exc:  # noqa: BLE001 -- one bad log must not stop the batch
                failed.append((lid, f"{type(exc).__name__}: {exc}"))
                bar.advance()
        by_log = _embed_batch(described, embedder, failed)
        bar.advance(len(described))
        save_log_graph(store, graph_id, by_log, embedder.model, wanted)
    try:
        graph = load_graph(store, graph_id)
    except GraphNotBuiltError:  # every log failed: its own message would say to run graph build
        causes = "; ".join(f"{lid}: {why}" for lid, why in failed[:3])
        raise GraphNotBuiltError(
            f"no log of the store could be described ({len(failed)} failed: {causes})"
        ) from None
    levels = leiden_communities(graph.elements, s.resolutions, s.seed)
    store.corpus(COMMUNITIES_TABLE, _SCHEMA).upsert(
        {
            graph_id: {
                "levels": [
                    {"level": lv.level, "resolution": lv.resolution, "membership": lv.membership}
                    for lv in levels
                ]
            }
        }
    )
    summaries = []
    summary_failures: list[tuple[str, str]] = []
    if client is not None and cid and labels is not None:
        wids, _logs, z = load_embeddings(store, graph_id, logs)
        lab = np.asarray([label_of.get(w, -1) for w in wids.tolist()], np.int64)
        summaries += cluster_summaries(
            store, graph, wids, z, lab, client, embedder, s.summaries, bar, summary_failures
        )
    if client is not None:
        summaries += community_reports(
            store, graph, levels, client, embedder, s.summaries, bar, summary_failures
        )
    return GraphBuildReport(
        graph_id=graph_id,
        clustering_id=cid,
        n_logs=len(graph_logs(store, graph_id)),
        n_logs_built=len(todo) - len(failed),
        n_samples=len(graph.samples),
        n_entities=len(graph.elements.entities),
        n_relationships=len(graph.elements.relationships),
        communities_per_level=tuple(len(set(lv.membership.values())) for lv in levels),
        n_summaries=len(summaries),
        n_llm_calls=sum(not x.cached for x in summaries),
        failed=tuple(failed),
        failed_summaries=tuple(summary_failures),
    )


def load_communities(store: ScenarioStore, graph_id: str) -> list[CommunityLevel]:
    """The communities stored by the last build of ``graph_id`` (empty if none)."""
    row = store.corpus(COMMUNITIES_TABLE, _SCHEMA).get(graph_id)
    if row is None:
        return []
    return [
        CommunityLevel(
            int(lv["level"]), float(lv["resolution"]), {k: int(v) for k, v in lv["membership"].items()}
        )
        for lv in row.data["levels"]
    ]
