"""Configuration of rule-based tagging and key-object identification (braking paper, III-B, III-C, IV-B).

Values the braking paper states are its defaults (veering/turning angles, TTC and overlap
horizons, distance bands). Where it defers to Guo et al. (2023) without numbers (standstill
speed, acceleration thresholds, the expansion margin of VERY_CLOSE), the defaults below are
chosen for 10 Hz annotated logs after Savitzky-Golay smoothing and the reasoning is given per field.
"""

from __future__ import annotations

from dataclasses import dataclass, field

#: Key-object identification methods (``tags.keyident.method``).
KEYIDENT_METHODS: tuple[str, ...] = ("tags", "counterfactual", "combined")


@dataclass(frozen=True)
class CounterfactualConfig:
    """Counterfactual conflict search: which object would the ego have met had it not braked.

    For each braking segment (a run of DECELERATING / STANDING_STILL frames of the ego that starts
    at a speed of at least ``min_onset_speed_mps``), the ego is moved at its speed at braking onset
    along its heading and along its own driven path, from its position at several reference
    times, and every object is moved with constant velocity and turn rate; an object
    whose predicted box overlaps a predicted ego box within ``max_gap_s`` is a candidate.

    Attributes:
        horizon_s: prediction horizon, seconds (5 s: a smooth yield starts 3-5 s before the conflict).
        step_s: prediction time step, seconds (the log's 10 Hz).
        min_onset_speed_mps: braking that starts slower than this (m/s) is not searched (creeping).
        ref_before_s: the first reference time is this many seconds before the onset (the ego's
            reaction delay: the object was already on its way when the driver decided to brake).
        ref_step_s: reference times are this far apart, seconds ...
        ref_after_s: ... up to this many seconds after the onset (or the end of the segment).
        max_gap_s: ego and object boxes overlapping at times at most this far apart (seconds, a
            predicted post-encroachment time) conflict; 0 would ask for a predicted collision.
        margin_m: each box grows by this on every side (metres) when testing overlap.
        max_range_m: objects farther than this from the ego at a reference time are ignored (metres).
        ctrv_max_yaw_rate_radps: object yaw rates are clipped to ± this (rad/s) for prediction.
        ref_weight: ranking cost per second of reference time after the onset.
        late_weight: ranking cost per second an object is first seen after the onset.
        gap_weight: ranking cost per second of the conflict's time gap.
        max_late_s: objects first seen more than this many seconds after the onset are not candidates.
        max_per_segment: candidates kept per braking segment, best ranked first (1: the key object).
        ego_width_shrink_m: the counterfactual ego's box is narrowed by this on each side (metres),
            so that an object in the next lane whose predicted box grazes the ego's (heading noise)
            is no conflict; an object in the ego's lane still is.
        driven_path_weight: ranking cost (seconds) of a conflict found only along the path the ego
            actually drove, not along its heading (that path holds later manoeuvres, e.g. the lane
            change around the stopped car that made it brake).
    """

    horizon_s: float = 5.0
    step_s: float = 0.1
    min_onset_speed_mps: float = 2.0
    ref_before_s: float = 0.5
    ref_step_s: float = 0.5
    ref_after_s: float = 3.0
    max_gap_s: float = 1.5
    margin_m: float = 0.0
    max_range_m: float = 80.0
    ctrv_max_yaw_rate_radps: float = 1.0
    ref_weight: float = 0.5
    late_weight: float = 1.0
    gap_weight: float = 1.0
    max_late_s: float = 1.0
    max_per_segment: int = 1
    driven_path_weight: float = 2.0
    ego_width_shrink_m: float = 0.4

    def __post_init__(self) -> None:
        if not 0 < self.step_s <= self.horizon_s:
            raise ValueError("tags.keyident.counterfactual: need 0 < step_s <= horizon_s")
        if self.ref_step_s <= 0:
            raise ValueError("tags.keyident.counterfactual: ref_step_s must be > 0")
        if self.max_per_segment < 1:
            raise ValueError("tags.keyident.counterfactual: max_per_segment must be >= 1")
        for name in (
            "min_onset_speed_mps",
            "ref_before_s",
            "ref_after_s",
            "max_gap_s",
            "margin_m",
            "max_range_m",
            "ctrv_max_yaw_rate_radps",
            "ref_weight",
            "late_weight",
            "gap_weight",
            "max_late_s",
            "driven_path_weight",
            "ego_width_shrink_m",
        ):
            if getattr(self, name) < 0:
                raise ValueError(f"tags.keyident.counterfactual: {name} must be >= 0")


