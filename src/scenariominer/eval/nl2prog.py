"""Scoring the description -> program step on an evaluation set of our own (issue 18, item 5).

The set (``nl2prog_set.toml``, shipped beside this module) holds natural-language descriptions,
each with a hand-written reference program in the mining DSL, a split and family tags:

* ``dev``: may be looked at while tuning prompts;
* ``holdout``: never a few-shot example and never used for prompt tuning. It lives outside the
  example-bank files, so :func:`~scenariominer.mine.programs.load_examples` never reads it, and
  the few-shot selector of :func:`generator_provider` additionally drops any bank entry with a
  holdout description (there is none: a test keeps it so);
* ``published``: a second hold-out, held like ``holdout``, whose descriptions are not ours: a
  seeded sample of the descriptions RefAV published for the Argoverse 2 scenario-mining task
  (their wording, our reference programs), drawn before the phrase rules
  (:mod:`~scenariominer.mine.plan_reader`) were extended from the rest of that list;
* ``challenge``: a third hold-out, held like ``holdout``, also not ours: a seeded sample
  (``random.Random(2026)``, 36) of the Argoverse 2 scenario-mining 2025 challenge test
  descriptions (as listed in ``refAV/llm_prompting/all_descriptions.txt`` of JiangXiaobai00/SML,
  MIT), taken from those without a near-identical description already in use and answerable over
  tracked boxes and the map (colours, lights, intent, speed limits and sub-types AV2 does not
  annotate filtered out first); their wording, our reference programs; drawn before the phrase
  rules were extended from the rest of that list (``tests/mine/data/challenge_dev.txt``).
* ``fresh``: a fourth hold-out (session 15), written after every other split was spent, by a
  separate pass that did not read the phrase rules, the prompts, the example bank or the other
  splits (only the DSL's docstrings), with reference programs checked to run on the three real
  logs; run once with the rules frozen.

:func:`evaluate_nl2prog` asks a *candidate provider* (a ``Callable[[str], str | None]``:
description in, program or ``None`` out) for a program per description and runs it next to the
reference on every log. Per (description, log) cell the score is the Jaccard index of the two
sets of referred (track id, timestamp) pairs. Aggregates:

* **mean Jaccard** over the cells where the reference finds something (a candidate that did not
  run scores 0 there); cells where the reference finds nothing carry no overlap to measure and
  are reported as *empty agreement* instead (the share where the candidate also finds nothing);
* **runnable share**: descriptions for which the provider gave a program that ran without error
  on every log the reference ran on;
* the same numbers **per family**.

Providers: :func:`generator_provider` (the language-model loop with a few-shot selector over the
shipped bank only, leave-one-out, optionally without the bank entries most similar to each
description), :func:`reference_provider` (the reference itself: a sanity check scoring 1) and
:func:`bank_provider` (the bank program with exactly the same description, if any).
"""

from __future__ import annotations

import re
import time
import tomllib
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass, replace
from importlib import resources
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from scenariominer import errors as _errors
from scenariominer.llm.embeddings import Embedder
from scenariominer.mine.context import LogContext
from scenariominer.mine.programs import ExampleProgram, load_examples
from scenariominer.mine.sandbox import ProgramResult, run_program, run_trusted_program
from scenariominer.mine.scenario import Scenario
from scenariominer.mine.synthesis import ExampleSelector, normalize_description

if TYPE_CHECKING:
    from scenariominer.config import Config
    from scenariominer.llm.usage import UsageCounter
    from scenariominer.mine.loop import ProgramCache
    from scenariominer.mine.synthesis import ProgramSynthesizer

__all__ = [
    "EVAL_SET_FILE",
    "FAMILIES",
    "SPLITS",
    "BankOnlySelector",
    "CandidateProvider",
    "CellScore",
    "DescriptionScore",
    "EvalEntry",
    "EvalSetError",
    "FamilyScore",
    "GeneratorProvider",
    "Nl2ProgEvaluation",
    "ProgramRunner",
    "bank_provider",
    "description_key",
    "evaluate_nl2prog",
    "family_counts",
    "generator_provider",
    "jaccard",
    "load_eval_set",
    "nearest_bank_provider",
    "parse_eval_set",
    "reference_provider",
    "referred_cells",
    "similar_bank_entries",
]

