"""Atomic mining predicates: the functions a mining program may call.

These functions are the vocabulary of the mining DSL. Their signatures follow RefAV's atomic
functions (Davidson et al., 2025) so that programs written for RefAV read the same, and their
docstrings are the reference text given to the language model, so each one states exactly:

* which argument is the SUBJECT: ``track_candidates``, the objects the result refers to;
* which argument is the REFERENCE: ``related_candidates``, the objects a relation is measured
  against (they become the *related objects* of the result);
* units, defaults and thresholds, and what is returned.

Conventions shared by every predicate:

* A *scenario* (:class:`~scenariominer.mine.scenario.Scenario`) is the set of (object,
  timestamp) pairs where something holds, plus related objects. Predicates take scenarios and
  return a scenario that is a SUBSET of ``track_candidates``: same objects, fewer timestamps.
* ``log_dir`` is the log being mined. In a program it is the predefined variable ``log_dir``
  (a :class:`~scenariominer.mine.context.LogContext`, not a path); pass it where RefAV passes
  its log folder.
* Distances are metres, speeds m/s, accelerations m/s², angles degrees. An object's frame has
  ``x`` forward along its heading and ``y`` to its left; "left"/"right"/"forward"/"backward"
  are always seen from the object named as the frame's owner.
* Map predicates (crossings, lanes, intersections, drivable area, stop signs) need the log's
  HD map and raise :class:`~scenariominer.mine.context.MapRequiredError` without one.

Everything is vectorised over tracks × timestamps with arrays shared through the log's
:class:`~scenariominer.mine.context.LogContext`.
"""

from __future__ import annotations

from scenariominer.mine.dsl._reference import (
    DSL_FUNCTIONS,
    library_reference,
)
from scenariominer.mine.dsl.category import (
    get_objects_of_category,
    is_category,
)
from scenariominer.mine.dsl.map import (
    at_pedestrian_crossing,
    at_stop_sign,
    in_drivable_area,
    in_same_lane,
    near_intersection,
    on_intersection,
    on_lane_type,
    on_relative_side_of_road,
    on_road,
)
from scenariominer.mine.dsl.motion import (
    accelerating,
    changing_lanes,
    has_lateral_acceleration,
    has_velocity,
    stationary,
    turning,
)
from scenariominer.mine.dsl.output import (
    OutputError,
    OutputSink,
    capture_output,
    output_scenario,
)
from scenariominer.mine.dsl.relation import (
    being_crossed_by,
    facing_toward,
    following,
    get_objects_in_relative_direction,
    has_objects_in_relative_direction,
    heading_in_relative_direction_to,
    heading_toward,
    near_objects,
)
from scenariominer.mine.scenario import (
    reverse_relationship,
    scenario_and,
    scenario_not,
    scenario_or,
)

__all__ = [
    "DSL_FUNCTIONS",
    "OutputError",
    "OutputSink",
    "accelerating",
    "at_pedestrian_crossing",
    "at_stop_sign",
    "being_crossed_by",
    "capture_output",
    "changing_lanes",
    "facing_toward",
    "following",
    "get_objects_in_relative_direction",
    "get_objects_of_category",
    "has_lateral_acceleration",
    "has_objects_in_relative_direction",
    "has_velocity",
    "heading_in_relative_direction_to",
    "heading_toward",
    "in_drivable_area",
    "in_same_lane",
    "is_category",
    "library_reference",
    "near_intersection",
    "near_objects",
    "on_intersection",
    "on_lane_type",
    "on_relative_side_of_road",
    "on_road",
    "output_scenario",
    "reverse_relationship",
    "scenario_and",
    "scenario_not",
    "scenario_or",
    "stationary",
    "turning",
]
