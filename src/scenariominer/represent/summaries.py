"""LLM summaries of clusters (stages 2-3 of section 3.3) and of graph communities, cached in the store.

Language-model calls are spent only here, per cluster and per community, never per sample:

* **cluster summary**: the ``n_neighbours`` (5) samples nearest to the cluster's centre in the
  trajectory embedding (Euclidean distance in the latent space, through
  :func:`scenariominer.retrieval.top_k`);
* **cluster contrast**: ``n_contrast`` (5) samples drawn at random (seeded) from the other clusters,
  compared with the cluster's summary (one call per cluster, not one per pair of clusters);
* **community report**: the counted facts and some relationships of a Leiden community (the
  ``max_reports`` largest communities of at least ``min_community_size`` entities per level).

Table ``graph_summaries`` (schema 1), key ``<graph id>|<kind>|<subject>``: JSON ``kind``,
``subject``, ``title``, ``text``, ``window_ids``, ``entity_ids``, ``inputs`` (hash of the prompt,
so an unchanged cluster or community is never asked again) and the blob holds the text's vector.
"""

from __future__ import annotations

import hashlib
import io
import json
from collections import Counter
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any, TypeVar

import numpy as np
from numpy.typing import NDArray
from pydantic import BaseModel

from scenariominer.llm.client import ChatClient
from scenariominer.llm.embeddings import Embedder
from scenariominer.progress import NullProgress, Progress
from scenariominer.represent import graph_prompts as prompts
from scenariominer.represent.graph import CommunityLevel, StoredGraph
from scenariominer.retrieval import top_k
from scenariominer.store import ScenarioStore

_Out = TypeVar("_Out", bound=BaseModel)

__all__ = [
    "SUMMARIES_TABLE",
    "Summary",
    "SummarySettings",
    "cluster_summaries",
    "community_reports",
    "load_summaries",
]

SUMMARIES_TABLE = "graph_summaries"
_SCHEMA = 1


@dataclass(frozen=True)
class SummarySettings:
    """How many samples and communities the language model sees.

    Attributes:
        n_neighbours: samples nearest to a cluster's centre (the paper's 5).
        n_contrast: random samples of other clusters per contrast (the paper's 5).
        max_clusters: largest clusters summarised (by size).
        levels: community levels that get reports.
        min_community_size: smallest community (entities) that gets a report.
        max_reports: largest communities per level that get reports.
        max_tokens: answer length bound per call.
        seed: seed of the random contrast samples.
    """

    n_neighbours: int = 5
    n_contrast: int = 5
    max_clusters: int = 60
    levels: tuple[int, ...] = (0, 1)
    min_community_size: int = 8
    max_reports: int = 12
    max_tokens: int = 220
    seed: int = 0


@dataclass(frozen=True)
class Summary:
    """A stored summary.

    Attributes:
        key: its row key.
        kind: ``cluster``, ``contrast`` or ``report``.
        subject: cluster label, or ``<level>.<community>`` for a report.
        title: short name.
        text: the summary text (embedded for retrieval).
        window_ids: samples it refers to.
        entity_ids: graph entities it refers to (reports).
        cached: read from the store rather than asked now.
    """

    key: str
    kind: str
    subject: str
    title: str
    text: str
    window_ids: tuple[str, ...]
    entity_ids: tuple[str, ...]
    cached: bool


def _hash(*parts: object) -> str:
    return hashlib.sha256(json.dumps([prompts.PROMPT_VERSION, *parts], default=str).encode()).hexdigest()[:16]


def _vec(v: NDArray[np.float32]) -> bytes:
    buf = io.BytesIO()
    np.save(buf, np.asarray(v, dtype=np.float32))
    return buf.getvalue()


class _Cache:
    """Rows of ``graph_summaries`` of one graph, read once, written per answer."""

    def __init__(self, store: ScenarioStore, graph_id: str) -> None:
        self.table = store.corpus(SUMMARIES_TABLE, _SCHEMA)
        self.graph_id = graph_id
        self.rows = {r.key: r for r in self.table.rows() if r.key.startswith(f"{graph_id}|")}

    def get(self, key: str, inputs: str) -> Summary | None:
        row = self.rows.get(key)
        if row is None or row.data.get("inputs") != inputs:
            return None
        d = row.data
        return Summary(
            key,
            str(d["kind"]),
            str(d["subject"]),
            str(d["title"]),
            str(d["text"]),
            tuple(d["window_ids"]),
            tuple(d["entity_ids"]),
            True,
        )

    def put(self, s: Summary, inputs: str, embedder: Embedder) -> None:
        vec = embedder.embed([f"{s.title}. {s.text}"]).vectors[0]
        data = {
            "graph_id": self.graph_id,
            "kind": s.kind,
            "subject": s.subject,
            "title": s.title,
            "text": s.text,
            "window_ids": list(s.window_ids),
            "entity_ids": list(s.entity_ids),
            "inputs": inputs,
        }
        self.table.upsert({s.key: data}, {s.key: _vec(vec)})


