"""The SUMO road network of an urban braking scenario and its Argoverse 2 vector map.

One four-arm junction at the origin of SUMO's coordinates. Arm ``k`` leaves the centre at angle
:attr:`UrbanNetSpec.arm_angles_deg` ``[k]`` (counter-clockwise from +x): the ego enters on arm 0
(drawn near 180°, so it drives towards +x), arm 2 lies opposite, arm 1 is on the ego's left, arm 3
on its right. The angles between neighbouring arms vary (junctions from about 50° to 130°), the
ego's approach can bend (a curved road), the arms through the junction of the ego carry two lanes
each way, the others one or two. Every road has sidewalks and every arm a zebra crossing where
pedestrians have priority over vehicles; either the ego's road or the crossing road is the
priority road. Connections get a long :data:`VISIBILITY_M`, so a vehicle on a minor link does not
slow down for a junction that it can see is free (it brakes only for a real foe).

:func:`build_network` writes ``urban.nod.xml``, ``urban.edg.xml``, ``urban.con.xml`` and runs
``netconvert`` (twice: the second pass sets the visibility on every vehicle connection);
:func:`network_map` turns the ``.net.xml`` into an :class:`~scenariominer.data.adapters.av2.map.Av2Map`
(lane segments from SUMO's lane shapes and widths, the lane graph from its connections, crossings
from its crossing edges, the drivable area as the union of the vehicle lanes).
"""

from __future__ import annotations

import os
import subprocess
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import shapely

from scenariominer.data.adapters.av2.map import (
    Av2Map,
    DrivableArea,
    LaneSegment,
    LaneType,
    PedestrianCrossing,
)
from scenariominer.data.log import FloatArray
from scenariominer.errors import DataError

__all__ = [
    "VISIBILITY_M",
    "UrbanNetSpec",
    "UrbanSimError",
    "build_network",
    "edge_ids",
    "network_map",
]

#: Distance (metres) from which a vehicle on a minor link sees the junction's foes.
VISIBILITY_M = 45.0
#: Lane width of the roads, metres.
LANE_WIDTH_M = 3.3
#: First id of lane segments and of crossings in the exported map.
_FIRST_LANE_ID = 50_000_001
_FIRST_CROSSING_ID = 60_000_001


class UrbanSimError(DataError):
    """An urban simulation cannot be set up or run (bad setting, SUMO missing or failing)."""


@dataclass(frozen=True)
class UrbanNetSpec:
    """Geometry of one junction network.

    Attributes:
        arm_angles_deg: ``(4,)`` direction of each arm from the centre, degrees CCW from +x.
        arm_lengths_m: ``(4,)`` length of each arm, metres.
        arm_lanes: ``(4,)`` vehicle lanes each way on each arm.
        ego_major: whether arms 0/2 (the ego's road) are the priority road; otherwise arms 1/3 are.
        bend_m: lateral offset (metres) of the ego's approach at its far end (0: straight road).
        speed_mps: speed limit of every road, m/s.
    """

    arm_angles_deg: tuple[float, float, float, float]
    arm_lengths_m: tuple[float, float, float, float]
    arm_lanes: tuple[int, int, int, int]
    ego_major: bool = True
    bend_m: float = 0.0
    speed_mps: float = 13.89


def edge_ids(arm: int) -> tuple[str, str]:
    """``(inbound, outbound)`` SUMO edge ids of arm ``arm``."""
    return f"in{arm}", f"out{arm}"


def _arm_shape(spec: UrbanNetSpec, arm: int) -> FloatArray:
    """``(P, 2)`` centre line of arm ``arm`` from its far end to the junction centre."""
    a = np.deg2rad(spec.arm_angles_deg[arm])
    length = spec.arm_lengths_m[arm]
    u = np.array([np.cos(a), np.sin(a)])
    n = np.array([-u[1], u[0]])
    s = np.linspace(length, 0.0, 9 if arm == 0 and spec.bend_m else 2)
    # A bend that fades out 60 m before the junction (quadratic in the distance beyond that).
    off = spec.bend_m * np.clip((s - 60.0) / max(length - 60.0, 1.0), 0.0, 1.0) ** 2 if arm == 0 else 0 * s
    return np.asarray(s[:, None] * u + off[:, None] * n, dtype=np.float64)


