"""Interaction tags (collision, heading, position, distance, trajectory overlap) with known answers."""

from __future__ import annotations

import numpy as np
import pytest
import shapely
from tag_scenarios import (
    Track,
    braking_lead_scene,
    crossing_pedestrian_scene,
    integrate,
    left_turn_scene,
    make_log,
    times,
)

from scenariominer.config.tags import TagConfig
from scenariominer.data.log import Log
from scenariominer.geometry import OrientedBoxes, ctrv_predict, yaw_rate_radps
from scenariominer.tags.interaction import (
    collision_tags,
    distance_tags,
    heading_codes,
    heading_tags,
    log_boxes,
    position_codes,
    position_tags,
    swept_overlap,
    traj_overlap_tags,
    ttc_s,
)
from scenariominer.tags.vocab import (
    ABSENT,
    CollisionTag,
    DistanceTag,
    HeadingTag,
    PositionTag,
    TrajOverlapTag,
    codes_to_names,
)

CFG = TagConfig()


def _names(enum_cls: type, codes: np.ndarray) -> list[str | None]:
    return list(codes_to_names(enum_cls, codes))


def _during(log: Log, row: np.ndarray, lo_s: float, hi_s: float) -> set[object]:
    t = log.t_s
    return {row[k] for k in np.flatnonzero((t > lo_s) & (t < hi_s))}


def _static_scene(ego_yaw: float, objects: list[tuple[float, float, float]]) -> Log:
    """A standing ego at (5, -3) and standing objects given as (x, y, yaw); two frames."""
    t = times(0.1)
    tracks = [Track("ego", "EGO_VEHICLE", np.full(2, 5.0), np.full(2, -3.0), np.full(2, ego_yaw))]
    for k, (x, y, yaw) in enumerate(objects):
        tracks.append(Track(f"o{k}", "REGULAR_VEHICLE", np.full(2, x), np.full(2, y), np.full(2, yaw)))
    return make_log(tracks, t, smooth=False)


# ---------------------------------------------------------------------- heading and position


@pytest.mark.parametrize("offset_deg", [-40.0, 0.0, 40.0])
def test_each_position_sector_in_the_ego_frame(offset_deg: float) -> None:
    ego_yaw = 0.7
    bearings = np.deg2rad(np.arange(8) * 45.0 + offset_deg)
    objects = [(5.0 + 20 * np.cos(ego_yaw + b), -3.0 + 20 * np.sin(ego_yaw + b), 0.0) for b in bearings]
    log = _static_scene(ego_yaw, objects)
    codes = position_tags(log)
    names = [_names(PositionTag, codes[log.track_index(f"o{k}")])[0] for k in range(8)]
    # Sectors are 45° wide, centred on multiples of 45°: an offset of ±40° reaches the neighbour.
    shift = int(round(offset_deg / 45.0))
    expected = [list(PositionTag)[(k + shift) % 8].value for k in range(8)]
    assert names == expected


def test_each_heading_sector_relative_to_the_ego() -> None:
    ego_yaw = -2.5
    rel = np.deg2rad([0, 30, -30, 90, 60, 120, 180, -150, 150, -90, -60, -120])
    expected = ["SAME", "SAME", "SAME", "LEFT", "LEFT", "LEFT", "OPPOSITE", "OPPOSITE", "OPPOSITE"]
    expected += ["RIGHT", "RIGHT", "RIGHT"]
    log = _static_scene(ego_yaw, [(30.0 + 10 * k, 0.0, ego_yaw + r) for k, r in enumerate(rel)])
    codes = heading_tags(log)
    names = [_names(HeadingTag, codes[log.track_index(f"o{k}")])[0] for k in range(rel.size)]
    assert names == expected


def test_sector_boundaries_belong_to_the_counter_clockwise_sector() -> None:
    assert heading_codes(np.deg2rad(np.array([45.0, 135.0, -135.0, -45.0]))).tolist() == [1, 2, 3, 0]
    assert position_codes(np.deg2rad(np.array([22.5, -22.5, 180.0]))).tolist() == [1, 0, 4]


