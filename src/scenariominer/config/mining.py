"""Configuration of program-based scenario mining: predicate thresholds, post-processing, sandbox.

The atomic predicates of :mod:`scenariominer.mine.dsl` take their *tunable arguments*
(``within_distance``, ``min_velocity``, ...) from the program that calls them; the thresholds below
are the ones a program cannot set: what counts as "moving", how much heading change makes a turn,
how far ahead a lead vehicle may be for "following", and so on. Defaults follow RefAV (Davidson et
al., 2025) where its code fixes a number, and the reason is given per field otherwise.

Example ``scenariominer.toml``::

    [mining]
    stationary_max_displacement_m = 2.5

    [mining.sandbox]
    timeout_s = 10

    [mining.generation]
    max_attempts = 5
    few_shot_k = 3
    reference_style = "compact"

    [mining.clip]
    model_path = "/models/clip-vit-base-patch32"
    top_k_crops = 50
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from enum import StrEnum

__all__ = ["ClipFilterConfig", "GenerationConfig", "MiningConfig", "ReferenceStyle", "SandboxConfig"]


class ReferenceStyle(StrEnum):
    """How much of the predicate library's documentation goes into the program-synthesis prompt."""

    COMPACT = "compact"
    """Signature, summary, subject/reference roles and one example per function (~4.5k tokens)."""
    FULL = "full"
    """Every signature with its complete docstring (~9k tokens; needs ``llm.n_ctx`` >= 12288)."""


@dataclass(frozen=True)
class SandboxConfig:
    """Limits for running untrusted (LLM-written) mining programs.

    Attributes:
        timeout_s: wall-clock limit (seconds) for one program on one log, including the child
            process's start-up; a program running longer is killed and reported as ``timeout``.
        memory_mb: address space (MiB) the program may allocate on top of what the sandbox child
            holds after importing the predicate library; exceeding it raises ``MemoryError`` inside
            the child, reported as ``memory``.
        cpu_s: CPU-time limit (seconds) of the child as a backstop to the wall-clock limit.
        max_program_chars: longer program texts are refused before parsing (``forbidden``).
        max_ast_nodes: programs whose syntax tree has more nodes are refused (``forbidden``); a
            mining program is a few dozen calls, so 5,000 nodes leaves ample room.
        max_range_len: ``range(...)`` inside programs may yield at most this many values.
    """

    timeout_s: float = 30.0
    memory_mb: int = 1024
    cpu_s: int = 60
    max_program_chars: int = 20_000
    max_ast_nodes: int = 5_000
    max_range_len: int = 100_000

    def __post_init__(self) -> None:
        if self.timeout_s <= 0 or self.memory_mb <= 0 or self.cpu_s <= 0:
            raise ValueError("mining.sandbox: timeout_s, memory_mb and cpu_s must be > 0")
        if self.max_program_chars <= 0 or self.max_ast_nodes <= 0 or self.max_range_len <= 0:
            raise ValueError("mining.sandbox: program size limits must be > 0")