#: Name of the evaluation-set file shipped in this package.
EVAL_SET_FILE = "nl2prog_set.toml"

#: Who reads a description into a plan: the phrase rules (every word; every word of the model's
#: rewording; some words; some words of the rewording), or the model.
READERS: tuple[str, ...] = ("rules", "reworded", "partial", "reworded-partial", "model")

#: The splits of the set.
SPLITS: tuple[str, ...] = (
    "dev",
    "holdout",
    "published",
    "challenge",
    "fresh",
    "fresh2",
    "fresh3",
    "fresh4",
    "fresh5",
    "fresh6",
    "fresh7",
    "fresh8",
    "fresh9",
    "fresh10",
    "fresh11",
    "fresh12",
    "fresh13",
    "fresh14",
    "fresh15",
    "fresh16",
    "fresh17",
    "fresh18",
    "fresh19",
    "fresh20",
    "fresh21",
    "fresh22",
    "fresh23",
    "fresh24",
    "fresh25",
    "fresh26",
    "fresh27",
    "fresh28",
    "fresh29",
    "fresh30",
    "fresh31",
    "fresh32",
    "fresh33",
    "fresh34",
    "fresh35",
    "fresh36",
    "fresh37",
    "fresh38",
    "fresh39",
    "fresh40",
    "fresh41",
    "fresh42",
    "fresh43",
    "fresh44",
    "fresh45",
    "fresh46",
    "fresh47",
    "fresh48",
    "fresh49",
    "fresh50",
    "fresh51",
    "fresh52",
    "fresh53",
    "fresh54",
    "fresh55",
    "fresh56",
    "fresh59",
    "fresh60",
    "fresh57",
    "fresh58",
    "fresh61",
    "fresh62",
    "fresh63",
    "fresh64",
    "fresh65",
    "fresh66",
    "fresh67",
    "fresh68",
    "fresh69",
    "fresh70",
    "fresh71",
    "fresh72",
    "fresh73",
    "fresh74",
    "fresh75",
    "fresh76",
    "fresh77",
    "fresh78",
    "fresh79",
    "fresh80",
    "fresh81",
    "fresh82",
    "fresh83",
    "fresh84",
    "fresh85",
    "fresh86",
    "fresh87",
    "fresh88",
    "fresh89",
    "fresh90",
    "fresh91",
    "fresh92",
    "fresh93",
    "fresh94",
    "fresh95",
    "fresh96",
    "fresh97",
    "fresh98",
    "fresh99",
)

#: The splits held out from tuning: never few-shot examples, never read while writing prompts or rules.
#: Every split but ``dev`` (a new split is held out by being listed in :data:`SPLITS`).
HELD_OUT_SPLITS: tuple[str, ...] = tuple(split for split in SPLITS if split != "dev")

#: Family tags an entry may carry (what its description exercises); the set covers every one.
FAMILIES: dict[str, str] = {
    "category": "a specific Argoverse 2 category (trucks, bollards, scooters, strollers, ...)",
    "category_group": "a category group: VEHICLE (incl. bicycles), VULNERABLE_ROAD_USER or ANY",
    "motion": "speed, acceleration or lateral acceleration of the object itself",
    "stopping": "stopped, standing still, parked or braking",
    "turning": "turning left or right",
    "lane_change": "changing lanes",
    "relation": "a relation between two sets of objects",
    "direction": "objects in a relative direction (ahead, behind, left, right)",
    "heading": "moving toward something, or travelling in a direction relative to it",
    "facing": "pointing at something",
    "following": "following a lead object in the same lane",
    "near": "near other objects, counts of nearby objects",
    "crossing": "crossing in front of or past something, pedestrian crossings",
    "map": "needs the HD map",
    "lane": "lanes: lane types, same lane, side of the road",
    "intersection": "on or near an intersection",
    "stop_sign": "stop signs",
    "drivable_area": "the drivable area",
    "composition": "scenario_and / scenario_or / scenario_not(is_category) / reverse_relationship",
    "negation": "scenario_not of a predicate (not on the road, not turning, ...)",
    "pedestrian": "pedestrians",
    "cyclist": "bicycles and cyclists",
    "bus": "buses, school buses, bus lanes",
    "ego": "the ego vehicle",
}

#: Runs one program on one log: ``(program, context, description) -> ProgramResult``.
ProgramRunner = Callable[[str, LogContext, str], ProgramResult]

