"""Program-based scenario mining (RefAV-style): atomic predicates, scenarios, sandboxed programs.

* :mod:`~scenariominer.mine.context`: :class:`LogContext`, the per-log arrays every predicate shares;
* :mod:`~scenariominer.mine.scenario`: :class:`Scenario` and its Boolean composition;
* :mod:`~scenariominer.mine.dsl`: the atomic functions mining programs call (the DSL);
* :mod:`~scenariominer.mine.sandbox`: checking and running programs safely;
* :mod:`~scenariominer.mine.programs`: the hand-written example bank;
* :mod:`~scenariominer.mine.prompts`, :mod:`~scenariominer.mine.synthesis`: writing programs with
  a language model (few-shot examples chosen by embedding similarity);
* :mod:`~scenariominer.mine.loop`: fault-tolerant iterative generation (check, run, repair, K tries);
* :mod:`~scenariominer.mine.keywords`, :mod:`~scenariominer.mine.clip_filter`: the optional
  coarse-to-fine filter over camera crops;
* :mod:`~scenariominer.mine.export`: store tables and the Argoverse 2 submission;
* :mod:`~scenariominer.mine.query`: one query over many logs (the stage the ``mine`` use case of
  :mod:`scenariominer.api.mining` calls).

Importing this package loads neither a language model, spaCy, torch nor transformers.
"""

from scenariominer.mine.clip_filter import (
    CandidateTracklets,
    ClipEncoder,
    CropEncoder,
    CropTable,
    rank_crops,
)
from scenariominer.mine.context import LogContext, MapIndex, MapRequiredError
from scenariominer.mine.dsl import DSL_FUNCTIONS, library_reference
from scenariominer.mine.export import (
    LogMatches,
    ObjectLabel,
    av2_frames,
    evaluation_timestamps,
    read_av2_submission,
    write_av2_submission,
)
from scenariominer.mine.keywords import KeywordSet, extract_keywords
from scenariominer.mine.loop import (
    Attempt,
    GenerationReport,
    GenerationStatus,
    ProgramCache,
    generate_program,
)
from scenariominer.mine.programs import ExampleProgram, load_examples
from scenariominer.mine.prompts import PROMPT_VERSION
from scenariominer.mine.query import (
    LogFailure,
    ProgramSource,
    QueryReport,
    av2_submission,
    mine_logs,
)
from scenariominer.mine.sandbox import (
    ErrorKind,
    ProgramError,
    ProgramResult,
    check_program,
    run_program,
    run_trusted_program,
)
from scenariominer.mine.scenario import (
    Scenario,
    postprocess_scenario,
    reverse_relationship,
    scenario_and,
    scenario_not,
    scenario_or,
)
from scenariominer.mine.synthesis import ExampleSelector, ProgramSynthesizer, extract_program

__all__ = [
    "DSL_FUNCTIONS",
    "PROMPT_VERSION",
    "Attempt",
    "CandidateTracklets",
    "ClipEncoder",
    "CropEncoder",
    "CropTable",
    "ErrorKind",
    "ExampleProgram",
    "ExampleSelector",
    "GenerationReport",
    "GenerationStatus",
    "KeywordSet",
    "LogContext",
    "LogFailure",
    "LogMatches",
    "MapIndex",
    "MapRequiredError",
    "ObjectLabel",
    "ProgramCache",
    "ProgramError",
    "ProgramResult",
    "ProgramSource",
    "ProgramSynthesizer",
    "QueryReport",
    "Scenario",
    "av2_frames",
    "av2_submission",
    "check_program",
    "evaluation_timestamps",
    "extract_keywords",
    "extract_program",
    "generate_program",
    "library_reference",
    "load_examples",
    "mine_logs",
    "postprocess_scenario",
    "rank_crops",
    "read_av2_submission",
    "reverse_relationship",
    "run_program",
    "run_trusted_program",
    "scenario_and",
    "scenario_not",
    "scenario_or",
    "write_av2_submission",
]
