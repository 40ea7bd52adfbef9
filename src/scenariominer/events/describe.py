"""Structured text description of an ego–guest pair (braking paper, section III-D.1, Fig. 4c).

The text is rendered from :class:`~scenariominer.events.segments.PairSegments` by a fixed
template, so it is a deterministic function of the tags:

1. an overview: total duration, the two actors (with the guest's category), and when the
   KeyIdent event (ego braking while the guest poses a risk) happens inside the window;
2. the initial value of every tag: the ego's and the guest's longitudinal and lateral activity,
   then the guest's collision risk, relative heading, relative position, distance and trajectory
   overlap with respect to the ego;
3. one line per later segment listing only the tags that change there, each with how long its
   new value lasts.

Example::

    Overview: a 4.0-second scenario between the ego vehicle and a guest REGULAR_VEHICLE. ...
    Initial tags (at 0.0 s):
    - ego: longitudinal CRUISING, lateral FACING_FORWARD
    ...
    Changes:
    - at 1.0 s: ego longitudinal DECELERATING (for 3.0 s); guest collision risk LOW (for 1.5 s)
    End at 4.0 s.
"""

from __future__ import annotations

from scenariominer.events.segments import (
    PAIR_FEATURES,
    Actor,
    PairSegments,
    pair_tags,
    segment_pair,
)
from scenariominer.tags.engine import LogTags

__all__ = ["DESCRIPTION_VERSION", "FAMILY_LABELS", "NOT_OBSERVED", "describe_pair", "describe_segments"]

#: Version of the description template; part of the analysis fingerprint, bump it on any change.
DESCRIPTION_VERSION = "describe/2"

#: Words used for each tag family in a description.
FAMILY_LABELS: dict[str, str] = {
    "longitude": "longitudinal",
    "latitude": "lateral",
    "collision": "collision risk",
    "heading": "relative heading",
    "position": "relative position",
    "distance": "distance",
    "traj_overlap": "trajectory overlap risk",
}

#: Written where a tag is undefined because the guest is not observed.
NOT_OBSERVED = "not observed"

_ACTOR_LINES: tuple[tuple[Actor, str], ...] = (
    (Actor.EGO, "ego"),
    (Actor.GUEST, "guest"),
    (Actor.PAIR, "guest relative to ego"),
)
_CHANGE_PREFIX = {Actor.EGO: "ego", Actor.GUEST: "guest", Actor.PAIR: "guest"}


def _seconds(value: float) -> str:
    """Format seconds with one decimal (``-0.0`` printed as ``0.0``)."""
    text = f"{value:.1f}"
    return "0.0" if text == "-0.0" else text


def describe_segments(segments: PairSegments) -> str:
    """Render the structured description of a pair's segments (see the module docstring).

    Args:
        segments: the pair's duration segments from :func:`~scenariominer.events.segments.segment_pair`.

    Returns:
        Multi-line text without a trailing newline.
    """
    pair = segments.pair
    t0 = int(pair.timestamps_ns[0])
    event_from = (pair.event_start_ns - t0) * 1e-9
    event_to = (pair.event_end_ns - t0) * 1e-9
    lines = [
        f"Overview: a {_seconds(pair.duration_s)}-second scenario between the ego vehicle and a guest "
        f"{pair.guest_category}. The ego brakes while the guest poses a risk from {_seconds(event_from)} s "
        f"to {_seconds(event_to)} s.",
        "Initial tags (at 0.0 s):",
    ]
    for actor, label in _ACTOR_LINES:
        parts = [
            f"{FAMILY_LABELS[f.family]} {segments.value(i, 0) or NOT_OBSERVED}"
            for i, f in enumerate(PAIR_FEATURES)
            if f.actor is actor
        ]
        lines.append(f"- {label}: {', '.join(parts)}")
    if segments.n_segments > 1:
        lines.append("Changes:")
        for s in range(1, segments.n_segments):
            parts = []
            for i, feature in enumerate(PAIR_FEATURES):
                if not segments.changed[i, s]:
                    continue
                value = segments.value(i, s) or NOT_OBSERVED
                parts.append(
                    f"{_CHANGE_PREFIX[feature.actor]} {FAMILY_LABELS[feature.family]} {value} "
                    f"(for {_seconds(float(segments.value_duration_s[i, s]))} s)"
                )
            lines.append(f"- at {_seconds(float(segments.start_s[s]))} s: {'; '.join(parts)}")
    else:
        lines.append("Changes: none, every tag keeps its initial value.")
    lines.append(f"End at {_seconds(pair.duration_s)} s.")
    return "\n".join(lines)


def describe_pair(
    tags: LogTags,
    guest_id: str,
    start_ns: int,
    end_ns: int,
    *,
    context_before_s: float = 0.0,
    context_after_s: float = 0.0,
    min_segment_s: float = 0.0,
) -> str:
    """Describe an ego–guest pair over an event window plus context.

    Args:
        tags: the log's tags.
        guest_id: the guest's track id.
        start_ns: first timestamp of the event.
        end_ns: last timestamp of the event (inclusive).
        context_before_s: seconds of context before the event.
        context_after_s: seconds of context after the event.
        min_segment_s: shorter heading, position and distance values are merged into their
            neighbour (see :func:`~scenariominer.events.segments.segment_pair`).

    Raises:
        KeyError: the guest is not in the log.
        ValueError: the window holds no timestamp.
    """
    pair = pair_tags(
        tags, guest_id, start_ns, end_ns, context_before_s=context_before_s, context_after_s=context_after_s
    )
    return describe_segments(segment_pair(pair, min_segment_s))
