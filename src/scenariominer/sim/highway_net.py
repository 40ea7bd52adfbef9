"""The SUMO road network of a highway scenario: a straight carriageway, an on-ramp, a lane drop.

Geometry (SUMO coordinates, metres): the carriageway runs along +x; its left border (next to the
median) is the line ``y = 0`` and its lanes lie below it, SUMO lane index 0 being the rightmost.
Every edge is built with ``spreadType="right"`` from nodes on ``y = 0``, so a lane keeps its
lateral place when the lane count changes: an acceleration lane is added on the right and ends
there, a dropped lane is the rightmost one. Counting lanes from the left border ("left index"
``j = n - 1 - i`` for lane ``i`` of an ``n``-lane edge) therefore names the same strip of road
along the whole carriageway, and that is what the recording's ``laneId`` encodes.

Layout along x: an upstream stretch where vehicles enter and settle (:data:`UPSTREAM_M`), the
recorded section ``[section_start_m, section_end_m]`` holding the on-ramp's merge (acceleration
lane of :data:`ACCEL_LANE_M`) and the lane drop, and a downstream stretch (:data:`DOWNSTREAM_M`)
so that vehicles leave the section in ordinary traffic.
"""

from __future__ import annotations

import subprocess
from dataclasses import dataclass
from pathlib import Path

from scenariominer.sim.highway_scenario import HighwayScenario, HighwaySimError

__all__ = [
    "ACCEL_LANE_M",
    "DOWNSTREAM_M",
    "UPSTREAM_M",
    "HighwayNetwork",
    "build_network",
    "layout",
]

#: Road before the recorded section, metres (vehicles are inserted at its start).
UPSTREAM_M = 600.0
#: Road after the recorded section, metres.
DOWNSTREAM_M = 400.0
#: Length of the on-ramp's acceleration lane, metres.
ACCEL_LANE_M = 250.0
#: Length of the on-ramp itself, metres (vehicles are inserted at its start).
RAMP_M = 350.0
#: Ramp speed limit, m/s (80 km/h).
RAMP_SPEED_MPS = 80.0 / 3.6
#: Advisory speed on unlimited sections, m/s (130 km/h, the German "Richtgeschwindigkeit").
ADVISORY_SPEED_MPS = 130.0 / 3.6


@dataclass(frozen=True)
class HighwayNetwork:
    """The built network and what the conversion needs to know about it.

    Attributes:
        net_file: SUMO ``.net.xml``.
        edge_ids: main-road edges in driving order.
        edge_lanes: lanes of each main-road edge.
        edge_start_m: x where each main-road edge starts (SUMO coordinates).
        ramp_edge: id of the on-ramp edge, ``""`` without one.
        merge_edge_index: index into ``edge_ids`` of the edge with the acceleration lane (-1 without).
        section_start_m, section_end_m: recorded x range (SUMO coordinates).
        lane_width_m: lane width.
        max_lanes: most lanes any main-road edge has inside the section (the recording's lanes).
        speed_mps: main-road edge speed (the limit, or the advisory speed when unlimited).
    """

    net_file: Path
    edge_ids: tuple[str, ...]
    edge_lanes: tuple[int, ...]
    edge_start_m: tuple[float, ...]
    ramp_edge: str
    merge_edge_index: int
    section_start_m: float
    section_end_m: float
    lane_width_m: float
    max_lanes: int
    speed_mps: float

    @property
    def main_route(self) -> tuple[str, ...]:
        """Edges of a trip along the whole main road."""
        return self.edge_ids

    @property
    def ramp_route(self) -> tuple[str, ...]:
        """Edges of a trip from the on-ramp to the end (empty without an on-ramp)."""
        if not self.ramp_edge:
            return ()
        return (self.ramp_edge, *self.edge_ids[self.merge_edge_index :])


@dataclass(frozen=True)
class _Layout:
    breaks_m: tuple[float, ...]  # node x positions, first 0, last the road's end
    lanes: tuple[int, ...]  # lanes of the edge after each break (one fewer than breaks)
    merge_index: int
    section: tuple[float, float]


def layout(scenario: HighwayScenario) -> _Layout:
    """Node positions and lane counts along the main road (pure, no files)."""
    x0 = UPSTREAM_M
    x1 = x0 + scenario.section_m
    n = scenario.lanes
    events: list[tuple[float, int]] = []  # (x, lane-count change)
    merge_x = x0 + max(100.0, 0.15 * scenario.section_m)
    if scenario.on_ramp:
        events += [(merge_x, +1), (merge_x + ACCEL_LANE_M, -1)]
    if scenario.lane_drop:
        drop_x = max(
            x0 + 0.7 * scenario.section_m, merge_x + ACCEL_LANE_M + 100.0 if scenario.on_ramp else 0.0
        )
        events.append((min(drop_x, x1 - 50.0), -1))
    events.sort()
    breaks = [0.0]
    lanes = [n]
    merge_index = -1
    for x, change in events:
        breaks.append(x)
        lanes.append(lanes[-1] + change)
        if change > 0:
            merge_index = len(lanes) - 1
    breaks.append(x1 + DOWNSTREAM_M)
    return _Layout(tuple(breaks), tuple(lanes), merge_index, (x0, x1))


