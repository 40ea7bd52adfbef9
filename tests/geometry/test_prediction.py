"""Path following and predicted footprint conflicts, on hand-made geometry with known answers."""

from __future__ import annotations

import numpy as np
import pytest

from scenariominer.geometry import OrientedBoxes
from scenariominer.geometry.prediction import first_conflicts, poses_along_path


def test_poses_along_an_l_shaped_path_and_its_continuation() -> None:
    # 10 m east, then 10 m north; a standing sample repeated at the start; continued north.
    x = np.array([0.0, 0.0, 5.0, 10.0, 10.0, 10.0])
    y = np.array([0.0, 0.0, 0.0, 0.0, 5.0, 10.0])
    px, py, yaw = poses_along_path(x, y, np.pi / 2, np.array([0.0, 7.0, 12.0, 25.0]))
    np.testing.assert_allclose(px, [0.0, 7.0, 10.0, 10.0], atol=1e-12)
    np.testing.assert_allclose(py, [0.0, 0.0, 2.0, 15.0], atol=1e-12)
    np.testing.assert_allclose(yaw, [0.0, 0.0, np.pi / 2, np.pi / 2], atol=1e-12)


def test_a_standing_path_continues_along_the_given_heading() -> None:
    px, py, yaw = poses_along_path(np.full(5, 3.0), np.full(5, 4.0), np.pi, np.array([0.0, 2.0]))
    np.testing.assert_allclose(px, [3.0, 1.0])
    np.testing.assert_allclose(py, [4.0, 4.0])
    np.testing.assert_allclose(yaw, [np.pi, np.pi])


def test_a_path_without_finite_samples_is_an_error() -> None:
    with pytest.raises(ValueError, match="finite"):
        poses_along_path(np.array([np.nan]), np.array([np.nan]), 0.0, np.array([0.0]))


def _boxes(
    x: np.ndarray, y: np.ndarray, yaw: float, length: float = 2.0, width: float = 2.0
) -> OrientedBoxes:
    return OrientedBoxes(x, y, np.full_like(x, yaw), np.full_like(x, length), np.full_like(x, width))


def test_crossing_paths_conflict_with_a_time_gap() -> None:
    t = np.arange(0.0, 5.01, 0.5)
    ego = _boxes(-10.0 + 5.0 * t, np.zeros_like(t), 0.0)  # reaches x = 0 at t = 2
    # Object 0 crosses x = 0 northwards, at the origin at t = 1.5 (before the ego).
    # Object 1 crosses at t = 4.5 (long after the ego): no conflict within 1 s.
    # Object 2 drives beside the ego 5 m to the left: never overlaps.
    xs = np.stack([np.zeros_like(t), np.zeros_like(t), -10.0 + 5.0 * t])
    ys = np.stack([-3.0 + 2.0 * t, -9.0 + 2.0 * t, np.full_like(t, 5.0)])
    objs = OrientedBoxes(xs, ys, np.full_like(xs, np.pi / 2), np.full_like(xs, 2.0), np.full_like(xs, 2.0))
    found = first_conflicts(ego, objs, t, max_gap_s=1.0)
    assert found.found.tolist() == [True, False, False]
    # The boxes (2 m squares) can touch once the ego's centre is within 2 m of x = 0: t >= 1.6,
    # sampled 2.0; the object occupies the overlapping spot at t = 0.5 ... 2.5, the closest is 2.0.
    assert found.ego_time_s[0] == pytest.approx(2.0)
    assert found.object_time_s[0] == pytest.approx(2.0)
    assert found.gap_s[0] == pytest.approx(0.0)
    assert np.isinf(found.gap_s[1])


def test_object_arriving_after_the_ego_is_excluded_by_the_asymmetric_band() -> None:
    t = np.arange(0.0, 4.01, 0.5)
    ego = _boxes(5.0 * t, np.zeros_like(t), 0.0)
    follower = OrientedBoxes(
        (-5.0 + 5.0 * t)[None, :],
        np.zeros((1, t.size)),
        np.zeros((1, t.size)),
        np.full((1, t.size), 2.0),
        np.full((1, t.size), 2.0),
    )
    assert first_conflicts(ego, follower, t, max_gap_s=1.5).found.tolist() == [True]
    assert first_conflicts(ego, follower, t, max_gap_s=1.5, object_after_s=0.3).found.tolist() == [False]


def test_no_objects() -> None:
    t = np.arange(3.0)
    ego = _boxes(t, t, 0.0)
    empty = OrientedBoxes(*(np.zeros((0, 3)) for _ in range(5)))
    assert first_conflicts(ego, empty, t, 1.0).ego_time_s.shape == (0,)
