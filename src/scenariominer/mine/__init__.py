"""Program-based scenario mining (RefAV-style): atomic predicates, scenarios, sandboxed programs.

* :mod:`~scenariominer.mine.context`: :class:`LogContext`, the per-log arrays every predicate shares;
* :mod:`~scenariominer.mine.scenario`: :class:`Scenario` and its Boolean composition;
* :mod:`~scenariominer.mine.predicates`: the atomic functions mining programs call (the DSL);
* :mod:`~scenariominer.mine.sandbox`: checking and running programs safely;
* :mod:`~scenariominer.mine.programs`: the hand-written example bank.
"""

from scenariominer.mine.context import LogContext, MapIndex, MapRequiredError
from scenariominer.mine.predicates import DSL_FUNCTIONS, library_reference
from scenariominer.mine.programs import ExampleProgram, load_examples
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

__all__ = [
    "DSL_FUNCTIONS",
    "ErrorKind",
    "ExampleProgram",
    "LogContext",
    "MapIndex",
    "MapRequiredError",
    "ProgramError",
    "ProgramResult",
    "Scenario",
    "check_program",
    "library_reference",
    "load_examples",
    "postprocess_scenario",
    "reverse_relationship",
    "run_program",
    "run_trusted_program",
    "scenario_and",
    "scenario_not",
    "scenario_or",
]
