"""Hand-built logs and an HD map with known answers, shared by the mining tests.

``street_scene`` is a 6 s, 10 Hz scene on a straight eastbound road (two vehicle lanes and a
bike lane) with a westbound lane, a crosswalk, a stop sign and an intersection ahead. Every
object's path is written down in closed form below, so the expected answers of the predicates
follow from the numbers (see the comments on each track).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from scenariominer.data.adapters.av2.map import (
    Av2Map,
    DrivableArea,
    LaneSegment,
    LaneType,
    PedestrianCrossing,
)
from scenariominer.data.log import Log, build_log
from scenariominer.mine.context import LogContext
from scenariominer.mine.plan_program import compile_plan
from scenariominer.mine.plan_reader import read_plan
from scenariominer.mine.sandbox import run_trusted_program

DT_S = 0.1
T_S = np.round(np.arange(61) * DT_S, 6)  # 0.0 .. 6.0 s


@dataclass
class Obj:
    """One track: id, category, per-timestamp x, y, yaw and a box size."""

    track_id: str
    category: str
    x_m: np.ndarray
    y_m: np.ndarray
    yaw_rad: np.ndarray
    length_m: float = 4.5
    width_m: float = 2.0
    present: np.ndarray | None = None


def const(value: float, t_s: np.ndarray = T_S) -> np.ndarray:
    return np.full(t_s.shape, float(value))


def make_log(
    objs: list[Obj], t_s: np.ndarray = T_S, *, log_id: str = "scene", dataset: str = "synthetic"
) -> Log:
    """A log from exact tracks (the first object is the ego); velocities by finite differences."""
    tid: list[str] = []
    cat: list[str] = []
    ts: list[np.ndarray] = []
    cols: dict[str, list[np.ndarray]] = {k: [] for k in ("x_m", "y_m", "yaw_rad", "length_m", "width_m")}
    for o in objs:
        keep = np.ones(t_s.size, dtype=bool) if o.present is None else o.present
        k = int(keep.sum())
        tid += [o.track_id] * k
        cat += [o.category] * k
        ts.append(np.round(t_s[keep] * 1e9).astype(np.int64))
        cols["x_m"].append(o.x_m[keep])
        cols["y_m"].append(o.y_m[keep])
        cols["yaw_rad"].append(o.yaw_rad[keep])
        cols["length_m"].append(np.full(k, o.length_m))
        cols["width_m"].append(np.full(k, o.width_m))
    return build_log(
        log_id=log_id,
        track_id=tid,
        category=cat,
        timestamp_ns=np.concatenate(ts),
        fields={k: np.concatenate(v) for k, v in cols.items()},
        ego_track_id=objs[0].track_id,
        source="<scene>",
        dataset=dataset,
    )


def _pts(*xy: tuple[float, float]) -> np.ndarray:
    return np.array([[x, y, 0.0] for x, y in xy])


def street_map() -> Av2Map:
    """Lanes (ids): 1 eastbound vehicle lane y in [-1.8, 1.8], x in [-60, 80]; 2 eastbound vehicle
    lane y in [1.8, 5.4]; 3 eastbound BIKE lane y in [-5.4, -1.8]; 4 westbound lane y in [5.4, 9];
    5 intersection lane continuing lane 1 for x in [80, 100]. Crosswalk x in [48, 52] across the
    road; drivable area = the road plus the intersection block x in [80, 100], y in [-30, 9]."""
    lane1 = LaneSegment(
        id=1,
        lane_type=LaneType.VEHICLE,
        is_intersection=False,
        left_boundary_m=_pts((-60, 1.8), (80, 1.8)),
        right_boundary_m=_pts((-60, -1.8), (80, -1.8)),
        successors=(5,),
        left_neighbor_id=2,
        right_neighbor_id=3,
    )
    lane2 = LaneSegment(
        id=2,
        lane_type=LaneType.VEHICLE,
        is_intersection=False,
        left_boundary_m=_pts((-60, 5.4), (80, 5.4)),
        right_boundary_m=_pts((-60, 1.8), (80, 1.8)),
        left_neighbor_id=4,
        right_neighbor_id=1,
    )
    lane3 = LaneSegment(
        id=3,
        lane_type=LaneType.BIKE,
        is_intersection=False,
        left_boundary_m=_pts((-60, -1.8), (80, -1.8)),
        right_boundary_m=_pts((-60, -5.4), (80, -5.4)),
        left_neighbor_id=1,
    )
    lane4 = LaneSegment(  # westbound: its left is the south edge
        id=4,
        lane_type=LaneType.VEHICLE,
        is_intersection=False,
        left_boundary_m=_pts((100, 5.4), (-60, 5.4)),
        right_boundary_m=_pts((100, 9.0), (-60, 9.0)),
        left_neighbor_id=2,
    )
    lane5 = LaneSegment(
        id=5,
        lane_type=LaneType.VEHICLE,
        is_intersection=True,
        left_boundary_m=_pts((80, 1.8), (100, 1.8)),
        right_boundary_m=_pts((80, -1.8), (100, -1.8)),
        predecessors=(1,),
    )
    crossing = PedestrianCrossing(
        id=10, edge1_m=_pts((48, -5.4), (48, 9.0)), edge2_m=_pts((52, -5.4), (52, 9.0))
    )
    road = DrivableArea(id=20, boundary_m=_pts((-60, -5.4), (100, -5.4), (100, 9.0), (-60, 9.0)))
    block = DrivableArea(id=21, boundary_m=_pts((80, -30), (100, -30), (100, -5.4), (80, -5.4)))
    return Av2Map(
        lane_segments=(lane1, lane2, lane3, lane4, lane5),
        pedestrian_crossings=(crossing,),
        drivable_areas=(road, block),
    )


def street_objects() -> list[Obj]:
    """The tracks of :func:`street_scene`, ego first (see the comment on each)."""
    t = T_S
    zero = const(0.0)
    objs = [
        # ego: lane 1, eastbound at 10 m/s from x = 0
        Obj("ego", "EGO_VEHICLE", 10 * t, zero, zero),
        # lead: 15 m ahead of the ego in lane 1, same speed (the ego follows it)
        Obj("lead", "REGULAR_VEHICLE", 10 * t + 15, zero, zero),
        # bike: beside the ego in the bike lane (3.6 m to its right), same speed
        Obj("bike", "BICYCLE", 10 * t, const(-3.6), zero, length_m=1.8, width_m=0.6),
        # ped: walks north on the crosswalk at x = 50, 2 m/s, crossing y = 0 at t = 3 s,
        # 2.75 m ahead of the lead's front bumper then (the ego's front is 17.75 m away)
        Obj("ped", "PEDESTRIAN", const(50.0), -6 + 2 * t, const(np.pi / 2), length_m=0.6, width_m=0.6),
        # parked: stationary car in the westbound lane
        Obj("parked", "REGULAR_VEHICLE", const(30.0), const(7.2), const(np.pi)),
        # stop sign beside the eastbound road, facing west (toward approaching traffic)
        Obj("stop", "STOP_SIGN", const(46.0), const(-6.0), const(np.pi), length_m=0.2, width_m=0.8),
    ]
    # changer: 20 m behind the ego in lane 1, moves to lane 2 between t = 2 s and 4 s
    ramp = np.clip((t - 2.0) / 2.0, 0.0, 1.0)
    y_ch = 1.8 * (1 - np.cos(np.pi * ramp))
    dy = np.where((t > 2.0) & (t < 4.0), 1.8 * np.pi / 2 * np.sin(np.pi * ramp), 0.0)
    objs.append(Obj("changer", "REGULAR_VEHICLE", 10 * t - 20, y_ch, np.arctan2(dy, 10.0)))
    # turner: eastbound at 5 m/s on the intersection lane, then a 90-degree right turn of radius
    # 10 m between t = 1 s and 4 s, then southbound
    phi = np.clip((t - 1.0) / 3.0, 0.0, 1.0) * np.pi / 2
    x_t = np.where(t < 1.0, 80 + 5 * t, np.where(t <= 4.0, 85 + 10 * np.sin(phi), 95.0))
    y_t = np.where(t < 1.0, 0.0, np.where(t <= 4.0, -10 + 10 * np.cos(phi), -10 - 5 * (t - 4.0)))
    objs.append(Obj("turner", "REGULAR_VEHICLE", x_t, y_t, -phi))
    # ped2: stands beside the turner's path
    objs.append(Obj("ped2", "PEDESTRIAN", const(98.0), const(-12.0), zero, length_m=0.6, width_m=0.6))
    # oncoming: westbound at 12 m/s in lane 4, passes the ego around t = 4.5 s
    objs.append(Obj("oncoming", "REGULAR_VEHICLE", 100 - 12 * t, const(7.2), const(np.pi)))
    # bus: in the bike lane 40 m behind the bike, accelerating at 1.5 m/s^2 from 5 m/s
    objs.append(Obj("bus", "BUS", -40 + 5 * t + 0.75 * t**2, const(-3.6), zero, length_m=12.0, width_m=2.6))
    # overtaker: lane 2 at 15 m/s, passes the ego's centre line at t = 4 s
    objs.append(Obj("overtaker", "REGULAR_VEHICLE", 15 * t - 20, const(3.6), zero))
    # two pedestrians standing 1 m apart; pedA faces north (toward the road), pedB south
    objs.append(
        Obj("pedA", "PEDESTRIAN", const(20.0), const(-8.0), const(np.pi / 2), length_m=0.5, width_m=0.5)
    )
    objs.append(
        Obj("pedB", "PEDESTRIAN", const(21.0), const(-8.0), const(-np.pi / 2), length_m=0.5, width_m=0.5)
    )
    return objs


def street_scene(with_map: bool = True) -> LogContext:
    """The street scene as a mining context (exact kinematics, no smoothing)."""
    log = make_log(street_objects(), log_id="street")
    return LogContext(log, hd_map=street_map() if with_map else None)


def idx(ctx: LogContext, track_id: str) -> int:
    return ctx.log.track_index(track_id)


def t_index(t_s: float) -> int:
    return int(round(t_s / DT_S))


def rules_program(description: str) -> str:
    """The program the phrase rules build for ``description`` (asserts that they read it in full)."""
    plan = read_plan(description)
    assert plan is not None, f"the rules should read {description!r}"
    assert plan["read_by"] == "rules"
    return compile_plan(plan).program


def rules_referred(ctx: LogContext, description: str) -> set[str]:
    """The track ids that the rules' program for ``description`` refers to in ``ctx``."""
    result = run_trusted_program(rules_program(description), ctx, description=description)
    assert result.ok, result.error
    assert result.scenario is not None
    return {ctx.log.track_ids[int(i)] for i in result.scenario.referred_tracks}
