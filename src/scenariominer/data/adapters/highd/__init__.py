"""highD adapter: drone recordings of German highways cut into ego-centred logs, and a writer.

A highD recording ``NN`` is three CSV files (see ``docs/highd.md``):

* ``NN_tracks.csv``: one row per (vehicle, frame): ``frame, id, x, y, width, height, xVelocity,
  yVelocity, xAcceleration, yAcceleration, frontSightDistance, backSightDistance, dhw, thw, ttc,
  precedingXVelocity, precedingId, followingId, leftPrecedingId, leftAlongsideId, leftFollowingId,
  rightPrecedingId, rightAlongsideId, rightFollowingId, laneId``;
* ``NN_tracksMeta.csv``: one row per vehicle (``class`` Car/Truck, ``drivingDirection`` 1 = towards
  -x ("left"), 2 = towards +x ("right"), frame span and summary statistics);
* ``NN_recordingMeta.csv``: one row (``frameRate``, location, speed limit, lane markings).

Coordinate conversion. highD positions are image-aligned: ``x`` grows to the right along the road,
``y`` grows *downwards*, and ``(x, y)`` is the **upper-left corner** of the axis-aligned box whose
extent along x is the column ``width`` (the vehicle's length) and along y the column ``height``
(the vehicle's width). The canonical frame of this package is right-handed with yaw
counter-clockwise, so the adapter uses

* ``x_m = x + width / 2`` and ``y_m = -(y + height / 2)`` (box centre, y flipped),
* ``length_m = width``, ``width_m = height``, ``vx_mps = xVelocity``, ``vy_mps = -yVelocity``,
  ``ax_mps2 = xAcceleration``, ``ay_mps2 = -yAcceleration``,
* ``yaw_rad = atan2(vy_mps, vx_mps)``; when the vehicle is (nearly) stopped or its velocity points
  against its driving direction, the yaw of the driving direction (0 for direction 2, pi for 1),
* ``height_m``: highD has no heights; :data:`ASSUMED_HEIGHT_M` per class,
* time ``t_ns = frame / frameRate`` in nanoseconds.

Windowing. Any vehicle can be the ego. Each chosen ego's visible span is cut into consecutive full
windows of ``config.ingest.highd_window_s`` (a remainder shorter than a window is not used); each
(ego, window) is one :class:`~scenariominer.data.log.Log` named
``highd-<recording:02d>-ego<id>-w<k>`` with the ego at row 0 and every vehicle observed within
``radius_m`` of the ego (like a sensor range; a vehicle appears while it is within range).
"""

from scenariominer.data.adapters.highd.format import (
    ASSUMED_HEIGHT_M,
    DEFAULT_RADIUS_M,
    RECORDING_META_COLUMNS,
    TRACKS_COLUMNS,
    TRACKS_META_COLUMNS,
    HighDDirection,
    HighDFiles,
    HighDRecording,
    HighDRecordingMeta,
    read_highd_recording,
)
from scenariominer.data.adapters.highd.reader import (
    HighDReader,
    HighDWindow,
    plan_windows,
    window_log,
)
from scenariominer.data.adapters.highd.writer import (
    HighDVehicle,
    write_highd_recording,
)

__all__ = [
    "ASSUMED_HEIGHT_M",
    "DEFAULT_RADIUS_M",
    "HighDDirection",
    "HighDFiles",
    "HighDReader",
    "HighDRecording",
    "HighDRecordingMeta",
    "HighDVehicle",
    "HighDWindow",
    "RECORDING_META_COLUMNS",
    "TRACKS_COLUMNS",
    "TRACKS_META_COLUMNS",
    "plan_windows",
    "read_highd_recording",
    "window_log",
    "write_highd_recording",
]