#: Writes a program for a description (``None``: no program).
CandidateProvider = Callable[[str], str | None]


class EvalSetError(_errors.EvaluationError):
    """The evaluation-set file is unreadable or malformed; the message names the file and entry."""


# ====================================================================== the set


@dataclass(frozen=True)
class EvalEntry:
    """One description of the evaluation set with its reference program.

    Attributes:
        description: the natural-language description.
        program: the hand-written reference program (mining DSL, ends with ``output_scenario``).
        split: one of :data:`SPLITS`.
        families: what the description exercises (keys of :data:`FAMILIES`).
    """

    description: str
    program: str
    split: str
    families: tuple[str, ...]


def _entry(raw: Any, index: int, source: str) -> EvalEntry:
    where = f"{source}: entry {index + 1}"
    if not isinstance(raw, dict):
        raise EvalSetError(f"{where} is not a table")
    unknown = sorted(set(raw) - {"description", "program", "split", "family"})
    if unknown:
        raise EvalSetError(f"{where} has unknown key(s) {unknown}")
    description, program, split = raw.get("description"), raw.get("program"), raw.get("split")
    if not isinstance(description, str) or not description.strip():
        raise EvalSetError(f"{where} needs a non-empty string 'description'")
    where = f"{where} ({description!r})"
    if not isinstance(program, str) or "output_scenario" not in program:
        raise EvalSetError(f"{where} needs a 'program' string that calls output_scenario")
    if split not in SPLITS:
        raise EvalSetError(f"{where}: 'split' must be one of {list(SPLITS)}, got {split!r}")
    family = raw.get("family")
    if not isinstance(family, list) or not family or not all(isinstance(f, str) for f in family):
        raise EvalSetError(f"{where}: 'family' must be a non-empty list of strings")
    bad = sorted(set(family) - set(FAMILIES))
    if bad:
        raise EvalSetError(f"{where}: unknown family tag(s) {bad}; known: {sorted(FAMILIES)}")
    return EvalEntry(description.strip(), program.strip() + "\n", split, tuple(family))


def parse_eval_set(text: str, source: str = "<text>") -> tuple[EvalEntry, ...]:
    """Parse evaluation-set TOML text (an array of ``[[entry]]`` tables).

    Raises:
        EvalSetError: invalid TOML, a malformed entry, or two entries with the same description.
    """
    try:
        doc = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise EvalSetError(f"{source}: not valid TOML ({exc})") from None
    raw = doc.get("entry")
    if not isinstance(raw, list):
        raise EvalSetError(f"{source}: expected an array of [[entry]] tables")
    entries = tuple(_entry(r, i, source) for i, r in enumerate(raw))
    seen: set[str] = set()
    for e in entries:
        key = normalize_description(e.description)
        if key in seen:
            raise EvalSetError(f"{source}: the description {e.description!r} occurs twice")
        seen.add(key)
    return entries


def load_eval_set(split: str | None = None, path: str | Path | None = None) -> tuple[EvalEntry, ...]:
    """The evaluation set (the shipped file, or ``path``), optionally one split only.

    Args:
        split: one of :data:`SPLITS`, or ``None``/``all`` for every split.
        path: a TOML file of the same format instead of the shipped set.

    Raises:
        EvalSetError: unknown split, unreadable or malformed file.
    """
    if split not in (None, "all", *SPLITS):
        raise EvalSetError(f"unknown split {split!r}; use one of {[*SPLITS, 'all']}")
    if path is None:
        text = resources.files(__package__).joinpath(EVAL_SET_FILE).read_text(encoding="utf-8")
        source = EVAL_SET_FILE
    else:
        try:
            text, source = Path(path).read_text(encoding="utf-8"), str(path)
        except OSError as exc:
            raise EvalSetError(f"{path}: cannot read the evaluation set ({exc.strerror or exc})") from None
    entries = parse_eval_set(text, source)
    return entries if split in (None, "all") else tuple(e for e in entries if e.split == split)


_STOP_WORDS = frozenset(
    {
        *("a", "an", "the", "of", "to", "its", "their", "his", "her", "them", "it", "on", "in", "at"),
        *("by", "with", "and", "or", "is", "are", "that", "which", "who", "some", "any", "another"),
        *("other", "each"),
    }
)


