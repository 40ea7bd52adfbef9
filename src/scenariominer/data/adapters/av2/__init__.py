"""Argoverse 2 adapter: sensor-dataset logs (annotations, ego poses) and their vector maps.

:mod:`.logs` reads and writes log folders (the ego at its box centre; see its docstring for the
pose convention) and :mod:`.map` reads and writes the ``log_map_archive_*.json`` vector maps.
"""

from scenariominer.data.adapters.av2.logs import (
    ANNOTATION_COLUMNS,
    ANNOTATIONS_FILE,
    ANNOTATIONS_WITH_EGO_FILE,
    AV2_EGO_CENTER_OFFSET_M,
    AV2_EGO_SIZE_M,
    MAP_FILE_GLOB,
    MAP_FOLDER,
    MAX_DISCOVERY_DEPTH,
    POSE_COLUMNS,
    POSES_FILE,
    Av2Reader,
    av2_source,
    estimate_interior_points,
    is_av2_log_dir,
    read_av2_log,
    write_av2_log,
)

__all__ = [
    "ANNOTATIONS_FILE",
    "ANNOTATIONS_WITH_EGO_FILE",
    "ANNOTATION_COLUMNS",
    "AV2_EGO_CENTER_OFFSET_M",
    "AV2_EGO_SIZE_M",
    "MAP_FILE_GLOB",
    "MAP_FOLDER",
    "MAX_DISCOVERY_DEPTH",
    "POSES_FILE",
    "POSE_COLUMNS",
    "Av2Reader",
    "av2_source",
    "estimate_interior_points",
    "is_av2_log_dir",
    "read_av2_log",
    "write_av2_log",
]
