"""Fault-tolerant iterative code generation (the paper's Algorithm 1) with a program cache.

For one description:

1. compose the first request (library, categories, few-shot examples, description);
2. for attempt ``i = 1 .. K``: ask the model for a program; check it statically
   (:func:`~scenariominer.mine.sandbox.check_program`); run it in the sandbox on the validation
   log(s); if all succeed, accept it; otherwise re-prompt with the faulty program and its error
   (:func:`~scenariominer.mine.prompts.repair_messages`); decoding is greedy, so when the model
   repeats a program that already failed, the next request says so and samples
   (``generation.retry_temperature``, seeded by the attempt number) instead of replaying the
   same answer;
3. after ``K`` failures, flag the description for manual review and keep every attempt.

A *runtime* failure is anything :class:`~scenariominer.mine.sandbox.ProgramError` reports: syntax
errors, forbidden constructs, exceptions, time and memory limits, and programs that never call
``output_scenario``. An empty scenario is a valid answer (the description may not occur in the
validation log).

Programs are data: the outcome (program, status and every attempt) is cached on disk, keyed by
the description, the model, the prompt version and the digest of the whole first request (which
covers the library text, the chosen examples and the style), so mining the same description
again costs nothing. The cache is one SQLite file in the LLM cache directory.
"""

from __future__ import annotations

import ast
import hashlib
import json
import sqlite3
import threading
import time
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass, field
from enum import StrEnum
from pathlib import Path
from typing import Any

from scenariominer.config.mining import GenerationConfig, MiningConfig
from scenariominer.llm.base import Message
from scenariominer.llm.cache import resolve_cache_dir
from scenariominer.mine.context import LogContext
from scenariominer.mine.grammar import program_grammar
from scenariominer.mine.plan_program import PLAN_PROGRAM_VERSION, PlanCompileError, compile_plan
from scenariominer.mine.plan_reader import PLAN_READER_VERSION
from scenariominer.mine.prompts import PROMPT_VERSION, repair_messages
from scenariominer.mine.sandbox import ErrorKind, ProgramError, ProgramResult, check_program, run_program
from scenariominer.mine.synthesis import ProgramSynthesizer, normalize_description

__all__ = [
    "PROGRAM_CACHE_FILENAME",
    "Attempt",
    "GenerationReport",
    "GenerationStatus",
    "ProgramCache",
    "ProgramRunner",
    "generate_program",
    "plan_cache_key",
    "program_cache_key",
    "validate_program",
]

#: File name of the program cache inside the LLM cache directory.
PROGRAM_CACHE_FILENAME = "mining-programs.sqlite3"

#: Runs one program on one log: ``(program, context, description) -> ProgramResult``.
ProgramRunner = Callable[[str, LogContext, str], ProgramResult]


class GenerationStatus(StrEnum):
    """Final state of the generation loop for one description."""

    OK = "ok"
    """A program passed the checks and ran on every validation log."""
    MANUAL_REVIEW = "manual_review"
    """Every one of the K attempts failed; a person should look at the attempts."""


@dataclass(frozen=True)
class Attempt:
    """One try of the loop.

    Attributes:
        index: 1-based attempt number; 0 for the program built from the plan (no model answer).
        program: the program extracted from the model's answer.
        reply: the model's raw answer.
        error: why the program was rejected, or ``None`` for the accepted one.
        generation_s: seconds the model call took.
        execution_s: seconds spent checking and running the program on the validation logs.
        cached_reply: whether the answer came from the LLM response cache.
    """

    index: int
    program: str
    reply: str
    error: ProgramError | None
    generation_s: float
    execution_s: float
    cached_reply: bool = False

    def to_json_dict(self) -> dict[str, Any]:
        """Plain-JSON form (for the program cache)."""
        d = asdict(self)
        d["error"] = None if self.error is None else {**asdict(self.error), "kind": self.error.kind.value}
        return d

    @classmethod
    def from_json_dict(cls, data: dict[str, Any]) -> Attempt:
        """Inverse of :meth:`to_json_dict`."""
        err = data.get("error")
        error = None if err is None else ProgramError(ErrorKind(err["kind"]), err["message"], err.get("line"))
        return cls(
            index=int(data["index"]),
            program=str(data["program"]),
            reply=str(data["reply"]),
            error=error,
            generation_s=float(data["generation_s"]),
            execution_s=float(data["execution_s"]),
            cached_reply=bool(data.get("cached_reply", False)),
        )