def _write_inputs(spec: UrbanNetSpec, work_dir: Path) -> tuple[Path, Path, Path]:
    nodes = ["<nodes>", '  <node id="C" x="0.00" y="0.00" type="priority"/>']
    edges = ["<edges>"]
    crossings = ["<connections>"]
    for arm in range(4):
        shape = _arm_shape(spec, arm)
        x, y = shape[0]
        nodes.append(f'  <node id="A{arm}" x="{x:.2f}" y="{y:.2f}"/>')
        major = (arm % 2 == 0) == spec.ego_major
        prio = 3 if major else 1
        e_in, e_out = edge_ids(arm)
        pts_in = " ".join(f"{px:.2f},{py:.2f}" for px, py in shape)
        pts_out = " ".join(f"{px:.2f},{py:.2f}" for px, py in shape[::-1])
        common = (
            f'numLanes="{spec.arm_lanes[arm]}" speed="{spec.speed_mps:.2f}" priority="{prio}" '
            f'width="{LANE_WIDTH_M}"'
        )
        edges.append(f'  <edge id="{e_in}" from="A{arm}" to="C" {common} shape="{pts_in}"/>')
        edges.append(f'  <edge id="{e_out}" from="C" to="A{arm}" {common} shape="{pts_out}"/>')
        crossings.append(f'  <crossing node="C" edges="{e_in} {e_out}" priority="true" width="4.0"/>')
    nodes.append("</nodes>")
    edges.append("</edges>")
    crossings.append("</connections>")
    paths = (work_dir / "urban.nod.xml", work_dir / "urban.edg.xml", work_dir / "urban.con.xml")
    for path, lines in zip(paths, (nodes, edges, crossings), strict=True):
        path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return paths


def _netconvert(netconvert: str, args: list[str], work_dir: Path) -> None:
    env = dict(os.environ)
    try:
        done = subprocess.run(
            [netconvert, *args], cwd=work_dir, capture_output=True, text=True, check=False, env=env
        )
    except OSError as exc:
        raise UrbanSimError(f"cannot start netconvert ({netconvert}): {exc}") from None
    if done.returncode != 0:
        errors = [
            ln for ln in done.stderr.splitlines() if ln.startswith("Error")
        ] or done.stderr.splitlines()[-3:]
        raise UrbanSimError(
            f"netconvert failed (exit {done.returncode}): {' | '.join(errors) or 'no message'}"
        )


def build_network(spec: UrbanNetSpec, work_dir: Path, netconvert: str) -> Path:
    """Write the plain-XML inputs into ``work_dir``, run netconvert and return ``urban.net.xml``.

    Raises:
        UrbanSimError: netconvert cannot be started or fails (its error lines are quoted).
    """
    work_dir.mkdir(parents=True, exist_ok=True)
    nod, edg, con = _write_inputs(spec, work_dir)
    raw = work_dir / "urban.raw.net.xml"
    _netconvert(
        netconvert,
        [
            "-n", nod.name, "-e", edg.name, "-x", con.name, "-o", raw.name,
            "--sidewalks.guess", "--sidewalks.guess.min-speed", "1", "--sidewalks.guess.max-speed", "40",
            "--no-turnarounds",
            "--junctions.corner-detail", "8", "--seed", "1",
        ],
        work_dir,
    )  # fmt: skip
    sumolib = _sumolib()
    net = sumolib.net.readNet(str(raw))
    lines = ["<connections>"]
    for edge in net.getEdges():
        for conns in edge.getOutgoing().values():
            for c in conns:
                if c.getFromLane().getEdge().getFunction() or c.getToLane().getEdge().getFunction():
                    continue
                if not c.getFromLane().allows("passenger"):
                    continue
                lines.append(
                    f'  <connection from="{c.getFrom().getID()}" to="{c.getTo().getID()}" '
                    f'fromLane="{c.getFromLane().getIndex()}" toLane="{c.getToLane().getIndex()}" '
                    f'visibility="{VISIBILITY_M}"/>'
                )
    lines.append("</connections>")
    vis = work_dir / "urban.vis.con.xml"
    vis.write_text("\n".join(lines) + "\n", encoding="utf-8")
    out = work_dir / "urban.net.xml"
    _netconvert(netconvert, ["-s", raw.name, "-x", vis.name, "-o", out.name], work_dir)
    return out