@dataclass(frozen=True)
class GenerationConfig:
    """How mining programs are written by the language model (fault-tolerant generation loop).

    Attributes:
        max_attempts: K of the generate-check-run-repair loop: the model gets at most this many
            tries; after K failures the description is flagged for manual review with every
            attempt kept (the paper uses K = 5).
        few_shot_k: number of example programs from the bank shown in the prompt, chosen by
            embedding similarity of their descriptions to the query (0 disables few-shot).
        reference_style: ``compact`` or ``full`` library documentation in the prompt (see
            :class:`ReferenceStyle`); ``full`` needs a context window of about 12k tokens.
        max_tokens: upper bound on the tokens of one generated program (a mining program is
            5-15 lines, about 100-250 tokens); bounds the time a rambling answer costs.
        examples_files: extra example-bank TOML files (same format as the shipped bank) whose
            programs join the few-shot pool; an entry with a shipped description replaces it.
        validation_logs: how many of the logs being mined a candidate program must run on
            without error before it is accepted (the first ones given; at least 1).
        retry_temperature: sampling temperature of a repair request made after the model
            repeated a program that had already failed. Decoding is greedy otherwise, and a greedy
            model shown the same program and error answers the same again, which would spend the
            remaining tries on one answer; the seed is the attempt number, so runs stay
            reproducible. 0 keeps repairs greedy.
        cache_programs: keep the outcome of the loop on disk, keyed by description, model,
            prompt version and prompt text, so mining the same description again costs nothing.
        consensus_samples: candidate programs per description, the loop's own included; above 1,
            the extra ones are sampled at ``consensus_temperature`` and the candidate whose output
            the others agree with most is run (:mod:`scenariominer.mine.consensus`). 1 = off.
        consensus_temperature: sampling temperature of the extra candidates.
        consensus_min_agreement: below this mean Jaccard agreement the result is flagged for review.
        grammar: decode under the program grammar built from the predicates' signatures
            (:mod:`scenariominer.mine.grammar`), so every answer is a program of calls to existing
            functions with arguments of the right kinds (backends without grammar support ignore it).
        plan: before writing, extract a structured plan of the description (subject and related
            categories, relations, conditions, stated numbers; :mod:`scenariominer.mine.plan`)
            with one schema-constrained call, show it in the program request and store it. On by
            default: with ``plan_program`` it gave the best hold-out figures (docs/mining.md).
        plan_program: with ``plan`` on, first try the program built from the plan by fixed rules
            (:mod:`scenariominer.mine.plan_program`); the model writes one only when the rules
            cannot express the plan or their program fails on the validation logs.
        plan_rules: with ``plan`` on, first read the description with the phrase rules
            (:mod:`scenariominer.mine.plan_reader`); the model reads it only when a word of it is
            not one of the known phrases.
        plan_partial: with ``plan_rules`` on, a description with words the phrase rules do not
            know is read by them partially (the known phrases; the other words listed in the
            plan as not read) when they read its subject; the model reads only the rest. On by
            default: on the descriptions the rules could not read in full, the partial plans
            agreed with the references far better than the model's (docs/mining.md).
        plan_reword: with ``plan_rules`` on, a description the phrase rules cannot read in full
            is first rewritten in plain words by one short model call, and the rules' full reading
            of the rewording is used when it keeps the description's numbers and road users
            (:mod:`scenariominer.mine.plan_reword`); before the partial reading.
        plan_reword_tries: how many rewordings the rewording step asks for at most: after one
            the rules read only in part, the next request shows the model its rewording and asks
            for a simpler one without the words they left out. 1: no second request.
    """

    max_attempts: int = 5
    few_shot_k: int = 3
    reference_style: ReferenceStyle = ReferenceStyle.COMPACT
    max_tokens: int = 400
    examples_files: tuple[str, ...] = ()
    validation_logs: int = 1
    retry_temperature: float = 0.7
    cache_programs: bool = True
    consensus_samples: int = 1
    consensus_temperature: float = 0.7
    consensus_min_agreement: float = 0.5
    grammar: bool = False
    plan: bool = True
    plan_program: bool = True
    plan_rules: bool = True
    plan_partial: bool = True
    plan_reword: bool = True
    plan_reword_tries: int = 2

    def __post_init__(self) -> None:
        try:
            object.__setattr__(self, "reference_style", ReferenceStyle(self.reference_style))
        except ValueError:
            raise ValueError(
                f"mining.generation.reference_style must be one of {[s.value for s in ReferenceStyle]}, "
                f"got {self.reference_style!r}"
            ) from None
        if self.max_attempts < 1:
            raise ValueError(f"mining.generation.max_attempts must be >= 1, got {self.max_attempts}")
        if self.plan_reword_tries < 1:
            raise ValueError(
                f"mining.generation.plan_reword_tries must be >= 1, got {self.plan_reword_tries}"
            )
        if self.few_shot_k < 0:
            raise ValueError(f"mining.generation.few_shot_k must be >= 0, got {self.few_shot_k}")
        if self.max_tokens < 16:
            raise ValueError(f"mining.generation.max_tokens must be >= 16, got {self.max_tokens}")
        if self.validation_logs < 1:
            raise ValueError(f"mining.generation.validation_logs must be >= 1, got {self.validation_logs}")
        if self.consensus_samples < 1:
            raise ValueError(
                f"mining.generation.consensus_samples must be >= 1, got {self.consensus_samples}"
            )
        if not 0 <= self.consensus_min_agreement <= 1:
            raise ValueError(
                "mining.generation.consensus_min_agreement must be in [0, 1], "
                f"got {self.consensus_min_agreement}"
            )
        if not 0 <= self.retry_temperature <= 2:
            raise ValueError(
                f"mining.generation.retry_temperature must be in [0, 2], got {self.retry_temperature}"
            )


