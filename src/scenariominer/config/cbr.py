"""Configuration of case-based reasoning for evasive manoeuvres (seed 002).

The paper's risk types and manoeuvres (Table 1) ship as TOML files in ``scenariominer/cbr/``;
``risk_types_file`` / ``manoeuvres_file`` replace them. Retrieval follows section 3.2 (captions
embedded, the k most similar cases of the same risk type); the prompt follows section 3.3. The
rollout check is ours (not in the paper): its defaults are explained per field.
"""

from __future__ import annotations

from dataclasses import dataclass, field

#: How few-shot cases are chosen (section 4.5: similarity vs random sampling).
SELECTION_CHOICES = ("similarity", "random")

#: Our scenario categories (why-braking, seed 000) mapped to the paper's risk types.
DEFAULT_CATEGORY_MAP: dict[str, str] = {
    "lead_brake": "vehicle_ahead",
    "approach_stop": "vehicle_ahead",
    "cut_in": "merging_vehicle",
    "obj_crossing": "adjacent_vehicle",
    "left_oppo": "opposite_turning_vehicle",
    "right_ped": "pedestrian",
    "ped_crossing": "pedestrian",
}


@dataclass(frozen=True)
class RolloutConfig:
    """The kinematic re-simulation of the ego (beyond the paper).

    Attributes:
        lead_s: the manoeuvre starts this many seconds before the conflict (the closest approach,
            or the first overlap of the recorded ego); 1.5 s is a typical driver's reaction budget
            left after perception.
        horizon_s: seconds simulated from the start of the manoeuvre.
        dt_s: time step of the re-simulation (the other road users are interpolated onto it).
        margin_m: boxes closer than this count as a collision (0 = only true overlap).
        max_speed_mps: the accelerating manoeuvres stop gaining speed here.
    """

    lead_s: float = 1.5
    horizon_s: float = 5.0
    dt_s: float = 0.1
    margin_m: float = 0.0
    max_speed_mps: float = 36.0

    def __post_init__(self) -> None:
        if not (self.lead_s > 0 and self.horizon_s > 0 and self.dt_s > 0):
            raise ValueError("cbr.rollout: lead_s, horizon_s and dt_s must be positive")
        if self.margin_m < 0:
            raise ValueError("cbr.rollout: margin_m must be >= 0")
        if not self.max_speed_mps > 0:
            raise ValueError("cbr.rollout: max_speed_mps must be positive")


@dataclass(frozen=True)
class CbrConfig:
    """Case base, retrieval, prompt and evaluation settings.

    Attributes:
        risk_types_file: TOML file of risk types (``""``: the paper's seven, Table 1).
        manoeuvres_file: TOML file of manoeuvres with their kinematics (``""``: the paper's eight).
        table: name of the store's corpus table holding the case base.
        duplicate_threshold: a new case whose caption has cosine similarity at or above this with
            a stored case of the same risk type is a near-duplicate (reported, not stored).
        k: few-shot cases per prompt (0 = zero-shot); the paper compares 0, 1, 3 and 5.
        selection: ``similarity`` (the paper's CBR) or ``random`` (its comparison arm).
        risk_aware: give the risk type and its definition in the task prompt (section 4.4).
        seed: seed of the random arm (the same query draws the same cases).
        max_field_chars: cap on each free-text field of the answer (JSON-schema ``maxLength``), so
            a call on the small embedded model stays a few seconds.
        max_tokens: cap on generated tokens per recommendation.
        category_map: our scenario categories -> risk type (a pedestrian or cyclist guest is
            always ``pedestrian``); a category not listed uses ``default_risk_type``.
        default_risk_type: risk type of an event whose category is not mapped.
        rollout: the kinematic rollout check.
    """

    risk_types_file: str = ""
    manoeuvres_file: str = ""
    table: str = "cbr_cases"
    duplicate_threshold: float = 0.97
    k: int = 3
    selection: str = "similarity"
    risk_aware: bool = True
    seed: int = 0
    max_field_chars: int = 120
    max_tokens: int = 256
    category_map: dict[str, str] = field(default_factory=lambda: dict(DEFAULT_CATEGORY_MAP))
    default_risk_type: str = "vehicle_ahead"
    rollout: RolloutConfig = field(default_factory=RolloutConfig)

    def __post_init__(self) -> None:
        if not 0.0 < self.duplicate_threshold <= 1.0:
            raise ValueError("cbr: duplicate_threshold must be in (0, 1]")
        if self.k < 0:
            raise ValueError("cbr: k must be >= 0")
        if self.selection not in SELECTION_CHOICES:
            raise ValueError(f"cbr: selection must be one of {SELECTION_CHOICES}, got {self.selection!r}")
        if self.max_field_chars < 20:
            raise ValueError("cbr: max_field_chars must be at least 20")
        if self.max_tokens < 32:
            raise ValueError("cbr: max_tokens must be at least 32")
