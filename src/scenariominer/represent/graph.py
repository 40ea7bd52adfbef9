"""Knowledge graph of samples (section 3.4), computed from the window facts, never by an LLM.

Entities (``entity_id`` prefixes):

* ``S:`` sample (a window), ``V:`` vehicle (``V:<log>/<track>``), ``C:`` cluster of the embedding,
  ``L:`` lane (by lane id), ``M:`` manoeuvre (lane change left/right, multi-lane change,
  overtaking, pass-by, cut-in, following, acceleration, ...), ``T:`` traffic state.

Relationships (``rel_id`` = ``<log id>#<n>``, stable while the log's windows are): ``follows``,
``overtakes``, ``passes``, ``cuts_in_front_of`` (vehicle -> vehicle), ``changes_lane_into``
(vehicle -> lane), ``drives_in`` (vehicle -> lane), ``performs`` (vehicle -> manoeuvre),
``shows`` (sample -> manoeuvre), ``has_traffic`` (sample -> traffic state), ``contains``
(sample -> vehicle) and ``belongs_to_cluster`` (sample -> cluster). Each carries the window it
comes from, its time and highD frame where it has one.

Communities: Leiden (``leidenalg`` over an ``igraph`` graph, modularity with a resolution
parameter) at several resolutions, coarse to fine; level ``i`` uses ``resolutions[i]``.

The graph is stored per log (corpus table ``graph_elements``, key ``<graph id>|<log id>``) with the
text vectors of its entities and relationships, so adding a log adds rows without touching the
others; entities shared by logs (lanes, clusters, manoeuvres, traffic states) are merged on load.
"""

from __future__ import annotations

import io
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from scenariominer._optional import require
from scenariominer.represent.describe import WindowDescription
from scenariominer.store import ScenarioStore

__all__ = [
    "ELEMENTS_TABLE",
    "EMBEDDED_ENTITIES",
    "EMBEDDED_RELATIONS",
    "GRAPH_SCHEMA",
    "SAMPLES_TABLE",
    "CommunityLevel",
    "Entity",
    "GraphElements",
    "Relationship",
    "StoredGraph",
    "graph_elements",
    "graph_logs",
    "leiden_communities",
    "load_graph",
    "sample_manoeuvres",
    "save_log_graph",
]

#: Relationship kinds whose texts are embedded (the others are reached over the graph).
EMBEDDED_RELATIONS = frozenset({"follows", "overtakes", "passes", "cuts_in_front_of", "changes_lane_into"})
#: Entity kinds whose texts are embedded (samples are embedded through their descriptions).
EMBEDDED_ENTITIES = frozenset({"cluster", "lane", "manoeuvre", "traffic"})

ELEMENTS_TABLE = "graph_elements"
SAMPLES_TABLE = "graph_samples"
GRAPH_SCHEMA = 1

Float32Array = NDArray[np.float32]


@dataclass(frozen=True)
class Entity:
    """A node of the graph.

    Attributes:
        entity_id: unique id (prefix gives the type, see the module docstring).
        kind: ``sample``, ``vehicle``, ``cluster``, ``lane``, ``manoeuvre`` or ``traffic``.
        name: short name.
        text: the text that is embedded and shown to the LLM.
        window_ids: samples it occurs in.
    """

    entity_id: str
    kind: str
    name: str
    text: str
    window_ids: tuple[str, ...]


@dataclass(frozen=True)
class Relationship:
    """An edge of the graph.

    Attributes:
        rel_id: unique id ``<log id>#<n>``.
        source: entity id.
        target: entity id.
        kind: relation name (see the module docstring).
        text: the text that is embedded and shown to the LLM.
        window_id: the sample it comes from.
        t_s: when, seconds since the log's first timestamp (NaN when it spans the sample).
        frame: highD frame, ``None`` for other logs or without a moment.
        weight: edge weight for the communities.
    """

    rel_id: str
    source: str
    target: str
    kind: str
    text: str
    window_id: str
    t_s: float
    frame: int | None
    weight: float


@dataclass(frozen=True)
class GraphElements:
    """Entities and relationships (of one log, or merged over logs)."""

    entities: tuple[Entity, ...]
    relationships: tuple[Relationship, ...]


def sample_manoeuvres(d: WindowDescription) -> list[str]:
    """Names of the manoeuvres the chosen agent of ``d`` shows (entity names of ``M:`` nodes)."""
    me = d.vehicles[0] if d.vehicles else None
    out: list[str] = []
    if me is not None:
        out += _vehicle_manoeuvres(me.lane_changes, me.speed_trend, me.peak_lateral_mps)
    for i in d.interactions:
        if i.kind == "follows" and i.subject == d.agent_id:
            out.append("following")
        elif i.kind == "overtakes":
            out.append("overtaking")
        elif i.kind == "passes":
            out.append(f"pass-by from the {i.side}")
        elif i.kind == "cuts_in_front_of":
            out.append("cut-in")
    return sorted(set(out))


