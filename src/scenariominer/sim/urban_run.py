"""One headless SUMO run of an urban scenario under TraCI, recorded at every 0.1 s step.

The ego (vehicle id :data:`EGO_ID`) is inserted at the start of arm 0 and never changes lanes by
itself; background road users (vehicles on the other arms, pedestrians on the sidewalks) are
inserted at drawn times. The *guest* (id :data:`GUEST_ID`) acts through TraCI when its trigger
fires: a pedestrian steps onto a crossing, an oncoming or crossing vehicle is inserted so that it
reaches the junction about when the ego does, the leader brakes, a vehicle on the next lane
changes into the ego's lane, or a vehicle stands in the ego's lane from the start. Each scenario
is run twice, with and without the guest (:func:`run_scenario` ``with_guest``), so the label can
say what the guest changed.

Recorded per step: every road user's box (centre, heading, size, category) and the simulator's
view of the ego: speed, acceleration, leader and gap (``vehicle.getLeader``), junction foes
(``vehicle.getJunctionFoes``), distance to the junction, lane; and of the guest: speed,
acceleration, lane, edge.
"""

from __future__ import annotations

import contextlib
import itertools
import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from scenariominer.data.adapters.av2 import AV2_EGO_SIZE_M
from scenariominer.data.log import FloatArray
from scenariominer.sim.urban_net import UrbanSimError, edge_ids
from scenariominer.sim.urban_scenario import DriverStyle, UrbanScenario
from scenariominer.synth.vocab import ScenarioCategory

__all__ = ["EGO_ID", "GUEST_ID", "STEP_S", "ObjectTrack", "RunRecord", "run_scenario"]

#: SUMO ids of the ego and of the guest (vehicle or person).
EGO_ID = "ego"
GUEST_ID = "guest"
#: Simulation step, seconds.
STEP_S = 0.1
#: Longest run, seconds.
MAX_RUN_S = 60.0

#: SUMO vehicle types of the other road users: id -> (AV2 category, vClass, length, width, height, share).
_TYPES: dict[str, tuple[str, str, float, float, float, float]] = {
    "car": ("REGULAR_VEHICLE", "passenger", 4.6, 1.85, 1.5, 0.7),
    "van": ("LARGE_VEHICLE", "passenger", 5.9, 2.1, 2.4, 0.1),
    "truck": ("BOX_TRUCK", "passenger", 7.5, 2.45, 3.3, 0.07),
    "bus": ("BUS", "passenger", 12.0, 2.55, 3.2, 0.05),
    "moto": ("MOTORCYCLIST", "passenger", 2.2, 0.9, 1.6, 0.08),
}
_PERSON_SIZE_M = (0.6, 0.6, 1.75)
_counter = itertools.count()


@dataclass(frozen=True, eq=False)
class ObjectTrack:
    """One road user over the run.

    Attributes:
        category: AV2 category name.
        size_m: ``(length, width, height)``.
        x_m, y_m, yaw_rad: ``(T,)`` box centre and heading in SUMO coordinates (NaN when absent).
    """

    category: str
    size_m: tuple[float, float, float]
    x_m: FloatArray
    y_m: FloatArray
    yaw_rad: FloatArray


@dataclass(frozen=True, eq=False)
class RunRecord:
    """Everything recorded in one run.

    Attributes:
        t_s: ``(T,)`` simulation time of each step.
        objects: id -> track (the ego and guest included, under :data:`EGO_ID` / :data:`GUEST_ID`).
        ego_speed_mps, ego_accel_mps2: ``(T,)`` the ego's speed and acceleration (NaN when absent).
        ego_to_junction_m: ``(T,)`` the ego's distance to the end of its inbound edge (NaN past it).
        ego_leader: ``(T,)`` id of the ego's leader within 100 m (``""`` none).
        ego_leader_gap_m: ``(T,)`` gap to that leader (NaN none).
        ego_lane: ``(T,)`` the ego's lane index (-1 when absent).
        ego_foes: ``(T,)`` ids of the ego's junction foes within 100 m.
        guest_speed_mps, guest_accel_mps2: ``(T,)`` the guest's speed and acceleration (NaN absent).
        guest_lane: ``(T,)`` a guest vehicle's lane index (-1 otherwise).
        guest_edge: ``(T,)`` the guest's edge id (``""`` when absent).
        guest_action_s: time the guest's trigger fired (NaN never).
        collisions: ids of vehicles that collided with the ego.
    """

    t_s: FloatArray
    objects: dict[str, ObjectTrack]
    ego_speed_mps: FloatArray
    ego_accel_mps2: FloatArray
    ego_to_junction_m: FloatArray
    ego_leader: list[str]
    ego_leader_gap_m: FloatArray
    ego_lane: list[int]
    ego_foes: list[tuple[str, ...]]
    guest_speed_mps: FloatArray
    guest_accel_mps2: FloatArray
    guest_lane: list[int]
    guest_edge: list[str]
    guest_action_s: float
    collisions: tuple[str, ...] = field(default=())