def _sumolib() -> Any:
    from scenariominer._optional import require

    return require("sumolib", extra="sim", purpose="reading SUMO networks")


# ---------------------------------------------------------------------- vector map


def _offset(line: FloatArray, d: float) -> FloatArray:
    """``(P, 2)`` polyline shifted ``d`` metres to its left (negative: right), per-vertex normals."""
    tang = np.gradient(line, axis=0)
    tang /= np.maximum(np.linalg.norm(tang, axis=1, keepdims=True), 1e-9)
    normal = np.column_stack([-tang[:, 1], tang[:, 0]])
    return np.asarray(line + d * normal, dtype=np.float64)


def network_map(net_file: Path, tf: Callable[[FloatArray], FloatArray], z_m: float) -> Av2Map:
    """The Argoverse 2 vector map of a SUMO network, every point passed through ``tf``.

    Vehicle lanes (normal and junction-internal) become lane segments: SUMO's lane shape is the
    centre line, the boundaries lie half the lane width to either side, successors and
    predecessors follow SUMO's connections (through the junction-internal lanes), neighbours are
    the adjacent lanes of the same edge. Crossing edges become pedestrian crossings (the two long
    sides of the crossing's strip). The drivable area is the union of the lane polygons.

    Args:
        net_file: a ``.net.xml`` with junction-internal lanes.
        tf: ``(K, 2) -> (K, 2)`` map from SUMO coordinates to the city frame.
        z_m: height of every map point, metres.
    """
    sumolib = _sumolib()
    net = sumolib.net.readNet(str(net_file), withInternal=True, withPedestrianConnections=True)
    lanes = [
        lane
        for edge in net.getEdges(withInternal=True)
        if edge.getFunction() in ("", "internal")
        for lane in edge.getLanes()
        if lane.allows("passenger")
    ]
    ids = {lane.getID(): _FIRST_LANE_ID + i for i, lane in enumerate(lanes)}
    succ: dict[str, list[str]] = {lane.getID(): [] for lane in lanes}
    for lane in lanes:
        for conn in lane.getOutgoing():
            via = conn.getViaLaneID() if hasattr(conn, "getViaLaneID") else ""
            target = via or conn.getToLane().getID()
            if target in ids:
                succ[lane.getID()].append(target)
        if lane.getEdge().getFunction() == "internal":
            for conn in lane.getOutgoing():
                target = conn.getToLane().getID()
                if target in ids and target not in succ[lane.getID()]:
                    succ[lane.getID()].append(target)
    pred: dict[str, list[str]] = {k: [] for k in succ}
    for a, bs in succ.items():
        for b in bs:
            pred[b].append(a)

    def xyz(xy: FloatArray) -> FloatArray:
        return np.column_stack([tf(xy), np.full(len(xy), z_m)])

    segments = []
    for lane in lanes:
        line = np.asarray(lane.getShape(), dtype=np.float64)[:, :2]
        if len(line) < 2 or np.linalg.norm(line[-1] - line[0]) < 1e-3:
            continue
        half = 0.5 * float(lane.getWidth())
        edge = lane.getEdge()
        internal = edge.getFunction() == "internal"
        siblings = [ln for ln in edge.getLanes() if ln.allows("passenger")]
        idx = siblings.index(lane)
        left = siblings[idx + 1].getID() if idx + 1 < len(siblings) else None
        right = siblings[idx - 1].getID() if idx > 0 else None
        segments.append(
            LaneSegment(
                id=ids[lane.getID()],
                lane_type=LaneType.VEHICLE,
                is_intersection=internal,
                left_boundary_m=xyz(_offset(line, half)),
                right_boundary_m=xyz(_offset(line, -half)),
                left_mark_type="NONE" if internal else ("DASHED_WHITE" if left else "SOLID_YELLOW"),
                right_mark_type="NONE" if internal else ("DASHED_WHITE" if right else "SOLID_WHITE"),
                successors=tuple(ids[s] for s in succ[lane.getID()]),
                predecessors=tuple(ids[p] for p in pred[lane.getID()]),
                left_neighbor_id=None if internal or left is None else ids[left],
                right_neighbor_id=None if internal or right is None else ids[right],
            )
        )
    crossings = []
    for i, edge in enumerate(e for e in net.getEdges(withInternal=True) if e.getFunction() == "crossing"):
        lane = edge.getLanes()[0]
        line = np.asarray(lane.getShape(), dtype=np.float64)[:, :2][[0, -1]]
        half = 0.5 * float(lane.getWidth())
        crossings.append(
            PedestrianCrossing(
                id=_FIRST_CROSSING_ID + i, edge1_m=xyz(_offset(line, half)), edge2_m=xyz(_offset(line, -half))
            )
        )
    union = shapely.union_all([s.polygon for s in segments]).buffer(0.05)
    polys = list(union.geoms) if hasattr(union, "geoms") else [union]
    areas = tuple(
        DrivableArea(
            id=20_000_001 + i,
            boundary_m=np.column_stack(
                [
                    np.asarray(shapely.get_coordinates(p.exterior))[:-1],
                    np.full(len(p.exterior.coords) - 1, z_m),
                ]
            ),
        )
        for i, p in enumerate(polys)
    )
    # The drivable area was built in the city frame already (from the transformed lanes).
    return Av2Map(lane_segments=tuple(segments), pedestrian_crossings=tuple(crossings), drivable_areas=areas)