def _sample_text(graph: StoredGraph) -> dict[str, str]:
    return {str(s["window_id"]): str(s["text"]) for s in graph.samples}


def _chat(
    client: ChatClient,
    messages: Any,
    model: type[_Out],
    max_tokens: int,
    subject: str,
    failures: list[tuple[str, str]] | None,
) -> _Out | None:
    """The model's answer, or ``None`` with ``(subject, error)`` added to ``failures``.

    A garbled answer (or a failing backend) costs that one summary, never the build; without a
    ``failures`` list the error propagates.
    """
    try:
        return client.chat(messages, model, max_tokens=max_tokens)
    except Exception as exc:  # noqa: BLE001 -- reported per summary, the rest go on
        if failures is None:
            raise
        failures.append((subject, f"{type(exc).__name__}: {exc}"))
        return None


def cluster_summaries(
    store: ScenarioStore,
    graph: StoredGraph,
    window_ids: NDArray[np.str_],
    z: NDArray[np.float32],
    labels: NDArray[np.int64],
    client: ChatClient,
    embedder: Embedder,
    settings: SummarySettings | None = None,
    progress: Progress | None = None,
    failures: list[tuple[str, str]] | None = None,
) -> list[Summary]:
    """Summary and contrast of each cluster (``window_ids`` ``(W,)``, ``z`` ``(W, D)``, ``labels`` ``(W,)``).

    Clusters whose prompt inputs are unchanged are read back from the store without a call.
    """
    s = settings or SummarySettings()
    bar = progress or NullProgress()
    texts = _sample_text(graph)
    have = np.asarray([w in texts for w in window_ids.tolist()], dtype=bool)
    window_ids, z, labels = window_ids[have], z[have], labels[have]
    sizes = Counter(int(c) for c in labels if c >= 0)
    clusters = [c for c, _n in sizes.most_common(s.max_clusters)]
    cache = _Cache(store, graph.graph_id)
    out: list[Summary] = []
    bar.start("cluster summaries", total=len(clusters))
    for c in clusters:
        members = np.flatnonzero(labels == c)
        centre = z[members].mean(axis=0)
        dist = np.linalg.norm(z[members] - centre, axis=1)  # latent space is Euclidean
        near = [window_ids[members[int(j)]] for j in top_k(-dist[None, :], s.n_neighbours)[0]]
        near_texts = [texts[str(w)] for w in near]
        name = f"cluster {c}"
        key = f"{graph.graph_id}|cluster|{c}"
        inputs = _hash(near_texts)
        summary = cache.get(key, inputs)
        if summary is None:
            ans = _chat(
                client,
                prompts.cluster_summary_messages(name, near_texts),
                prompts.ClusterSummaryOut,
                s.max_tokens,
                f"{name} summary",
                failures,
            )
            if ans is None:
                bar.advance()
                continue
            summary = Summary(
                key,
                "cluster",
                str(c),
                ans.title,
                f"{name}: {ans.traffic} {ans.behaviour}",
                tuple(str(w) for w in near),
                (f"C:{c}",),
                False,
            )
            cache.put(summary, inputs, embedder)
        out.append(summary)
        others = np.flatnonzero((labels != c) & (labels >= 0))
        rng = np.random.default_rng([s.seed, c + 1])
        pick: list[int] = rng.choice(others, size=min(s.n_contrast, others.size), replace=False).tolist()
        other_texts = [texts[str(window_ids[i])] for i in pick]
        if other_texts:
            ckey = f"{graph.graph_id}|contrast|{c}"
            cinputs = _hash(summary.text, other_texts)
            contrast = cache.get(ckey, cinputs)
            if contrast is None:
                ans2 = _chat(
                    client,
                    prompts.cluster_contrast_messages(name, summary.text, other_texts),
                    prompts.ClusterContrastOut,
                    s.max_tokens,
                    f"{name} contrast",
                    failures,
                )
                if ans2 is None:
                    bar.advance()
                    continue
                contrast = Summary(
                    ckey,
                    "contrast",
                    str(c),
                    f"{name} versus other clusters",
                    f"{name} differs from other clusters: {ans2.difference} Others: {ans2.others}",
                    tuple(str(window_ids[i]) for i in pick),
                    (f"C:{c}",),
                    False,
                )
                cache.put(contrast, inputs=cinputs, embedder=embedder)
            out.append(contrast)
        bar.advance()
    return out