@dataclass(frozen=True)
class KeyIdentConfig:
    """How key objects are identified (III-C) and their candidates merged into braking events.

    Attributes:
        max_gap_s: two candidate timestamps of the same object closer than this (seconds, measured
            between the timestamps) belong to one event; bridges a few frames where a tag flickers.
        min_duration_s: events shorter than this (seconds from first to last candidate timestamp)
            are dropped; 0 keeps every candidate, as in the paper.
        method: ``"tags"`` (the paper: collision / trajectory-overlap tags while the ego brakes),
            ``"counterfactual"`` (the conflict search of :class:`CounterfactualConfig`) or
            ``"combined"`` (the tag events, plus the counterfactual key object of every braking
            segment no tag event explains).
        counterfactual: settings of the counterfactual conflict search.
    """

    max_gap_s: float = 1.0
    min_duration_s: float = 0.0
    method: str = "combined"
    counterfactual: CounterfactualConfig = field(default_factory=CounterfactualConfig)

    def __post_init__(self) -> None:
        if self.max_gap_s < 0 or self.min_duration_s < 0:
            raise ValueError("tags.keyident: max_gap_s and min_duration_s must be >= 0")
        if self.method not in KEYIDENT_METHODS:
            raise ValueError(
                f"tags.keyident.method must be one of {list(KEYIDENT_METHODS)}, got {self.method!r}"
            )


@dataclass(frozen=True)
class StitchConfig:
    """Repair of tracker noise before tagging: id switches, ghost detections, dropped frames.

    Attributes:
        enabled: whether tracks are cleaned before tagging.
        max_gap_s: a track ending and another starting at most this many seconds later (and at
            least one frame later) may be one object whose id switched.
        max_position_error_m: the new track's first position must lie within this distance
            (metres) of the old track's last position extrapolated over the gap at its velocity ...
        position_error_per_s_m: ... plus this many metres per second of gap (unknown acceleration).
        max_speed_change_mps: ... its speed may differ by at most this (m/s) ...
        max_size_change_m: ... and its length and width each by at most this (metres).
        ghost_max_frames: a track observed in at most this many frames that is not stitched to
            another is a ghost detection and is dropped (a real object stays in view longer).
        ghost_max_speed_mps: a track whose median speed exceeds this (m/s, far above urban
            traffic) is a ghost (boxes of different objects joined) and is dropped.
        fill_gap_s: gaps inside a (stitched) track up to this many seconds are interpolated
            linearly (dropped frames); longer gaps stay unobserved.
    """

    enabled: bool = True
    max_gap_s: float = 1.5
    max_position_error_m: float = 2.0
    position_error_per_s_m: float = 2.0
    max_speed_change_mps: float = 3.0
    max_size_change_m: float = 1.5
    ghost_max_frames: int = 3
    ghost_max_speed_mps: float = 60.0
    fill_gap_s: float = 1.5

    def __post_init__(self) -> None:
        if self.ghost_max_frames < 0:
            raise ValueError("tags.stitch: ghost_max_frames must be >= 0")
        for name in (
            "max_gap_s",
            "max_position_error_m",
            "position_error_per_s_m",
            "max_speed_change_mps",
            "max_size_change_m",
            "ghost_max_speed_mps",
            "fill_gap_s",
        ):
            if getattr(self, name) < 0:
                raise ValueError(f"tags.stitch: {name} must be >= 0")


