"""Shared check of the phrase-rule tests: a description read in full and the program it builds."""

from __future__ import annotations

from scenariominer.mine.plan_program import compile_plan
from scenariominer.mine.plan_reader import read_plan


def assert_program_has(description: str, calls: list[str]) -> str:
    """The program the rules build for ``description``, asserting it is read in full and holds ``calls``."""
    plan = read_plan(description)
    assert plan is not None, f"not read in full: {description!r}"
    program = compile_plan(plan).program
    for call in calls:
        assert call in program, program
    return program
