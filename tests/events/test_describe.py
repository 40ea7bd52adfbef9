"""Structured scenario descriptions: exact text for hand-built tags (Fig. 4c)."""

from __future__ import annotations

import numpy as np

from scenariominer.events.describe import describe_pair
from scenariominer.tags import LogTags
from scenariominer.tags.vocab import TAG_FAMILIES, names_to_codes

DT_NS = 100_000_000
T0_NS = 1_000_000_000_000


def _runs(*parts: tuple[str | None, int]) -> list[str | None]:
    return [name for name, n in parts for _ in range(n)]


def _tags(
    t: int, ego: dict[str, list[str | None]], guest: dict[str, list[str | None]], category: str
) -> LogTags:
    arrays = {}
    for family, enum_cls in TAG_FAMILIES.items():
        rows = np.empty((2, t), dtype=object)
        rows[0] = ego.get(family, [None] * t)
        rows[1] = guest[family]
        arrays[family] = names_to_codes(enum_cls, rows)
    return LogTags(
        log_id="log",
        track_ids=np.array(["ego", "guest"]),
        categories=np.array(["EGO_VEHICLE", category]),
        timestamps_ns=T0_NS + np.arange(t, dtype=np.int64) * DT_NS,
        ttc_s=np.full((2, t), np.inf),
        distance_m=np.full((2, t), 20.0),
        **arrays,
    )


def _cut_in_tags() -> LogTags:
    """4 s at 10 Hz: a car ahead-right moves in front (0.5 s), the ego brakes (1.0 s), risk grows."""
    t = 40
    return _tags(
        t,
        ego={
            "longitude": _runs(("CRUISING", 10), ("DECELERATING", 30)),
            "latitude": _runs(("FACING_FORWARD", 40)),
        },
        guest={
            "longitude": _runs(("CRUISING", 20), ("DECELERATING", 20)),
            "latitude": _runs(("FACING_FORWARD", 40)),
            "collision": _runs(("NO", 15), ("LOW", 15), ("HIGH", 10)),
            "heading": _runs(("SAME", 40)),
            "position": _runs(("FRONT_RIGHT", 5), ("FRONT", 35)),
            "distance": _runs(("MEDIUM", 20), ("CLOSE", 20)),
            "traj_overlap": _runs(("NO", 40)),
        },
        category="REGULAR_VEHICLE",
    )


def test_description_lists_initial_tags_then_only_the_changes() -> None:
    text = describe_pair(
        _cut_in_tags(), "guest", T0_NS + 15 * DT_NS, T0_NS + 35 * DT_NS, context_before_s=5, context_after_s=5
    )
    assert text == (
        "Overview: a 4.0-second scenario between the ego vehicle and a guest REGULAR_VEHICLE. "
        "The ego brakes while the guest poses a risk from 1.5 s to 3.5 s.\n"
        "Initial tags (at 0.0 s):\n"
        "- ego: longitudinal CRUISING, lateral FACING_FORWARD\n"
        "- guest: longitudinal CRUISING, lateral FACING_FORWARD\n"
        "- guest relative to ego: collision risk NO, relative heading SAME, relative position FRONT_RIGHT, "
        "distance MEDIUM, trajectory overlap risk NO\n"
        "Changes:\n"
        "- at 0.5 s: guest relative position FRONT (for 3.5 s)\n"
        "- at 1.0 s: ego longitudinal DECELERATING (for 3.0 s)\n"
        "- at 1.5 s: guest collision risk LOW (for 1.5 s)\n"
        "- at 2.0 s: guest longitudinal DECELERATING (for 2.0 s); guest distance CLOSE (for 2.0 s)\n"
        "- at 3.0 s: guest collision risk HIGH (for 1.0 s)\n"
        "End at 4.0 s."
    )


def test_window_with_context_restarts_the_clock_and_initial_values() -> None:
    # Window: event 1.5-2.5 s plus 0.5 s before and after -> 1.0 s to 3.0 s of the log.
    text = describe_pair(
        _cut_in_tags(),
        "guest",
        T0_NS + 15 * DT_NS,
        T0_NS + 25 * DT_NS,
        context_before_s=0.5,
        context_after_s=0.5,
    )
    assert text.splitlines() == [
        "Overview: a 2.1-second scenario between the ego vehicle and a guest REGULAR_VEHICLE. "
        "The ego brakes while the guest poses a risk from 0.5 s to 1.5 s.",
        "Initial tags (at 0.0 s):",
        "- ego: longitudinal DECELERATING, lateral FACING_FORWARD",
        "- guest: longitudinal CRUISING, lateral FACING_FORWARD",
        "- guest relative to ego: collision risk NO, relative heading SAME, relative position FRONT, "
        "distance MEDIUM, trajectory overlap risk NO",
        "Changes:",
        "- at 0.5 s: guest collision risk LOW (for 1.5 s)",
        "- at 1.0 s: guest longitudinal DECELERATING (for 1.1 s); guest distance CLOSE (for 1.1 s)",
        "- at 2.0 s: guest collision risk HIGH (for 0.1 s)",
        "End at 2.1 s.",
    ]


def test_unobserved_guest_and_constant_tags() -> None:
    t = 10
    guest = {
        f: _runs((None, 2), (v, 8))
        for f, v in [
            ("longitude", "STANDING_STILL"),
            ("latitude", "FACING_FORWARD"),
            ("collision", "NO"),
            ("heading", "RIGHT"),
            ("position", "FRONT"),
            ("distance", "CLOSE"),
            ("traj_overlap", "HIGH"),
        ]
    }
    tags = _tags(
        t,
        ego={"longitude": _runs(("STANDING_STILL", 10)), "latitude": _runs(("FACING_FORWARD", 10))},
        guest=guest,
        category="PEDESTRIAN",
    )
    text = describe_pair(tags, "guest", T0_NS + 2 * DT_NS, T0_NS + 9 * DT_NS, context_before_s=1.0)
    lines = text.splitlines()
    assert lines[3] == "- guest: longitudinal not observed, lateral not observed"
    assert lines[6] == (
        "- at 0.2 s: guest longitudinal STANDING_STILL (for 0.8 s); "
        "guest lateral FACING_FORWARD (for 0.8 s); "
        "guest collision risk NO (for 0.8 s); guest relative heading RIGHT (for 0.8 s); guest relative "
        "position FRONT (for 0.8 s); guest distance CLOSE (for 0.8 s); guest trajectory overlap risk HIGH "
        "(for 0.8 s)"
    )
    steady = describe_pair(tags, "guest", T0_NS + 2 * DT_NS, T0_NS + 9 * DT_NS)
    assert "Changes: none, every tag keeps its initial value." in steady.splitlines()
    assert "a guest PEDESTRIAN." in steady


def test_description_is_deterministic() -> None:
    tags = _cut_in_tags()
    a = describe_pair(tags, "guest", T0_NS + 15 * DT_NS, T0_NS + 35 * DT_NS, context_before_s=1.0)
    b = describe_pair(tags, "guest", T0_NS + 15 * DT_NS, T0_NS + 35 * DT_NS, context_before_s=1.0)
    assert a == b