def description_key(text: str) -> str:
    """A description reduced to its content words, for spotting near-identical descriptions.

    Lower-cased, punctuation and stop words dropped, plural ``-s`` removed, words sorted: "the
    vehicles with a bicycle to their right" and "vehicle with bicycle to its right." share a key.
    """
    words = re.findall(r"[a-z0-9/]+", normalize_description(text))
    out = set()
    for w in words:
        if w in _STOP_WORDS:
            continue
        if len(w) > 3 and w.endswith("s") and not w.endswith("ss"):
            w = w[:-1]
        out.add(w)
    return " ".join(sorted(out))


def similar_bank_entries(
    description: str, bank: Iterable[ExampleProgram], min_overlap: float = 0.6
) -> list[ExampleProgram]:
    """Bank entries whose content words overlap ``description``'s by at least ``min_overlap`` (Jaccard).

    Used to check that no holdout description has a near-identical bank entry.
    """
    mine = set(description_key(description).split())
    out = []
    for e in bank:
        theirs = set(description_key(e.description).split())
        union = mine | theirs
        if union and len(mine & theirs) / len(union) >= min_overlap:
            out.append(e)
    return out


# ====================================================================== scoring

#: A referred cell: (track id, timestamp in ns).
Cell = tuple[str, int]


def referred_cells(scenario: Scenario) -> frozenset[Cell]:
    """The (track id, timestamp ns) pairs a scenario refers to."""
    return frozenset(
        (track, int(t)) for track, stamps in scenario.referred_timestamps().items() for t in stamps.tolist()
    )


def jaccard(a: frozenset[Cell], b: frozenset[Cell]) -> float:
    """``|a & b| / |a | b|``; 1 when both are empty."""
    union = len(a | b)
    return 1.0 if union == 0 else len(a & b) / union


@dataclass(frozen=True)
class CellScore:
    """A candidate against the reference on one log.

    Attributes:
        log_id: the log.
        reference_cells: referred (track, timestamp) pairs of the reference (0 when it failed).
        candidate_cells: referred pairs of the candidate (0 when it did not run).
        shared_cells: pairs both refer to.
        jaccard: the Jaccard index (0 when the candidate did not run; 1 when both find nothing);
            ``None`` when the reference itself failed on this log (the cell is not scored).
        reference_error: why the reference failed (e.g. a log without a map), else ``None``.
        candidate_error: why the candidate failed on this log, else ``None``.
    """

    log_id: str
    reference_cells: int
    candidate_cells: int
    shared_cells: int
    jaccard: float | None
    reference_error: str | None = None
    candidate_error: str | None = None

    @property
    def scored(self) -> bool:
        """Whether the cell counts for the mean Jaccard: the reference ran and found something."""
        return self.reference_error is None and self.reference_cells > 0


@dataclass(frozen=True)
class DescriptionScore:
    """A candidate program for one description, scored on every log.

    Attributes:
        description: the description.
        split: its split.
        families: its family tags.
        program: the candidate program (``None`` when the provider gave none).
        runnable: a program was given and ran without error on every log the reference ran on.
        error: the first failure (provider error, no program, or the program's error), else ``None``.
        cells: one score per log.
        provider_s: seconds the provider took (e.g. the model loop).
        execution_s: seconds running the candidate on the logs.
        reader: who read the description into a plan: ``rules`` (the phrase rules, every word;
            :mod:`scenariominer.mine.plan_reader`), ``partial`` (the phrase rules, some words
            left out) or ``model``.
    """

    description: str
    split: str
    families: tuple[str, ...]
    program: str | None
    runnable: bool
    error: str | None
    cells: tuple[CellScore, ...]
    provider_s: float
    execution_s: float
    reader: str = "model"

    @property
    def read_by_rules(self) -> bool:
        """Whether the phrase rules read every word of the description."""
        return self.reader == "rules"

    @property
    def scored_cells(self) -> tuple[CellScore, ...]:
        """The logs where the reference finds something."""
        return tuple(c for c in self.cells if c.scored)

    @property
    def mean_jaccard(self) -> float | None:
        """Mean Jaccard over :attr:`scored_cells` (``None`` when the reference finds nothing)."""
        scored = [c.jaccard for c in self.scored_cells if c.jaccard is not None]
        return float(np.mean(scored)) if scored else None

    @property
    def seconds(self) -> float:
        """Provider plus candidate execution time."""
        return self.provider_s + self.execution_s

    def to_json_dict(self) -> dict[str, Any]:
        """Plain-JSON form."""
        mj = self.mean_jaccard
        return {
            "description": self.description,
            "split": self.split,
            "families": list(self.families),
            "runnable": self.runnable,
            "mean_jaccard": None if mj is None else round(mj, 4),
            "error": self.error,
            "provider_s": round(self.provider_s, 3),
            "execution_s": round(self.execution_s, 3),
            "read_by_rules": self.read_by_rules,
            "reader": self.reader,
            "program": self.program,
            "logs": [
                {
                    "log_id": c.log_id,
                    "reference_cells": c.reference_cells,
                    "candidate_cells": c.candidate_cells,
                    "shared_cells": c.shared_cells,
                    "jaccard": None if c.jaccard is None else round(c.jaccard, 4),
                    "reference_error": c.reference_error,
                    "candidate_error": c.candidate_error,
                }
                for c in self.cells
            ],
        }