def _vehicle_manoeuvres(changes: Sequence[object], trend: str, peak_lat: float) -> list[str]:
    out = [trend]
    dirs = [getattr(c, "direction", "") for c in changes]
    for d in sorted(set(dirs)):
        out.append(f"lane change to the {d}")
        if dirs.count(d) >= 2:
            out.append(f"multi-lane change to the {d}")
    if not changes:
        out.append("lane keeping")
        if peak_lat > 0.6:
            out.append("lateral movement without lane change")
    return out


def graph_elements(descriptions: Sequence[WindowDescription], embedding: str = "") -> GraphElements:
    """Entities and relationships of the samples of one log (ids numbered in sample order)."""
    entities: dict[str, Entity] = {}
    rels: list[Relationship] = []

    def entity(eid: str, kind: str, name: str, text: str, wid: str) -> str:
        old = entities.get(eid)
        wids = (old.window_ids if old else ()) + ((wid,) if not old or wid not in old.window_ids else ())
        entities[eid] = Entity(eid, kind, name, text, wids)
        return eid

    def rel(
        log: str, src: str, dst: str, kind: str, text: str, wid: str, t: float, fr: int | None, w: float
    ) -> None:
        rels.append(Relationship(f"{log}#{len(rels)}", src, dst, kind, text, wid, t, fr, w))

    nan = float("nan")
    for d in descriptions:
        wid, log = d.window_id, d.log_id
        s = entity(f"S:{wid}", "sample", wid, d.text, wid)
        if d.cluster is not None:
            name = "outliers" if d.cluster < 0 else f"cluster {d.cluster}"
            c = entity(
                f"C:{d.cluster}", "cluster", name, f"{name} of the {embedding or 'trajectory'} embedding", wid
            )
            rel(log, s, c, "belongs_to_cluster", f"sample {wid} belongs to {name}", wid, nan, None, 3.0)
        t = entity(f"T:{d.density}", "traffic", d.density, f"traffic state: {d.density} traffic", wid)
        rel(log, s, t, "has_traffic", f"sample {wid} is in {d.density} traffic", wid, nan, None, 0.5)
        for m in sample_manoeuvres(d):
            mid = entity(f"M:{m}", "manoeuvre", m, f"manoeuvre: {m}", wid)
            rel(log, s, mid, "shows", f"sample {wid} shows {m} by vehicle {d.agent_id}", wid, nan, None, 0.5)
        for f in d.vehicles:
            vid = entity(
                f"V:{log}/{f.track_id}",
                "vehicle",
                f"vehicle {f.track_id}",
                f"vehicle {f.track_id} ({f.category.lower()}) in log {log}, "
                f"{f.speed_mean_mps:.1f} m/s mean speed, {f.speed_trend}",
                wid,
            )
            rel(
                log,
                s,
                vid,
                "contains",
                f"sample {wid} contains vehicle {f.track_id}",
                wid,
                nan,
                None,
                2.0 if f.chosen else 1.0,
            )
            if f.lane_start >= 0:
                lid = entity(f"L:{f.lane_start}", "lane", f"lane {f.lane_start}", f"lane {f.lane_start}", wid)
                rel(
                    log,
                    vid,
                    lid,
                    "drives_in",
                    f"vehicle {f.track_id} drives in lane {f.lane_start}",
                    wid,
                    d.start_s,
                    d.start_frame,
                    0.5,
                )
            for lc in f.lane_changes:
                at = f" at {lc.t_s:.1f} s" + (f", frame {lc.frame}" if lc.frame is not None else "")
                if lc.to_lane >= 0:
                    lid = entity(f"L:{lc.to_lane}", "lane", f"lane {lc.to_lane}", f"lane {lc.to_lane}", wid)
                    text = (
                        f"vehicle {f.track_id} changes lane from {lc.from_lane} into lane {lc.to_lane} "
                        f"to the {lc.direction}{at}"
                    )
                    rel(log, vid, lid, "changes_lane_into", text, wid, lc.t_s, lc.frame, 1.0)
            for m in _vehicle_manoeuvres(f.lane_changes, f.speed_trend, f.peak_lateral_mps):
                mid = entity(f"M:{m}", "manoeuvre", m, f"manoeuvre: {m}", wid)
                first = f.lane_changes[0] if f.lane_changes and "lane change" in m else None
                t_m = first.t_s if first else nan
                at = (
                    f" at {first.t_s:.1f} s"
                    + (f", frame {first.frame}" if first and first.frame is not None else "")
                    if first
                    else ""
                )
                rel(
                    log,
                    vid,
                    mid,
                    "performs",
                    f"vehicle {f.track_id} performs {m}{at} in sample {wid}",
                    wid,
                    t_m,
                    first.frame if first else None,
                    0.5,
                )
        for i in d.interactions:
            a = f"V:{log}/{i.subject}"
            b = f"V:{log}/{i.obj}"
            verb = i.kind.replace("_", " ")
            side = f" on the {i.side}" if i.side else ""
            at = f" at {i.t_s:.1f} s" + (f", frame {i.frame}" if i.frame is not None else "")
            text = f"vehicle {i.subject} {verb} vehicle {i.obj}{side}{at} (sample {wid}, {d.density} traffic)"
            rel(log, a, b, i.kind, text, wid, i.t_s, i.frame, 1.5)
    return GraphElements(tuple(entities.values()), tuple(rels))


