"""Braking events: key objects that likely made the ego brake (braking paper, section III-C)."""

from scenariominer.events.keyident import KeyEvent, find_key_objects, key_candidates

__all__ = ["KeyEvent", "find_key_objects", "key_candidates"]