@dataclass(frozen=True)
class TagConfig:
    """Thresholds of the rule-based activity and interaction tags (Table I).

    Attributes:
        standing_speed_mps: below this ground speed (m/s) an actor is STANDING_STILL; 0.3 m/s sits
            above the residual speed of a parked car's smoothed box jitter (~0.05-0.15 m/s) and below
            a slow pedestrian's walk (~1 m/s).
        reversing_speed_mps: REVERSING needs the velocity component along the heading (m/s) to be
            below minus this value, so a standing box with a jittering heading is not reversing.
        accel_enter_mps2: ACCELERATING starts when the acceleration along the heading (m/s^2)
            exceeds this; 0.5 m/s^2 is a clearly intended speed change, above smoothed annotation noise.
        accel_exit_mps2: ... and lasts until it drops below this (hysteresis, m/s^2).
        decel_enter_mps2: DECELERATING starts when the acceleration along the heading falls below
            minus this value (m/s^2); light braking is about 1 m/s^2, coasting about 0.3 m/s^2.
        decel_exit_mps2: ... and lasts until it rises above minus this value (hysteresis, m/s^2).
        accel_window_s: the acceleration along the heading is averaged over a centred window of
            this many seconds before thresholding, i.e. the mean speed change over the window. The
            second derivative of a smoothed track is noisy (about 0.35 m/s^2 for 5 cm of position
            jitter at 10 Hz); one second of averaging brings that to about 0.15 m/s^2, while a
            real brake or launch lasts longer than that.
        min_segment_s: longitude and turn-direction segments shorter than this (seconds) are
            absorbed by the preceding segment (or the following one at the start of a track).
        turn_min_yaw_rate_radps: a moving actor is in a turning segment while the magnitude of its
            yaw rate (rad/s) exceeds this; the accumulated heading change over the segment decides
            veering or turning. 0.02 rad/s is a 1 km radius at 20 m/s.
        veer_angle_rad: accumulated heading change (rad) from which a segment is VEERING (paper: 0.05).
        turn_angle_rad: accumulated heading change (rad) above which it is TURNING (paper: 0.17).
        ttc_horizon_s: CTRV prediction horizon (seconds); TTC beyond it is CollisionTag NO (paper: 3 s).
        ttc_step_s: time step of the CTRV prediction (seconds); also the TTC resolution.
        ttc_high_s: TTC below this (seconds) is CollisionTag HIGH (paper: 1.5 s); up to the horizon LOW.
        ctrv_max_yaw_rate_radps: the yaw rate used for prediction is clipped to ± this (rad/s); a car's
            tightest urban turn is about 0.8 rad/s, larger values are heading noise of small objects.
        distance_margin_m: each box is enlarged by this margin on every side (metres) for VERY_CLOSE;
            two boxes within about twice the margin (a door's width) are very close.
        distance_close_m: box distance (metres) below which DistanceTag is CLOSE (paper: 10 m).
        distance_far_m: box distance (metres) above which DistanceTag is FAR (paper: 50 m); between MEDIUM.
        overlap_high_s: window (seconds) of recorded future boxes for TrajOverlapTag HIGH (paper: 1.5 s).
        overlap_low_s: window (seconds) for TrajOverlapTag LOW (paper: 3 s).
        keyident: key-object identification and the merging of its candidates into events.
        stitch: repair of tracker noise (id switches, ghosts, dropped frames) before tagging.
    """

    standing_speed_mps: float = 0.3
    reversing_speed_mps: float = 0.5
    accel_enter_mps2: float = 0.5
    accel_exit_mps2: float = 0.25
    decel_enter_mps2: float = 0.5
    decel_exit_mps2: float = 0.25
    accel_window_s: float = 1.0
    min_segment_s: float = 0.3
    turn_min_yaw_rate_radps: float = 0.02
    veer_angle_rad: float = 0.05
    turn_angle_rad: float = 0.17
    ttc_horizon_s: float = 3.0
    ttc_step_s: float = 0.1
    ttc_high_s: float = 1.5
    ctrv_max_yaw_rate_radps: float = 1.0
    distance_margin_m: float = 0.5
    distance_close_m: float = 10.0
    distance_far_m: float = 50.0
    overlap_high_s: float = 1.5
    overlap_low_s: float = 3.0
    keyident: KeyIdentConfig = field(default_factory=KeyIdentConfig)
    stitch: StitchConfig = field(default_factory=StitchConfig)

    def __post_init__(self) -> None:
        problems = []
        if not 0 <= self.accel_exit_mps2 <= self.accel_enter_mps2:
            problems.append("need 0 <= accel_exit_mps2 <= accel_enter_mps2")
        if not 0 <= self.decel_exit_mps2 <= self.decel_enter_mps2:
            problems.append("need 0 <= decel_exit_mps2 <= decel_enter_mps2")
        if not 0 <= self.veer_angle_rad <= self.turn_angle_rad:
            problems.append("need 0 <= veer_angle_rad <= turn_angle_rad")
        if not 0 < self.ttc_step_s <= self.ttc_horizon_s:
            problems.append("need 0 < ttc_step_s <= ttc_horizon_s")
        if not 0 <= self.ttc_high_s <= self.ttc_horizon_s:
            problems.append("need 0 <= ttc_high_s <= ttc_horizon_s")
        if not 0 <= self.distance_close_m <= self.distance_far_m:
            problems.append("need 0 <= distance_close_m <= distance_far_m")
        if not 0 <= self.overlap_high_s <= self.overlap_low_s:
            problems.append("need 0 <= overlap_high_s <= overlap_low_s")
        for name in (
            "standing_speed_mps",
            "reversing_speed_mps",
            "accel_window_s",
            "min_segment_s",
            "turn_min_yaw_rate_radps",
            "ctrv_max_yaw_rate_radps",
            "distance_margin_m",
        ):
            if getattr(self, name) < 0:
                problems.append(f"{name} must be >= 0")
        if problems:
            raise ValueError("tags: " + "; ".join(problems))