@dataclass(frozen=True)
class FamilyScore:
    """The aggregates over the descriptions of one family.

    Attributes:
        family: the family tag.
        n_descriptions: descriptions carrying the tag.
        n_runnable: of those, how many got a runnable candidate.
        n_scored_cells: (description, log) cells where the reference finds something.
        mean_jaccard: mean Jaccard over those cells (``None`` when there are none).
    """

    family: str
    n_descriptions: int
    n_runnable: int
    n_scored_cells: int
    mean_jaccard: float | None

    @property
    def runnable_share(self) -> float:
        """Share of the family's descriptions with a runnable candidate."""
        return self.n_runnable / self.n_descriptions if self.n_descriptions else float("nan")

    def to_json_dict(self) -> dict[str, Any]:
        """Plain-JSON form (without the tag, which keys it)."""
        return {
            "n_descriptions": self.n_descriptions,
            "n_runnable": self.n_runnable,
            "n_scored_cells": self.n_scored_cells,
            "mean_jaccard": None if self.mean_jaccard is None else round(self.mean_jaccard, 4),
        }


def _aggregate(scores: Sequence[DescriptionScore]) -> tuple[int, int, float | None]:
    runnable = sum(s.runnable for s in scores)
    values = [c.jaccard for s in scores for c in s.scored_cells if c.jaccard is not None]
    return runnable, len(values), (float(np.mean(values)) if values else None)


@dataclass(frozen=True)
class Nl2ProgEvaluation:
    """The scores of one provider on a set of descriptions over a set of logs.

    Attributes:
        descriptions: one score per description, in set order.
        log_ids: the logs, in order.
    """

    descriptions: tuple[DescriptionScore, ...]
    log_ids: tuple[str, ...]

    @property
    def n_runnable(self) -> int:
        """Descriptions with a runnable candidate."""
        return sum(s.runnable for s in self.descriptions)

    @property
    def runnable_share(self) -> float:
        """Share of descriptions with a runnable candidate (NaN without descriptions)."""
        return self.n_runnable / len(self.descriptions) if self.descriptions else float("nan")

    @property
    def n_scored_cells(self) -> int:
        """(description, log) cells where the reference finds something."""
        return _aggregate(self.descriptions)[1]

    @property
    def mean_jaccard(self) -> float | None:
        """Mean Jaccard over the cells where the reference finds something."""
        return _aggregate(self.descriptions)[2]

    @property
    def empty_cells(self) -> tuple[int, int]:
        """``(agreeing, total)`` over the cells where the reference ran and found nothing.

        ``agreeing`` counts those where the candidate ran and found nothing too.
        """
        empty = [c for s in self.descriptions for c in s.cells if c.reference_error is None and not c.scored]
        return sum(c.candidate_error is None and c.candidate_cells == 0 for c in empty), len(empty)

    @property
    def n_reference_failures(self) -> int:
        """(description, log) cells where the reference failed (not scored)."""
        return sum(c.reference_error is not None for s in self.descriptions for c in s.cells)

    @property
    def seconds(self) -> float:
        """Provider plus candidate time over all descriptions."""
        return sum(s.seconds for s in self.descriptions)

    def per_family(self) -> dict[str, FamilyScore]:
        """Aggregates per family tag (every tag of :data:`FAMILIES` that occurs), in tag order."""
        out: dict[str, FamilyScore] = {}
        for family in FAMILIES:
            members = [s for s in self.descriptions if family in s.families]
            if members:
                runnable, n_cells, mean = _aggregate(members)
                out[family] = FamilyScore(family, len(members), runnable, n_cells, mean)
        return out

    def by_reader(self) -> dict[str, FamilyScore]:
        """Aggregates per reader: the phrase rules in full (``rules``), in part (``partial``), the model."""
        out: dict[str, FamilyScore] = {}
        for name in READERS:
            members = [s for s in self.descriptions if s.reader == name]
            runnable, n_cells, mean = _aggregate(members)
            out[name] = FamilyScore(name, len(members), runnable, n_cells, mean)
        return out

    def to_json_dict(self) -> dict[str, Any]:
        """Plain-JSON form: the summary, the per-family table and every description."""
        agree, empty = self.empty_cells
        mj = self.mean_jaccard
        return {
            "n_descriptions": len(self.descriptions),
            "log_ids": list(self.log_ids),
            "n_runnable": self.n_runnable,
            "runnable_share": round(self.runnable_share, 4) if self.descriptions else None,
            "mean_jaccard": None if mj is None else round(mj, 4),
            "n_scored_cells": self.n_scored_cells,
            "empty_cells": empty,
            "empty_cells_agreeing": agree,
            "n_reference_failures": self.n_reference_failures,
            "seconds": round(self.seconds, 3),
            "families": {f.family: f.to_json_dict() for f in self.per_family().values()},
            "read_by": {f.family: f.to_json_dict() for f in self.by_reader().values()},
            "descriptions": [s.to_json_dict() for s in self.descriptions],
        }


