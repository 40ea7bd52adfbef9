"""Vocabulary of the rule-based activity tags (braking paper, Table I).

Each tag family is a ``str`` enum. In the dense ``tracks × timestamps`` tag matrices a tag is
stored as an ``int8`` *code*: the member's position in its enum's definition order, with
:data:`ABSENT` (``-1``) where the track (or, for interaction tags, the ego) is not observed,
and for the ego's own row of an interaction tag.

Example::

    code_of(LongitudeTag.DECELERATING)       # 3
    member_of(LongitudeTag, 3)               # LongitudeTag.DECELERATING
"""

from __future__ import annotations

from enum import StrEnum
from typing import TypeVar

import numpy as np
from numpy.typing import NDArray

__all__ = [
    "ABSENT",
    "ACTOR_FAMILIES",
    "INTERACTION_FAMILIES",
    "TAG_FAMILIES",
    "CollisionTag",
    "DistanceTag",
    "HeadingTag",
    "LatitudeTag",
    "LongitudeTag",
    "PositionTag",
    "TagEnum",
    "TrajOverlapTag",
    "code_of",
    "codes_to_names",
    "member_of",
    "names_to_codes",
]

#: Code of a cell where the tag is undefined (track absent, or the ego's row of an interaction tag).
ABSENT: int = -1


class LongitudeTag(StrEnum):
    """Longitudinal motion of an actor along its heading.

    Attributes:
        CRUISING: moving forward with an acceleration inside the dead band.
        STANDING_STILL: ground speed below the standstill threshold.
        ACCELERATING: longitudinal acceleration above the accelerating threshold.
        DECELERATING: longitudinal acceleration below minus the decelerating threshold.
        REVERSING: moving backwards relative to the box heading.
    """

    CRUISING = "CRUISING"
    STANDING_STILL = "STANDING_STILL"
    ACCELERATING = "ACCELERATING"
    DECELERATING = "DECELERATING"
    REVERSING = "REVERSING"


class LatitudeTag(StrEnum):
    """Change of an actor's heading over its current turning segment (yaw counter-clockwise = left).

    Attributes:
        FACING_FORWARD: accumulated heading change below the veering threshold, or not moving.
        VEERING_LEFT: accumulated counter-clockwise change between the veering and turning thresholds.
        VEERING_RIGHT: the clockwise counterpart of ``VEERING_LEFT``.
        TURNING_LEFT: accumulated counter-clockwise change above the turning threshold.
        TURNING_RIGHT: the clockwise counterpart of ``TURNING_LEFT``.
    """

    FACING_FORWARD = "FACING_FORWARD"
    VEERING_LEFT = "VEERING_LEFT"
    VEERING_RIGHT = "VEERING_RIGHT"
    TURNING_LEFT = "TURNING_LEFT"
    TURNING_RIGHT = "TURNING_RIGHT"


class CollisionTag(StrEnum):
    """Collision risk from the time-to-collision of a Constant Turn Rate and Velocity prediction.

    Attributes:
        NO: no predicted box overlap within the low-risk horizon.
        LOW: predicted overlap between the high- and low-risk horizons.
        HIGH: predicted overlap sooner than the high-risk horizon.
    """

    NO = "NO"
    LOW = "LOW"
    HIGH = "HIGH"


class HeadingTag(StrEnum):
    """Heading of the object relative to the ego's, in four equal 90° sectors.

    Attributes:
        SAME: within ±45° of the ego's heading.
        LEFT: pointing to the ego's left (relative heading 45°..135°).
        OPPOSITE: relative heading beyond ±135°.
        RIGHT: pointing to the ego's right (relative heading -135°..-45°).
    """

    SAME = "SAME"
    LEFT = "LEFT"
    OPPOSITE = "OPPOSITE"
    RIGHT = "RIGHT"


class PositionTag(StrEnum):
    """Bearing of the object's centre in the ego frame (x forward, y left), eight equal 45° sectors.

    Attributes:
        FRONT: bearing within ±22.5° of straight ahead.
        FRONT_LEFT: centred on +45°.
        LEFT: centred on +90°.
        BACK_LEFT: centred on +135°.
        BACK: centred on 180°.
        BACK_RIGHT: centred on -135°.
        RIGHT: centred on -90°.
        FRONT_RIGHT: centred on -45°.
    """

    FRONT = "FRONT"
    FRONT_LEFT = "FRONT_LEFT"
    LEFT = "LEFT"
    BACK_LEFT = "BACK_LEFT"
    BACK = "BACK"
    BACK_RIGHT = "BACK_RIGHT"
    RIGHT = "RIGHT"
    FRONT_RIGHT = "FRONT_RIGHT"


