"""Demand (vehicle types, flows) of a highway scenario and one headless SUMO run.

Vehicle types (SUMO's Krauss car-following and SL2015 sub-lane lane-change models, lateral
resolution :data:`LATERAL_RESOLUTION_M`):

* ``car`` — ordinary drivers: desired speed spread around the limit, keep right, change lanes
  for speed gain;
* ``assertive`` — a share of the cars: faster, short time gap, eager and assertive lane changes
  with quicker lateral moves (cut-ins, multi-lane changes);
* ``truck`` — 15 m semi-trailers limited to 90 km/h that rarely overtake.

Demand comes as one flow per period (``period_s``) on the main road and, with an on-ramp, one on
the ramp. SUMO writes floating-car data (positions, lanes, leaders) and its lane-change log as CSV
(``--output.column-header plain``); :mod:`scenariominer.sim.highway_convert` turns them into a
highD recording.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from scenariominer.sim.highway_net import HighwayNetwork
from scenariominer.sim.highway_scenario import HighwayScenario, HighwaySimError

__all__ = [
    "FCD_FILE",
    "LANE_CHANGE_FILE",
    "LATERAL_RESOLUTION_M",
    "LEADER_RANGE_M",
    "VEHICLE_TYPES",
    "SumoBinaries",
    "VehicleType",
    "find_sumo",
    "run_sumo",
    "write_demand",
]

#: SUMO's sub-lane resolution, metres (switches on the SL2015 lane-change model).
LATERAL_RESOLUTION_M = 0.8
#: Leaders are written to the floating-car data within this distance, metres.
LEADER_RANGE_M = 150.0
#: Floating-car data file in the work folder.
FCD_FILE = "fcd.csv"
#: SUMO's lane-change log in the work folder.
LANE_CHANGE_FILE = "lanechanges.csv"

_STEP_RE = re.compile(rb"Step #(\d+(?:\.\d+)?)")


@dataclass(frozen=True)
class VehicleType:
    """Size and highD class of a SUMO vehicle type.

    Attributes:
        length_m: vehicle length, metres.
        width_m: vehicle width, metres.
        highd_class: ``Car`` or ``Truck``.
    """

    length_m: float
    width_m: float
    highd_class: str


#: The vehicle types of :func:`write_demand`, by SUMO type id.
VEHICLE_TYPES: dict[str, VehicleType] = {
    "car": VehicleType(4.6, 1.85, "Car"),
    "assertive": VehicleType(4.8, 1.9, "Car"),
    "truck": VehicleType(15.0, 2.55, "Truck"),
}


@dataclass(frozen=True)
class SumoBinaries:
    """Paths of the SUMO programs used.

    Attributes:
        sumo: the headless simulator.
        netconvert: the network builder.
        sumo_home: SUMO's installation folder (set as ``SUMO_HOME`` for the runs), ``""`` unknown.
    """

    sumo: str
    netconvert: str
    sumo_home: str


def find_sumo(error: type[Exception] = HighwaySimError) -> SumoBinaries:
    """Locate ``sumo`` and ``netconvert`` with :func:`sumolib.checkBinary` (``SUMO_HOME``, the package).

    Raises:
        MissingExtraError: sumolib is not installed.
        HighwaySimError: (or ``error``) a binary cannot be found.
    """
    from scenariominer._optional import require

    sumolib = require("sumolib", extra="sim", purpose="simulating traffic with SUMO")
    found: dict[str, str] = {}
    for name in ("sumo", "netconvert"):
        path = str(sumolib.checkBinary(name))
        resolved = path if os.path.isfile(path) else shutil.which(path)
        if not resolved:
            raise error(
                f"SUMO's {name!r} program was not found: pip install 'scenariominer[sim]' (eclipse-sumo) "
                f"or set SUMO_HOME to a SUMO installation"
            )
        found[name] = resolved
    home = str(Path(found["sumo"]).resolve().parent.parent)
    return SumoBinaries(sumo=found["sumo"], netconvert=found["netconvert"], sumo_home=home)


def _speed_factor(limited: bool, kind: str) -> str:
    """SUMO ``speedFactor`` distribution (desired speed / edge speed), truncated normal."""
    if kind == "truck":
        return "normc(1.0,0.05,0.9,1.1)"
    if kind == "assertive":
        return "normc(1.12,0.08,0.95,1.35)" if limited else "normc(1.3,0.12,1.05,1.6)"
    return "normc(1.0,0.1,0.75,1.25)" if limited else "normc(1.0,0.15,0.7,1.4)"


def write_demand(scenario: HighwayScenario, net: HighwayNetwork, path: Path) -> None:
    """Write the route file: vehicle types, routes and one flow per demand period."""
    limited = scenario.speed_limit_kmh is not None
    trucks = scenario.truck_share
    assertive = (1.0 - trucks) * scenario.aggressive_share
    cars = 1.0 - trucks - assertive
    car, fast, truck = VEHICLE_TYPES["car"], VEHICLE_TYPES["assertive"], VEHICLE_TYPES["truck"]
    lines = [
        "<routes>",
        '  <vTypeDistribution id="traffic">',
        f'    <vType id="car" vClass="passenger" length="{car.length_m}" width="{car.width_m}" '
        f'accel="2.6" decel="4.5" sigma="0.5" tau="1.0" speedFactor="{_speed_factor(limited, "car")}" '
        f'lcSpeedGain="1.0" lcKeepRight="2.5" maxSpeedLat="1.0" probability="{cars:.4f}"/>',
        f'    <vType id="assertive" vClass="passenger" length="{fast.length_m}" width="{fast.width_m}" '
        f'accel="3.5" decel="5.0" sigma="0.3" tau="0.6" minGap="1.5" '
        f'speedFactor="{_speed_factor(limited, "assertive")}" lcSpeedGain="3.0" lcKeepRight="0.3" '
        f'lcAssertive="2.5" lcCooperative="0.4" lcImpatience="0.6" maxSpeedLat="2.2" '
        f'probability="{assertive:.4f}"/>',
        f'    <vType id="truck" vClass="truck" length="{truck.length_m}" width="{truck.width_m}" '
        f'maxSpeed="25.0" accel="1.1" decel="4.0" sigma="0.3" tau="1.2" '
        f'speedFactor="{_speed_factor(limited, "truck")}" lcSpeedGain="0.3" lcKeepRight="3.0" '
        f'maxSpeedLat="0.7" probability="{trucks:.4f}"/>',
        "  </vTypeDistribution>",
        f'  <route id="main" edges="{" ".join(net.main_route)}"/>',
    ]
    if net.ramp_edge:
        lines.append(f'  <route id="onramp" edges="{" ".join(net.ramp_route)}"/>')
    flows: list[tuple[float, str]] = []
    for k, vph in enumerate(scenario.demand_vph):
        begin = k * scenario.period_s
        end = min((k + 1) * scenario.period_s, scenario.end_s)
        if begin >= end or vph <= 0:
            continue
        flows.append(
            (
                begin,
                f'  <flow id="main{k}" type="traffic" route="main" begin="{begin:.1f}" end="{end:.1f}" '
                f'vehsPerHour="{vph:.1f}" departLane="random" departSpeed="max" departPos="base"/>',
            )
        )
    if net.ramp_edge and scenario.ramp_demand_vph > 0:
        flows.append(
            (
                0.0,
                f'  <flow id="ramp" type="traffic" route="onramp" begin="0.0" end="{scenario.end_s:.1f}" '
                f'vehsPerHour="{scenario.ramp_demand_vph:.1f}" departLane="0" departSpeed="max" '
                f'departPos="base"/>',
            )
        )
    lines += [text for _, text in sorted(flows, key=lambda f: f[0])]
    lines.append("</routes>")
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")


def _config(scenario: HighwayScenario, net: HighwayNetwork, routes: Path) -> str:
    """A ``.sumocfg`` that reproduces the run (``sumo -c highway.sumocfg``; sumo-gui works too)."""
    step = 1.0 / scenario.frame_rate_hz
    options = {
        "input": {"net-file": net.net_file.name, "route-files": routes.name},
        "time": {"begin": "0", "end": f"{scenario.end_s:.1f}", "step-length": f"{step:.4f}"},
        "processing": {"lateral-resolution": f"{LATERAL_RESOLUTION_M}"},
        "random_number": {"seed": str(scenario.sumo_seed)},
        "output": {
            "fcd-output": FCD_FILE,
            "fcd-output.attributes": "x,y,angle,type,speed,lane,posLat,acceleration,leaderID,leaderGap",
            "fcd-output.max-leader-distance": f"{LEADER_RANGE_M}",
            "device.fcd.begin": f"{scenario.warmup_s:.1f}",
            "lanechange-output": LANE_CHANGE_FILE,
            "output.column-header": "plain",
            "precision": "3",
        },
        "report": {
            "no-warnings": "true",
            "duration-log.disable": "true",
            "step-log.period": str(max(1, round(10.0 * scenario.frame_rate_hz))),
            "xml-validation": "never",
        },
    }
    body = []
    for section, values in options.items():
        body.append(f"  <{section}>")
        body += [f'    <{key} value="{value}"/>' for key, value in values.items()]
        body.append(f"  </{section}>")
    return "<configuration>\n" + "\n".join(body) + "\n</configuration>\n"


def run_sumo(
    scenario: HighwayScenario,
    net: HighwayNetwork,
    binaries: SumoBinaries,
    work_dir: Path,
    on_step: Callable[[float], None] | None = None,
) -> None:
    """Write routes and config into ``work_dir`` and run SUMO headless to the scenario's end.

    Args:
        scenario: what to simulate.
        net: the network built in ``work_dir``.
        binaries: SUMO programs.
        work_dir: folder of the run (outputs :data:`FCD_FILE`, :data:`LANE_CHANGE_FILE`,
            ``sumo.log``).
        on_step: called with the simulated time (s) about every 10 simulated seconds.

    Raises:
        HighwaySimError: SUMO cannot be started or exits with an error (the message quotes
            SUMO's last error lines and names the log file).
    """
    routes = work_dir / "highway.rou.xml"
    write_demand(scenario, net, routes)
    cfg = work_dir / "highway.sumocfg"
    cfg.write_text(_config(scenario, net, routes), encoding="utf-8")
    log = work_dir / "sumo.log"
    env = dict(os.environ)
    if binaries.sumo_home:
        env.setdefault("SUMO_HOME", binaries.sumo_home)
    try:
        with log.open("wb") as err:
            proc = subprocess.Popen(
                [binaries.sumo, "-c", cfg.name], cwd=work_dir, stdout=subprocess.PIPE, stderr=err, env=env
            )
            assert proc.stdout is not None
            tail = b""
            try:
                while chunk := proc.stdout.read(256):
                    tail = (tail + chunk)[-256:]
                    steps = _STEP_RE.findall(tail)
                    if steps and on_step is not None:
                        on_step(float(steps[-1]))
                code = proc.wait()
            except BaseException:  # interrupted (Ctrl-C, a failing callback): leave no SUMO behind
                proc.kill()
                proc.wait()
                raise
    except OSError as exc:
        raise HighwaySimError(f"cannot start SUMO ({binaries.sumo}): {exc}") from None
    if code != 0:
        lines = log.read_text(encoding="utf-8", errors="replace").strip().splitlines()
        errors = [line for line in lines if line.startswith("Error")] or lines[-3:]
        raise HighwaySimError(
            f"SUMO failed on recording {scenario.recording_id:02d} (exit {code}): "
            f"{' | '.join(errors[-3:]) or 'no message'} (log: {log})"
        )
