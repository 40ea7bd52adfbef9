"""The DSL's function table and the reference text built from the predicates' docstrings."""

from __future__ import annotations

import inspect
from collections.abc import Callable
from typing import Any

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

# ====================================================================== the DSL

#: Every function a mining program may call, in the order they are presented to the model.
DSL_FUNCTIONS: dict[str, Callable[..., Any]] = {
    f.__name__: f
    for f in (
        get_objects_of_category,
        is_category,
        has_objects_in_relative_direction,
        get_objects_in_relative_direction,
        being_crossed_by,
        near_objects,
        following,
        facing_toward,
        heading_toward,
        heading_in_relative_direction_to,
        turning,
        changing_lanes,
        has_lateral_acceleration,
        accelerating,
        has_velocity,
        stationary,
        at_pedestrian_crossing,
        on_lane_type,
        near_intersection,
        on_intersection,
        at_stop_sign,
        in_drivable_area,
        on_road,
        in_same_lane,
        on_relative_side_of_road,
        scenario_and,
        scenario_or,
        scenario_not,
        reverse_relationship,
        output_scenario,
    )
}


def library_reference(names: list[str] | None = None) -> str:
    """The signatures and docstrings of the DSL functions as one text (for prompts and docs).

    Args:
        names: functions to include, in this order; default all of :data:`DSL_FUNCTIONS`.
    """
    chosen = names if names is not None else list(DSL_FUNCTIONS)
    parts = []
    for name in chosen:
        f = DSL_FUNCTIONS[name]
        sig = str(inspect.signature(f)).replace("'", "")
        doc = inspect.getdoc(f) or ""
        parts.append(
            f"def {name}{sig}:\n"
            + "\n".join(f"    {line}" if line else "" for line in ['"""', *doc.splitlines(), '"""'])
        )
    return "\n\n".join(parts)