def _route_file(scenario: UrbanScenario, path: Path) -> None:
    le, we, he = AV2_EGO_SIZE_M
    s = scenario
    model = 'carFollowModel="IDM" delta="4"' if s.style is DriverStyle.SMOOTH else 'sigma="0.1"'
    lines = [
        "<routes>",
        f'  <vType id="ego_t" vClass="passenger" length="{le}" width="{we}" height="{he}" '
        f'accel="{s.ego_accel_mps2:.2f}" decel="{s.ego_decel_mps2:.2f}" emergencyDecel="9" '
        f'tau="{1.2 if s.style is DriverStyle.SMOOTH else 0.9}" minGap="{2.5}" {model} speedFactor="1"/>',
    ]
    for tid, (_, vclass, length, width, height, _) in _TYPES.items():
        lines.append(
            f'  <vType id="{tid}" vClass="{vclass}" length="{length}" width="{width}" height="{height}" '
            f'accel="2.6" decel="4.5" sigma="0.3" speedFactor="normc(1,0.1,0.8,1.2)"/>'
        )
    lines.append('  <vType id="ped" vClass="pedestrian" length="0.6" width="0.6" height="1.75"/>')
    for a in range(4):
        for b in range(4):
            if a != b:
                lines.append(f'  <route id="r{a}{b}" edges="{edge_ids(a)[0]} {edge_ids(b)[1]}"/>')
    lines.append("</routes>")
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")