def _trusted(program: str, context: LogContext, description: str) -> ProgramResult:
    return run_trusted_program(program, context, description=description)


def _sandboxed(program: str, context: LogContext, description: str) -> ProgramResult:
    return run_program(program, context, description=description)


def _score_entry(
    entry: EvalEntry,
    contexts: Sequence[LogContext],
    provider: CandidateProvider,
    candidate_runner: ProgramRunner,
    reference_runner: ProgramRunner,
    reference_cache: dict[tuple[str, str], ProgramResult],
) -> DescriptionScore:
    t0 = time.perf_counter()
    error: str | None = None
    try:
        program = provider(entry.description)
    except _errors.LLMError:
        raise  # the model is missing or unreachable: every description would fail the same way
    except Exception as exc:  # a faulty provider makes this description not runnable
        program, error = None, f"the provider failed: {type(exc).__name__}: {exc}"
    provider_s = time.perf_counter() - t0
    if program is None and error is None:
        error = "the provider gave no program"
    cells: list[CellScore] = []
    execution_s = 0.0
    for ctx in contexts:
        key = (entry.description, ctx.log_id)
        if key not in reference_cache:
            reference_cache[key] = reference_runner(entry.program, ctx, entry.description)
        ref = reference_cache[key]
        ref_error = None if ref.ok else (ref.error.feedback() if ref.error else "no scenario")
        ref_cells = referred_cells(ref.scenario) if ref.scenario is not None and ref_error is None else None
        cand_cells: frozenset[Cell] | None = None
        cand_error = error
        if program is not None:
            t1 = time.perf_counter()
            result = candidate_runner(program, ctx, entry.description)
            execution_s += time.perf_counter() - t1
            if result.ok and result.scenario is not None:
                cand_cells = referred_cells(result.scenario)
            else:
                cand_error = result.error.feedback() if result.error else "the program gave no scenario"
        if ref_cells is None:
            score = None
        elif cand_cells is None:
            score = 0.0
        else:
            score = jaccard(ref_cells, cand_cells)
        shared = len(ref_cells & cand_cells) if ref_cells is not None and cand_cells is not None else 0
        cells.append(
            CellScore(
                ctx.log_id,
                len(ref_cells) if ref_cells is not None else 0,
                len(cand_cells) if cand_cells is not None else 0,
                shared,
                score,
                ref_error,
                cand_error,
            )
        )
    ran_everywhere = all(c.candidate_error is None for c in cells if c.reference_error is None)
    runnable = program is not None and ran_everywhere
    if error is None and not runnable:
        error = next((c.candidate_error for c in cells if c.candidate_error is not None), None)
    return DescriptionScore(
        entry.description,
        entry.split,
        entry.families,
        program,
        runnable,
        error,
        tuple(cells),
        provider_s,
        execution_s,
    )