class DistanceTag(StrEnum):
    """Box-to-box distance between the ego and the object.

    Attributes:
        VERY_CLOSE: the boxes, each expanded by the configured margin, overlap.
        CLOSE: closer than the close threshold (10 m).
        MEDIUM: between the close and far thresholds (10 m to 50 m).
        FAR: beyond the far threshold (50 m).
    """

    VERY_CLOSE = "VERY_CLOSE"
    CLOSE = "CLOSE"
    MEDIUM = "MEDIUM"
    FAR = "FAR"


class TrajOverlapTag(StrEnum):
    """Overlap of the regions swept by the recorded future boxes of ego and object.

    Attributes:
        NO: the swept regions do not intersect within the low-risk window.
        LOW: they intersect within the low-risk window (3 s) but not the high-risk one.
        HIGH: they intersect within the high-risk window (1.5 s).
    """

    NO = "NO"
    LOW = "LOW"
    HIGH = "HIGH"


TagEnum = LongitudeTag | LatitudeTag | CollisionTag | HeadingTag | PositionTag | DistanceTag | TrajOverlapTag

#: Actor tags (one per track, the ego included), keyed by the column name used in tables.
ACTOR_FAMILIES: dict[str, type[StrEnum]] = {"longitude": LongitudeTag, "latitude": LatitudeTag}

#: Interaction tags of each object with respect to the ego, keyed by column name.
INTERACTION_FAMILIES: dict[str, type[StrEnum]] = {
    "collision": CollisionTag,
    "heading": HeadingTag,
    "position": PositionTag,
    "distance": DistanceTag,
    "traj_overlap": TrajOverlapTag,
}

#: Every tag family in the column order of :class:`scenariominer.tags.engine.LogTags` tables.
TAG_FAMILIES: dict[str, type[StrEnum]] = {**ACTOR_FAMILIES, **INTERACTION_FAMILIES}

E = TypeVar("E", bound=StrEnum)


def code_of(member: StrEnum) -> int:
    """Return the ``int8`` code of a tag value: its position in its enum's definition order."""
    return list(type(member)).index(member)


def member_of(enum_cls: type[E], code: int) -> E | None:
    """Return the tag value for ``code`` in ``enum_cls``; ``None`` for :data:`ABSENT`.

    Raises:
        ValueError: ``code`` is neither :data:`ABSENT` nor a valid position in ``enum_cls``.
    """
    if code == ABSENT:
        return None
    members = list(enum_cls)
    if not 0 <= code < len(members):
        raise ValueError(f"{code} is not a code of {enum_cls.__name__} (0..{len(members) - 1} or {ABSENT})")
    return members[code]


def codes_to_names(enum_cls: type[StrEnum], codes: NDArray[np.int8]) -> NDArray[np.object_]:
    """Map an array of codes to tag names (``str``), ``None`` where :data:`ABSENT`. Any shape."""
    lookup = np.array([m.value for m in enum_cls] + [None], dtype=object)
    idx = np.where(codes == ABSENT, len(lookup) - 1, codes)
    return lookup[idx]  # type: ignore[no-any-return]


def names_to_codes(
    enum_cls: type[StrEnum], names: NDArray[np.object_], what: str = "tag"
) -> NDArray[np.int8]:
    """Map an array of tag names (``None`` or ``""`` for absent) to ``int8`` codes. Any shape.

    Raises:
        ValueError: a name is not a member of ``enum_cls``; the message names ``what`` and the value.
    """
    flat = np.asarray(names, dtype=object).ravel()
    is_none = np.asarray(flat == None, dtype=bool)  # noqa: E711  (element-wise comparison)
    filled = np.where(is_none, "", flat).astype(str)
    uniq, inverse = np.unique(filled, return_inverse=True)
    valid_names = {m.value: i for i, m in enumerate(enum_cls)}
    mapped = np.empty(uniq.size, dtype=np.int8)
    for j, name in enumerate(uniq):  # one entry per distinct name, not per cell
        if name == "":
            mapped[j] = ABSENT
        elif name in valid_names:
            mapped[j] = valid_names[name]
        else:
            raise ValueError(
                f"{what}: {str(name)!r} is not a {enum_cls.__name__} (known: {sorted(valid_names)})"
            )
    return mapped[inverse].reshape(np.shape(names))