def parked_spots(net_file: Path, n: int, rng: np.random.Generator) -> list[tuple[float, float, float]]:
    """``n`` places ``(x, y, yaw)`` (SUMO coordinates) for parked cars beside the roads.

    Each lies along a random arm's outer vehicle lane, 20-150 m from the junction, beyond that
    lane's sidewalk (off the carriageway), heading with the traffic of the lane.
    """
    sumolib = _sumolib()
    net = sumolib.net.readNet(str(net_file))
    edges = [e for e in net.getEdges() if e.getFunction() == ""]
    spots = []
    for _ in range(n):
        edge = edges[int(rng.integers(0, len(edges)))]
        lanes = [ln for ln in edge.getLanes() if ln.allows("passenger")]
        walk = [ln for ln in edge.getLanes() if not ln.allows("passenger")]
        lane = lanes[0]
        line = np.asarray(lane.getShape(), dtype=np.float64)[:, :2]
        seg = np.linalg.norm(np.diff(line, axis=0), axis=1)
        cum = np.concatenate([[0.0], np.cumsum(seg)])
        from_junction = float(rng.uniform(20.0, min(150.0, cum[-1] - 5.0)))
        s = cum[-1] - from_junction if edge.getID().startswith("in") else from_junction
        i = int(np.clip(np.searchsorted(cum, s) - 1, 0, len(seg) - 1))
        d = (line[i + 1] - line[i]) / max(seg[i], 1e-9)
        p = line[i] + (s - cum[i]) * d
        off = 0.5 * float(lane.getWidth()) + sum(float(w.getWidth()) for w in walk) + 1.3
        x, y = p + off * np.array([d[1], -d[0]])  # to the right of the direction of travel
        spots.append((float(x), float(y), float(np.arctan2(d[1], d[0]))))
    return spots
