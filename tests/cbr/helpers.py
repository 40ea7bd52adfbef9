"""Builders shared by the CBR tests: a tiny case base over a hashing embedder, scripted answers."""

from __future__ import annotations

import json
from pathlib import Path

from scenariominer.cbr.cases import Case, CaseBase
from scenariominer.cbr.vocab import load_manoeuvres, load_risk_types
from scenariominer.llm.embeddings import HashingEmbedder
from scenariominer.store import ScenarioStore

EMBEDDER = HashingEmbedder(256)

CASES = [
    Case(
        "a1",
        "vehicle_ahead",
        "a stopped truck blocks the lane far ahead on a wet road",
        manoeuvre="emergency_braking",
    ),
    Case(
        "a2",
        "vehicle_ahead",
        "the car in front brakes suddenly in dense traffic",
        manoeuvre="emergency_braking",
    ),
    Case(
        "a3",
        "vehicle_ahead",
        "a stopped truck very close ahead with the left lane free",
        manoeuvre="evasive_steering_left",
    ),
    Case(
        "p1", "pedestrian", "a stopped truck hides a pedestrian who steps out", manoeuvre="emergency_braking"
    ),
    Case("p2", "pedestrian", "a child runs across the road from the right", manoeuvre="emergency_braking"),
    Case("h1", "head_on", "a wrong-way car comes straight at the ego", manoeuvre="evasive_steering_right"),
]


def answer(manoeuvre: str = "emergency_braking", **fields: str) -> str:
    """A schema-valid JSON answer."""
    data = {
        "road_context": "two-lane road",
        "other_vehicle_position": "ahead in the ego lane",
        "other_vehicle_action": "stopped",
        "event_context": "the ego closes in on a stopped car",
        "manoeuvre": manoeuvre,
        "justification": "braking stops the car before the obstacle",
    }
    data.update(fields)
    return json.dumps(data)


def case_base(tmp_path: Path, cases: list[Case] | None = None) -> CaseBase:
    """A case base in a fresh store holding ``cases`` (default :data:`CASES`)."""
    store = ScenarioStore.open(tmp_path / "store")
    base = CaseBase(store, "cbr_cases", load_risk_types(), load_manoeuvres())
    report = base.add(CASES if cases is None else cases, EMBEDDER, 0.97)
    assert not report.rejected and not report.duplicates
    return base