@dataclass(frozen=True)
class GenerationReport:
    """Outcome of the loop for one description.

    Attributes:
        description: the description.
        status: ``ok`` or ``manual_review``.
        program: the accepted program, or ``None`` under manual review.
        attempts: every attempt, in order (all K of them under manual review).
        model: ``backend:model`` that wrote the programs.
        prompt_version: :data:`~scenariominer.mine.prompts.PROMPT_VERSION` of the prompts.
        validation_log_ids: the logs every accepted program ran on.
        max_attempts: the K the loop ran with.
        from_cache: whether this report was read from the program cache (no model call made).
        plan: the description's plan when planning is on (:mod:`scenariominer.mine.plan`).
    """

    description: str
    status: GenerationStatus
    program: str | None
    attempts: tuple[Attempt, ...]
    model: str
    prompt_version: str = PROMPT_VERSION
    validation_log_ids: tuple[str, ...] = ()
    max_attempts: int = 5
    from_cache: bool = False
    plan: dict[str, Any] | None = None

    @property
    def ok(self) -> bool:
        """Whether a program was accepted."""
        return self.status is GenerationStatus.OK

    @property
    def attempts_used(self) -> int:
        """Number of model answers the loop needed (K under manual review; the plan's program is none)."""
        return sum(1 for a in self.attempts if a.index > 0)

    @property
    def generation_s(self) -> float:
        """Seconds spent in model calls, over all attempts."""
        return sum(a.generation_s for a in self.attempts)

    @property
    def validation_s(self) -> float:
        """Seconds spent checking and running candidate programs on the validation logs."""
        return sum(a.execution_s for a in self.attempts)

    @property
    def last_error(self) -> ProgramError | None:
        """The error of the last attempt (``None`` when it was accepted)."""
        return self.attempts[-1].error if self.attempts else None

    def to_json(self) -> str:
        """Serialise for the program cache (``from_cache`` is not stored)."""
        d = {
            "description": self.description,
            "status": self.status.value,
            "program": self.program,
            "attempts": [a.to_json_dict() for a in self.attempts],
            "model": self.model,
            "prompt_version": self.prompt_version,
            "validation_log_ids": list(self.validation_log_ids),
            "max_attempts": self.max_attempts,
            "plan": self.plan,
        }
        return json.dumps(d, ensure_ascii=False)

    @classmethod
    def from_json(cls, blob: str, *, from_cache: bool = True) -> GenerationReport:
        """Inverse of :meth:`to_json`."""
        d = json.loads(blob)
        return cls(
            description=d["description"],
            status=GenerationStatus(d["status"]),
            program=d["program"],
            attempts=tuple(Attempt.from_json_dict(a) for a in d["attempts"]),
            model=d["model"],
            prompt_version=d["prompt_version"],
            validation_log_ids=tuple(d.get("validation_log_ids", ())),
            max_attempts=int(d.get("max_attempts", len(d["attempts"]))),
            from_cache=from_cache,
            plan=d.get("plan"),
        )


def program_cache_key(
    description: str,
    model: str,
    first_messages: Sequence[Message],
    config: GenerationConfig,
    *,
    plan_program: bool = False,
) -> str:
    """SHA-256 (hex) identifying a generation: description, model, prompt version, prompt, K.

    The digest of the first request covers the library text, the categories, the chosen
    examples and the style, so editing the example bank or the predicates' docstrings yields
    a new key.
    """
    payload = {
        "description": normalize_description(description),
        "model": model,
        "prompt_version": PROMPT_VERSION,
        "messages": [m.to_dict() for m in first_messages],
        "max_attempts": config.max_attempts,
        "max_tokens": config.max_tokens,
        "retry_temperature": config.retry_temperature,
    }
    if config.grammar:  # only when on, so caches of grammar-free runs keep their keys
        payload["grammar"] = hashlib.sha256(program_grammar().encode("utf-8")).hexdigest()
    if plan_program:
        payload["plan_program"] = PLAN_PROGRAM_VERSION
    blob = json.dumps(payload, sort_keys=True, separators=(",", ":"), ensure_ascii=False)
    return hashlib.sha256(blob.encode("utf-8")).hexdigest()


def plan_cache_key(description: str, model: str, plan: dict[str, Any]) -> str:
    """SHA-256 (hex) of a program built from a plan the phrase rules read: description, plan, rules.

    The phrase rules' reading and :data:`PLAN_PROGRAM_VERSION` fix the program, so no prompt
    enters the key (the model identity does, as the report names it).
    """
    payload = {
        "description": normalize_description(description),
        "model": model,
        "plan": plan,
        "plan_program": PLAN_PROGRAM_VERSION,
        "plan_reader": PLAN_READER_VERSION,
    }
    blob = json.dumps(payload, sort_keys=True, separators=(",", ":"), ensure_ascii=False)
    return hashlib.sha256(blob.encode("utf-8")).hexdigest()


