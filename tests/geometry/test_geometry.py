"""Oriented-box geometry agrees with shapely and with closed-form motion."""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely

from scenariominer.geometry import (
    OrientedBoxes,
    box_distance_m,
    boxes_overlap,
    ctrv_predict,
    point_box_distance_m,
    quaternion_matrix,
    quaternion_x_axis,
    wrap_angle,
    yaw_rate_radps,
)


def _box(x: float, y: float, yaw: float = 0.0, length: float = 4.0, width: float = 2.0) -> OrientedBoxes:
    return OrientedBoxes(*(np.asarray(v, dtype=float) for v in (x, y, yaw, length, width)))


def _random_boxes(rng: np.random.Generator, n: int, spread_m: float) -> OrientedBoxes:
    return OrientedBoxes(
        rng.uniform(-spread_m, spread_m, n),
        rng.uniform(-spread_m, spread_m, n),
        rng.uniform(-np.pi, np.pi, n),
        rng.uniform(0.3, 12.0, n),
        rng.uniform(0.3, 3.0, n),
    )


def _polygons(boxes: OrientedBoxes) -> np.ndarray:
    return shapely.polygons(boxes.corners())


def test_corners_of_a_box_turned_by_90_degrees() -> None:
    corners = _box(1.0, 2.0, np.pi / 2, 4.0, 2.0).corners()
    # Length now along +y: front-left corner is at (centre.x - 1, centre.y + 2).
    np.testing.assert_allclose(corners, [[0.0, 4.0], [0.0, 0.0], [2.0, 0.0], [2.0, 4.0]], atol=1e-12)


def test_overlap_and_distance_match_shapely_for_random_rectangles() -> None:
    rng = np.random.default_rng(7)
    a, b = _random_boxes(rng, 3000, 5.0), _random_boxes(rng, 3000, 5.0)
    pa_, pb_ = _polygons(a), _polygons(b)
    expected_overlap = shapely.intersects(pa_, pb_)
    assert 0.2 < expected_overlap.mean() < 0.8  # both outcomes are well represented
    np.testing.assert_array_equal(boxes_overlap(a, b), expected_overlap)
    np.testing.assert_allclose(box_distance_m(a, b), shapely.distance(pa_, pb_), atol=1e-9)


def test_edge_contact_counts_as_overlap() -> None:
    assert boxes_overlap(_box(0, 0), _box(4.0, 0))
    assert not boxes_overlap(_box(0, 0), _box(4.0 + 1e-6, 0))
    assert box_distance_m(_box(0, 0), _box(4.0, 0)) == 0.0


def test_distance_of_boxes_side_by_side_and_corner_to_corner() -> None:
    assert box_distance_m(_box(0, 0), _box(0, 5.0)) == pytest.approx(3.0)
    # Corner to corner: gaps of 3 m along x and 4 m along y give 5 m.
    assert box_distance_m(_box(0, 0), _box(7.0, 6.0)) == pytest.approx(5.0)


def test_geometry_broadcasts_over_leading_axes() -> None:
    ego = _box(0, 0)
    others = OrientedBoxes(
        np.linspace(0, 20, 6)[:, None] * np.ones((1, 4)),
        np.zeros((6, 4)),
        np.zeros((6, 4)),
        np.full((6, 4), 4.0),
        np.full((6, 4), 2.0),
    )
    assert boxes_overlap(ego, others).shape == (6, 4)
    dist = box_distance_m(ego, others)
    np.testing.assert_allclose(dist[:, 0], np.maximum(np.linspace(0, 20, 6) - 4.0, 0.0))


def test_point_inside_a_box_has_zero_distance() -> None:
    box = _box(0, 0, 0.3)
    assert point_box_distance_m(np.asarray(0.5), np.asarray(0.2), box) == 0.0
    assert point_box_distance_m(np.asarray(0.0), np.asarray(4.0), _box(0, 0)) == pytest.approx(3.0)


def test_nan_boxes_neither_overlap_nor_have_a_distance() -> None:
    assert not boxes_overlap(_box(np.nan, 0), _box(0, 0))
    assert np.isnan(box_distance_m(_box(np.nan, 0), _box(0, 0)))