@dataclass(frozen=True)
class ClipFilterConfig:
    """The optional coarse-to-fine filter: CLIP similarity of object crops to query keywords.

    Attributes:
        model_path: folder of a CLIP model saved with ``save_pretrained`` (Hugging Face
            ``transformers`` layout: ``config.json``, weights, tokenizer and processor files).
            Never downloaded; empty disables the filter.
        top_k_crops: the crops most similar to the keywords that are kept; their tracks become the
            candidate tracklets.
        min_similarity: crops below this cosine similarity are never kept, even inside the top K
            (-1 keeps the top K whatever their score).
        tracklet_margin_s: each kept crop makes its track a candidate from this many seconds
            before to this many seconds after the crop's timestamp (crops are sparse in time;
            the program needs a little context to measure motion).
        batch_size: crops per CLIP forward pass.
        text_template: how a keyword phrase is put to the text encoder (``{}`` is the phrase).
        use_spatial_keywords: also embed spatial words ("left", "behind"); crops show one object,
            so by default only colour and object phrases are matched against them.
    """

    model_path: str = ""
    top_k_crops: int = 50
    min_similarity: float = -1.0
    tracklet_margin_s: float = 1.0
    batch_size: int = 32
    text_template: str = "a photo of a {}"
    use_spatial_keywords: bool = False

    def __post_init__(self) -> None:
        if self.top_k_crops < 1:
            raise ValueError(f"mining.clip.top_k_crops must be >= 1, got {self.top_k_crops}")
        if not -1.0 <= self.min_similarity <= 1.0:
            raise ValueError(f"mining.clip.min_similarity must be in [-1, 1], got {self.min_similarity}")
        if not self.tracklet_margin_s >= 0:
            raise ValueError(f"mining.clip.tracklet_margin_s must be >= 0, got {self.tracklet_margin_s}")
        if self.batch_size < 1:
            raise ValueError(f"mining.clip.batch_size must be >= 1, got {self.batch_size}")
        if "{}" not in self.text_template:
            raise ValueError("mining.clip.text_template must contain '{}' where the keyword goes")