def evaluate_nl2prog(
    entries: Sequence[EvalEntry],
    contexts: Sequence[LogContext],
    provider: CandidateProvider,
    *,
    candidate_runner: ProgramRunner | None = None,
    reference_runner: ProgramRunner | None = None,
    on_description: Callable[[DescriptionScore], None] | None = None,
    reader: Callable[[str], str] | None = None,
) -> Nl2ProgEvaluation:
    """Score ``provider``'s programs against the references on every log.

    Args:
        entries: the descriptions (e.g. :func:`load_eval_set` of one split).
        contexts: the logs.
        provider: description in, program (or ``None``) out; called once per description. An
            exception from it makes that description not runnable, except an
            :class:`~scenariominer.errors.LLMError` (model missing or unreachable), which propagates.
        candidate_runner: how candidate programs run; default the resource-limited sandbox
            (:func:`~scenariominer.mine.sandbox.run_program`), as they may be model-written.
        reference_runner: how reference programs run; default in-process (trusted).
        on_description: called with each description's score (progress).
        reader: who the provider's plan step has read a description (one of :data:`READERS`;
            labels each score, for :meth:`Nl2ProgEvaluation.by_reader`); ``None``: the model.

    Raises:
        ValueError: no logs.
        LLMError: the provider's model failed.
    """
    if not contexts:
        raise ValueError("evaluate_nl2prog needs at least one log")
    cand = candidate_runner or _sandboxed
    ref = reference_runner or _trusted
    cache: dict[tuple[str, str], ProgramResult] = {}
    scores = []
    for entry in entries:
        score = _score_entry(entry, contexts, provider, cand, ref, cache)
        if reader is not None:
            score = replace(score, reader=reader(entry.description))
        scores.append(score)
        if on_description is not None:
            on_description(score)
    return Nl2ProgEvaluation(tuple(scores), tuple(ctx.log_id for ctx in contexts))


# ====================================================================== providers


def reference_provider(entries: Iterable[EvalEntry]) -> CandidateProvider:
    """The reference program itself (scores Jaccard 1 wherever the reference finds something)."""
    programs = {normalize_description(e.description): e.program for e in entries}
    return lambda description: programs.get(normalize_description(description))


def bank_provider(examples: Sequence[ExampleProgram] | None = None) -> CandidateProvider:
    """The example-bank program with exactly the description (normalised), else ``None``."""
    bank = {
        normalize_description(e.description): e.program
        for e in (examples if examples is not None else load_examples())
    }
    return lambda description: bank.get(normalize_description(description))


def nearest_bank_provider(examples: Sequence[ExampleProgram] | None = None) -> CandidateProvider:
    """A model-free baseline: the program of the bank entry sharing most content words.

    Content words as in :func:`description_key`; ties go to the earlier bank entry; ``None``
    when no bank entry shares a word. Shows what copying the closest few-shot example scores.
    """
    bank = [
        (set(description_key(e.description).split()), e.program)
        for e in (examples if examples is not None else load_examples())
    ]

    def provide(description: str) -> str | None:
        words = set(description_key(description).split())
        best, best_score = None, 0.0
        for theirs, program in bank:
            union = words | theirs
            score = len(words & theirs) / len(union) if union else 0.0
            if score > best_score:
                best, best_score = program, score
        return best

    return provide


class BankOnlySelector(ExampleSelector):
    """Few-shot selector for evaluation: a bank without hidden descriptions, leave-one-out.

    Optionally it also leaves out the bank entries most similar to each query.

    Args:
        examples: the bank (the shipped one for evaluation).
        embedder: the description embedder.
        hidden: descriptions whose bank entries are never shown (the holdout).
        exclude_most_similar: per query, leave out this many of the bank entries most similar to
            it (after leave-one-out), to measure generation without near-duplicate examples.
    """

    def __init__(
        self,
        examples: Sequence[ExampleProgram],
        embedder: Embedder,
        *,
        hidden: Iterable[str] = (),
        exclude_most_similar: int = 0,
    ) -> None:
        if exclude_most_similar < 0:
            raise ValueError(f"exclude_most_similar must be >= 0, got {exclude_most_similar}")
        keys = {normalize_description(d) for d in hidden}
        super().__init__([e for e in examples if normalize_description(e.description) not in keys], embedder)
        self.exclude_most_similar = exclude_most_similar

    def select(self, description: str, k: int, *, leave_one_out: bool = True) -> list[ExampleProgram]:
        """The ``k`` most similar entries, skipping the query's own and the excluded most similar ones."""
        if self.exclude_most_similar == 0:
            return super().select(description, k, leave_one_out=leave_one_out)
        if k <= 0 or not self.examples:
            return []
        order = np.argsort(-self.similarities(description), kind="stable")
        key = normalize_description(description)
        ranked = [
            self.examples[int(i)]
            for i in order
            if not (leave_one_out and normalize_description(self.examples[int(i)].description) == key)
        ]
        return ranked[self.exclude_most_similar :][:k]


