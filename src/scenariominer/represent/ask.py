"""Natural-language questions over the scenario graph (section 3.4): retrieve, expand, answer with citations.

Retrieval (no language model; :class:`GraphIndex.search`):

1. the question's vector is ranked against the sample descriptions, the embedded entities
   (manoeuvres, traffic states, lanes, clusters), the embedded relationships (follows, overtakes,
   passes, cuts in front of, changes lane into) and the summaries (cluster summaries, contrasts,
   community reports), each through :class:`scenariominer.retrieval.ExactCosineIndex`;
2. graph expansion: the samples linked to the best entities (one hop, sample -> entity edges), to
   the best relationships (their sample) and to the best summaries (their samples and clusters)
   become candidates beside the best descriptions;
3. each candidate scores ``cos(question, description) + w_relationship * best relationship cosine
   + w_entity * best entity cosine + w_report * best summary cosine`` and the top ``k`` are kept
   (:func:`scenariominer.retrieval.top_k`). With ``graph = False`` only step 1's descriptions count:
   the plain vector-search baseline.

The weights are fixed a priori (not tuned on the evaluation queries; see docs/graph.md).

Answer (:func:`ask_graph`): the top samples, their best relationships and the best summaries are
numbered ``[S#]``, ``[R#]``, ``[C#]`` in the prompt; the model's JSON answer lists the numbers it
used, which are mapped back to sample, relationship and report ids (numbers outside the context
are reported as invalid citations).
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from scenariominer.llm.client import ChatClient
from scenariominer.llm.embeddings import Embedder
from scenariominer.represent import graph_prompts as prompts
from scenariominer.represent.graph import StoredGraph
from scenariominer.represent.summaries import Summary
from scenariominer.represent.windows import WindowSet
from scenariominer.retrieval import ExactCosineIndex, top_k
from scenariominer.store import ScenarioStore

__all__ = [
    "AskResult",
    "AskSettings",
    "GraphIndex",
    "OpenGraph",
    "RankedSample",
    "Retrieval",
    "ask_graph",
    "open_graph",
    "write_samples_picture",
]

IntArray = NDArray[np.intp]
Float32Array = NDArray[np.float32]


@dataclass(frozen=True)
class AskSettings:
    """Retrieval and answer settings.

    Attributes:
        k: samples returned.
        graph: use the graph (entities, relationships, summaries); False: descriptions only.
        n_candidates: best descriptions taken as candidates.
        n_entities: best entities expanded.
        n_relationships: best relationships expanded (and shown to the model).
        n_summaries: best summaries expanded (and shown to the model).
        w_entity: weight of the best entity cosine.
        w_relationship: weight of the best relationship cosine.
        w_report: weight of the best summary cosine.
        max_tokens: answer length bound.
    """

    k: int = 5
    graph: bool = True
    n_candidates: int = 200
    n_entities: int = 2
    n_relationships: int = 8
    n_summaries: int = 3
    w_entity: float = 0.3
    w_relationship: float = 0.3
    w_report: float = 0.2
    max_tokens: int = 400


def _csr(groups: Sequence[Sequence[int]]) -> tuple[IntArray, IntArray]:
    """Offsets ``(G + 1,)`` and flat members of integer groups."""
    sizes = np.asarray([len(g) for g in groups], dtype=np.intp)
    ptr = np.concatenate([[0], np.cumsum(sizes)]).astype(np.intp)
    flat = np.asarray([i for g in groups for i in g], dtype=np.intp)
    return ptr, flat


def _index(vectors: Float32Array) -> ExactCosineIndex | None:
    if vectors.shape[0] == 0:
        return None
    idx = ExactCosineIndex(vectors.shape[1])
    idx.add([str(i) for i in range(vectors.shape[0])], vectors)
    return idx


@dataclass(frozen=True)
class Retrieval:
    """What one search found (row numbers into the :class:`GraphIndex` arrays).

    Attributes:
        samples: ``(k,)`` sample rows, best first.
        scores: ``(k,)`` their fused scores.
        relationships: best relationship rows (into ``rel_ids``) and cosines.
        entities: best entity rows (into ``entity_ids``) and cosines.
        summaries: best summary rows and cosines.
    """

    samples: IntArray
    scores: NDArray[np.float64]
    relationships: tuple[tuple[int, float], ...]
    entities: tuple[tuple[int, float], ...]
    summaries: tuple[tuple[int, float], ...]


class GraphIndex:
    """Vector indexes of a graph plus its sample links, ready for many searches.

    Args:
        sample_ids: ``(W,)`` window ids.
        sample_vectors: ``(W, D)`` unit vectors of the descriptions.
        entity_ids: ``(E,)`` embedded entity ids; ``entity_vectors`` ``(E, D)``.
        entity_samples: per entity, the sample rows linked to it.
        rel_ids: ``(R,)`` embedded relationship ids; ``rel_vectors`` ``(R, D)``; ``rel_sample``
            ``(R,)`` the sample row of each.
        summary_ids: ``(C,)`` summary keys; ``summary_vectors`` ``(C, D)``; ``summary_samples``:
            per summary, its sample rows.
    """

    def __init__(
        self,
        sample_ids: Sequence[str],
        sample_vectors: Float32Array,
        entity_ids: Sequence[str],
        entity_vectors: Float32Array,
        entity_samples: Sequence[Sequence[int]],
        rel_ids: Sequence[str],
        rel_vectors: Float32Array,
        rel_sample: Sequence[int],
        summary_ids: Sequence[str] = (),
        summary_vectors: Float32Array | None = None,
        summary_samples: Sequence[Sequence[int]] = (),
    ) -> None:
        self.sample_ids = list(sample_ids)
        self.sample_vectors = np.asarray(sample_vectors, dtype=np.float32)
        self.samples = _index(self.sample_vectors)
        self.entity_ids = list(entity_ids)
        self.entities = _index(np.asarray(entity_vectors, dtype=np.float32))
        self.entity_ptr, self.entity_flat = _csr(entity_samples)
        self.rel_ids = list(rel_ids)
        self.rels = _index(np.asarray(rel_vectors, dtype=np.float32))
        self.rel_sample = np.asarray(rel_sample, dtype=np.intp)
        self.summary_ids = list(summary_ids)
        sv = (
            np.zeros((0, self.sample_vectors.shape[1]), np.float32)
            if summary_vectors is None
            else summary_vectors
        )
        self.summaries = _index(np.asarray(sv, dtype=np.float32))
        self.summary_ptr, self.summary_flat = _csr(summary_samples)

    @classmethod
    def from_graph(
        cls,
        graph: StoredGraph,
        summaries: Sequence[Summary] = (),
        summary_vectors: Float32Array | None = None,
    ) -> GraphIndex:
        """The index of a stored graph and its summaries."""
        row = {str(s["window_id"]): i for i, s in enumerate(graph.samples)}
        ents = graph.elements.entities
        rels = graph.elements.relationships
        linked: dict[str, list[int]] = {}
        for r in rels:
            if r.source.startswith("S:") and r.window_id in row:
                linked.setdefault(r.target, []).append(row[r.window_id])
        entity_ids = [ents[i].entity_id for i in graph.entity_rows]
        cluster_members = {eid: linked.get(eid, []) for eid in entity_ids if eid.startswith("C:")}
        summary_samples = []
        for s in summaries:
            members = {row[w] for w in s.window_ids if w in row}
            for eid in s.entity_ids:
                members.update(cluster_members.get(eid, []))
            summary_samples.append(sorted(members))
        return cls(
            list(row),
            graph.sample_vectors,
            entity_ids,
            graph.entity_vectors,
            [sorted(set(linked.get(e, []))) for e in entity_ids],
            [rels[i].rel_id for i in graph.rel_rows],
            graph.rel_vectors,
            [row.get(rels[i].window_id, 0) for i in graph.rel_rows],
            [s.key for s in summaries],
            summary_vectors if summaries else None,
            summary_samples,
        )

    def __len__(self) -> int:
        return len(self.sample_ids)

    def search(self, query: Float32Array, settings: AskSettings) -> Retrieval:
        """Fused ranking of the samples for one query vector ``(D,)`` (see the module docstring)."""
        if self.samples is None:
            return Retrieval(np.zeros(0, np.intp), np.zeros(0), (), (), ())
        q = np.asarray(query, dtype=np.float32)
        q = q / max(float(np.linalg.norm(q)), 1e-12)
        hits = self.samples.search(q, min(settings.n_candidates, len(self)))
        cand = [np.asarray([int(h.id) for h in hits], dtype=np.intp)]
        boosts: list[tuple[IntArray, NDArray[np.float64], float]] = []
        found: dict[str, tuple[tuple[int, float], ...]] = {"e": (), "r": (), "c": ()}
        if settings.graph:
            for key, idx, n, w in (
                ("e", self.entities, settings.n_entities, settings.w_entity),
                ("r", self.rels, settings.n_relationships, settings.w_relationship),
                ("c", self.summaries, settings.n_summaries, settings.w_report),
            ):
                if idx is None or n <= 0:
                    continue
                top = [(int(h.id), float(h.score)) for h in idx.search(q, min(n, len(idx)))]
                found[key] = tuple(top)
                rows_l, sims_l = [], []
                for r, sim in top:
                    if key == "r":
                        members = self.rel_sample[r : r + 1]
                    elif key == "e":
                        members = self.entity_flat[self.entity_ptr[r] : self.entity_ptr[r + 1]]
                    else:
                        members = self.summary_flat[self.summary_ptr[r] : self.summary_ptr[r + 1]]
                    rows_l.append(members)
                    sims_l.append(np.full(members.size, sim))
                if rows_l:
                    rows = np.concatenate(rows_l)
                    boosts.append((rows, np.concatenate(sims_l), w))
                    cand.append(rows)
        cands = np.unique(np.concatenate(cand))
        score = (self.sample_vectors[cands] @ q).astype(np.float64)
        for rows, sims, w in boosts:
            where = np.searchsorted(cands, rows)
            best = np.zeros_like(score)
            np.maximum.at(best, where, sims)
            score += w * best
        order = top_k(score[None, :], settings.k)[0]
        return Retrieval(cands[order], score[order], found["r"], found["e"], found["c"])


@dataclass(frozen=True)
class RankedSample:
    """A retrieved sample with its references.

    Attributes:
        rank: 1-based.
        window_id: the sample.
        log_id: its log.
        agent_id: its chosen agent's track id.
        track_ids: every road user in it.
        start_s: start, seconds since the log's first timestamp.
        end_s: end.
        start_frame: highD frame of the start (``None`` elsewhere).
        end_frame: highD frame of the end.
        cluster: cluster label (``None`` when not clustered).
        score: fused retrieval score.
        text: its description.
    """

    rank: int
    window_id: str
    log_id: str
    agent_id: str
    track_ids: tuple[str, ...]
    start_s: float
    end_s: float
    start_frame: int | None
    end_frame: int | None
    cluster: int | None
    score: float
    text: str


@dataclass(frozen=True)
class AskResult:
    """Answer to one question.

    Attributes:
        question: as asked.
        graph_id: the graph searched.
        samples: ranked samples.
        context_relationships: ``(id, text)`` of the relationships shown to the model, ``[R1]`` first.
        context_summaries: ``(key, text)`` of the summaries shown to the model, ``[C1]`` first.
        answer: the model's answer (``""`` without a model).
        cited_samples: window ids the answer cites.
        cited_entities: entity ids of the cited samples and their chosen vehicles.
        cited_relationships: relationship ids the answer cites.
        cited_reports: summary keys the answer cites.
        invalid_citations: cited numbers that were not in the context.
        retrieval_ms: embedding the question excluded, graph + vector search time.
        embed_ms: time to embed the question.
        llm_s: time of the model's answer (0 without a model).
        llm_status: ``answered``, ``no model`` or the error.
    """

    question: str
    graph_id: str
    samples: tuple[RankedSample, ...]
    context_relationships: tuple[tuple[str, str], ...]
    context_summaries: tuple[tuple[str, str], ...]
    answer: str
    cited_samples: tuple[str, ...]
    cited_entities: tuple[str, ...]
    cited_relationships: tuple[str, ...]
    cited_reports: tuple[str, ...]
    invalid_citations: tuple[str, ...]
    retrieval_ms: float
    embed_ms: float
    llm_s: float
    llm_status: str


def _ranked(graph: StoredGraph, found: Retrieval) -> tuple[RankedSample, ...]:
    out = []
    for i, (row, score) in enumerate(zip(found.samples.tolist(), found.scores.tolist(), strict=True), 1):
        s = graph.samples[row]
        c = s.get("cluster")
        out.append(
            RankedSample(
                i,
                str(s["window_id"]),
                str(s["log_id"]),
                str(s["agent_id"]),
                tuple(s["track_ids"]),  # type: ignore[arg-type]
                float(s["start_s"]),
                float(s["end_s"]),  # type: ignore[arg-type]
                None if s.get("start_frame") is None else int(s["start_frame"]),  # type: ignore[call-overload]
                None if s.get("end_frame") is None else int(s["end_frame"]),  # type: ignore[call-overload]
                None if c is None else int(c),
                float(score),
                str(s["text"]),  # type: ignore[call-overload]
            )
        )
    return tuple(out)


def ask_graph(
    graph: StoredGraph,
    index: GraphIndex,
    question: str,
    embedder: Embedder,
    client: ChatClient | None,
    settings: AskSettings | None = None,
    summaries: Sequence[Summary] = (),
) -> AskResult:
    """Retrieve samples for ``question`` and (with ``client``) answer it with citations."""
    s = settings or AskSettings()
    t0 = time.perf_counter()
    q = embedder.embed([question]).vectors[0]
    t1 = time.perf_counter()
    found = index.search(q, s)
    t2 = time.perf_counter()
    ranked = _ranked(graph, found)
    rels = graph.elements.relationships
    rel_by_id = {r.rel_id: r for r in rels}
    top_windows = {r.window_id for r in ranked}
    own = [i for i in graph.rel_rows.tolist() if rels[i].window_id in top_windows][: s.n_relationships]
    ctx_rels = [rels[i] for i in own]
    for row, _sim in found.relationships:
        r = rel_by_id.get(index.rel_ids[row])
        if r is not None and r not in ctx_rels and len(ctx_rels) < s.n_relationships:
            ctx_rels.append(r)
    ctx_sums = [summaries[row] for row, _sim in found.summaries if row < len(summaries)]
    answer, status, llm_s = "", "no model", 0.0
    cited: dict[str, list[str]] = {"S": [], "R": [], "C": []}
    invalid: list[str] = []
    if client is not None and ranked:
        t3 = time.perf_counter()
        try:
            out = client.chat(
                prompts.answer_messages(
                    question,
                    [r.text for r in ranked],
                    [r.text for r in ctx_rels],
                    [f"{x.title}: {x.text}" for x in ctx_sums],
                ),
                prompts.AnswerOut,
                max_tokens=s.max_tokens,
            )
            answer, status = out.answer, "answered"
            for tag, nums, pool in (
                ("S", out.samples, [r.window_id for r in ranked]),
                ("R", out.relationships, [r.rel_id for r in ctx_rels]),
                ("C", out.reports, [x.key for x in ctx_sums]),
            ):
                for n in nums:
                    if 1 <= n <= len(pool):
                        if pool[n - 1] not in cited[tag]:
                            cited[tag].append(pool[n - 1])
                    else:
                        invalid.append(f"{tag}{n}")
        except Exception as exc:  # noqa: BLE001 -- the ranking stands without an answer
            status = f"{type(exc).__name__}: {exc}"
        llm_s = time.perf_counter() - t3
    by_wid = {r.window_id: r for r in ranked}
    entities = [e for w in cited["S"] for e in (f"S:{w}", f"V:{by_wid[w].log_id}/{by_wid[w].agent_id}")]
    return AskResult(
        question=question,
        graph_id=graph.graph_id,
        samples=ranked,
        context_relationships=tuple((r.rel_id, r.text) for r in ctx_rels),
        context_summaries=tuple((x.key, f"{x.title}: {x.text}") for x in ctx_sums),
        answer=answer,
        cited_samples=tuple(cited["S"]),
        cited_entities=tuple(entities),
        cited_relationships=tuple(cited["R"]),
        cited_reports=tuple(cited["C"]),
        invalid_citations=tuple(invalid),
        retrieval_ms=(t2 - t1) * 1e3,
        embed_ms=(t1 - t0) * 1e3,
        llm_s=llm_s,
        llm_status=status,
    )


def write_samples_picture(windows: WindowSet, ranked: Sequence[RankedSample], path: Path) -> Path:
    """PNG of the ranked samples' trajectories (``windows`` must hold them).

    One panel per sample in rank order: every road user's path in the chosen agent's frame (the
    chosen agent in red, others grey), titled with log, track and time range.
    """
    from scenariominer._optional import require

    figure_mod = require("matplotlib.figure", extra="represent", purpose="drawing retrieved samples")
    agg = require("matplotlib.backends.backend_agg", extra="represent", purpose="drawing retrieved samples")
    ids = windows.window_ids.tolist()
    n = max(len(ranked), 1)
    fig = figure_mod.Figure(figsize=(8.0, 1.9 * n), dpi=110)
    agg.FigureCanvasAgg(fig)
    for i, r in enumerate(ranked):
        ax = fig.add_subplot(n, 1, i + 1)
        if r.window_id not in ids:
            ax.set_axis_off()
            continue
        w = ids.index(r.window_id)
        xy, valid = windows.xy_m[w], windows.valid[w]
        for a in range(xy.shape[0]):
            ok = valid[a]
            if ok.any():
                colour, width = ("red", 2.0) if a == 0 else ("0.55", 1.0)
                ax.plot(xy[a, ok, 0], xy[a, ok, 1], color=colour, lw=width)
                ax.plot(xy[a, ok, 0][-1:], xy[a, ok, 1][-1:], "o", color=colour, ms=3)
        frames = f", frames {r.start_frame}-{r.end_frame}" if r.start_frame is not None else ""
        ax.set_title(
            f"#{r.rank} {r.log_id} track {r.agent_id}, {r.start_s:.1f}-{r.end_s:.1f} s{frames}", fontsize=8
        )
        ax.set_xlabel("forward [m]", fontsize=7)
        ax.set_ylabel("left [m]", fontsize=7)
        ax.tick_params(labelsize=6)
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path)
    return path


@dataclass(frozen=True, eq=False)
class OpenGraph:
    """A stored graph with its summaries and search index, loaded once for many questions."""

    graph: StoredGraph
    summaries: tuple[Summary, ...]
    index: GraphIndex


def open_graph(store: ScenarioStore, graph_id: str) -> OpenGraph:
    """Load graph ``graph_id``, its summaries and their vectors, and index them.

    Raises:
        GraphNotBuiltError: no such graph in the store.
    """
    from scenariominer.represent.graph import load_graph
    from scenariominer.represent.summaries import load_summaries

    graph = load_graph(store, graph_id)
    summaries, vectors = load_summaries(store, graph_id)
    if summaries and vectors.shape[1] != graph.sample_vectors.shape[1]:
        summaries, vectors = [], np.zeros((0, graph.sample_vectors.shape[1]), np.float32)
    return OpenGraph(graph, tuple(summaries), GraphIndex.from_graph(graph, summaries, vectors))