@dataclass(frozen=True)
class CommunityLevel:
    """Leiden communities at one resolution.

    Attributes:
        level: 0 (coarsest) upwards.
        resolution: the modularity resolution parameter.
        membership: entity id -> community number at this level.
    """

    level: int
    resolution: float
    membership: dict[str, int]

    def members(self) -> dict[int, list[str]]:
        """Community number -> its entity ids (sorted)."""
        out: dict[int, list[str]] = {}
        for eid, c in sorted(self.membership.items()):
            out.setdefault(c, []).append(eid)
        return out


def leiden_communities(
    elements: GraphElements, resolutions: Sequence[float] = (0.1, 0.5, 2.0), seed: int = 0
) -> list[CommunityLevel]:
    """Leiden communities of the graph at each resolution (``igraph`` + ``leidenalg``)."""
    ig = require("igraph", extra="represent", purpose="building the scenario knowledge graph")
    la = require("leidenalg", extra="represent", purpose="graph communities")
    names = [e.entity_id for e in elements.entities]
    index = {n: i for i, n in enumerate(names)}
    edges = [
        (index[r.source], index[r.target])
        for r in elements.relationships
        if r.source in index and r.target in index
    ]
    weights = [r.weight for r in elements.relationships if r.source in index and r.target in index]
    g = ig.Graph(n=len(names), edges=edges, directed=False)
    g.es["weight"] = weights
    out: list[CommunityLevel] = []
    for level, res in enumerate(resolutions):
        part = la.find_partition(
            g, la.RBConfigurationVertexPartition, weights="weight", resolution_parameter=float(res), seed=seed
        )
        out.append(
            CommunityLevel(
                level, float(res), {n: int(c) for n, c in zip(names, part.membership, strict=True)}
            )
        )
    return out


# ----------------------------------------------------------------------------------- storage


def _npz(**arrays: Float32Array) -> bytes:
    buf = io.BytesIO()
    np.savez(buf, **{k: np.ascontiguousarray(v, dtype=np.float32) for k, v in arrays.items()})  # type: ignore[arg-type]
    return buf.getvalue()


def save_log_graph(
    store: ScenarioStore,
    graph_id: str,
    by_log: Mapping[str, tuple[Sequence[WindowDescription], GraphElements, dict[str, Float32Array]]],
    embed_model: str,
    sources: Mapping[str, str],
) -> None:
    """Store descriptions, graph elements and their text vectors of several logs (one row each).

    ``by_log``: log id -> (descriptions, elements, vectors ``{"samples": (W, D), "entities":
    (E', D), "relationships": (R', D)}`` of the descriptions and of the embedded entities and
    relationships (:data:`EMBEDDED_ENTITIES`, :data:`EMBEDDED_RELATIONS`) in order). ``sources``:
    log id -> stamp of its inputs (window settings, clustering, labels), to find stale rows.
    """
    from scenariominer.represent.graph_store import description_row, element_rows

    samples: dict[str, dict[str, object]] = {}
    elements: dict[str, dict[str, object]] = {}
    blobs: dict[str, bytes] = {}
    for log_id, (descs, els, vecs) in by_log.items():
        key = f"{graph_id}|{log_id}"
        samples[key] = {
            "graph_id": graph_id,
            "log_id": log_id,
            "source": sources.get(log_id, ""),
            "embed_model": embed_model,
            "samples": [description_row(d) for d in descs],
        }
        elements[key] = {
            "graph_id": graph_id,
            "log_id": log_id,
            "embed_model": embed_model,
            **element_rows(els),
        }
        blobs[key] = _npz(**vecs)
    if samples:
        store.corpus(SAMPLES_TABLE, GRAPH_SCHEMA).upsert(samples)
        store.corpus(ELEMENTS_TABLE, GRAPH_SCHEMA).upsert(elements, blobs)


