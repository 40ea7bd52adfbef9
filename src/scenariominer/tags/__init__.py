"""Rule-based, map-free activity and interaction tags (braking paper, section III-B, Tables I-II)."""

from scenariominer.config.tags import TagConfig
from scenariominer.tags.engine import LogTags, TagTableError, tag_log
from scenariominer.tags.vocab import (
    ABSENT,
    TAG_FAMILIES,
    CollisionTag,
    DistanceTag,
    HeadingTag,
    LatitudeTag,
    LongitudeTag,
    PositionTag,
    TrajOverlapTag,
)

__all__ = [
    "ABSENT",
    "TAG_FAMILIES",
    "CollisionTag",
    "DistanceTag",
    "HeadingTag",
    "LatitudeTag",
    "LogTags",
    "LongitudeTag",
    "PositionTag",
    "TagConfig",
    "TagTableError",
    "TrajOverlapTag",
    "tag_log",
]
