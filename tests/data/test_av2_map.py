"""Argoverse 2 vector map: parsing, geometry, vectorised look-ups, and the JSON writer."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pyarrow.feather as feather
import pytest

from scenariominer.data.adapters.av2.map import (
    Av2Map,
    DrivableArea,
    LaneSegment,
    LaneType,
    PedestrianCrossing,
    find_map_file,
    read_av2_map,
    validate_av2_map,
    write_av2_map,
)
from scenariominer.data.log import LogFormatError


def _pts(*xy: tuple[float, float]) -> np.ndarray:
    return np.array([[x, y, 0.0] for x, y in xy])


def _cross_map() -> Av2Map:
    """An eastbound lane (y in [-2, 2], x in [-20, 20]) crossed by a northbound intersection lane
    (x in [-2, 2], y in [-20, 20]); a crosswalk at x in [10, 13]; drivable area = the eastbound road."""
    east = LaneSegment(
        id=1,
        lane_type=LaneType.VEHICLE,
        is_intersection=False,
        left_boundary_m=_pts((-20, 2), (20, 2)),
        right_boundary_m=_pts((-20, -2), (20, -2)),
        successors=(3,),
        right_neighbor_id=None,
    )
    north = LaneSegment(
        id=2,
        lane_type=LaneType.BUS,
        is_intersection=True,
        left_boundary_m=_pts((-2, -20), (-2, 20)),
        right_boundary_m=_pts((2, -20), (2, 20)),
        predecessors=(7,),
        left_neighbor_id=9,
    )
    crossing = PedestrianCrossing(id=5, edge1_m=_pts((10, -2), (10, 2)), edge2_m=_pts((13, -2), (13, 2)))
    area = DrivableArea(id=6, boundary_m=_pts((-20, -2), (20, -2), (20, 2), (-20, 2)))
    return Av2Map(lane_segments=(east, north), pedestrian_crossings=(crossing,), drivable_areas=(area,))


# ---------------------------------------------------------------------- real map (facts read off the file)


@pytest.fixture(scope="module")
def real_map(av2_log_dir: Path) -> Av2Map:
    return read_av2_map(av2_log_dir)


def test_real_map_layers(real_map: Av2Map, av2_log_dir: Path) -> None:
    assert real_map.n_lanes == 150
    assert len(real_map.pedestrian_crossings) == 6
    assert len(real_map.drivable_areas) == 5
    assert int(real_map.lane_is_intersection.sum()) == 48
    assert set(real_map.lane_types.tolist()) == {"VEHICLE"}
    assert real_map.source_path is not None and real_map.source_path.parent == av2_log_dir / "map"
    lane = real_map.lane_segments[real_map.lane_index(37979824)]
    assert lane.left_mark_type == "SOLID_YELLOW" and lane.successors == (37996592, 37996593)
    assert lane.left_neighbor_id == 37985322 and lane.right_neighbor_id == 37992207


def test_real_ego_path_lies_in_drivable_area_and_lanes(real_map: Av2Map, av2_log_dir: Path) -> None:
    poses = feather.read_table(av2_log_dir / "city_SE3_egovehicle.feather")
    xy = np.stack([poses.column("tx_m").to_numpy(), poses.column("ty_m").to_numpy()], axis=1)
    assert real_map.in_drivable_area(xy).all()
    lanes = real_map.lane_index_at(xy)
    assert (lanes >= 0).all()
    assert real_map.is_intersection(lanes).any() and not real_map.is_intersection(lanes).all()
    assert real_map.in_crosswalk(xy).any()
    dist = real_map.distance_to_intersection(xy)
    assert dist.min() == 0.0 and 0.0 < dist.max() < 50.0


def test_find_map_file_accepts_file_map_folder_and_log_folder(av2_log_dir: Path) -> None:
    file = find_map_file(av2_log_dir)
    assert find_map_file(av2_log_dir / "map") == file == find_map_file(file)


# ---------------------------------------------------------------------- queries on a hand-built map


def test_lane_index_at_picks_the_containing_lane_and_resolves_overlaps() -> None:
    m = _cross_map()
    xy = np.array([[-10.0, 0.0], [0.0, 15.0], [0.0, 0.3], [0.3, 0.0], [50.0, 50.0], [np.nan, 0.0]])
    # (0, 0.3) is 0.3 m from the east lane's centre line and 0 m from the north one's; (0.3, 0) the reverse.
    assert m.lane_index_at(xy).tolist() == [0, 1, 1, 0, -1, -1]
    # A heading along +x pulls the overlap point (0, 0.3) into the eastbound lane.
    yaw = np.array([0.0, np.pi / 2, 0.0, np.pi / 2, 0.0, 0.0])
    assert m.lane_index_at(xy, yaw_rad=yaw).tolist() == [0, 1, 0, 1, -1, -1]


def test_area_and_crosswalk_membership() -> None:
    m = _cross_map()
    xy = np.array([[0.0, 0.0], [11.0, 0.0], [11.0, 3.0], [20.0, 2.0], [0.0, 10.0]])
    assert m.in_drivable_area(xy).tolist() == [True, True, False, True, False]
    assert m.in_crosswalk(xy).tolist() == [False, True, False, False, False]


def test_distance_to_intersection_is_zero_inside_and_euclidean_outside() -> None:
    m = _cross_map()
    d = m.distance_to_intersection(np.array([[0.0, 5.0], [7.0, 0.0], [-5.0, 24.0], [np.nan, 1.0]]))
    np.testing.assert_allclose(d[:3], [0.0, 5.0, 5.0])
    assert np.isnan(d[3])


def test_lane_attributes_by_index_with_no_lane_as_minus_one() -> None:
    m = _cross_map()
    assert m.is_intersection(np.array([0, 1, -1])).tolist() == [False, True, False]
    assert m.lane_type(np.array([[1, -1]])).tolist() == [["BUS", ""]]
    assert bool(m.is_intersection(1))


def test_empty_map_answers_no_lane_everywhere() -> None:
    m = Av2Map(lane_segments=())
    xy = np.array([[0.0, 0.0]])
    assert m.lane_index_at(xy).tolist() == [-1]
    assert not m.in_drivable_area(xy).any() and not m.in_crosswalk(xy).any()
    assert np.isinf(m.distance_to_intersection(xy)).all()


def test_points_must_be_k_by_2() -> None:
    with pytest.raises(ValueError, match=r"shape \(K, 2\)"):
        _cross_map().in_drivable_area(np.zeros((3, 3)))


def test_centerline_averages_boundaries_resampled_by_arc_length() -> None:
    lane = LaneSegment(
        id=1,
        lane_type=LaneType.VEHICLE,
        is_intersection=False,
        left_boundary_m=_pts((0, 2), (10, 2)),
        right_boundary_m=_pts((0, -2), (4, -2), (10, -2)),
    )
    np.testing.assert_allclose(lane.centerline_m()[:, :2], [[0, 0], [5, 0], [10, 0]])
    assert lane.polygon.area == pytest.approx(40.0)


# ---------------------------------------------------------------------- writer and bad input


def test_write_then_read_round_trips(tmp_path: Path) -> None:
    m = _cross_map()
    path = write_av2_map(m, tmp_path / "map" / "log_map_archive_x____SYN_city_0.json")
    back = read_av2_map(tmp_path)
    assert back.source_path == path
    assert back.lane_ids.tolist() == [1, 2]
    assert back.lane_segments[1].lane_type is LaneType.BUS and back.lane_segments[1].predecessors == (7,)
    assert back.lane_segments[1].left_neighbor_id == 9 and back.lane_segments[0].right_neighbor_id is None
    np.testing.assert_allclose(back.lane_segments[0].left_boundary_m, m.lane_segments[0].left_boundary_m)
    np.testing.assert_allclose(back.pedestrian_crossings[0].edge2_m, m.pedestrian_crossings[0].edge2_m)
    assert back.drivable_polygons[0].area == pytest.approx(160.0)


def _write_doc(tmp_path: Path, doc: object) -> Path:
    path = tmp_path / "log_map_archive_bad.json"
    path.write_text(json.dumps(doc) if not isinstance(doc, str) else doc)
    return path


@pytest.mark.parametrize(
    ("mutate", "message"),
    [
        (lambda d: d.pop("drivable_areas"), "lacks the 'drivable_areas' layer"),
        (
            lambda d: d["lane_segments"]["1"].update(lane_type="HOVERCRAFT"),
            "lane segment 1 has unknown lane_type",
        ),
        (
            lambda d: d["lane_segments"]["2"].pop("left_lane_boundary"),
            "lane segment 2 lacks the key 'left_lane_boundary'",
        ),
        (
            lambda d: d["lane_segments"]["1"]["right_lane_boundary"][0].pop("x"),
            "right_lane_boundary has a malformed point",
        ),
        (
            lambda d: d["pedestrian_crossings"]["5"].update(edge1=[{"x": 0, "y": 0, "z": 0}]),
            "edge1 has 1 point",
        ),
        (
            lambda d: d["drivable_areas"]["6"]["area_boundary"][0].update(x=None),
            "drivable area 6 has non-finite coordinates",
        ),
        # each of these passes the JSON layer but fails one record (the quick check must see it too)
        (
            lambda d: d["lane_segments"]["1"].update(successors=["north"]),
            "lane segment 1 has a malformed field",
        ),
        (
            lambda d: d["lane_segments"]["2"].update(left_neighbor_id="left"),
            "lane segment 2 has a malformed field",
        ),
        (
            lambda d: d["lane_segments"]["2"]["left_lane_boundary"][1].update(y="nan"),
            "lane segment 2 left_lane_boundary has non-finite coordinates",
        ),
        (lambda d: d["pedestrian_crossings"]["5"].update(edge2="none"), "edge2 is not a list of points"),
    ],
)
def test_malformed_maps_raise_format_errors_naming_the_record(
    tmp_path: Path, mutate: object, message: str
) -> None:
    doc = _cross_map().to_json()
    mutate(doc)  # type: ignore[operator]
    path = _write_doc(tmp_path, doc)
    with pytest.raises(LogFormatError, match=message) as err:
        read_av2_map(path)
    assert err.value.source == str(path)
    with pytest.raises(LogFormatError, match=message):  # the ingest-time check finds the same problem
        validate_av2_map(path)


def test_validate_accepts_what_read_reads(av2_log_dir: Path, tmp_path: Path) -> None:
    assert validate_av2_map(av2_log_dir) == find_map_file(av2_log_dir)
    assert validate_av2_map(write_av2_map(_cross_map(), tmp_path / "log_map_archive_x.json")).is_file()


def test_invalid_json_and_missing_map(tmp_path: Path) -> None:
    with pytest.raises(LogFormatError, match="not valid JSON"):
        read_av2_map(_write_doc(tmp_path, "{nope"))
    with pytest.raises(LogFormatError, match="no Argoverse 2 vector map"):
        read_av2_map(tmp_path / "elsewhere")
