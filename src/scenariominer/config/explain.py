"""Configuration of braking-event explanation (braking paper, sections III-D and III-E).

Covers what happens to a KeyIdent event after it is found: the time window its description and
criticality measures look at, how tag segments are merged, which scenario categories the LLM
chooses from, the picture of an event, and the defaults of a search.

Example ``scenariominer.toml``::

    [explain]
    context_before_s = 3.0
    categories_file = "my_categories.toml"
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["ExplainConfig"]


@dataclass(frozen=True)
class ExplainConfig:
    """How braking events are described, classified, measured and shown (``[explain]``).

    Attributes:
        context_before_s: the *analysis window* of an event starts this many seconds before the
            first KeyIdent timestamp, so the description shows how the situation arose (a cut-in
            starts with the guest beside the ego, seconds before any collision risk).
        context_after_s: ... and ends this many seconds after the last KeyIdent timestamp (how the
            ego's braking ended).
        min_segment_s: in a description, a relative heading, position or distance value lasting
            less than this (seconds) is merged into the preceding value (the following one at the
            window start), so a guest near a sector boundary does not flood the text; collision and
            trajectory-overlap risk are never merged; 0 keeps every change.
        pet_horizon_s: post-encroachment time looks this many seconds past the analysis window for
            the second actor to reach the shared region (a pedestrian crossing after the ego stopped).
        min_ego_speed_mps: a log whose ego never reaches this ground speed (m/s) has no braking to
            explain: it is recorded as skipped (``no_ego_motion``) instead of producing events.
        headway_min_speed_mps: time headway is defined only while the ego moves at least this fast
            (m/s); below it the gap divided by the speed is meaningless.
        categories_file: TOML file of scenario categories (``name = "definition"``) given to the
            LLM; empty means the braking paper's categories (see
            :mod:`scenariominer.explain.categories`).
        llm_max_tokens: upper bound on the tokens of one LLM answer; the prompt asks for two short
            sentences (about 80 tokens with the JSON), and the bound caps the time a rambling answer
            takes on the embedded model (an answer cut off there is invalid and gets the repair round).
        show_past_s: the picture of an event draws the past trajectory over this many seconds
            before the key time (solid lines).
        show_future_s: ... and the future trajectory over this many seconds after it (dashed).
        search_k: number of results a search returns by default.
        judge: who decides an event's category: ``"hybrid"`` (the rules where exactly one holds,
            the LLM among the rules' candidates otherwise; the LLM always writes the description
            and a fact-based explanation), ``"llm"`` (the LLM among every category) or
            ``"rules"`` (no model; see :mod:`scenariominer.explain.judge`).
        turn_lookahead_s: the rules' "the ego turns" (``left_oppo``, ``right_ped``) also holds when
            the ego turns within this many seconds after the analysis window: an ego waiting to
            turn left brakes while still facing forward, and turns only once the oncoming car has
            passed; 0 looks at the window only.
    """

    context_before_s: float = 2.0
    context_after_s: float = 1.0
    min_segment_s: float = 0.3
    pet_horizon_s: float = 5.0
    min_ego_speed_mps: float = 1.0
    headway_min_speed_mps: float = 1.0
    categories_file: str = ""
    llm_max_tokens: int = 200
    show_past_s: float = 3.0
    show_future_s: float = 3.0
    search_k: int = 10
    judge: str = "hybrid"
    turn_lookahead_s: float = 8.0

    def __post_init__(self) -> None:
        from scenariominer.config import ConfigError  # late: scenariominer.config imports this module

        for name in (
            "context_before_s",
            "context_after_s",
            "min_segment_s",
            "pet_horizon_s",
            "min_ego_speed_mps",
            "headway_min_speed_mps",
            "show_past_s",
            "show_future_s",
            "turn_lookahead_s",
        ):
            value = getattr(self, name)
            if not value >= 0:
                raise ConfigError(f"explain.{name} must be >= 0, got {value!r}")
        if self.llm_max_tokens < 1:
            raise ConfigError(f"explain.llm_max_tokens must be >= 1, got {self.llm_max_tokens}")
        if self.judge not in ("hybrid", "llm", "rules"):
            raise ConfigError(f"explain.judge must be one of ['hybrid', 'llm', 'rules'], got {self.judge!r}")
        if self.search_k < 1:
            raise ConfigError(f"explain.search_k must be >= 1, got {self.search_k}")
