"""Properties every geometry formula must keep, checked on random inputs with hypothesis."""

from __future__ import annotations

import math

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from scenariominer.geometry import (
    OrientedBoxes,
    box_distance_m,
    boxes_overlap,
    from_local,
    path_curvature_1pm,
    point_box_distance_m,
    to_local,
    wrap_angle,
    yaw_rate_radps,
)

coord = st.floats(-50.0, 50.0, allow_nan=False)
angle = st.floats(-20.0, 20.0, allow_nan=False)
size = st.floats(0.2, 8.0, allow_nan=False)
box = st.tuples(coord, coord, angle, size, size)


def _boxes(b: tuple[float, ...]) -> OrientedBoxes:
    return OrientedBoxes(*(np.asarray([v], dtype=float) for v in b))


def _moved(b: tuple[float, ...], dx: float, dy: float, theta: float) -> OrientedBoxes:
    x, y = from_local(b[0], b[1], theta)
    return _boxes((float(x) + dx, float(y) + dy, b[2] + theta, b[3], b[4]))


@given(st.floats(-1e6, 1e6, allow_nan=False))
def test_wrap_angle_range_idempotence_and_equivalence(a: float) -> None:
    w = float(wrap_angle(a))
    assert -math.pi <= w < math.pi
    assert float(wrap_angle(w)) == w
    assert math.isclose(math.cos(w), math.cos(a), abs_tol=1e-6)
    assert math.isclose(math.sin(w), math.sin(a), abs_tol=1e-6)


def test_wrap_angle_convention_and_nan() -> None:
    assert wrap_angle(math.pi) == -math.pi and wrap_angle(-math.pi) == -math.pi
    assert np.isnan(wrap_angle(np.nan))
    assert wrap_angle(np.zeros((2, 3))).shape == (2, 3)


@given(box, box)
def test_overlap_and_distance_are_symmetric(a: tuple[float, ...], b: tuple[float, ...]) -> None:
    ba, bb = _boxes(a), _boxes(b)
    assert boxes_overlap(ba, bb)[0] == boxes_overlap(bb, ba)[0]
    assert math.isclose(box_distance_m(ba, bb)[0], box_distance_m(bb, ba)[0], abs_tol=1e-9)


@given(box, box, coord, coord, angle)
@settings(max_examples=200)
def test_overlap_and_distance_are_invariant_under_rigid_motion(
    a: tuple[float, ...], b: tuple[float, ...], dx: float, dy: float, theta: float
) -> None:
    d0 = box_distance_m(_boxes(a), _boxes(b))[0]
    d1 = box_distance_m(_moved(a, dx, dy, theta), _moved(b, dx, dy, theta))[0]
    assert math.isclose(d0, d1, abs_tol=1e-6)
    if d0 > 1e-6:  # away from touching, the overlap verdict cannot flip
        assert not boxes_overlap(_moved(a, dx, dy, theta), _moved(b, dx, dy, theta))[0]


@given(box, box)
def test_distance_is_zero_exactly_when_boxes_overlap(a: tuple[float, ...], b: tuple[float, ...]) -> None:
    ba, bb = _boxes(a), _boxes(b)
    assert (box_distance_m(ba, bb)[0] == 0.0) == bool(boxes_overlap(ba, bb)[0])


@given(box, coord, coord)
def test_points_inside_a_box_have_distance_zero(b: tuple[float, ...], u: float, v: float) -> None:
    # a point at fractions (u, v) of the half extents, expressed in the world
    fx, fy = u / 50.0 * b[3] / 2, v / 50.0 * b[4] / 2
    px, py = from_local(fx, fy, b[2])
    assert point_box_distance_m(px + b[0], py + b[1], _boxes(b))[0] < 1e-9


@given(coord, coord, angle)
def test_world_to_local_round_trip(x: float, y: float, yaw: float) -> None:
    f, left = to_local(x, y, yaw)
    back = from_local(f, left, yaw)
    assert math.isclose(float(back[0]), x, abs_tol=1e-9) and math.isclose(float(back[1]), y, abs_tol=1e-9)
    assert math.isclose(math.hypot(float(f), float(left)), math.hypot(x, y), abs_tol=1e-9)


@given(st.floats(-2.0, 2.0, allow_nan=False), angle)
def test_yaw_rate_of_a_constant_rate_rotation(rate: float, start: float) -> None:
    t = np.arange(30) * 0.1
    yaw = wrap_angle(start + rate * t)[None, :]  # crosses the +-pi seam freely
    np.testing.assert_allclose(yaw_rate_radps(yaw, t)[0], rate, atol=1e-9)


@given(st.floats(2.0, 200.0, allow_nan=False), st.booleans())
def test_curvature_of_a_circle_is_one_over_its_radius(radius: float, left: bool) -> None:
    s = np.linspace(0.0, 1.0, 50)  # one radian of arc
    sign = 1.0 if left else -1.0
    x, y = radius * np.sin(s), sign * radius * (1 - np.cos(s))
    k = path_curvature_1pm(x, y)
    np.testing.assert_allclose(k[2:-2], sign / radius, rtol=1e-3)
