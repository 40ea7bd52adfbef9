"""The shared vocabulary of choices that several layers (stages, api/, cli/, server/) name.

Kept free of heavy imports: the command line builds its options from these enums before it imports
any stage.
"""

from __future__ import annotations

from enum import StrEnum

__all__ = ["ExportFormat", "Judge", "SortKey"]


class SortKey(StrEnum):
    """Orders of braking-event search results.

    Attributes:
        SCORE: best cosine similarity first (text queries; log and time order otherwise).
        TTC: smallest minimum time-to-collision first.
        DECEL: largest peak deceleration first.
        PET: smallest post-encroachment time first.
        HEADWAY: smallest time headway first.
    """

    SCORE = "score"
    TTC = "ttc"
    DECEL = "decel"
    PET = "pet"
    HEADWAY = "headway"


class ExportFormat(StrEnum):
    """Output formats of ``mine --export``."""

    AV2 = "av2"
    """The Argoverse 2 scenario-mining submission pickle."""


class Judge(StrEnum):
    """Who decides a braking event's category (see :mod:`scenariominer.explain.judge`).

    Attributes:
        RULES: the first rule that holds; no model.
        LLM: the LLM among every category.
        HYBRID: the rules where exactly one holds, the LLM among the rules' candidates otherwise;
            the LLM always writes the description and the explanation.
    """

    RULES = "rules"
    LLM = "llm"
    HYBRID = "hybrid"
