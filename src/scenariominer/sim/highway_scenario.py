"""What one simulated highway recording is made of, and how a set of them is varied from a seed.

A :class:`HighwaySettings` says what the user asked for (``None`` fields are left to the variety
preset); :func:`plan_scenarios` turns it into one :class:`HighwayScenario` per recording. With the
``mixed`` preset every unpinned parameter is drawn from a generator seeded with
``(seed, recording_id)``, so recording ``k`` of a set is the same whatever the number of recordings;
with ``fixed`` every recording uses the pinned values or the ``FIXED_*`` constants.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from scenariominer.errors import DataError

__all__ = [
    "VARIETY_PRESETS",
    "HighwayScenario",
    "HighwaySettings",
    "HighwaySimError",
    "plan_scenarios",
]

#: Names of the variety presets.
VARIETY_PRESETS: tuple[str, ...] = ("mixed", "fixed")

# Values of the ``fixed`` preset for parameters the user did not pin (no on-ramp, no lane drop).
FIXED_LANES = 3
FIXED_DEMAND_VPH = 3600.0
FIXED_SPEED_LIMIT_KMH = 120.0
FIXED_TRUCK_SHARE = 0.15
FIXED_AGGRESSIVE_SHARE = 0.1
FIXED_RAMP_VPH = 400.0

#: Speed limits the ``mixed`` preset draws from, km/h (``None``: unlimited, as on many German
#: autobahn sections; highD writes ``-1``).
_LIMITS_KMH: tuple[float | None, ...] = (80.0, 100.0, 120.0, 130.0, None)


class HighwaySimError(DataError):
    """A highway simulation cannot be set up or run (bad setting, SUMO missing or failing)."""


@dataclass(frozen=True)
class HighwaySettings:
    """What to simulate; ``None`` leaves a parameter to the variety preset.

    Attributes:
        recordings: number of recordings ``K`` (written as ``01`` .. ``K``).
        minutes: recorded minutes per recording (after the warm-up).
        seed: seed of the whole set (SUMO's seed and the variety draws derive from it).
        variety: ``mixed`` (vary every unpinned parameter per recording) or ``fixed``.
        lanes: main-road lanes (2..4) upstream of any lane drop.
        demand_vph: mean main-road demand, vehicles per hour over all lanes.
        speed_limit_kmh: posted limit, km/h; ``0`` pins "unlimited".
        truck_share: fraction of trucks, 0..1.
        on_ramp: add an on-ramp with an acceleration lane inside the recorded section.
        lane_drop: end the rightmost lane inside the recorded section.
        section_m: length of the recorded road section, metres.
        frame_rate_hz: frames per second of the recording (SUMO's step is its inverse).
        warmup_s: simulated seconds before recording starts (the road fills).
    """

    recordings: int = 6
    minutes: float = 10.0
    seed: int = 1
    variety: str = "mixed"
    lanes: int | None = None
    demand_vph: float | None = None
    speed_limit_kmh: float | None = None
    truck_share: float | None = None
    on_ramp: bool | None = None
    lane_drop: bool | None = None
    section_m: float = 1000.0
    frame_rate_hz: float = 10.0
    warmup_s: float = 120.0

    def __post_init__(self) -> None:
        """Check every value; raise :class:`HighwaySimError` naming the setting."""
        checks: list[tuple[bool, str]] = [
            (
                1 <= self.recordings <= 99,
                f"recordings must be 1..99 (highD ids are two digits), got {self.recordings}",
            ),
            (
                math.isfinite(self.minutes) and 0.0 < self.minutes <= 240.0,
                f"minutes must be in (0, 240], got {self.minutes}",
            ),
            (0 <= self.seed < 2**31, f"seed must be in [0, 2^31), got {self.seed}"),
            (
                self.variety in VARIETY_PRESETS,
                f"variety must be one of {list(VARIETY_PRESETS)}, got {self.variety!r}",
            ),
            (self.lanes is None or 2 <= self.lanes <= 4, f"lanes must be 2, 3 or 4, got {self.lanes}"),
            (
                self.demand_vph is None
                or (math.isfinite(self.demand_vph) and 0.0 < self.demand_vph <= 12000.0),
                f"demand must be in (0, 12000] vehicles per hour, got {self.demand_vph}",
            ),
            (
                self.speed_limit_kmh is None
                or self.speed_limit_kmh == 0.0
                or (math.isfinite(self.speed_limit_kmh) and 40.0 <= self.speed_limit_kmh <= 200.0),
                f"speed limit must be 0 (unlimited) or 40..200 km/h, got {self.speed_limit_kmh}",
            ),
            (
                self.truck_share is None or 0.0 <= self.truck_share <= 1.0,
                f"truck share must be in [0, 1], got {self.truck_share}",
            ),
            (
                math.isfinite(self.section_m) and 300.0 <= self.section_m <= 5000.0,
                f"section length must be 300..5000 m, got {self.section_m}",
            ),
            (
                self.frame_rate_hz in (10.0, 20.0, 25.0),
                f"frame rate must be 10, 20 or 25 Hz, got {self.frame_rate_hz}",
            ),
            (
                math.isfinite(self.warmup_s) and 0.0 <= self.warmup_s <= 3600.0,
                f"warm-up must be 0..3600 s, got {self.warmup_s}",
            ),
        ]
        for ok, message in checks:
            if not ok:
                raise HighwaySimError(f"simulate highway: {message}")


@dataclass(frozen=True)
class HighwayScenario:
    """Everything that defines one simulated recording (all drawn, nothing left open).

    Attributes:
        recording_id: highD recording id ``NN``.
        sumo_seed: SUMO's ``--seed``.
        lanes: main-road lanes upstream of the lane drop.
        speed_limit_kmh: posted limit, km/h; ``None`` unlimited (SUMO uses 130 km/h as the
            advisory speed and a wider spread of desired speeds).
        truck_share: fraction of trucks.
        aggressive_share: fraction of assertive cars (short headway, eager lane changes).
        demand_vph: main-road demand per period, vehicles per hour (all lanes); see ``period_s``.
        period_s: length of one demand period, seconds.
        on_ramp: whether an on-ramp with an acceleration lane joins inside the section.
        ramp_demand_vph: on-ramp demand, vehicles per hour (0 without an on-ramp).
        lane_drop: whether the rightmost lane ends inside the section.
        section_m: recorded section length, metres.
        lane_width_m: lane width, metres.
        frame_rate_hz: frames per second.
        warmup_s: simulated seconds before recording starts.
        record_s: recorded seconds.
    """

    recording_id: int
    sumo_seed: int
    lanes: int
    speed_limit_kmh: float | None
    truck_share: float
    aggressive_share: float
    demand_vph: tuple[float, ...]
    period_s: float
    on_ramp: bool
    ramp_demand_vph: float
    lane_drop: bool
    section_m: float
    lane_width_m: float
    frame_rate_hz: float
    warmup_s: float
    record_s: float

    @property
    def end_s(self) -> float:
        """Simulated seconds in all (warm-up plus recording)."""
        return self.warmup_s + self.record_s

    @property
    def speed_limit_mps(self) -> float | None:
        """Posted limit in m/s (``None``: unlimited)."""
        return None if self.speed_limit_kmh is None else self.speed_limit_kmh / 3.6

    def to_json(self) -> dict[str, object]:
        """The scenario as a JSON-ready dict (written to the set's manifest)."""
        return {
            "recording_id": self.recording_id,
            "sumo_seed": self.sumo_seed,
            "lanes": self.lanes,
            "speed_limit_kmh": self.speed_limit_kmh,
            "truck_share": round(self.truck_share, 4),
            "aggressive_share": round(self.aggressive_share, 4),
            "demand_vph": [round(v, 1) for v in self.demand_vph],
            "period_s": self.period_s,
            "on_ramp": self.on_ramp,
            "ramp_demand_vph": round(self.ramp_demand_vph, 1),
            "lane_drop": self.lane_drop,
            "section_m": self.section_m,
            "lane_width_m": self.lane_width_m,
            "frame_rate_hz": self.frame_rate_hz,
            "warmup_s": self.warmup_s,
            "record_s": self.record_s,
        }


def _demand_profile(
    rng: np.random.Generator, mean_vph: float, n_periods: int, vary: bool
) -> tuple[float, ...]:
    """Per-period demand: a smooth random walk around ``mean_vph`` (constant when not ``vary``)."""
    if not vary:
        return tuple([float(mean_vph)] * n_periods)
    steps = rng.normal(0.0, 0.18, n_periods)
    walk = np.clip(np.cumsum(steps) - steps.mean() * np.arange(1, n_periods + 1), -0.45, 0.45)
    return tuple(float(v) for v in np.round(mean_vph * (1.0 + walk), 1))


@dataclass(frozen=True)
class _Draw:
    """One recording's draws under ``mixed`` (all drawn, in this order, whatever is pinned)."""

    lanes: int
    per_lane_vph: float
    limit_kmh: float | None
    trucks: float
    aggressive: float
    on_ramp: bool
    ramp_vph: float
    lane_drop: bool
    sumo_seed: int

    @classmethod
    def from_rng(cls, rng: np.random.Generator) -> _Draw:
        return cls(
            lanes=int(rng.integers(2, 5)),
            per_lane_vph=float(rng.uniform(900.0, 1900.0)),
            limit_kmh=_LIMITS_KMH[int(rng.integers(len(_LIMITS_KMH)))],
            trucks=float(rng.uniform(0.05, 0.30)),
            aggressive=float(rng.uniform(0.05, 0.20)),
            on_ramp=bool(rng.random() < 0.6),
            ramp_vph=float(rng.uniform(150.0, 700.0)),
            lane_drop=bool(rng.random() < 0.5),
            sumo_seed=int(rng.integers(0, 2**31 - 1)),
        )

    @classmethod
    def fixed(cls, sumo_seed: int) -> _Draw:
        return cls(
            lanes=FIXED_LANES,
            per_lane_vph=FIXED_DEMAND_VPH / FIXED_LANES,
            limit_kmh=FIXED_SPEED_LIMIT_KMH,
            trucks=FIXED_TRUCK_SHARE,
            aggressive=FIXED_AGGRESSIVE_SHARE,
            on_ramp=False,
            ramp_vph=FIXED_RAMP_VPH,
            lane_drop=False,
            sumo_seed=sumo_seed,
        )


def plan_scenarios(settings: HighwaySettings) -> list[HighwayScenario]:
    """One scenario per recording ``1..K``, drawn from ``(settings.seed, recording_id)``.

    Under ``mixed``: lanes 2-4; demand 900-1900 vehicles per hour and lane (so free flow,
    near-capacity and, with a bottleneck, congested recordings all occur), varied per 2-minute
    period; speed limit from 80, 100, 120, 130 km/h or unlimited; trucks 5-30 %; assertive cars
    5-20 %; an on-ramp with probability 0.6 (150-700 vehicles per hour); a lane drop with
    probability 0.5. Under ``fixed``: the ``FIXED_*`` values, constant demand. Pinned settings
    replace the draw; the draws of the other parameters do not change when one is pinned.
    """
    s = settings
    mixed = s.variety == "mixed"
    period_s = 120.0
    record_s = s.minutes * 60.0
    n_periods = max(1, math.ceil((s.warmup_s + record_s) / period_s))
    out: list[HighwayScenario] = []
    for rec in range(1, s.recordings + 1):
        rng = np.random.default_rng([s.seed, rec])
        drawn = _Draw.from_rng(rng)
        d = drawn if mixed else _Draw.fixed(drawn.sumo_seed)
        lanes = s.lanes if s.lanes is not None else d.lanes
        mean_vph = s.demand_vph if s.demand_vph is not None else d.per_lane_vph * lanes
        limit = d.limit_kmh if s.speed_limit_kmh is None else (s.speed_limit_kmh or None)
        on_ramp = d.on_ramp if s.on_ramp is None else s.on_ramp
        out.append(
            HighwayScenario(
                recording_id=rec,
                sumo_seed=d.sumo_seed,
                lanes=lanes,
                speed_limit_kmh=limit,
                truck_share=d.trucks if s.truck_share is None else s.truck_share,
                aggressive_share=d.aggressive,
                demand_vph=_demand_profile(rng, float(mean_vph), n_periods, mixed),
                period_s=period_s,
                on_ramp=on_ramp,
                ramp_demand_vph=d.ramp_vph if on_ramp else 0.0,
                lane_drop=d.lane_drop if s.lane_drop is None else s.lane_drop,
                section_m=s.section_m,
                lane_width_m=3.75,
                frame_rate_hz=s.frame_rate_hz,
                warmup_s=s.warmup_s,
                record_s=record_s,
            )
        )
    return out
