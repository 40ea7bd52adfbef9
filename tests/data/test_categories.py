"""Category names and groups: the VEHICLE group is RefAV's, and groups expand to Argoverse 2 names."""

from __future__ import annotations

import pytest

from scenariominer.data.categories import (
    AV2_CATEGORIES,
    CATEGORY_GROUPS,
    UnknownCategoryError,
    canonical_category,
    expand_categories,
)

#: RefAV's VEHICLE group (``refAV/utils.py``, CainanD/RefAV at 5c5be64) without ``CAR``, a nuScenes
#: name that no Argoverse 2 log contains.
REFAV_VEHICLE = {
    "EGO_VEHICLE",
    "ARTICULATED_BUS",
    "BOX_TRUCK",
    "BUS",
    "LARGE_VEHICLE",
    "MOTORCYCLE",
    "RAILED_VEHICLE",
    "REGULAR_VEHICLE",
    "SCHOOL_BUS",
    "TRUCK",
    "TRUCK_CAB",
}


def test_vehicle_group_is_refavs_motor_vehicles() -> None:
    assert set(CATEGORY_GROUPS["VEHICLE"]) == REFAV_VEHICLE
    # a trailer is not motorised: it is only found by its own name
    assert "VEHICULAR_TRAILER" not in expand_categories(["vehicle"])
    assert expand_categories(["VEHICULAR_TRAILER"]) == {"VEHICULAR_TRAILER"}


def test_groups_hold_argoverse_names_only() -> None:
    for members in CATEGORY_GROUPS.values():
        assert members <= set(AV2_CATEGORIES)
    assert CATEGORY_GROUPS["ANY"] == frozenset(AV2_CATEGORIES)


def test_aliases_and_unknown_names() -> None:
    assert canonical_category("car") == "REGULAR_VEHICLE"
    assert canonical_category(" pedestrian ") == "PEDESTRIAN"
    with pytest.raises(UnknownCategoryError, match="unknown object category"):
        canonical_category("spaceship")