def test_interaction_tags_are_absent_on_the_ego_row_and_where_the_object_is_missing() -> None:
    t = times(6.0)
    present = (t >= 1.0) & (t <= 3.0)
    log = make_log(
        [
            Track("ego", "EGO_VEHICLE", *integrate(t, 5.0)),
            Track("car", "REGULAR_VEHICLE", *integrate(t, 5.0, x0_m=15.0), present=present),
        ],
        t,
    )
    codes = [heading_tags(log), position_tags(log), traj_overlap_tags(log, CFG)]
    codes += [collision_tags(log, CFG)[0], distance_tags(log, CFG)[0]]
    for c in codes:
        assert np.all(c[0] == ABSENT)
        assert np.all(c[1, ~present] == ABSENT)
        assert np.all(c[1, present] != ABSENT)
    assert np.isnan(ttc_s(log, CFG)[1, ~present]).all()
    assert np.isnan(distance_tags(log, CFG)[1][1, ~present]).all()


# ---------------------------------------------------------------------- distance


def test_distance_bands_and_very_close_from_expanded_boxes() -> None:
    # Objects beside a 4.5 m x 2 m ego with lateral gaps of 0.8, 1.2, 6, 30 and 80 metres.
    gaps = [0.8, 1.2, 6.0, 30.0, 80.0]
    log = _static_scene(0.0, [(5.0, -3.0 + 2.0 + g, 0.0) for g in gaps])
    codes, dist = distance_tags(log, CFG)
    np.testing.assert_allclose(dist[1:, 0], gaps, atol=1e-9)
    # With a 0.5 m margin per box, gaps below 1 m are VERY_CLOSE.
    assert [_names(DistanceTag, codes[1 + k])[0] for k in range(5)] == [
        "VERY_CLOSE",
        "CLOSE",
        "CLOSE",
        "MEDIUM",
        "FAR",
    ]


def test_box_distance_over_a_log_matches_shapely() -> None:
    log = braking_lead_scene()
    _, dist = distance_tags(log, CFG)
    corners = log_boxes(log).corners()  # (N, T, 4, 2)
    polys = shapely.polygons(corners)
    expected = shapely.distance(polys[0][None, :], polys[1:])
    np.testing.assert_allclose(dist[1:], expected, atol=1e-9)


# ---------------------------------------------------------------------- collision


@pytest.mark.parametrize(("gap_m", "closing_mps", "object_mps"), [(12.34, 10.0, 0.0), (27.07, 15.0, -5.0)])
def test_straight_line_ttc_has_the_closed_form(gap_m: float, closing_mps: float, object_mps: float) -> None:
    # Ego drives +x at (closing + object) speed; the object drives +x at object speed
    # (negative = oncoming, modelled as driving backwards in the ego's lane).
    t = times(2.0)
    ego_mps = closing_mps + object_mps
    ego = integrate(t, ego_mps)
    obj = integrate(t, object_mps, x0_m=gap_m + 4.5)
    log = make_log(
        [Track("ego", "EGO_VEHICLE", *ego), Track("obj", "REGULAR_VEHICLE", *obj)], t, smooth=False
    )
    ttc = ttc_s(log, CFG)[1]
    remaining_gap = np.maximum(gap_m - closing_mps * t, 0.0)  # overlapping now: TTC 0
    expected = np.ceil(remaining_gap / closing_mps / CFG.ttc_step_s - 1e-9) * CFG.ttc_step_s
    expected = np.where(expected <= CFG.ttc_horizon_s + 1e-9, expected, np.inf)
    np.testing.assert_allclose(ttc, expected, atol=1e-9)
    codes = collision_tags(log, CFG)[0][1]
    want = np.where(expected < 1.5, "HIGH", np.where(np.isfinite(expected), "LOW", "NO"))
    assert _names(CollisionTag, codes) == want.tolist()


def test_ctrv_predicts_a_collision_that_a_straight_line_would_miss() -> None:
    # The ego turns left on a 10 m radius at 5 m/s; a car stands where the arc leads (10, 10),
    # far off the straight line ahead.
    t = times(1.0)
    ego = integrate(t, 5.0, 0.5)
    obj = (np.full(t.size, 10.0), np.full(t.size, 10.0), np.full(t.size, np.pi / 2))
    log = make_log(
        [Track("ego", "EGO_VEHICLE", *ego), Track("car", "REGULAR_VEHICLE", *obj)], t, smooth=False
    )
    assert np.isfinite(ttc_s(log, CFG)[1, 0])
    straight = make_log(
        [Track("ego", "EGO_VEHICLE", *integrate(t, 5.0)), Track("car", "REGULAR_VEHICLE", *obj)],
        t,
        smooth=False,
    )
    assert np.isinf(ttc_s(straight, CFG)[1, 0])