class ProgramCache:
    """Generation reports on disk (one SQLite file; safe across threads and processes).

    Args:
        path: database file, created with its parent directories when missing.
    """

    def __init__(self, path: str | Path) -> None:
        self.path = Path(path)
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self._lock = threading.Lock()
        self._conn = sqlite3.connect(self.path, timeout=30.0, check_same_thread=False, isolation_level=None)
        with self._lock:
            self._conn.execute("PRAGMA journal_mode=WAL")
            self._conn.execute(
                "CREATE TABLE IF NOT EXISTS programs (key TEXT PRIMARY KEY, description TEXT NOT NULL, "
                "status TEXT NOT NULL, report TEXT NOT NULL, created_s REAL NOT NULL)"
            )

    @classmethod
    def in_dir(cls, cache_dir: str | Path = "") -> ProgramCache:
        """Open :data:`PROGRAM_CACHE_FILENAME` in the (resolved) LLM cache directory."""
        return cls(resolve_cache_dir(cache_dir) / PROGRAM_CACHE_FILENAME)

    def get(self, key: str) -> GenerationReport | None:
        """The cached report for ``key`` (marked ``from_cache``), or ``None``."""
        with self._lock:
            row = self._conn.execute("SELECT report FROM programs WHERE key = ?", (key,)).fetchone()
        return None if row is None else GenerationReport.from_json(row[0])

    def put(self, key: str, report: GenerationReport) -> None:
        """Store ``report`` under ``key`` (replacing an older entry)."""
        with self._lock:
            self._conn.execute(
                "INSERT OR REPLACE INTO programs (key, description, status, report, created_s) "
                "VALUES (?, ?, ?, ?, ?)",
                (key, report.description, report.status.value, report.to_json(), time.time()),
            )

    def __len__(self) -> int:
        with self._lock:
            return int(self._conn.execute("SELECT COUNT(*) FROM programs").fetchone()[0])

    def close(self) -> None:
        """Close the database connection."""
        with self._lock:
            self._conn.close()

    def __enter__(self) -> ProgramCache:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def _sandboxed(config: MiningConfig | None) -> ProgramRunner:
    def run(program: str, context: LogContext, description: str) -> ProgramResult:
        return run_program(program, context, description=description, config=config)

    return run


def validate_program(
    program: str,
    contexts: Sequence[LogContext],
    description: str,
    *,
    config: MiningConfig | None = None,
    runner: ProgramRunner | None = None,
) -> ProgramError | None:
    """Check a candidate program and run it on every validation log; the first error or ``None``.

    Args:
        program: the candidate.
        contexts: validation logs (at least one).
        description: value of the program's ``description`` variable.
        config: mining thresholds and sandbox limits (defaults to each context's).
        runner: how to run the program; default the resource-limited sandbox
            (:func:`~scenariominer.mine.sandbox.run_program`).
    """
    if not contexts:
        raise ValueError("validate_program needs at least one validation log")
    cfg = config or contexts[0].config
    problem = check_program(program, cfg.sandbox)
    if problem is not None:
        return problem
    run = runner or _sandboxed(config)
    for ctx in contexts:
        result = run(program, ctx, description)
        if result.error is not None:
            if len(contexts) == 1:
                return result.error
            where = f"on log {ctx.log_id}: "
            return ProgramError(result.error.kind, where + result.error.message, result.error.line)
    return None


def _program_key(program: str) -> str:
    """A program's identity for repeat detection: its syntax tree (comments and layout ignored)."""
    try:
        return ast.dump(ast.parse(program))
    except (SyntaxError, ValueError, RecursionError, MemoryError):
        return " ".join(program.split())


@dataclass
class _LoopState:
    attempts: list[Attempt] = field(default_factory=list)
    accepted: str | None = None


def _try_plan_program(
    plan: dict[str, Any],
    description: str,
    validation: Sequence[LogContext],
    state: _LoopState,
    *,
    config: MiningConfig | None,
    runner: ProgramRunner | None,
) -> None:
    """Attempt 0: the program built from the plan by rules, checked like a model's answer.

    A plan the rules cannot express is recorded as a rejected attempt naming the part at fault;
    the model then writes the program (its attempts are numbered from 1 as always).
    """
    t0 = time.perf_counter()
    try:
        compiled = compile_plan(plan)
    except PlanCompileError as exc:
        error: ProgramError | None = ProgramError(ErrorKind.PLAN, f"the plan gives no program: {exc}")
        program, reply = "", ""
    else:
        program = compiled.program
        reply = "(built from the plan)" + "".join(f"\n# {note}" for note in compiled.notes)
        error = validate_program(program, validation, description, config=config, runner=runner)
    state.attempts.append(
        Attempt(
            index=0,
            program=program,
            reply=reply,
            error=error,
            generation_s=0.0,
            execution_s=time.perf_counter() - t0,
        )
    )
    if error is None:
        state.accepted = program