class _Guest:
    """The guest's trigger and action for one family (called once per step until it has acted)."""

    def __init__(self, scenario: UrbanScenario, conn: Any, rng: np.random.Generator) -> None:
        self.s = scenario
        self.c = conn
        self.rng = rng
        self.acted_s = float("nan")
        #: Speed commands still to give the guest: ``(time s, speed m/s)``, -1 hands it back to SUMO.
        self.pending: list[tuple[float, float]] = []

    def setup(self) -> None:
        s, c = self.s, self.c
        if s.family is ScenarioCategory.LEAD_BRAKE:
            tid = self._type()  # departPos is the front: the gap plus the guest's length ahead of the ego
            c.vehicle.add(
                GUEST_ID,
                "r02",
                typeID=tid,
                departPos=f"{10.0 + s.guest_param + _TYPES[tid][2]:.1f}",
                departSpeed=f"{s.ego_speed_mps:.2f}",
                departLane=str(s.ego_lane),
            )
            c.vehicle.setLaneChangeMode(GUEST_ID, 0)
            c.vehicle.setSpeed(GUEST_ID, s.ego_speed_mps)
        elif s.family is ScenarioCategory.CUT_IN:
            c.vehicle.add(
                GUEST_ID,
                "r02",
                typeID="car",
                departPos="38",
                departSpeed=f"{s.ego_speed_mps - 3:.2f}",
                departLane=str(3 - s.ego_lane),
            )
            c.vehicle.setLaneChangeMode(GUEST_ID, 0)
            c.vehicle.setSpeed(GUEST_ID, s.ego_speed_mps - 3.0)
        elif s.family is ScenarioCategory.APPROACH_STOP:
            c.vehicle.add(
                GUEST_ID,
                "r02",
                typeID=self._type(),
                departPos=f"{s.guest_param:.1f}",
                departSpeed="0",
                departLane=str(s.ego_lane),
            )
            c.vehicle.setLaneChangeMode(GUEST_ID, 0)
            c.vehicle.setSpeed(GUEST_ID, 0.0)
            self.acted_s = 0.0

    def _type(self) -> str:
        return str(self.rng.choice(["car", "car", "car", "van", "truck", "bus"]))

    def step(self, t_s: float, ego_to_junction_m: float, ego_speed_mps: float) -> None:
        s, c = self.s, self.c
        while self.pending and t_s >= self.pending[0][0]:
            if GUEST_ID in c.vehicle.getIDList():
                c.vehicle.setSpeed(GUEST_ID, self.pending[0][1])
            self.pending.pop(0)
        if not np.isnan(self.acted_s):
            return
        fam = s.family
        if fam in (ScenarioCategory.PED_CROSSING, ScenarioCategory.RIGHT_PED):
            if ego_to_junction_m <= s.trigger_m:
                arm = 3 if fam is ScenarioCategory.RIGHT_PED else (2 if self.rng.random() < 0.6 else 0)
                e_in, e_out = edge_ids(arm)
                start, end = (
                    (e_in, e_out)
                    if s.guest_param < 0.5 or fam is ScenarioCategory.RIGHT_PED and self.rng.random() < 0.5
                    else (e_out, e_in)
                )
                pos = c.lane.getLength(f"{start}_0") - 1.5 if start.startswith("in") else 1.5
                c.person.add(GUEST_ID, start, pos=pos, typeID="ped")
                c.person.appendWalkingStage(GUEST_ID, [start, end], arrivalPos=25.0, speed=s.guest_speed_mps)
                self.acted_s = t_s
        elif fam in (ScenarioCategory.LEFT_OPPO, ScenarioCategory.OBJ_CROSSING):
            if ego_to_junction_m <= s.trigger_m:
                if fam is ScenarioCategory.LEFT_OPPO:
                    src, route, lane = 2, "r20", int(self.rng.integers(1, 3))
                else:
                    src = int(self.rng.choice([1, 3]))
                    route, lane = f"r{src}{4 - src}", 1
                e_in = edge_ids(src)[0]
                lane = min(lane, c.edge.getLaneNumber(e_in) - 1)
                t_arrive = ego_to_junction_m / max(ego_speed_mps, 3.0) + s.guest_param
                length = c.lane.getLength(f"{e_in}_{lane}")
                pos = float(np.clip(length - s.guest_speed_mps * t_arrive, length - 90.0, length - 20.0))
                c.vehicle.add(
                    GUEST_ID,
                    route,
                    typeID=self._type(),
                    departPos=f"{pos:.1f}",
                    departSpeed=f"{s.guest_speed_mps:.2f}",
                    departLane=str(lane),
                )
                c.vehicle.setLaneChangeMode(GUEST_ID, 0)
                c.vehicle.setSpeed(GUEST_ID, s.guest_speed_mps)
                self.acted_s = t_s
        elif fam is ScenarioCategory.LEAD_BRAKE:
            if t_s >= s.trigger_m and GUEST_ID in c.vehicle.getIDList():
                v = c.vehicle.getSpeed(GUEST_ID)
                v_end = v * float(self.rng.uniform(0.0, 0.35))
                brake_s = max((v - v_end) / s.guest_speed_mps, 0.3)
                c.vehicle.slowDown(GUEST_ID, v_end, brake_s)
                hold_s = float(self.rng.uniform(1.5, 4.0))
                self.pending = [(t_s + brake_s, v_end), (t_s + brake_s + hold_s, -1.0)]
                self.acted_s = t_s
        elif fam is ScenarioCategory.CUT_IN and t_s >= s.trigger_m and GUEST_ID in c.vehicle.getIDList():
            ahead = c.vehicle.getLanePosition(GUEST_ID) > c.vehicle.getLanePosition(EGO_ID)
            gap = float(
                np.linalg.norm(np.subtract(c.vehicle.getPosition(GUEST_ID), c.vehicle.getPosition(EGO_ID)))
            ) - c.vehicle.getLength(GUEST_ID)
            if ahead and gap <= s.guest_param:
                c.vehicle.changeLane(GUEST_ID, s.ego_lane, 3.0)
                v = c.vehicle.getSpeed(GUEST_ID)
                c.vehicle.slowDown(GUEST_ID, v * s.guest_speed_mps, 2.5)
                resume_s = t_s + float(self.rng.uniform(4.0, 7.0))
                self.pending = [(t_s + 2.5, v * s.guest_speed_mps), (resume_s, -1.0)]
                self.acted_s = t_s


def _background(scenario: UrbanScenario, conn: Any, rng: np.random.Generator) -> None:
    """Schedule the other road users (ids ``bg0``, ``bg1``, ...) at drawn times within the first 30 s."""
    names = list(_TYPES)
    shares = np.asarray([_TYPES[n][5] for n in names])
    for i in range(scenario.n_background):
        bid = f"bg{i}"
        t = float(rng.uniform(0.0, 30.0))
        if rng.random() < 0.65:
            src = int(rng.choice([1, 2, 2, 3]))
            dst = int(rng.choice([d for d in range(4) if d != src]))
            tid = names[int(rng.choice(len(names), p=shares / shares.sum()))]
            conn.vehicle.add(
                bid, f"r{src}{dst}", typeID=tid, depart=f"{t:.1f}", departSpeed="max", departLane="best"
            )
        else:
            arm = int(rng.integers(0, 4))
            edge = edge_ids(arm)[int(rng.integers(0, 2))]
            length = conn.lane.getLength(f"{edge}_0")
            a, b = sorted(rng.uniform(30.0, length - 5.0, size=2))
            conn.person.add(bid, edge, pos=float(a), depart=t, typeID="ped")
            conn.person.appendWalkingStage(bid, [edge], arrivalPos=float(min(max(b, a + 10.0), length - 1.0)))