def test_ttc_matches_an_unfiltered_shapely_check_of_every_predicted_step() -> None:
    # Random turning traffic around a turning ego; no prefilter on the reference side.
    rng = np.random.default_rng(2)
    t = times(2.0)
    long_t = times(6.0)
    ego_x, ego_y, _ = integrate(long_t, 8.0, 0.3)
    tracks = [Track("ego", "EGO_VEHICLE", ego_x[: t.size], ego_y[: t.size], integrate(t, 8.0, 0.3)[2])]
    for k in range(10):
        # Heading for where the ego will be after 1-5 s, missing it by a random lateral offset.
        meet = int(rng.integers(10, 50))
        aim, speed = rng.uniform(-np.pi, np.pi), rng.uniform(2, 10)
        miss = rng.normal(0, 2.0)
        x0 = ego_x[meet] - speed * long_t[meet] * np.cos(aim) - miss * np.sin(aim)
        y0 = ego_y[meet] - speed * long_t[meet] * np.sin(aim) + miss * np.cos(aim)
        tracks.append(Track(f"o{k}", "REGULAR_VEHICLE", *integrate(t, speed, 0.0, x0, y0, aim)))
    log = make_log(tracks, t)
    ttc = ttc_s(log, CFG)
    rate = np.clip(yaw_rate_radps(log.yaw_rad, log.t_s), -1.0, 1.0)
    tau = np.arange(31) * 0.1

    def predicted_polygons(i: int, k: int) -> np.ndarray:
        x, y, yaw = ctrv_predict(
            *(np.asarray(a[i, k]) for a in (log.x_m, log.y_m, log.yaw_rad, log.vx_mps, log.vy_mps, rate)), tau
        )
        size = (np.full(tau.size, log.length_m[i, k]), np.full(tau.size, log.width_m[i, k]))
        return shapely.polygons(OrientedBoxes(x, y, yaw, *size).corners())

    expected = np.full(ttc.shape, np.nan)
    for k in range(t.size):
        ego = predicted_polygons(0, k)
        for i in range(1, log.n_tracks):
            hit = shapely.intersects(ego, predicted_polygons(i, k))
            expected[i, k] = tau[np.argmax(hit)] if hit.any() else np.inf
    np.testing.assert_allclose(ttc, expected)
    # The scene exercises misses as well as TTCs across the whole horizon.
    assert np.isinf(expected).any()
    assert np.unique(expected[np.isfinite(expected)]).size > 20


def test_braking_lead_raises_the_collision_risk_of_the_follower() -> None:
    log = braking_lead_scene()
    codes, ttc = collision_tags(log, CFG)
    lead = _names(CollisionTag, codes[log.track_index("lead")])
    # Before the lead brakes both drive at 10 m/s: no predicted collision.
    assert _during(log, np.array(lead), 0.0, 3.0) == {"NO"}
    # The follower closes in while the lead stops: HIGH risk at some point, LOW before it.
    assert "HIGH" in lead
    first_high = lead.index("HIGH")
    assert "LOW" in lead[:first_high]
    for name in ("far", "parked"):
        assert set(_names(CollisionTag, codes[log.track_index(name)])) == {"NO"}
    assert np.nanmin(ttc[log.track_index("lead")]) < CFG.ttc_high_s


# ---------------------------------------------------------------------- trajectory overlap


def test_traj_overlap_windows_for_a_car_driving_into_a_standing_one() -> None:
    # Ego at 10 m/s towards a standing car 20 m ahead (bumper gap); the recorded track passes
    # through it. Gap at time now: 20 - 10 now. HIGH while the gap is covered within 1.5 s
    # (now >= 0.5 s) until the ego has passed (rear beyond the car's front at now = 2.9 s).
    t = times(5.0)
    log = make_log(
        [
            Track("ego", "EGO_VEHICLE", *integrate(t, 10.0)),
            Track("car", "REGULAR_VEHICLE", *integrate(t, 0.0, x0_m=24.5)),
        ],
        t,
        smooth=False,
    )
    names = np.array(_names(TrajOverlapTag, traj_overlap_tags(log, CFG)[1]))
    assert _during(log, names, -0.1, 0.45) == {"LOW"}
    assert _during(log, names, 0.55, 2.85) == {"HIGH"}
    assert _during(log, names, 2.95, 5.1) == {"NO"}