def graph_logs(store: ScenarioStore, graph_id: str) -> dict[str, str]:
    """Log id -> ``source`` of every log stored in graph ``graph_id``."""
    prefix = f"{graph_id}|"
    rows = store.corpus(SAMPLES_TABLE, GRAPH_SCHEMA).rows()
    return {str(r.data["log_id"]): str(r.data.get("source", "")) for r in rows if r.key.startswith(prefix)}


@dataclass(frozen=True, eq=False)
class StoredGraph:
    """A whole stored graph, merged over logs, with its text vectors.

    Attributes:
        graph_id: its id.
        embed_model: the text embedder of every vector.
        samples: per-sample records (see :func:`~.graph_store.description_row`), ``W`` of them.
        sample_vectors: ``(W, D)`` float32 unit vectors of the sample descriptions.
        elements: merged entities and relationships.
        entity_rows: ``(E',)`` rows of ``elements.entities`` that are embedded (kinds
            :data:`EMBEDDED_ENTITIES`).
        entity_vectors: ``(E', D)`` float32, in ``entity_rows`` order.
        rel_rows: ``(R',)`` rows of ``elements.relationships`` that are embedded (kinds
            :data:`EMBEDDED_RELATIONS`).
        rel_vectors: ``(R', D)`` float32, in ``rel_rows`` order.
    """

    graph_id: str
    embed_model: str
    samples: tuple[dict[str, object], ...]
    sample_vectors: Float32Array
    elements: GraphElements
    entity_rows: NDArray[np.intp]
    entity_vectors: Float32Array
    rel_rows: NDArray[np.intp]
    rel_vectors: Float32Array
    _entity_index: dict[str, int] = field(default_factory=dict)

    def entity_index(self) -> dict[str, int]:
        """Entity id -> row."""
        if not self._entity_index:
            self._entity_index.update({e.entity_id: i for i, e in enumerate(self.elements.entities)})
        return self._entity_index


def load_graph(store: ScenarioStore, graph_id: str) -> StoredGraph:
    """The stored graph ``graph_id`` merged over its logs (log order).

    Raises:
        GraphNotBuiltError: nothing is stored under ``graph_id``.
    """
    from scenariominer.represent.graph_store import GraphNotBuiltError, entity_from, relationship_from

    logs = sorted(graph_logs(store, graph_id))
    if not logs:
        raise GraphNotBuiltError(
            f"no graph {graph_id!r} in the store; build it first (scenariominer graph build)"
        )
    keys = [f"{graph_id}|{log}" for log in logs]
    srows = {r.key: r for r in store.corpus(SAMPLES_TABLE, GRAPH_SCHEMA).rows(keys)}
    erows = {r.key: r for r in store.corpus(ELEMENTS_TABLE, GRAPH_SCHEMA).rows(keys, with_blobs=True)}
    samples: list[dict[str, object]] = []
    svec: list[Float32Array] = []
    entities: dict[str, Entity] = {}
    evec: dict[str, Float32Array] = {}
    rels: list[Relationship] = []
    rvec: list[Float32Array] = []
    model = ""
    for key in keys:
        if key not in srows or key not in erows:
            continue
        s, e = srows[key], erows[key]
        model = str(e.data.get("embed_model", model))
        arrays = np.load(io.BytesIO(e.blob or b""))
        samples += list(s.data["samples"])
        svec.append(arrays["samples"])
        n_embedded = 0
        for raw in e.data["entities"]:
            ent = entity_from(raw)
            old = entities.get(ent.entity_id)
            if ent.kind in EMBEDDED_ENTITIES:
                evec.setdefault(ent.entity_id, arrays["entities"][n_embedded])
                n_embedded += 1
            if old is not None:
                ent = Entity(old.entity_id, old.kind, old.name, old.text, old.window_ids + ent.window_ids)
            entities[ent.entity_id] = ent
        rels += [relationship_from(raw) for raw in e.data["relationships"]]
        rvec.append(arrays["relationships"])
    dim = svec[0].shape[1] if svec else 0

    def stack(parts: list[Float32Array]) -> Float32Array:
        return np.concatenate(parts) if parts else np.zeros((0, dim), np.float32)

    ents = tuple(entities.values())
    ent_rows = np.asarray([i for i, x in enumerate(ents) if x.kind in EMBEDDED_ENTITIES], dtype=np.intp)
    rrows = np.asarray([i for i, r in enumerate(rels) if r.kind in EMBEDDED_RELATIONS], dtype=np.intp)
    return StoredGraph(
        graph_id,
        model,
        tuple(samples),
        stack(svec),
        GraphElements(ents, tuple(rels)),
        ent_rows,
        np.stack([evec[ents[i].entity_id] for i in ent_rows])
        if ent_rows.size
        else np.zeros((0, dim), np.float32),
        rrows,
        stack(rvec),
    )