@dataclass(frozen=True)
class MiningConfig:
    """Thresholds of the atomic mining predicates that programs cannot set themselves.

    Attributes:
        stationary_max_displacement_m: ``stationary`` holds for a track whose observed positions
            all fit in a box whose diagonal is below this (metres); RefAV uses 3 m because box
            centres of parked cars jitter by up to a metre over a log.
        moving_min_speed_mps: ``following`` needs both the follower and the lead to be at least
            this fast (m/s); 0.5 m/s is above the speed jitter of annotated parked cars.
        heading_min_speed_mps: ``heading_in_relative_direction_to`` uses the velocity direction of
            objects at least this fast (m/s) and the box heading of slower agents (RefAV: 1 m/s).
        same_direction_max_deg: travel directions at most this far apart (degrees) are "same".
        opposite_direction_min_deg: travel directions at least this far apart (degrees) are
            "opposite"; in between they are "perpendicular" (RefAV: 45 and 135 degrees).
        turn_min_heading_change_deg: a run of same-sign yaw rate is a turn when the heading changes
            by more than this over the run (degrees; RefAV: 45).
        turn_partial_min_heading_change_deg: a run cut by the start or end of the track (the turn
            began before or ended after the recording) is a turn when its heading change exceeds
            this (degrees; RefAV: 15) and its mean yaw rate exceeds ``turn_min_yaw_rate_deg_s``.
        turn_min_yaw_rate_deg_s: see above (degrees per second; RefAV: 5).
        turn_yaw_rate_deadband_deg_s: yaw rates smaller in magnitude than this (deg/s) count as
            zero when splitting a track into same-sign runs, so heading jitter of a straight-driving
            car does not cut a turn into pieces.
        lane_change_min_lateral_speed_mps: a lane change is only registered while the speed
            component across the old lane is at least this (m/s; RefAV: 0.1).
        lane_change_max_heading_deg: ... and while the direction of travel is within this angle of
            the lane direction (degrees; RefAV: cosine 0.5, i.e. 60 degrees).
        lane_change_min_lateral_m: the sideways movement around the lane switch must add up to
            at least this (metres across the lane); a real lane change moves about 3.5 m, while a
            car drifting near a lane boundary crosses it with a few decimetres.
        following_max_gap_m: ``following``: the lead's centre is at most this far (metres) ahead
            of the follower's front bumper (RefAV: 25 m).
        following_max_lateral_m: ``following`` without an HD map: the lead's centre is at most this
            far (metres) to either side of the follower's centre line (about half a lane, so a car
            in the neighbouring lane is not a lead); with a map the lanes decide and a 5 m band is used.
        following_min_heading_cos: ``following``: cosine of the angle between the two directions
            of travel must exceed this (RefAV: 0.5).
        crossing_min_speed_mps: ``being_crossed_by``: the related object's speed across the
            midplane must exceed this (m/s; RefAV: 0.2) for the crossing to count and to continue.
        stop_sign_max_right_m: ``at_stop_sign``: the object is at most this far (metres) to the
            right of the stop sign's forward axis (RefAV: 7 m); the forward distance is an argument.
        stop_sign_min_behind_m: ... and at most this far (metres) behind the sign's plane (RefAV: 1 m).
        postprocess_min_timestamps: after a program ran, referred tracks referred at fewer than
            this many timestamps are dropped as noise (RefAV's docstring and its unused
            ``filter_by_length``: 2; its code does not apply it).
        postprocess_min_run_timestamps: a run of ``k`` referred timestamps shorter than this
            (``m``) is widened by ``(m - k) // 2`` timestamps on both sides, so a single-frame
            hit becomes three frames for ``m = 3`` (our choice: RefAV's docstring widens short
            runs to 1.5 s, 15 frames at 10 Hz, but its code never calls that dilation).
        postprocess_max_relation_distance_m: relations whose objects never come closer than this
            (metres, centre to centre, in the ground plane) at the relation's timestamps are
            dropped, and with them the referred cells left without a related object (RefAV:
            50 m, measured in 3-D).
        sandbox: limits for running untrusted programs.
        generation: the language-model program-generation loop.
        clip: the optional CLIP crop filter.
    """

    stationary_max_displacement_m: float = 3.0
    moving_min_speed_mps: float = 0.5
    heading_min_speed_mps: float = 1.0
    same_direction_max_deg: float = 45.0
    opposite_direction_min_deg: float = 135.0
    turn_min_heading_change_deg: float = 45.0
    turn_partial_min_heading_change_deg: float = 15.0
    turn_min_yaw_rate_deg_s: float = 5.0
    turn_yaw_rate_deadband_deg_s: float = 1.0
    lane_change_min_lateral_speed_mps: float = 0.1
    lane_change_max_heading_deg: float = 60.0
    lane_change_min_lateral_m: float = 1.0
    following_max_gap_m: float = 25.0
    following_max_lateral_m: float = 1.75
    following_min_heading_cos: float = 0.5
    crossing_min_speed_mps: float = 0.2
    stop_sign_max_right_m: float = 7.0
    stop_sign_min_behind_m: float = 1.0
    postprocess_min_timestamps: int = 2
    postprocess_min_run_timestamps: int = 3
    postprocess_max_relation_distance_m: float = 50.0
    sandbox: SandboxConfig = field(default_factory=SandboxConfig)
    generation: GenerationConfig = field(default_factory=GenerationConfig)
    clip: ClipFilterConfig = field(default_factory=ClipFilterConfig)

    def __post_init__(self) -> None:
        positive = {
            "stationary_max_displacement_m": self.stationary_max_displacement_m,
            "following_max_gap_m": self.following_max_gap_m,
            "following_max_lateral_m": self.following_max_lateral_m,
            "stop_sign_max_right_m": self.stop_sign_max_right_m,
            "postprocess_max_relation_distance_m": self.postprocess_max_relation_distance_m,
        }
        for name, value in positive.items():
            if not value > 0:
                raise ValueError(f"mining.{name} must be > 0, got {value}")
        non_negative = {
            "moving_min_speed_mps": self.moving_min_speed_mps,
            "heading_min_speed_mps": self.heading_min_speed_mps,
            "turn_min_heading_change_deg": self.turn_min_heading_change_deg,
            "turn_partial_min_heading_change_deg": self.turn_partial_min_heading_change_deg,
            "turn_min_yaw_rate_deg_s": self.turn_min_yaw_rate_deg_s,
            "turn_yaw_rate_deadband_deg_s": self.turn_yaw_rate_deadband_deg_s,
            "lane_change_min_lateral_speed_mps": self.lane_change_min_lateral_speed_mps,
            "lane_change_min_lateral_m": self.lane_change_min_lateral_m,
            "crossing_min_speed_mps": self.crossing_min_speed_mps,
            "stop_sign_min_behind_m": self.stop_sign_min_behind_m,
            "postprocess_min_timestamps": self.postprocess_min_timestamps,
            "postprocess_min_run_timestamps": self.postprocess_min_run_timestamps,
        }
        for name, value in non_negative.items():
            if value < 0 or not math.isfinite(value):
                raise ValueError(f"mining.{name} must be a finite number >= 0, got {value}")
        if not 0 <= self.same_direction_max_deg <= self.opposite_direction_min_deg <= 180:
            raise ValueError(
                "mining: need 0 <= same_direction_max_deg <= opposite_direction_min_deg <= 180, got "
                f"{self.same_direction_max_deg} and {self.opposite_direction_min_deg}"
            )
        if not 0 < self.lane_change_max_heading_deg <= 90:
            raise ValueError("mining.lane_change_max_heading_deg must be in (0, 90]")
        if not -1 <= self.following_min_heading_cos <= 1:
            raise ValueError("mining.following_min_heading_cos must be in [-1, 1]")
