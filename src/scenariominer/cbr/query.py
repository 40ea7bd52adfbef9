"""From our own logs: an analysed braking event becomes a CBR query and a rollout scene.

Caption: the event's measured facts (who, speeds, relative heading, manoeuvres, gap, TTC; one clause
each, separated by semicolons) followed by its description (the LLM's rephrased description when it
has one, else the overview sentence of the rule-based tag description), cut at
:data:`MAX_CAPTION_CHARS`. Risk type: a pedestrian or cyclist guest is ``pedestrian``; otherwise the
event's category through ``cbr.category_map`` (``lead_brake``/``approach_stop`` -> vehicle ahead,
``cut_in`` -> merging vehicle, ``obj_crossing`` -> adjacent vehicle, ``left_oppo`` -> opposite
turning vehicle, ``right_ped`` -> pedestrian), and ``cbr.default_risk_type`` for anything else. The
conflict time is the event's closest ego-guest approach.
"""

from __future__ import annotations

from scenariominer.cbr.recommend import Query
from scenariominer.cbr.rollout import RolloutScene, scene_from_log
from scenariominer.config.cbr import CbrConfig
from scenariominer.explain.records import EventRecord, records_from_table
from scenariominer.explain.search import load_events
from scenariominer.store import ScenarioStore

__all__ = [
    "MAX_CAPTION_CHARS",
    "VULNERABLE_CATEGORIES",
    "find_event",
    "query_from_event",
    "risk_type_of",
    "scene_of_event",
]

#: Longest caption given to the model (the prompt stays short enough for a few seconds per call).
MAX_CAPTION_CHARS = 700
#: Guest categories that make an event a pedestrian conflict whatever its scenario category.
VULNERABLE_CATEGORIES = frozenset({"PEDESTRIAN", "BICYCLIST", "BICYCLE", "WHEELCHAIR", "WHEELED_RIDER"})


def risk_type_of(record: EventRecord, cfg: CbrConfig) -> str:
    """The risk type of an analysed event (see the module docstring)."""
    if record.guest_category.upper() in VULNERABLE_CATEGORIES:
        return "pedestrian"
    return cfg.category_map.get(record.category, cfg.default_risk_type)


def query_from_event(record: EventRecord, cfg: CbrConfig) -> Query:
    """The CBR query of an analysed event (caption at most :data:`MAX_CAPTION_CHARS` long)."""
    text = " ".join((record.llm_description or record.tag_description.split("Initial tags", 1)[0]).split())
    # the facts are one "name: value" per line: kept apart as clauses, not run into one another
    facts = "; ".join(" ".join(line.split()) for line in record.facts.splitlines() if line.strip())
    caption = f"{facts}. {text}" if facts and text else facts or text
    if len(caption) > MAX_CAPTION_CHARS:
        caption = caption[: MAX_CAPTION_CHARS - 3].rsplit(" ", 1)[0] + "..."
    return Query(record.event_id, caption, risk_type_of(record, cfg))


def find_event(store: ScenarioStore, log_id: str, event_id: str | None) -> EventRecord:
    """An analysed event of a log (by id, ``<guest>:<start_ns>`` or guest id; default the hardest).

    Raises:
        ExplainError: the store holds no analysed events, or the log has no such event.
    """
    from scenariominer.explain.show import _find_event

    return _find_event(records_from_table(load_events(store, [log_id])), log_id, event_id)


def scene_of_event(store: ScenarioStore, record: EventRecord, cfg: CbrConfig) -> RolloutScene:
    """The rollout scene of an event: from ``lead_s`` before its closest approach on.

    Every annotated object counts (parked cars, bollards and cones too: steering into one is a
    collision).
    """
    log = store.load_log(record.log_id)
    return scene_from_log(
        log,
        record.closest_ns,
        lead_s=cfg.rollout.lead_s,
        horizon_s=cfg.rollout.horizon_s,
    )