def run_scenario(scenario: UrbanScenario, net_file: Path, sumo: str, *, with_guest: bool) -> RunRecord:
    """Run ``scenario`` on ``net_file`` with SUMO under TraCI and record every step.

    The run ends 12 s after the ego has left the junction, when it leaves the network, or after
    :data:`MAX_RUN_S`. SUMO's routes (``urban.rou.xml``) and error log (``sumo.log``) are written
    beside ``net_file``.

    Args:
        scenario: what to simulate.
        net_file: the network built by :func:`~scenariominer.sim.urban_net.build_network`.
        sumo: path of the ``sumo`` program.
        with_guest: insert the guest and let it act; ``False`` gives the run without it.

    Raises:
        MissingExtraError: traci is not installed.
        UrbanSimError: SUMO cannot be started or stops with an error.
    """
    from scenariominer._optional import require

    traci = require("traci", extra="sim", purpose="running SUMO scenarios under TraCI")
    work = net_file.parent
    routes = work / "urban.rou.xml"
    _route_file(scenario, routes)
    label = f"urban-{os.getpid()}-{next(_counter)}"
    cmd = [
        sumo, "-n", str(net_file), "-r", str(routes), "--step-length", f"{STEP_S}",
        "--seed", str(scenario.sumo_seed), "--no-step-log", "--no-warnings", "--duration-log.disable",
        "--lanechange.duration", "2.0", "--collision.action", "warn", "--time-to-teleport", "-1",
        "--pedestrian.model", "striping", "--xml-validation", "never", "--error-log", str(work / "sumo.log"),
    ]  # fmt: skip
    try:
        with open(os.devnull, "w") as devnull, contextlib.redirect_stdout(devnull):
            traci.start(cmd, label=label, numRetries=20, stdout=devnull)
    except (OSError, traci.exceptions.TraCIException, traci.exceptions.FatalTraCIError) as exc:
        raise UrbanSimError(f"cannot start SUMO ({sumo}): {exc}") from None
    conn = traci.getConnection(label)
    try:
        return _drive(scenario, conn, with_guest)
    except (traci.exceptions.TraCIException, traci.exceptions.FatalTraCIError) as exc:
        log = work / "sumo.log"
        lines = log.read_text(encoding="utf-8", errors="replace").splitlines() if log.is_file() else []
        said = " | ".join([ln for ln in lines if ln.startswith("Error")][-2:])
        raise UrbanSimError(
            f"SUMO stopped in scenario {scenario.index} ({scenario.family.value}): {exc}"
            + (f" ({said})" if said else "")
        ) from None
    finally:
        with contextlib.suppress(Exception):  # the connection may already be gone
            conn.close()


