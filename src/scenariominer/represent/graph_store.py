"""JSON rows of the graph tables (samples, entities, relationships) and the graph's errors."""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

from scenariominer.represent.describe import WindowDescription
from scenariominer.represent.errors import RepresentError

__all__ = [
    "GraphNotBuiltError",
    "description_row",
    "element_rows",
    "entity_from",
    "relationship_from",
]


class GraphNotBuiltError(RepresentError, LookupError):
    """The knowledge graph asked for is not in the store."""


def description_row(d: WindowDescription) -> dict[str, object]:
    """The stored record of one sample: references, traffic state, manoeuvres and the text."""
    from scenariominer.represent.graph import sample_manoeuvres

    return {
        "window_id": d.window_id,
        "log_id": d.log_id,
        "agent_id": d.agent_id,
        "start_s": d.start_s,
        "end_s": d.end_s,
        "start_frame": d.start_frame,
        "end_frame": d.end_frame,
        "cluster": d.cluster,
        "density": d.density,
        "n_lanes": d.n_lanes,
        "mean_speed_mps": round(d.mean_speed_mps, 2),
        "track_ids": [v.track_id for v in d.vehicles],
        "manoeuvres": sample_manoeuvres(d),
        "text": d.text,
    }


def element_rows(els: Any) -> dict[str, list[dict[str, object]]]:
    """``entities`` and ``relationships`` of a :class:`~.graph.GraphElements` as JSON lists."""
    return {
        "entities": [
            {"id": e.entity_id, "kind": e.kind, "name": e.name, "text": e.text, "windows": list(e.window_ids)}
            for e in els.entities
        ],
        "relationships": [
            {
                "id": r.rel_id,
                "source": r.source,
                "target": r.target,
                "kind": r.kind,
                "text": r.text,
                "window_id": r.window_id,
                "t_s": None if math.isnan(r.t_s) else r.t_s,
                "frame": r.frame,
                "weight": r.weight,
            }
            for r in els.relationships
        ],
    }


def entity_from(raw: Mapping[str, Any]) -> Any:
    """An :class:`~.graph.Entity` from its JSON row."""
    from scenariominer.represent.graph import Entity

    return Entity(str(raw["id"]), str(raw["kind"]), str(raw["name"]), str(raw["text"]), tuple(raw["windows"]))


def relationship_from(raw: Mapping[str, Any]) -> Any:
    """A :class:`~.graph.Relationship` from its JSON row."""
    from scenariominer.represent.graph import Relationship

    t = raw.get("t_s")
    return Relationship(
        str(raw["id"]),
        str(raw["source"]),
        str(raw["target"]),
        str(raw["kind"]),
        str(raw["text"]),
        str(raw["window_id"]),
        float("nan") if t is None else float(t),
        None if raw.get("frame") is None else int(raw["frame"]),
        float(raw["weight"]),
    )