def test_traj_overlap_counts_boxes_at_different_times() -> None:
    log = crossing_pedestrian_scene()
    names = _names(TrajOverlapTag, traj_overlap_tags(log, CFG)[1])
    # The pedestrian leaves the ego's lane before the ego arrives: they are never in the same
    # place at the same time, yet their future swept regions overlap.
    polys = shapely.polygons(log_boxes(log).corners())
    assert not shapely.intersects(polys[0], polys[1]).any()
    assert "LOW" in names or "HIGH" in names
    assert names[0] == "NO"


def _brute_force_overlap(log: Log, window_s: float) -> np.ndarray:
    polys = shapely.polygons(np.nan_to_num(log_boxes(log).corners()))  # absent boxes are never selected
    t = log.t_s
    out = np.zeros(log.valid.shape, dtype=bool)
    for i in range(1, log.n_tracks):
        gaps = np.hypot(log.x_m[i][:, None] - log.x_m[0][None, :], log.y_m[i][:, None] - log.y_m[0][None, :])
        if np.nanmin(gaps) > 10.0:  # 4.5 m x 2 m boxes this far apart can never touch
            continue
        for now in range(t.size):
            if not (log.valid[0, now] and log.valid[i, now]):
                continue
            sel = (t >= t[now] - 1e-9) & (t <= t[now] + window_s + 1e-9)
            ego = shapely.union_all(polys[0][sel & log.valid[0]])
            obj = shapely.union_all(polys[i][sel & log.valid[i]])
            out[i, now] = bool(shapely.intersects(ego, obj))
    return out


def test_traj_overlap_matches_a_brute_force_union_of_boxes() -> None:
    rng = np.random.default_rng(5)
    t = times(3.5)
    tracks = [Track("ego", "EGO_VEHICLE", *integrate(t, 6.0, 0.15))]
    for k in range(6):
        start = rng.uniform([0.0, -6.0], [25.0, 6.0])
        present = np.ones(t.size, dtype=bool)
        present[rng.integers(0, t.size - 10) :][: rng.integers(0, 10)] = False
        motion = integrate(t, rng.uniform(0, 8), rng.uniform(-0.3, 0.3), *start, rng.uniform(-np.pi, np.pi))
        tracks.append(Track(f"o{k}", "REGULAR_VEHICLE", *motion, present=present))
    log = make_log(tracks, t)
    high, low = swept_overlap(log, (1.5, 3.0))
    np.testing.assert_array_equal(high, _brute_force_overlap(log, 1.5))
    np.testing.assert_array_equal(low, _brute_force_overlap(log, 3.0))
    assert low.any() and not low.all()


# ---------------------------------------------------------------------- the paper's scenes


def test_braking_lead_is_ahead_same_heading_and_close() -> None:
    log = braking_lead_scene()
    row = log.track_index("lead")
    assert set(_names(PositionTag, position_tags(log)[row])) == {"FRONT"}
    assert set(_names(HeadingTag, heading_tags(log)[row])) == {"SAME"}
    distance = np.array(_names(DistanceTag, distance_tags(log, CFG)[0][row]))
    assert _during(log, distance, 4.5, 10.1) == {"CLOSE"}
    overlap = np.array(_names(TrajOverlapTag, traj_overlap_tags(log, CFG)[row]))
    # Following at 1.55 s headway: the ego reaches the lead's present place within 3 s, not 1.5 s.
    assert _during(log, overlap, -0.1, 2.0) == {"LOW"}


def test_pedestrian_crossing_from_the_right() -> None:
    log = crossing_pedestrian_scene()
    position = np.array(_names(PositionTag, position_tags(log)[1]))
    assert position[0] == "FRONT_RIGHT"
    # While the pedestrian is in the ego's lane (|y| < 1 m, 5.3 s to 6.6 s) it is straight ahead.
    assert _during(log, position, 5.4, 6.5) == {"FRONT"}
    first_front = list(position).index("FRONT")
    assert set(position[:first_front]) == {"FRONT_RIGHT"}
    # Walking towards the ego's left.
    assert set(_names(HeadingTag, heading_tags(log)[1])) == {"LEFT"}


def test_oncoming_car_during_the_ego_left_turn() -> None:
    log = left_turn_scene()
    heading = np.array(_names(HeadingTag, heading_tags(log)[1]))
    position = np.array(_names(PositionTag, position_tags(log)[1]))
    # Before the cars pass each other (at 3.4 s) the oncoming car is ahead and opposite.
    assert _during(log, heading, -0.1, 3.4) == {"OPPOSITE"}
    assert _during(log, position, -0.1, 3.3) <= {"FRONT", "FRONT_LEFT"}
    assert "FRONT_LEFT" in _during(log, position, -0.1, 3.3)
