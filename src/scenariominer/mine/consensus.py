"""Execution-based consensus: sample several programs, keep the one the others agree with most.

Running a program on a log takes about 0.1 s, so a description's candidates can be judged by what
they *find*: each valid candidate's referred (log, track, timestamp) cells on the validation logs
are compared with every other's (Jaccard; two empty results agree fully), and the candidate with
the highest mean agreement is chosen (the greedy program on a tie, so one sample reproduces the
plain loop). That mean is reported as the confidence; below ``min_agreement``, or with fewer than
two valid candidates to compare, the result is flagged for review.

The first candidate is the fault-tolerant loop's program (greedy, repaired from errors); the others
are sampled from the same first request at ``temperature`` with distinct seeds and only checked and
run, not repaired.
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from scenariominer.config.mining import MiningConfig
from scenariominer.mine.context import LogContext
from scenariominer.mine.loop import GenerationReport, ProgramRunner, generate_program
from scenariominer.mine.sandbox import ProgramResult, check_program, run_program
from scenariominer.mine.synthesis import ProgramSynthesizer

__all__ = [
    "Candidate",
    "ConsensusReport",
    "cell_jaccard",
    "choose_by_consensus",
    "configured_consensus",
    "consensus_program",
]

#: A referred cell: (log id, track id, timestamp index).
Cell = tuple[str, str, int]


@dataclass(frozen=True)
class Candidate:
    """One sampled program and what it found.

    Attributes:
        program: the program text.
        cells: its referred cells on the validation logs, or ``None`` when it failed.
        error: why it failed ("" when it ran).
        seed: sampling seed (``None`` for the greedy loop's program).
    """

    program: str
    cells: frozenset[Cell] | None
    error: str = ""
    seed: int | None = None

    @property
    def ok(self) -> bool:
        """Whether the program ran on every validation log."""
        return self.cells is not None


@dataclass(frozen=True)
class ConsensusReport:
    """The outcome of consensus over one description's candidates.

    Attributes:
        program: the chosen program (``None`` when no candidate ran).
        candidates: every candidate, greedy first.
        agreement: per candidate, its mean Jaccard with the other valid candidates (NaN for a
            failed one, or when it is the only valid one).
        confidence: the chosen candidate's agreement (NaN with fewer than two valid candidates).
        needs_review: whether a person should look (no program, one valid candidate, or low agreement).
        generation: the greedy loop's report.
        seconds: wall time of sampling and running the extra candidates.
    """

    program: str | None
    candidates: tuple[Candidate, ...]
    agreement: tuple[float, ...]
    confidence: float
    needs_review: bool
    generation: GenerationReport | None = None
    seconds: float = 0.0


def cell_jaccard(a: frozenset[Cell], b: frozenset[Cell]) -> float:
    """|a ∩ b| / |a ∪ b|; 1 when both are empty (two programs that find nothing agree)."""
    union = len(a | b)
    return 1.0 if union == 0 else len(a & b) / union


def choose_by_consensus(candidates: Sequence[Candidate], min_agreement: float = 0.5) -> ConsensusReport:
    """Pick the valid candidate with the highest mean agreement with the other valid ones.

    Ties go to the earliest candidate (the greedy program when it is valid).
    """
    valid = [i for i, c in enumerate(candidates) if c.ok]
    agreement = [math.nan] * len(candidates)
    if not valid:
        return ConsensusReport(None, tuple(candidates), tuple(agreement), math.nan, True)
    if len(valid) == 1:
        return ConsensusReport(
            candidates[valid[0]].program, tuple(candidates), tuple(agreement), math.nan, True
        )
    sets = [candidates[i].cells or frozenset() for i in valid]
    pair = np.array([[cell_jaccard(x, y) for y in sets] for x in sets])
    means = (pair.sum(axis=1) - 1.0) / (len(valid) - 1)  # without the self-agreement of 1
    for k, i in enumerate(valid):
        agreement[i] = float(means[k])
    best = valid[int(np.argmax(means))]  # argmax keeps the first maximum
    confidence = agreement[best]
    return ConsensusReport(
        candidates[best].program, tuple(candidates), tuple(agreement), confidence, confidence < min_agreement
    )


def _cells(
    program: str, validation: Sequence[LogContext], description: str, runner: ProgramRunner
) -> tuple[frozenset[Cell] | None, str]:
    found: set[Cell] = set()
    for ctx in validation:
        result = runner(program, ctx, description)
        if result.error is not None or result.scenario is None:
            return None, str(result.error or "no scenario")
        ids = ctx.log.track_ids
        rows, cols = np.nonzero(result.scenario.referred)
        found.update((ctx.log_id, str(ids[r]), int(c)) for r, c in zip(rows, cols, strict=True))
    return frozenset(found), ""


def consensus_program(
    description: str,
    synthesizer: ProgramSynthesizer,
    validation: Sequence[LogContext],
    *,
    samples: int = 3,
    temperature: float = 0.7,
    min_agreement: float = 0.5,
    config: MiningConfig | None = None,
    runner: ProgramRunner | None = None,
) -> ConsensusReport:
    """Write ``samples`` candidate programs for ``description`` and choose one by consensus.

    Args:
        description: the scenario description.
        synthesizer: prompt composition and model calls.
        validation: logs every candidate runs on (their outputs are compared).
        samples: candidates in all, the greedy loop's program included (1 = the plain loop).
        temperature: sampling temperature of the extra candidates.
        min_agreement: below this confidence the result is flagged for review.
        config: mining configuration (the loop's K, sandbox limits).
        runner: how programs are run (default: the sandbox).

    Raises:
        ValueError: no validation log, or ``samples`` < 1.
        BackendError: a model call failed.
    """
    if samples < 1:
        raise ValueError(f"samples must be >= 1, got {samples}")
    if not validation:
        raise ValueError("consensus_program needs at least one validation log")

    def sandboxed(program: str, ctx: LogContext, desc: str) -> ProgramResult:
        return run_program(program, ctx, description=desc, config=config)

    run = runner or sandboxed
    report = generate_program(description, synthesizer, validation, config=config, runner=runner)
    t0 = time.perf_counter()
    candidates: list[Candidate] = []
    if report.program is not None:
        cells, error = _cells(report.program, validation, description, run)
        candidates.append(Candidate(report.program, cells, error))
    first = synthesizer.first_messages(description)
    for seed in range(1, samples if report.program is not None else samples + 1):
        generation = synthesizer.generate(first, temperature=temperature, seed=seed)
        problem = check_program(generation.program, (config or validation[0].config).sandbox)
        if problem is not None:
            candidates.append(Candidate(generation.program, None, str(problem), seed))
            continue
        cells, error = _cells(generation.program, validation, description, run)
        candidates.append(Candidate(generation.program, cells, error, seed))
    chosen = choose_by_consensus(candidates, min_agreement)
    return ConsensusReport(
        chosen.program,
        chosen.candidates,
        chosen.agreement,
        chosen.confidence,
        chosen.needs_review,
        generation=report,
        seconds=time.perf_counter() - t0,
    )


def configured_consensus(
    description: str,
    synthesizer: ProgramSynthesizer,
    validation: Sequence[LogContext],
    config: MiningConfig,
    runner: ProgramRunner | None = None,
) -> ConsensusReport:
    """:func:`consensus_program` with the sample count, temperature and threshold of ``config``."""
    gen = config.generation
    return consensus_program(
        description,
        synthesizer,
        validation,
        samples=gen.consensus_samples,
        temperature=gen.consensus_temperature,
        min_agreement=gen.consensus_min_agreement,
        config=config,
        runner=runner,
    )