def _xml_files(scenario: HighwayScenario, plan: _Layout, speed_mps: float) -> dict[str, str]:
    """Node, edge and connection files (left-aligned lane connections)."""
    w = scenario.lane_width_m
    nodes = [f'  <node id="n{k}" x="{x:.2f}" y="0.00"/>' for k, x in enumerate(plan.breaks_m)]
    edges = [
        f'  <edge id="hw{k}" from="n{k}" to="n{k + 1}" numLanes="{n}" speed="{speed_mps:.3f}" '
        f'width="{w:.2f}" spreadType="right"/>'
        for k, n in enumerate(plan.lanes)
    ]
    connections: list[str] = []
    for k in range(len(plan.lanes) - 1):
        n_from, n_to = plan.lanes[k], plan.lanes[k + 1]
        for i in range(n_from):
            j = i + n_to - n_from  # same left index on both edges
            if 0 <= j < n_to:
                connections.append(f'  <connection from="hw{k}" to="hw{k + 1}" fromLane="{i}" toLane="{j}"/>')
    if plan.merge_index >= 0:
        k = plan.merge_index
        merge_x = plan.breaks_m[k]
        n_acc = plan.lanes[k]
        y_lane = -(n_acc - 0.5) * w  # centre of the acceleration lane
        start = (merge_x - RAMP_M, y_lane - 40.0)
        nodes.append(f'  <node id="ramp0" x="{start[0]:.2f}" y="{start[1]:.2f}"/>')
        shape = f"{start[0]:.2f},{start[1]:.2f} {merge_x - 120.0:.2f},{y_lane:.2f} {merge_x:.2f},{y_lane:.2f}"
        edges.append(
            f'  <edge id="ramp" from="ramp0" to="n{k}" numLanes="1" speed="{RAMP_SPEED_MPS:.3f}" '
            f'width="{w:.2f}" spreadType="center" shape="{shape}"/>'
        )
        connections.append(f'  <connection from="ramp" to="hw{k}" fromLane="0" toLane="0"/>')
    return {
        "highway.nod.xml": "<nodes>\n" + "\n".join(nodes) + "\n</nodes>\n",
        "highway.edg.xml": "<edges>\n" + "\n".join(edges) + "\n</edges>\n",
        "highway.con.xml": "<connections>\n" + "\n".join(connections) + "\n</connections>\n",
    }


def build_network(scenario: HighwayScenario, work_dir: Path, netconvert: str) -> HighwayNetwork:
    """Write the plain XML files into ``work_dir`` and build ``highway.net.xml`` with netconvert.

    Raises:
        HighwaySimError: netconvert cannot be started or fails (its message is quoted).
    """
    plan = layout(scenario)
    limit = scenario.speed_limit_mps
    speed = ADVISORY_SPEED_MPS if limit is None else limit
    work_dir.mkdir(parents=True, exist_ok=True)
    for name, text in _xml_files(scenario, plan, speed).items():
        (work_dir / name).write_text(text, encoding="utf-8")
    net_file = work_dir / "highway.net.xml"
    cmd = [
        netconvert,
        "--node-files", "highway.nod.xml",
        "--edge-files", "highway.edg.xml",
        "--connection-files", "highway.con.xml",
        "--output-file", net_file.name,
        "--no-turnarounds", "true",
        "--offset.disable-normalization", "true",
        "--no-warnings", "true",
    ]  # fmt: skip
    try:
        done = subprocess.run(cmd, cwd=work_dir, capture_output=True, text=True, check=False)
    except OSError as exc:
        raise HighwaySimError(f"cannot start SUMO's netconvert ({netconvert}): {exc}") from None
    if done.returncode != 0 or not net_file.is_file():
        tail = (done.stderr or done.stdout).strip().splitlines()[-3:]
        raise HighwaySimError(f"netconvert failed (exit {done.returncode}): {' | '.join(tail)}")
    section = [n for n, x in zip(plan.lanes, plan.breaks_m, strict=False) if x < plan.section[1]]
    return HighwayNetwork(
        net_file=net_file,
        edge_ids=tuple(f"hw{k}" for k in range(len(plan.lanes))),
        edge_lanes=plan.lanes,
        edge_start_m=plan.breaks_m[:-1],
        ramp_edge="ramp" if plan.merge_index >= 0 else "",
        merge_edge_index=plan.merge_index,
        section_start_m=plan.section[0],
        section_end_m=plan.section[1],
        lane_width_m=scenario.lane_width_m,
        max_lanes=max(section),
        speed_mps=speed,
    )