def generate_program(
    description: str,
    synthesizer: ProgramSynthesizer,
    validation: Sequence[LogContext],
    *,
    config: MiningConfig | None = None,
    cache: ProgramCache | None = None,
    runner: ProgramRunner | None = None,
    force: bool = False,
) -> GenerationReport:
    """Write a program for ``description`` with up to K tries, repairing from the errors.

    Args:
        description: the scenario description.
        synthesizer: prompt composition and model calls.
        validation: the logs a program must run on without error (the first
            ``generation.validation_logs`` of the logs being mined, typically).
        config: mining configuration (``generation.max_attempts`` is K; sandbox limits);
            defaults to the first validation log's.
        cache: program cache; a hit returns the stored report without calling the model.
        runner: how candidate programs are run (default: the sandbox).
        force: ignore a cached report (the new one replaces it).

    Returns:
        The report: status, accepted program, every attempt with its error and timings.

    Raises:
        ValueError: no validation log given.
        BackendError: a model call failed (network, missing model); nothing is cached then.
    """
    if not validation:
        raise ValueError("generate_program needs at least one validation log")
    cfg = config or validation[0].config
    gen_cfg = cfg.generation
    plan = synthesizer.plan_for(description)
    from_plan = plan is not None and synthesizer.config.plan_program
    state = _LoopState()
    if plan is not None and from_plan and plan.get("read_by") == "rules":
        # Read by the phrase rules: try their program before composing the model's request (whose
        # few-shot examples need the embedding model, seconds to load); cached under the plan.
        rules_key = plan_cache_key(description, synthesizer.model, plan)
        hit = cache.get(rules_key) if cache is not None and not force else None
        if hit is not None:
            return hit
        _try_plan_program(plan, description, validation, state, config=config, runner=runner)
        if state.accepted is not None:
            report = _report(description, synthesizer, validation, gen_cfg, state, plan)
            if cache is not None:
                cache.put(rules_key, report)
            return report
    first = synthesizer.first_messages(description)
    key = program_cache_key(description, synthesizer.model, first, gen_cfg, plan_program=from_plan)
    if cache is not None and not force:
        hit = cache.get(key)
        if hit is not None:
            return hit
    if plan is not None and from_plan and not state.attempts:
        _try_plan_program(plan, description, validation, state, config=config, runner=runner)
    messages = first
    failed: set[str] = set()
    repeated = False
    for index in range(1, gen_cfg.max_attempts + 1):
        if state.accepted is not None:
            break
        # a greedy model shown the same program and error answers the same: sample instead
        if repeated and gen_cfg.retry_temperature > 0:
            generation = synthesizer.generate(messages, temperature=gen_cfg.retry_temperature, seed=index)
        else:
            generation = synthesizer.generate(messages)
        t0 = time.perf_counter()
        error = validate_program(generation.program, validation, description, config=config, runner=runner)
        if error is not None and generation.finish_reason == "length":
            error = ProgramError(
                error.kind,
                f"{error.message} (the answer was cut off after {generation.completion_tokens} tokens; "
                "write a shorter program)",
                error.line,
            )
        state.attempts.append(
            Attempt(
                index=index,
                program=generation.program,
                reply=generation.reply,
                error=error,
                generation_s=generation.latency_s,
                execution_s=time.perf_counter() - t0,
                cached_reply=generation.cached,
            )
        )
        if error is None:
            state.accepted = generation.program
            break
        identity = _program_key(generation.program)
        repeated = identity in failed
        failed.add(identity)
        messages = repair_messages(first, generation.program, error.feedback(), repeated=repeated)
    report = _report(description, synthesizer, validation, gen_cfg, state, plan)
    if cache is not None:
        cache.put(key, report)
    return report


def _report(
    description: str,
    synthesizer: ProgramSynthesizer,
    validation: Sequence[LogContext],
    gen_cfg: GenerationConfig,
    state: _LoopState,
    plan: dict[str, Any] | None,
) -> GenerationReport:
    return GenerationReport(
        description=description,
        status=GenerationStatus.OK if state.accepted is not None else GenerationStatus.MANUAL_REVIEW,
        program=state.accepted,
        attempts=tuple(state.attempts),
        model=synthesizer.model,
        validation_log_ids=tuple(ctx.log_id for ctx in validation),
        max_attempts=gen_cfg.max_attempts,
        plan=plan,
    )