def community_facts(graph: StoredGraph, members: Sequence[str]) -> tuple[str, list[str], tuple[str, ...]]:
    """Counted facts, relationship texts and sample ids of a community of entity ids ``members``."""
    ents = graph.entity_index()
    kinds = Counter(graph.elements.entities[ents[m]].kind for m in members if m in ents)
    member_set = set(members)
    samples = sorted({w for m in members if m in ents for w in graph.elements.entities[ents[m]].window_ids})
    rels = [r for r in graph.elements.relationships if r.source in member_set and r.target in member_set]
    by_kind = Counter(r.kind for r in rels)
    named = [
        graph.elements.entities[ents[m]].name
        for m in members
        if m[:2] in ("M:", "T:", "C:", "L:") and m in ents
    ]
    facts = (
        f"{len(samples)} samples, {kinds.get('vehicle', 0)} vehicles; "
        f"named nodes: {', '.join(named[:12]) or 'none'}; "
        f"relations: {', '.join(f'{k} {n}' for k, n in by_kind.most_common(8))}"
    )
    prefer = ("cuts_in_front_of", "overtakes", "passes", "changes_lane_into", "follows")
    chosen = sorted(rels, key=lambda r: prefer.index(r.kind) if r.kind in prefer else len(prefer))[:8]
    return facts, [r.text for r in chosen], tuple(samples)


def community_reports(
    store: ScenarioStore,
    graph: StoredGraph,
    levels: Sequence[CommunityLevel],
    client: ChatClient,
    embedder: Embedder,
    settings: SummarySettings | None = None,
    progress: Progress | None = None,
    failures: list[tuple[str, str]] | None = None,
) -> list[Summary]:
    """Reports of the largest communities of the chosen levels (unchanged communities are not re-asked)."""
    s = settings or SummarySettings()
    bar = progress or NullProgress()
    cache = _Cache(store, graph.graph_id)
    todo: list[tuple[int, int, list[str]]] = []
    for lv in levels:
        if lv.level not in s.levels:
            continue
        groups = sorted(lv.members().items(), key=lambda kv: -len(kv[1]))
        todo += [(lv.level, c, m) for c, m in groups if len(m) >= s.min_community_size][: s.max_reports]
    out: list[Summary] = []
    bar.start("community reports", total=len(todo))
    for level, c, members in todo:
        facts, rel_texts, samples = community_facts(graph, members)
        subject = f"{level}.{c}"
        key = f"{graph.graph_id}|report|{subject}"
        inputs = _hash(sorted(members), facts)
        report = cache.get(key, inputs)
        if report is None:
            ans = _chat(
                client,
                prompts.report_messages(subject, facts, rel_texts),
                prompts.ReportOut,
                s.max_tokens,
                f"community {subject} report",
                failures,
            )
            if ans is None:
                bar.advance()
                continue
            report = Summary(
                key, "report", subject, ans.title, f"{ans.summary} ({facts})", samples, tuple(members), False
            )
            cache.put(report, inputs, embedder)
        out.append(report)
        bar.advance()
    return out


def load_summaries(store: ScenarioStore, graph_id: str) -> tuple[list[Summary], NDArray[np.float32]]:
    """Every stored summary of ``graph_id`` and its vectors ``(n, D)`` (same order)."""
    rows = [
        r
        for r in store.corpus(SUMMARIES_TABLE, _SCHEMA).rows(with_blobs=True)
        if r.key.startswith(f"{graph_id}|")
    ]
    out = [
        Summary(
            r.key,
            str(r.data["kind"]),
            str(r.data["subject"]),
            str(r.data["title"]),
            str(r.data["text"]),
            tuple(r.data["window_ids"]),
            tuple(r.data["entity_ids"]),
            True,
        )
        for r in rows
    ]
    vecs = [np.load(io.BytesIO(r.blob or b"")) for r in rows]
    return out, (np.stack(vecs) if vecs else np.zeros((0, 0), np.float32))