def _drive(scenario: UrbanScenario, c: Any, with_guest: bool) -> RunRecord:
    rng = np.random.default_rng([scenario.sumo_seed, 7])
    ego_route = f"r0{scenario.ego_route[1][-1]}"
    c.vehicle.add(
        EGO_ID,
        ego_route,
        typeID="ego_t",
        departPos="10",
        departSpeed=f"{scenario.ego_speed_mps:.2f}",
        departLane=str(scenario.ego_lane),
    )
    c.vehicle.setLaneChangeMode(EGO_ID, 0)
    _background(scenario, c, np.random.default_rng([scenario.sumo_seed, 11]))
    guest = _Guest(scenario, c, rng)
    if with_guest:
        guest.setup()
    ego_in = scenario.ego_route[0]
    rows: dict[str, list[tuple[int, float, float, float]]] = {}
    meta: dict[str, tuple[str, tuple[float, float, float]]] = {}
    ego_rows: list[tuple[float, float, float, str, float, int, tuple[str, ...]]] = []
    guest_rows: list[tuple[float, float, int, str]] = []
    collisions: set[str] = set()
    t_list: list[float] = []
    left_at = None
    for k in range(int(MAX_RUN_S / STEP_S)):
        c.simulationStep()
        t = float(c.simulation.getTime())
        vehicles = c.vehicle.getIDList()
        if EGO_ID not in vehicles:
            break
        t_list.append(t)
        for vid in vehicles:
            x, y = c.vehicle.getPosition(vid)
            yaw = np.deg2rad(90.0 - c.vehicle.getAngle(vid))
            if vid not in meta:
                tid = c.vehicle.getTypeID(vid)
                cat = "EGO_VEHICLE" if vid == EGO_ID else _TYPES.get(tid, ("REGULAR_VEHICLE",))[0]
                size = (c.vehicle.getLength(vid), c.vehicle.getWidth(vid), c.vehicle.getHeight(vid))
                meta[vid] = (cat, size)
            half = 0.5 * meta[vid][1][0]
            rows.setdefault(vid, []).append((k, x - half * np.cos(yaw), y - half * np.sin(yaw), yaw))
        for pid in c.person.getIDList():
            x, y = c.person.getPosition(pid)
            rows.setdefault(pid, []).append((k, x, y, np.deg2rad(90.0 - c.person.getAngle(pid))))
            meta.setdefault(pid, ("PEDESTRIAN", _PERSON_SIZE_M))
        road = c.vehicle.getRoadID(EGO_ID)
        to_j = (
            c.lane.getLength(c.vehicle.getLaneID(EGO_ID)) - c.vehicle.getLanePosition(EGO_ID)
            if road == ego_in
            else float("nan")
        )
        ego_speed = c.vehicle.getSpeed(EGO_ID)
        leader = c.vehicle.getLeader(EGO_ID, 100.0)
        foes = tuple(sorted({f[0] for f in c.vehicle.getJunctionFoes(EGO_ID, 100.0)}))
        ego_rows.append(
            (
                ego_speed,
                c.vehicle.getAcceleration(EGO_ID),
                to_j,
                leader[0] if leader else "",
                leader[1] if leader else float("nan"),
                c.vehicle.getLaneIndex(EGO_ID),
                foes,
            )
        )
        if GUEST_ID in vehicles:
            guest_rows.append(
                (
                    c.vehicle.getSpeed(GUEST_ID),
                    c.vehicle.getAcceleration(GUEST_ID),
                    c.vehicle.getLaneIndex(GUEST_ID),
                    c.vehicle.getRoadID(GUEST_ID),
                )
            )
        elif GUEST_ID in c.person.getIDList():
            guest_rows.append((c.person.getSpeed(GUEST_ID), float("nan"), -1, c.person.getRoadID(GUEST_ID)))
        else:
            guest_rows.append((float("nan"), float("nan"), -1, ""))
        collisions |= {
            (col.collider if col.victim == EGO_ID else col.victim)
            for col in c.simulation.getCollisions()
            if EGO_ID in (col.collider, col.victim)
        }
        if with_guest:
            guest.step(t, to_j if np.isfinite(to_j) else -1.0, ego_speed)
        if road.startswith("out") and left_at is None:
            left_at = t
        if left_at is not None and t - left_at > 12.0:
            break
    if not t_list:
        raise UrbanSimError(f"the ego of scenario {scenario.index} was never inserted")
    n = len(t_list)
    objects = {}
    for oid, r in rows.items():
        arr = np.full((n, 3), np.nan)
        idx = np.asarray([q[0] for q in r])
        keep = idx < n
        arr[idx[keep]] = np.asarray([q[1:] for q in r])[keep]
        cat, size = meta[oid]
        objects[oid] = ObjectTrack(cat, size, arr[:, 0], arr[:, 1], arr[:, 2])
    e = list(zip(*ego_rows, strict=True))
    g = list(zip(*guest_rows, strict=True))
    return RunRecord(
        t_s=np.asarray(t_list),
        objects=objects,
        ego_speed_mps=np.asarray(e[0], dtype=np.float64),
        ego_accel_mps2=np.asarray(e[1], dtype=np.float64),
        ego_to_junction_m=np.asarray(e[2], dtype=np.float64),
        ego_leader=list(e[3]),
        ego_leader_gap_m=np.asarray(e[4], dtype=np.float64),
        ego_lane=list(e[5]),
        ego_foes=list(e[6]),
        guest_speed_mps=np.asarray(g[0], dtype=np.float64),
        guest_accel_mps2=np.asarray(g[1], dtype=np.float64),
        guest_lane=list(g[2]),
        guest_edge=list(g[3]),
        guest_action_s=guest.acted_s,
        collisions=tuple(sorted(collisions)),
    )