def test_ctrv_straight_line_is_constant_velocity() -> None:
    tau = np.array([0.0, 1.0, 2.5])
    x, y, yaw = ctrv_predict(*(np.asarray(v) for v in (1.0, 2.0, 0.3, 3.0, -4.0, 0.0)), tau)
    np.testing.assert_allclose(x, 1.0 + 3.0 * tau)
    np.testing.assert_allclose(y, 2.0 - 4.0 * tau)
    np.testing.assert_allclose(yaw, 0.3)


def test_ctrv_quarter_circle_ends_at_the_known_point() -> None:
    # 10 m/s along +x with a left turn of radius 20 m: quarter circle around (0, 20) ends at (20, 20).
    omega = 10.0 / 20.0
    tau = np.array([np.pi / 2 / omega])
    x, y, yaw = ctrv_predict(*(np.asarray(v) for v in (0.0, 0.0, 0.0, 10.0, 0.0, omega)), tau)
    np.testing.assert_allclose([x[0], y[0], yaw[0]], [20.0, 20.0, np.pi / 2], atol=1e-9)


def test_ctrv_tiny_yaw_rate_is_continuous_with_straight_motion() -> None:
    tau = np.linspace(0, 3, 31)
    state = [np.asarray(v) for v in (0.0, 0.0, 0.0, 8.0, 1.0)]
    straight = ctrv_predict(*state, np.asarray(0.0), tau)
    almost = ctrv_predict(*state, np.asarray(1e-9), tau)
    np.testing.assert_allclose(np.stack(almost), np.stack(straight), atol=1e-7)


def test_yaw_rate_is_correct_across_the_pi_wrap() -> None:
    t = np.arange(10) * 0.1
    yaw = wrap_angle(np.pi - 0.2 + 0.5 * t)[None, :]  # crosses +pi at t = 0.4 s
    np.testing.assert_allclose(yaw_rate_radps(yaw, t), 0.5, atol=1e-9)


def test_yaw_rate_is_nan_where_absent_and_zero_for_isolated_frames() -> None:
    t = np.arange(5) * 0.1
    yaw = np.array([[0.0, np.nan, 0.3, np.nan, np.nan]])
    rate = yaw_rate_radps(yaw, t)
    assert np.isnan(rate[0, [1, 3, 4]]).all()
    np.testing.assert_allclose(rate[0, [0, 2]], 0.0)


def test_box_distance_of_parallel_overlapping_and_rotated_boxes() -> None:
    def box(x: float, y: float, yaw: float, length: float, width: float) -> tuple[np.ndarray, ...]:
        return OrientedBoxes(*(np.array([v], dtype=float) for v in (x, y, yaw, length, width)))

    # two 4 x 2 boxes side by side, centres 3 m apart: gap 1 m
    assert box_distance_m(box(0, 0, 0, 4, 2), box(0, 3, 0, 4, 2))[0] == pytest.approx(1.0)
    assert box_distance_m(box(0, 0, 0, 4, 2), box(1, 1, 0, 4, 2))[0] == 0.0
    # a 2 x 2 box rotated 45 deg, its corner pointing at the first box's front face 1 m away
    corner = 1 + math.sqrt(2)
    assert box_distance_m(box(0, 0, 0, 4, 2), box(2 + corner, 0, math.pi / 4, 2, 2))[0] == pytest.approx(1.0)
    assert np.isnan(box_distance_m(box(0, 0, 0, 4, 2), box(np.nan, 0, 0, 4, 2))[0])


def test_quaternion_matrix_matches_scipy_for_unnormalised_quaternions() -> None:
    from scipy.spatial.transform import Rotation

    quat = np.random.default_rng(5).normal(size=(50, 4)) * 3.0  # (w, x, y, z), any length
    expected = Rotation.from_quat(quat, scalar_first=True).as_matrix()
    np.testing.assert_allclose(quaternion_matrix(quat), expected, atol=1e-12)
    np.testing.assert_allclose(quaternion_x_axis(quat), expected[:, :, 0], atol=1e-12)
    assert np.isnan(quaternion_x_axis([0.0, 0.0, 0.0, 0.0])).all()
    np.testing.assert_allclose(quaternion_matrix([1.0, 0.0, 0.0, 0.0]), np.eye(3))
    # a quarter turn about z takes x to y
    c = math.cos(math.pi / 4)
    quarter_turn = quaternion_matrix([c, 0.0, 0.0, c])
    np.testing.assert_allclose(quarter_turn @ [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], atol=1e-15)
