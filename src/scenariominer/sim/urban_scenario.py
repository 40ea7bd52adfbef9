"""What one urban braking scenario is: its family, network, ego driver, guest timing and noise.

A *family* is a way the ego can be forced to brake, one per scenario category of the braking
paper that a junction or a multi-lane road produces (``cut_in``, ``lead_brake``,
``approach_stop``, ``ped_crossing``, ``obj_crossing``, ``left_oppo``, ``right_ped``). Everything
is drawn from ``numpy.random.default_rng([seed, index, attempt])``, so a scenario depends only on
the set's seed, its index and the attempt (a scenario whose run gives no clean label is drawn
again with the next attempt).
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import StrEnum

import numpy as np

from scenariominer.sim.urban_net import UrbanNetSpec, UrbanSimError
from scenariominer.synth.vocab import ScenarioCategory

__all__ = [
    "FAMILIES",
    "NOISE_LEVELS",
    "DriverStyle",
    "NoiseLevel",
    "UrbanScenario",
    "draw_scenario",
    "noise_for",
]

#: The scenario categories the urban simulation makes, in the order a set cycles through them.
FAMILIES: tuple[ScenarioCategory, ...] = (
    ScenarioCategory.PED_CROSSING,
    ScenarioCategory.LEFT_OPPO,
    ScenarioCategory.CUT_IN,
    ScenarioCategory.LEAD_BRAKE,
    ScenarioCategory.OBJ_CROSSING,
    ScenarioCategory.RIGHT_PED,
    ScenarioCategory.APPROACH_STOP,
)


class NoiseLevel(StrEnum):
    """Tracker-like noise added to the exported annotations (see :mod:`.urban_export`)."""

    NONE = "none"
    LOW = "low"
    MEDIUM = "medium"
    HIGH = "high"


#: Names accepted by ``--noise`` (``mixed`` cycles low, medium, high over the set).
NOISE_LEVELS: tuple[str, ...] = (*(n.value for n in NoiseLevel), "mixed")


def noise_for(setting: str, index: int) -> NoiseLevel:
    """Noise level of log ``index`` under ``setting`` (a level, or ``mixed``).

    Raises:
        UrbanSimError: ``setting`` is not one of :data:`NOISE_LEVELS`.
    """
    if setting == "mixed":
        return (NoiseLevel.LOW, NoiseLevel.MEDIUM, NoiseLevel.HIGH)[index % 3]
    try:
        return NoiseLevel(setting)
    except ValueError:
        raise UrbanSimError(f"unknown noise level {setting!r}; choose one of {list(NOISE_LEVELS)}") from None


class DriverStyle(StrEnum):
    """How the ego drives: ``smooth`` (IDM, gentle) or ``harsh`` (Krauss, late and firm braking)."""

    SMOOTH = "smooth"
    HARSH = "harsh"


@dataclass(frozen=True)
class UrbanScenario:
    """One scenario to simulate.

    Attributes:
        index: position in the set.
        attempt: how many draws before this one gave no clean label.
        family: the intended scenario category.
        net: the junction network.
        style: the ego's driving style.
        ego_accel_mps2, ego_decel_mps2: the ego's comfortable acceleration and deceleration.
        ego_speed_mps: the ego's speed at insertion.
        ego_lane: SUMO lane index of the ego's approach lane (1 = rightmost vehicle lane).
        trigger_m: distance (m) of the ego to the junction, or (leader families) time (s) into the
            run, at which the guest acts.
        guest_param: family-specific draw (gap, speed or lead time of the guest).
        guest_speed_mps: speed of a guest vehicle or pedestrian.
        n_background: other road users (vehicles on the other arms, pedestrians on the sidewalks).
        n_parked: vehicles parked beside the roads (static, added at export; they take no part in
            the simulation and stand off the carriageway, so they cannot make the ego brake).
        noise: tracker-like noise of the export.
        sumo_seed: SUMO's ``--seed``.
    """

    index: int
    attempt: int
    family: ScenarioCategory
    net: UrbanNetSpec
    style: DriverStyle
    ego_accel_mps2: float
    ego_decel_mps2: float
    ego_speed_mps: float
    ego_lane: int
    trigger_m: float
    guest_param: float
    guest_speed_mps: float
    n_background: int
    n_parked: int
    noise: NoiseLevel
    sumo_seed: int

    @property
    def ego_route(self) -> tuple[str, str]:
        """Inbound and outbound edges of the ego (straight, left onto arm 1, right onto arm 3)."""
        if self.family is ScenarioCategory.LEFT_OPPO:
            return "in0", "out1"
        if self.family is ScenarioCategory.RIGHT_PED:
            return "in0", "out3"
        return "in0", "out2"


def _net(rng: np.random.Generator, family: ScenarioCategory) -> UrbanNetSpec:
    a0 = 180.0 + rng.uniform(-8.0, 8.0)
    a2 = rng.uniform(-10.0, 10.0)
    a1 = rng.uniform(52.0, 128.0)  # the junction's angle between the ego's exit and the left arm
    a3 = 360.0 - rng.uniform(52.0, 128.0)
    bend = float(rng.choice([0.0, rng.uniform(-40.0, 40.0)], p=[0.4, 0.6]))
    return UrbanNetSpec(
        arm_angles_deg=(float(a0), float(a1), float(a2), float(a3)),
        arm_lengths_m=(float(rng.uniform(280.0, 340.0)), 160.0, 200.0, 160.0),
        arm_lanes=(2, int(rng.integers(1, 3)), 2, int(rng.integers(1, 3))),
        ego_major=family is not ScenarioCategory.OBJ_CROSSING,
        bend_m=bend,
        speed_mps=float(rng.choice([11.11, 13.89, 13.89, 16.67])),
    )


def draw_scenario(
    family: ScenarioCategory, index: int, attempt: int, seed: int, noise: NoiseLevel
) -> UrbanScenario:
    """Draw scenario ``index`` (try ``attempt``) of family ``family`` from the set's ``seed``."""
    rng = np.random.default_rng([seed, index, attempt])
    net = _net(rng, family)
    style = DriverStyle(str(rng.choice([DriverStyle.SMOOTH.value, DriverStyle.HARSH.value])))
    harsh = style is DriverStyle.HARSH
    ego_lane = 2 if family is ScenarioCategory.LEFT_OPPO else 1
    if family in (ScenarioCategory.CUT_IN, ScenarioCategory.LEAD_BRAKE, ScenarioCategory.PED_CROSSING):
        ego_lane = int(rng.integers(1, 3))
    params = {
        # trigger (m to the junction, or s into the run), guest parameter, guest speed
        ScenarioCategory.PED_CROSSING: (
            rng.uniform(35.0, 70.0),
            float(rng.integers(0, 2)),
            rng.uniform(1.0, 1.7),
        ),
        ScenarioCategory.RIGHT_PED: (rng.uniform(30.0, 60.0), 0.0, rng.uniform(1.0, 1.7)),
        ScenarioCategory.LEFT_OPPO: (
            rng.uniform(45.0, 85.0),
            rng.uniform(-1.0, 1.5),
            rng.uniform(9.0, 14.0),
        ),
        ScenarioCategory.OBJ_CROSSING: (
            rng.uniform(45.0, 85.0),
            rng.uniform(-1.0, 1.5),
            rng.uniform(9.0, 14.0),
        ),
        ScenarioCategory.LEAD_BRAKE: (rng.uniform(5.0, 9.0), rng.uniform(14.0, 30.0), rng.uniform(3.0, 6.0)),
        ScenarioCategory.CUT_IN: (rng.uniform(4.0, 8.0), rng.uniform(4.0, 14.0), rng.uniform(0.5, 0.75)),
        ScenarioCategory.APPROACH_STOP: (0.0, rng.uniform(120.0, 190.0), 0.0),
    }[family]
    return UrbanScenario(
        index=index,
        attempt=attempt,
        family=family,
        net=net,
        style=style,
        ego_accel_mps2=float(rng.uniform(2.2, 3.2) if harsh else rng.uniform(1.2, 2.0)),
        ego_decel_mps2=float(rng.uniform(4.0, 6.0) if harsh else rng.uniform(2.0, 3.2)),
        ego_speed_mps=float(net.speed_mps * rng.uniform(0.8, 1.0)),
        ego_lane=ego_lane,
        trigger_m=float(params[0]),
        guest_param=float(params[1]),
        guest_speed_mps=float(params[2]),
        n_background=int(rng.integers(3, 11)),
        n_parked=int(rng.integers(0, 6)),
        noise=noise,
        sumo_seed=int(rng.integers(1, 2**31 - 1)),
    )
