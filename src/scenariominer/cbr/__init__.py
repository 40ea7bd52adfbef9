"""Case-based reasoning for evasive manoeuvres (seed 002), checked by a kinematic rollout.

* :mod:`.vocab`: the configurable risk types and manoeuvres (defaults: the paper's Table 1).
* :mod:`.cases`: the case base, a corpus table of the store; add (near-duplicates reported and
  skipped), list, show, remove, CSV/JSONL import.
* :mod:`.retrieve`: few-shot cases by caption similarity within the risk type, or at random.
* :mod:`.prompts` / :mod:`.recommend`: the dynamic prompt and one schema-constrained answer.
* :mod:`.rollout`: re-simulation of the ego under a manoeuvre against the recorded road users.
* :mod:`.scenes` / :mod:`.captions` / :mod:`.build`: the labelled synthetic case set.
* :mod:`.query`: an analysed braking event of our own logs as a query and a rollout scene.
* :mod:`.plot`: the picture of a rollout check.
"""

from scenariominer.cbr.cases import AddReport, Case, CaseBase, Duplicate, read_case_file
from scenariominer.cbr.recommend import Query, Recommendation, RecommendSettings, recommend
from scenariominer.cbr.rollout import RECORDED, RolloutOutcome, RolloutScene, rollout, scene_from_log
from scenariominer.cbr.vocab import (
    CbrError,
    Manoeuvre,
    ManoeuvreSet,
    RiskType,
    RiskTypeSet,
    load_manoeuvres,
    load_risk_types,
)

__all__ = [
    "RECORDED",
    "AddReport",
    "Case",
    "CaseBase",
    "CbrError",
    "Duplicate",
    "Manoeuvre",
    "ManoeuvreSet",
    "Query",
    "Recommendation",
    "RecommendSettings",
    "RiskType",
    "RiskTypeSet",
    "RolloutOutcome",
    "RolloutScene",
    "load_manoeuvres",
    "load_risk_types",
    "read_case_file",
    "recommend",
    "rollout",
    "scene_from_log",
]
