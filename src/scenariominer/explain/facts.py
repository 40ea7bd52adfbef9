"""Concrete facts of one braking event: who, where, how fast, how close, how soon.

The LLM of the hybrid judgement (:mod:`scenariominer.explain.judge`) reads these instead of the
long tag-by-tag description: they are short (about 100 tokens instead of 400) and they are what an
explanation must state, so the answer can quote them rather than the prompt's own wording. The
rules-only mode writes its explanation from the same facts (:func:`rules_explanation`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from scenariominer.data.log import Log
from scenariominer.events.criticality import Criticality
from scenariominer.events.segments import PAIR_FEATURES, Actor, PairFeature, PairTags
from scenariominer.tags.vocab import HeadingTag, LatitudeTag, PositionTag, member_of

__all__ = ["EventFacts", "event_facts", "rules_explanation"]

_LATERAL_WORDS = {
    LatitudeTag.TURNING_LEFT: "turns left",
    LatitudeTag.TURNING_RIGHT: "turns right",
    LatitudeTag.VEERING_LEFT: "veers left",
    LatitudeTag.VEERING_RIGHT: "veers right",
}
_HEADING_WORDS = {
    HeadingTag.SAME: "moving the same way as the ego",
    HeadingTag.OPPOSITE: "oncoming",
    HeadingTag.LEFT: "moving across the ego's path towards its left",
    HeadingTag.RIGHT: "moving across the ego's path towards its right",
}

#: Where the guest is, seen from the ego, as a phrase ("" — never observed — reads "near the ego").
_POSITION_WORDS = {
    PositionTag.FRONT: "ahead of the ego",
    PositionTag.FRONT_LEFT: "ahead and to the left of the ego",
    PositionTag.LEFT: "to the left of the ego",
    PositionTag.BACK_LEFT: "behind and to the left of the ego",
    PositionTag.BACK: "behind the ego",
    PositionTag.BACK_RIGHT: "behind and to the right of the ego",
    PositionTag.RIGHT: "to the right of the ego",
    PositionTag.FRONT_RIGHT: "ahead and to the right of the ego",
}


def _words(category: str) -> str:
    return category.lower().replace("_", " ")


@dataclass(frozen=True)
class EventFacts:
    """What happened around one braking event, in plain units.

    Attributes:
        guest: the guest's category in words (``"pedestrian"``, ``"regular vehicle"``).
        guest_is_pedestrian: whether the guest is a pedestrian.
        ego_speed_kmh: the ego's speed when the event starts, km/h.
        guest_speed_kmh: the guest's speed when the event starts, km/h (NaN if unobserved).
        position_start: where the guest is, seen from the ego, when the event starts (``FRONT``, ...).
        position_closest: where it is at the closest approach.
        heading: the guest's relative heading at the start (``SAME``, ``LEFT``, ...; "" if unknown).
        ego_lateral: what the ego does sideways in the window (``"turns right"``, "" if straight).
        guest_lateral: what the guest does sideways in the window ("" if straight).
        min_gap_m: smallest distance between the two boxes, metres.
        min_ttc_s: smallest time-to-collision, seconds (``inf`` when none was predicted).
        headway_s: smallest time headway while the guest leads, seconds (NaN if it never leads).
        peak_decel_mps2: the ego's hardest deceleration, m/s².
    """

    guest: str
    guest_is_pedestrian: bool
    ego_speed_kmh: float
    guest_speed_kmh: float
    position_start: str
    position_closest: str
    heading: str
    ego_lateral: str
    guest_lateral: str
    min_gap_m: float
    min_ttc_s: float
    headway_s: float
    peak_decel_mps2: float

    def lines(self) -> list[str]:
        """The facts as short ``name: value`` lines (the LLM's input)."""
        out = [
            f"guest: {self.guest}",
            f"ego speed at braking onset: {self.ego_speed_kmh:.0f} km/h",
        ]
        if math.isfinite(self.guest_speed_kmh):
            out.append(f"guest speed at braking onset: {self.guest_speed_kmh:.0f} km/h")
        where = f"{self.position_start} at onset, {self.position_closest} closest"
        out.append(f"guest position seen from the ego: {where}")
        if self.heading:
            words = _HEADING_WORDS[HeadingTag(self.heading)]
            out.append(f"guest heading relative to the ego: {self.heading} ({words})")
        out.append(f"ego manoeuvre: {self.ego_lateral or 'keeps straight'}")
        out.append(f"guest manoeuvre: {self.guest_lateral or 'keeps straight'}")
        out.append(f"smallest gap: {self.min_gap_m:.1f} m")
        if math.isfinite(self.min_ttc_s):
            out.append(f"smallest time to collision: {self.min_ttc_s:.1f} s")
        if math.isfinite(self.headway_s):
            out.append(f"smallest time headway behind the guest: {self.headway_s:.1f} s")
        out.append(f"ego's hardest deceleration: {self.peak_decel_mps2:.1f} m/s²")
        return out

    def text(self) -> str:
        """:meth:`lines` joined by newlines."""
        return "\n".join(self.lines())


def _row(pair: PairTags, actor: Actor, family: str) -> np.ndarray:
    return np.asarray(pair.codes[PAIR_FEATURES.index(PairFeature(actor, family))])


def _lateral(pair: PairTags, actor: Actor) -> str:
    """The first sideways manoeuvre of ``actor`` in the window, in words ("" if none)."""
    for code in _row(pair, actor, "latitude"):
        tag = member_of(LatitudeTag, int(code))
        if tag in _LATERAL_WORDS:
            return _LATERAL_WORDS[tag]  # type: ignore[index]
    return ""


def _tag_at(pair: PairTags, family: str, enum: type[PositionTag] | type[HeadingTag], t_ns: int) -> str:
    """The pair tag of ``family`` at the window timestamp nearest ``t_ns`` ("" if absent)."""
    i = int(np.argmin(np.abs(pair.timestamps_ns - t_ns)))
    codes = _row(pair, Actor.PAIR, family)
    tag = member_of(enum, int(codes[i]))
    if tag is None:  # the guest is unobserved there: the nearest observed timestamp
        seen = np.flatnonzero(codes >= 0)
        if seen.size == 0:
            return ""
        tag = member_of(enum, int(codes[seen[np.argmin(np.abs(seen - i))]]))
    return "" if tag is None else tag.value


def _speed_kmh(log: Log, track: int, t_ns: int) -> float:
    i = int(np.argmin(np.abs(log.timestamps_ns - t_ns)))
    v = float(log.speed_mps[track, i])
    return v * 3.6 if math.isfinite(v) else math.nan


def event_facts(log: Log, pair: PairTags, crit: Criticality, start_ns: int, min_gap_m: float) -> EventFacts:
    """Collect the facts of one event from the log, its pair tags and its criticality measures.

    Args:
        log: the log (speeds are read from it).
        pair: the ego–guest tags over the analysis window.
        crit: the event's criticality measures.
        start_ns: first timestamp of the event (braking onset as KeyIdent saw it).
        min_gap_m: smallest box distance of the event, metres.
    """
    guest_track = log.track_index(pair.guest_id)
    return EventFacts(
        guest=_words(pair.guest_category),
        guest_is_pedestrian=pair.guest_category == "PEDESTRIAN",
        ego_speed_kmh=_speed_kmh(log, log.ego_index, start_ns),
        guest_speed_kmh=_speed_kmh(log, guest_track, start_ns),
        position_start=_tag_at(pair, "position", PositionTag, start_ns),
        position_closest=_tag_at(pair, "position", PositionTag, crit.closest_ns),
        heading=_tag_at(pair, "heading", HeadingTag, start_ns),
        ego_lateral=_lateral(pair, Actor.EGO),
        guest_lateral=_lateral(pair, Actor.GUEST),
        min_gap_m=float(min_gap_m),
        min_ttc_s=float(crit.min_ttc_s),
        headway_s=float(crit.headway_s),
        peak_decel_mps2=float(crit.peak_decel_mps2),
    )


def rules_explanation(category: str, facts: EventFacts) -> str:
    """One sentence naming the facts behind a category, written without a model."""
    where = _POSITION_WORDS[PositionTag(facts.position_closest)] if facts.position_closest else "near the ego"
    parts = [f"a {facts.guest} {where}"]
    if facts.heading:
        parts.append(_HEADING_WORDS[HeadingTag(facts.heading)])
    if facts.guest_lateral:
        parts.append(f"it {facts.guest_lateral}")
    if facts.ego_lateral:
        parts.append(f"while the ego {facts.ego_lateral}")
    gap = f"gap {facts.min_gap_m:.1f} m"
    if math.isfinite(facts.min_ttc_s):
        gap += f", time to collision {facts.min_ttc_s:.1f} s"
    decel = f"{facts.peak_decel_mps2:.1f} m/s²"
    if not math.isfinite(facts.ego_speed_kmh):
        ego = f"the ego brakes at up to {decel}"
    elif abs(facts.ego_speed_kmh) < 0.5:
        # KeyIdent counts a standing ego as braking (held by the guest); "brakes from 0 km/h" is nonsense
        ego = f"the ego is standing still (its hardest deceleration around it: {decel})"
    else:
        ego = f"the ego brakes from {facts.ego_speed_kmh:.0f} km/h at up to {decel}"
    return f"{_words(category).capitalize()}: " + ", ".join(parts) + f" ({gap}); {ego}."