class GeneratorProvider:
    """The language-model loop as a provider (:func:`~scenariominer.mine.loop.generate_program`).

    The few-shot examples come from the SHIPPED bank only (``mining.generation.examples_files``
    is ignored), leave-one-out, never an entry with a holdout description; the model and the
    embedder are built on the first call (:func:`~scenariominer.mine.query.make_synthesizer`).
    Calling it returns the accepted program of a description, or ``None`` when the loop gave up
    (manual review); :meth:`plan_of` tells how the description was read.

    Args:
        validation: the logs a candidate must run on inside the loop.
        config: the configuration (``[llm]``, ``[embedding]``, ``mining.generation``).
        exclude_most_similar: leave out this many of the bank entries most similar to each
            description (0: the normal selection).
        cache: the program cache (keyed by the whole first request, so selections with and
            without the similar entries are cached apart).
        usage: counts model calls and tokens.
        hidden: descriptions never shown as examples; default the held-out splits.
    """

    def __init__(
        self,
        validation: Sequence[LogContext],
        config: Config,
        *,
        exclude_most_similar: int = 0,
        cache: ProgramCache | None = None,
        usage: UsageCounter | None = None,
        hidden: Iterable[str] | None = None,
    ) -> None:
        if not validation:
            raise ValueError("generator_provider needs at least one validation log")
        gen = replace(config.mining.generation, examples_files=())
        self.config = replace(config, mining=replace(config.mining, generation=gen))
        self.validation = validation
        self.exclude_most_similar = exclude_most_similar
        self.cache = cache
        self.usage = usage
        self.hidden = (
            tuple(hidden)
            if hidden is not None
            else tuple(e.description for e in load_eval_set() if e.split in HELD_OUT_SPLITS)
        )
        self._synth: ProgramSynthesizer | None = None

    def _synthesizer(self) -> ProgramSynthesizer:
        from scenariominer.mine.query import make_synthesizer

        if self._synth is None:
            synth = make_synthesizer(self.config, leave_one_out=True, usage=self.usage)
            if synth.selector is not None:
                synth.selector = BankOnlySelector(
                    load_examples(builtin=True),
                    synth.selector.embedder,
                    hidden=self.hidden,
                    exclude_most_similar=self.exclude_most_similar,
                )
            self._synth = synth
        return self._synth

    def __call__(self, description: str) -> str | None:
        """The accepted program of ``description``, or ``None`` when the loop gave up."""
        from scenariominer.mine.consensus import configured_consensus
        from scenariominer.mine.loop import generate_program

        synth = self._synthesizer()
        cfg = self.config.mining
        if cfg.generation.consensus_samples > 1:  # several candidates, chosen by agreement of outputs
            return configured_consensus(description, synth, self.validation, cfg).program
        return generate_program(description, synth, self.validation, config=cfg, cache=self.cache).program

    def plan_of(self, description: str) -> dict[str, Any] | None:
        """The plan the loop used for ``description`` (``None`` before it was asked, or plan off)."""
        return None if self._synth is None else self._synth.plans.get(description)


#: The language-model loop as a provider (the name the API calls; see :class:`GeneratorProvider`).
generator_provider = GeneratorProvider


def family_counts(entries: Iterable[EvalEntry]) -> Mapping[str, int]:
    """How many entries carry each family tag (tags of :data:`FAMILIES` in order; 0 when absent)."""
    counts = dict.fromkeys(FAMILIES, 0)
    for e in entries:
        for f in e.families:
            counts[f] += 1
    return counts
