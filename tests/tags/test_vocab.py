"""Tag vocabularies: the values of Table I and their int8 codes."""

from __future__ import annotations

import numpy as np
import pytest

from scenariominer.tags.vocab import (
    ABSENT,
    TAG_FAMILIES,
    LatitudeTag,
    LongitudeTag,
    PositionTag,
    code_of,
    codes_to_names,
    member_of,
    names_to_codes,
)


def test_vocabularies_are_those_of_table_i() -> None:
    assert [m.value for m in TAG_FAMILIES["longitude"]] == [
        "CRUISING",
        "STANDING_STILL",
        "ACCELERATING",
        "DECELERATING",
        "REVERSING",
    ]
    assert set(TAG_FAMILIES["latitude"]) == {
        LatitudeTag.FACING_FORWARD,
        LatitudeTag.VEERING_LEFT,
        LatitudeTag.VEERING_RIGHT,
        LatitudeTag.TURNING_LEFT,
        LatitudeTag.TURNING_RIGHT,
    }
    assert [m.value for m in TAG_FAMILIES["collision"]] == ["NO", "LOW", "HIGH"]
    assert [m.value for m in TAG_FAMILIES["traj_overlap"]] == ["NO", "LOW", "HIGH"]
    assert [m.value for m in TAG_FAMILIES["distance"]] == ["VERY_CLOSE", "CLOSE", "MEDIUM", "FAR"]
    assert set(m.value for m in TAG_FAMILIES["heading"]) == {"SAME", "LEFT", "RIGHT", "OPPOSITE"}
    # Position sectors run counter-clockwise from straight ahead, 45° apart.
    assert [m.value for m in PositionTag] == [
        "FRONT",
        "FRONT_LEFT",
        "LEFT",
        "BACK_LEFT",
        "BACK",
        "BACK_RIGHT",
        "RIGHT",
        "FRONT_RIGHT",
    ]


def test_codes_and_members_round_trip() -> None:
    for enum_cls in TAG_FAMILIES.values():
        for member in enum_cls:
            assert member_of(enum_cls, code_of(member)) is member
    assert member_of(LongitudeTag, ABSENT) is None
    with pytest.raises(ValueError, match="not a code of LongitudeTag"):
        member_of(LongitudeTag, 5)


def test_arrays_of_names_and_codes_convert_both_ways() -> None:
    codes = np.array([[0, -1], [4, 2]], dtype=np.int8)
    names = codes_to_names(LongitudeTag, codes)
    assert names.tolist() == [["CRUISING", None], ["REVERSING", "ACCELERATING"]]
    np.testing.assert_array_equal(names_to_codes(LongitudeTag, names), codes)
    with pytest.raises(ValueError, match="'SKIDDING' is not a LongitudeTag"):
        names_to_codes(LongitudeTag, np.array(["SKIDDING"], dtype=object))
