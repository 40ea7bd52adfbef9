"""The only copy of the project's geometry: angles, frames, oriented boxes, kinematics.

Everything is vectorised: functions broadcast over arbitrary leading shapes (tracks × timestamps,
or tracks × tracks × timestamps × horizon steps) and propagate NaN where an input is NaN. Angles
are radians counter-clockwise from the world +x axis; lengths are metres; times seconds.

* :mod:`.angles`: :func:`wrap_angle` (the one convention, ``[-pi, pi)``).
* :mod:`.frames`: world offsets into a heading's frame and back; rotation matrices of quaternions.
* :mod:`.boxes`: :class:`OrientedBoxes`, corners, separating-axis overlap, point/box distances.
* :mod:`.kinematics`: yaw rate (of any angle) from samples, path curvature, CTRV prediction.
"""

from scenariominer.geometry.angles import wrap_angle
from scenariominer.geometry.boxes import (
    OrientedBoxes,
    box_distance_m,
    boxes_overlap,
    point_box_distance_m,
)
from scenariominer.geometry.frames import (
    from_local,
    quaternion_matrix,
    quaternion_x_axis,
    rotate_xy,
    to_local,
)
from scenariominer.geometry.kinematics import ctrv_predict, path_curvature_1pm, yaw_rate_radps

__all__ = [
    "OrientedBoxes",
    "box_distance_m",
    "boxes_overlap",
    "ctrv_predict",
    "from_local",
    "path_curvature_1pm",
    "point_box_distance_m",
    "quaternion_matrix",
    "quaternion_x_axis",
    "rotate_xy",
    "to_local",
    "wrap_angle",
    "yaw_rate_radps",
]
