"""Rule-based baseline classifier: hand-written filter conditions over the same tags.

The braking paper compares its LLM classification with a rule-based retrieval in the style of
Guo et al. (2023): each known category is a filter condition over the tags of the ego–guest pair
inside the event's analysis window. The rules below are the conditions of the four categories;
they are tried in :data:`BASELINE_RULES` order and the first that holds names the category, else
``not_relevant``. Each rule is a small pure function of a :class:`PairTags`, vectorised over the
window's timestamps.

* ``right_ped``: the guest is a pedestrian and the ego turns (or veers) right in the window.
* ``left_oppo``: the ego turns (or veers) left and the guest is seen ahead (FRONT, FRONT_LEFT,
  FRONT_RIGHT) with OPPOSITE heading at some timestamp.
* ``cut_in``: the guest is not a pedestrian and moves sideways (VEERING or TURNING) with SAME
  heading: either it goes from FRONT_LEFT or FRONT_RIGHT to FRONT, or it veers while ahead of an
  ego that keeps facing forward.
* ``obj_crossing``: a guest other than a pedestrian is ahead with LEFT or RIGHT heading (moving
  across the ego's path) at some timestamp; crossing pedestrians are a category of their own in
  the paper's taxonomy (``ped_crossing``, Table III).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from numpy.typing import NDArray

from scenariominer.events.segments import PAIR_FEATURES, Actor, PairFeature, PairTags
from scenariominer.explain.categories import NOT_RELEVANT
from scenariominer.tags.vocab import HeadingTag, LatitudeTag, PositionTag, code_of

__all__ = [
    "BASELINE_RULES",
    "BASELINE_VERSION",
    "baseline_category",
    "is_cut_in",
    "is_left_oppo",
    "is_obj_crossing",
    "is_right_ped",
    "rule_candidates",
]

#: Version of the rules below; part of the analysis fingerprint, bump it when a rule changes.
BASELINE_VERSION = "baseline/1"

_PEDESTRIAN = "PEDESTRIAN"
_AHEAD = [code_of(p) for p in (PositionTag.FRONT, PositionTag.FRONT_LEFT, PositionTag.FRONT_RIGHT)]
_SIDE_AHEAD = [code_of(PositionTag.FRONT_LEFT), code_of(PositionTag.FRONT_RIGHT)]
_LEFTWARD = [code_of(LatitudeTag.TURNING_LEFT), code_of(LatitudeTag.VEERING_LEFT)]
_RIGHTWARD = [code_of(LatitudeTag.TURNING_RIGHT), code_of(LatitudeTag.VEERING_RIGHT)]
_LATERAL = _LEFTWARD + _RIGHTWARD
_CROSSING = [code_of(HeadingTag.LEFT), code_of(HeadingTag.RIGHT)]


def _row(pair: PairTags, actor: Actor, family: str) -> NDArray[np.int8]:
    return np.asarray(pair.codes[PAIR_FEATURES.index(PairFeature(actor, family))], dtype=np.int8)


def is_right_ped(pair: PairTags) -> bool:
    """The guest is a pedestrian while the ego turns or veers right."""
    ego_lat = _row(pair, Actor.EGO, "latitude")
    return pair.guest_category == _PEDESTRIAN and bool(np.isin(ego_lat, _RIGHTWARD).any())


def is_left_oppo(pair: PairTags) -> bool:
    """The ego turns or veers left and an oncoming guest is ahead of it."""
    ego_lat = _row(pair, Actor.EGO, "latitude")
    oncoming_ahead = (_row(pair, Actor.PAIR, "heading") == code_of(HeadingTag.OPPOSITE)) & np.isin(
        _row(pair, Actor.PAIR, "position"), _AHEAD
    )
    return bool(np.isin(ego_lat, _LEFTWARD).any() and oncoming_ahead.any())


def is_cut_in(pair: PairTags) -> bool:
    """A non-pedestrian guest ahead, heading SAME, moves sideways into the ego's lane.

    Holds when the guest moves from FRONT_LEFT/FRONT_RIGHT to FRONT (heading SAME) and veers or
    turns somewhere in the window, or when it veers or turns while ahead with heading SAME and the
    ego keeps facing forward. The second form is needed because sectors are equal angles: a car
    20 m ahead in the next lane is only 10 degrees off the ego's axis, i.e. already FRONT.
    """
    if pair.guest_category == _PEDESTRIAN:
        return False
    position = _row(pair, Actor.PAIR, "position")
    same = _row(pair, Actor.PAIR, "heading") == code_of(HeadingTag.SAME)
    sideways = np.isin(_row(pair, Actor.GUEST, "latitude"), _LATERAL)
    side = np.flatnonzero(np.isin(position, _SIDE_AHEAD))
    lead = (position == code_of(PositionTag.FRONT)) & same
    enters_front = side.size > 0 and bool(lead[side[0] + 1 :].any()) and bool(sideways.any())
    ego_straight = _row(pair, Actor.EGO, "latitude") == code_of(LatitudeTag.FACING_FORWARD)
    shifts_ahead = sideways & same & np.isin(position, _AHEAD) & ego_straight
    return enters_front or bool(shifts_ahead.any())


def is_obj_crossing(pair: PairTags) -> bool:
    """A non-pedestrian guest is ahead of the ego while heading LEFT or RIGHT relative to it."""
    if pair.guest_category == _PEDESTRIAN:
        return False  # a crossing pedestrian is its own category (ped_crossing, Table III)
    crossing = np.isin(_row(pair, Actor.PAIR, "heading"), _CROSSING) & np.isin(
        _row(pair, Actor.PAIR, "position"), _AHEAD
    )
    return bool(crossing.any())


#: The rules in the order they are tried: (category name, condition).
BASELINE_RULES: tuple[tuple[str, Callable[[PairTags], bool]], ...] = (
    ("right_ped", is_right_ped),
    ("left_oppo", is_left_oppo),
    ("cut_in", is_cut_in),
    ("obj_crossing", is_obj_crossing),
)


def baseline_category(pair: PairTags) -> str:
    """Category of the first rule of :data:`BASELINE_RULES` that holds, else ``not_relevant``."""
    for name, rule in BASELINE_RULES:
        if rule(pair):
            return name
    return NOT_RELEVANT


def rule_candidates(pair: PairTags) -> tuple[str, ...]:
    """Every category whose rule holds, in :data:`BASELINE_RULES` order (empty: none holds).

    One name means the rules decide; several mean the event is ambiguous for the rules (the
    hybrid judgement lets the LLM choose among them); none means no known category fits.
    """
    return tuple(name for name, rule in BASELINE_RULES if rule(pair))
