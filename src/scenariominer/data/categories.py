"""Object categories: the Argoverse 2 names are canonical; other datasets map onto them.

The canonical vocabulary is the Argoverse 2 sensor-dataset annotation taxonomy plus
``EGO_VEHICLE`` (used by ``annotations_with_ego.feather``). Adapters for other datasets
translate their own class names through :data:`CATEGORY_ALIASES`; an unknown name is an
error naming the file and the offending value, never a silent ``UNKNOWN``.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping

from scenariominer import errors as _errors

#: Argoverse 2 sensor-dataset categories, in the order of the official taxonomy, plus the ego.
AV2_CATEGORIES: tuple[str, ...] = (
    "REGULAR_VEHICLE",
    "PEDESTRIAN",
    "BICYCLIST",
    "MOTORCYCLIST",
    "WHEELED_RIDER",
    "BOLLARD",
    "CONSTRUCTION_CONE",
    "SIGN",
    "CONSTRUCTION_BARREL",
    "STOP_SIGN",
    "MOBILE_PEDESTRIAN_CROSSING_SIGN",
    "LARGE_VEHICLE",
    "BUS",
    "BOX_TRUCK",
    "TRUCK",
    "VEHICULAR_TRAILER",
    "TRUCK_CAB",
    "SCHOOL_BUS",
    "ARTICULATED_BUS",
    "MESSAGE_BOARD_TRAILER",
    "BICYCLE",
    "MOTORCYCLE",
    "WHEELED_DEVICE",
    "WHEELCHAIR",
    "STROLLER",
    "DOG",
    "OFFICIAL_SIGNALER",
    "TRAFFIC_LIGHT_TRAILER",
    "ANIMAL",
    "RAILED_VEHICLE",
    "EGO_VEHICLE",
)

EGO_CATEGORY = "EGO_VEHICLE"

#: Category groups usable wherever a category is expected (mining predicates, filters).
#:
#: ``VEHICLE`` is every motor vehicle, the ego included, as RefAV's code defines it
#: (``refAV/utils.py``; its nuScenes name ``CAR`` is not an Argoverse 2 category and is left out).
#: A ``VEHICULAR_TRAILER`` is not motorised and is not a member: ask for it by name.
CATEGORY_GROUPS: dict[str, frozenset[str]] = {
    "VEHICLE": frozenset(
        {
            "REGULAR_VEHICLE",
            "LARGE_VEHICLE",
            "BUS",
            "BOX_TRUCK",
            "TRUCK",
            "TRUCK_CAB",
            "SCHOOL_BUS",
            "ARTICULATED_BUS",
            "RAILED_VEHICLE",
            "MOTORCYCLE",
            "EGO_VEHICLE",
        }
    ),
    "VULNERABLE_ROAD_USER": frozenset(
        {
            "PEDESTRIAN",
            "BICYCLIST",
            "MOTORCYCLIST",
            "WHEELED_RIDER",
            "BICYCLE",
            "WHEELED_DEVICE",
            "WHEELCHAIR",
            "STROLLER",
            "OFFICIAL_SIGNALER",
        }
    ),
    "ANY": frozenset(AV2_CATEGORIES),
}

#: Names used by other datasets (lower-cased keys) and their Argoverse 2 equivalents.
CATEGORY_ALIASES: dict[str, str] = {
    # highD / exiD / inD / rounD
    "car": "REGULAR_VEHICLE",
    "truck": "TRUCK",
    "truck_bus": "TRUCK",
    "van": "REGULAR_VEHICLE",
    "bus": "BUS",
    "pedestrian": "PEDESTRIAN",
    "bicycle": "BICYCLIST",
    "motorcycle": "MOTORCYCLIST",
    # nuScenes / Waymo style names users commonly export
    "vehicle": "REGULAR_VEHICLE",
    "vehicle.car": "REGULAR_VEHICLE",
    "vehicle.truck": "TRUCK",
    "vehicle.bus": "BUS",
    "vehicle.bicycle": "BICYCLIST",
    "vehicle.motorcycle": "MOTORCYCLIST",
    "human.pedestrian.adult": "PEDESTRIAN",
    "cyclist": "BICYCLIST",
    "ego": "EGO_VEHICLE",
}


class UnknownCategoryError(_errors.DataError):
    """Raised when a category name is neither an Argoverse 2 name nor a known alias."""


def canonical_category(name: str, extra_aliases: Mapping[str, str] | None = None) -> str:
    """Return the Argoverse 2 name for ``name`` (case-insensitive); raise on unknown names."""
    upper = name.strip().upper()
    if upper in AV2_CATEGORIES:
        return upper
    key = name.strip().lower()
    if extra_aliases and key in extra_aliases:
        return canonical_category(extra_aliases[key])
    if key in CATEGORY_ALIASES:
        return CATEGORY_ALIASES[key]
    raise UnknownCategoryError(
        f"unknown object category {name!r}: use an Argoverse 2 name (e.g. REGULAR_VEHICLE, PEDESTRIAN) "
        f"or one of the aliases {sorted(CATEGORY_ALIASES)}"
    )


def expand_categories(names: Iterable[str]) -> frozenset[str]:
    """Expand group names (VEHICLE, ANY, ...) and aliases into a set of Argoverse 2 names."""
    out: set[str] = set()
    for name in names:
        upper = name.strip().upper()
        if upper in CATEGORY_GROUPS:
            out |= CATEGORY_GROUPS[upper]
        else:
            out.add(canonical_category(name))
    return frozenset(out)
