"""Braking events: key objects that likely made the ego brake (braking paper, section III-C)."""

from scenariominer.events.counterfactual import identify_key_objects
from scenariominer.events.criticality import Criticality, event_criticality
from scenariominer.events.describe import describe_pair, describe_segments
from scenariominer.events.keyident import KeyEvent, find_key_objects, key_candidates
from scenariominer.events.segments import PAIR_FEATURES, PairSegments, PairTags, pair_tags, segment_pair

__all__ = [
    "KeyEvent",
    "find_key_objects",
    "identify_key_objects",
    "key_candidates",
    "PAIR_FEATURES",
    "Criticality",
    "PairSegments",
    "PairTags",
    "describe_pair",
    "describe_segments",
    "event_criticality",
    "pair_tags",
    "segment_pair",
]
