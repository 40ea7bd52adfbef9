"""The mining stage: a description and logs in, matches per log out (no store or file I/O).

:func:`mine_logs` does one query:

1. **program**: a program given by the caller, else the hand-written bank program with the same
   description, else the language-model loop (:func:`~scenariominer.mine.loop.generate_program`,
   validated on the first ``generation.validation_logs`` logs, cached on disk);
2. **coarse filter** (optional): per log, the candidate tracklets of the CLIP crop filter
   (:mod:`scenariominer.mine.clip_filter`) restrict the program to those tracks and cells;
3. **execution** on every log: in the sandbox for model-written and user programs, in-process for
   the shipped bank (trusted); a log where the program fails is reported, the others still run;
4. a :class:`QueryReport` with the matches and the timings the issue asks for (attempts used,
   final status, generation time, execution time, number of logs).

:func:`av2_submission` turns a report into the Argoverse 2 submission frames; storing the
matches and loading the logs are use cases of :mod:`scenariominer.api.mining`.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from enum import StrEnum
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from scenariominer.config import Config
from scenariominer.config.mining import MiningConfig
from scenariominer.data.log import Log
from scenariominer.mine.clip_filter import (
    CandidateTracklets,
    ClipEncoder,
    CropEncoder,
    candidate_cells,
    restrict_context,
)
from scenariominer.mine.consensus import ConsensusReport, configured_consensus
from scenariominer.mine.context import LogContext
from scenariominer.mine.export import (
    LogMatches,
    av2_frames,
    program_sha256,
)
from scenariominer.mine.keywords import KeywordSet
from scenariominer.mine.loop import (
    GenerationReport,
    GenerationStatus,
    ProgramCache,
    ProgramRunner,
    generate_program,
)
from scenariominer.mine.programs import ExampleProgram, load_examples
from scenariominer.mine.sandbox import (
    ErrorKind,
    ProgramError,
    run_program,
    run_trusted_program,
)
from scenariominer.mine.synthesis import ProgramSynthesizer, normalize_description

if TYPE_CHECKING:
    from scenariominer.exec import Executor
    from scenariominer.llm.usage import UsageCounter

__all__ = [
    "LogFailure",
    "MineLogTask",
    "ProgramSource",
    "QueryReport",
    "av2_submission",
    "bank_program",
    "clip_candidates",
    "make_synthesizer",
    "mine_logs",
]


class ProgramSource(StrEnum):
    """Where the program of a query came from."""

    GIVEN = "given"
    """Passed by the caller (e.g. a file); run in the sandbox unless declared trusted."""
    BANK = "bank"
    """The shipped (or user) example bank has a program for exactly this description; trusted."""
    GENERATED = "generated"
    """Written by the language model (or read from the program cache); run in the sandbox."""


@dataclass(frozen=True)
class LogFailure:
    """A log on which the program failed.

    Attributes:
        log_id: the log.
        error: what went wrong.
    """

    log_id: str
    error: ProgramError


@dataclass(frozen=True)
class QueryReport:
    """Result of mining one description over a set of logs.

    Attributes:
        description: the description.
        source: where the program came from.
        status: ``ok`` when a program was available, ``manual_review`` when the model loop gave up.
        program: the program that ran (``None`` under manual review).
        attempts_used: model answers the loop needed (0 for a given or bank program; the
            cached count for a cached one).
        generation_s: seconds spent writing the program (model calls and validation runs; 0 when
            the program was given, found in the bank or in the cache).
        execution_s: seconds spent running the program over all logs.
        n_logs: logs the query covered.
        matches: per log where the program ran: what it found (possibly nothing).
        failures: logs where the program failed.
        generation: the loop's full report (every attempt), when the model was involved.
        filtered: whether the CLIP candidate filter restricted the program.
        consensus: the candidates and their agreement, when several were sampled.
    """

    description: str
    source: ProgramSource
    status: GenerationStatus
    program: str | None
    attempts_used: int
    generation_s: float
    execution_s: float
    n_logs: int
    matches: tuple[LogMatches, ...]
    failures: tuple[LogFailure, ...] = ()
    generation: GenerationReport | None = None
    filtered: bool = False
    consensus: ConsensusReport | None = None

    @property
    def program_sha256(self) -> str:
        """Hash of the program that ran ('' under manual review)."""
        return program_sha256(self.program) if self.program is not None else ""

    @property
    def n_matching_logs(self) -> int:
        """Logs with at least one referred object."""
        return sum(1 for m in self.matches if m.referred.any())

    def summary(self) -> dict[str, Any]:
        """Per-query numbers as plain JSON (what the note and the CLI report)."""
        return {
            "description": self.description,
            "source": self.source.value,
            "status": self.status.value,
            "attempts_used": self.attempts_used,
            "generation_s": round(self.generation_s, 3),
            "execution_s": round(self.execution_s, 3),
            "n_logs": self.n_logs,
            "n_matching_logs": self.n_matching_logs,
            "n_failed_logs": len(self.failures),
            "program_sha256": self.program_sha256,
            **self._consensus_summary(),
        }

    def _consensus_summary(self) -> dict[str, Any]:
        c = self.consensus
        if c is None:
            return {}
        confidence = None if c.confidence != c.confidence else round(c.confidence, 3)  # NaN: none
        return {
            "consensus_candidates": len(c.candidates),
            "consensus_valid": sum(1 for x in c.candidates if x.ok),
            "consensus_confidence": confidence,
            "needs_review": c.needs_review,
        }


def bank_program(description: str, examples: Sequence[ExampleProgram]) -> ExampleProgram | None:
    """The bank entry whose description equals ``description`` (normalised), if any."""
    key = normalize_description(description)
    return next((e for e in examples if normalize_description(e.description) == key), None)


def _context(log: Log | LogContext, config: MiningConfig) -> LogContext:
    return log if isinstance(log, LogContext) else LogContext(log, config)


def _resolve(
    log: Log | LogContext | str, load: Callable[[str], Log] | None, config: MiningConfig
) -> LogContext:
    """The context of a log, a context, or a log id (loaded with ``load``)."""
    if isinstance(log, str):
        if load is None:
            raise ValueError("logs given by id need a load function")
        return LogContext(load(log), config)
    return _context(log, config)


def _runner(trusted: bool, config: MiningConfig) -> ProgramRunner:
    if trusted:
        return lambda program, ctx, description: run_trusted_program(program, ctx, description=description)
    return lambda program, ctx, description: run_program(program, ctx, description=description, config=config)


def mine_logs(
    description: str,
    logs: Sequence[Log | LogContext | str],
    *,
    config: MiningConfig | None = None,
    program: str | None = None,
    trusted: bool | None = None,
    synthesizer: ProgramSynthesizer | Callable[[], ProgramSynthesizer] | None = None,
    examples: Sequence[ExampleProgram] | None = None,
    use_bank: bool = True,
    cache: ProgramCache | None = None,
    candidates: Mapping[str, CandidateTracklets] | None = None,
    force: bool = False,
    runner: ProgramRunner | None = None,
    on_log: Callable[[str], None] | None = None,
    executor: Executor | None = None,
    load: Callable[[str], Log] | None = None,
    record: Callable[[LogMatches | LogFailure, str], None] | None = None,
) -> QueryReport:
    """Mine one description over ``logs`` (see the module docstring for the steps).

    Args:
        description: the scenario description.
        logs: the logs to mine (preprocessed logs or their contexts).
        config: mining configuration (defaults to :class:`MiningConfig`).
        program: run this program instead of looking one up or generating one.
        trusted: run in-process without limits; default True only for bank programs.
        synthesizer: the language-model program writer, or a function that builds it (called
            only when needed, so the model is not loaded for bank programs); needed when no
            program is given and the bank has none for the description.
        examples: the example bank (default: shipped bank plus ``generation.examples_files``).
        use_bank: use a bank program with exactly this description when there is one.
        cache: program cache for generated programs.
        candidates: per log id, the CLIP filter's candidate tracklets; logs without an entry are
            mined whole.
        force: regenerate even if the program cache has this description.
        runner: run programs (validation and mining) with this function instead of the sandbox
            or the in-process runner chosen by ``trusted`` (tests, benchmarks).
        on_log: called with each log id after it was mined (progress).
        executor: run the program on the logs in its workers; ``logs`` may then be log ids
            that ``load`` (a picklable function, e.g. a store's loader) turns into logs in the
            worker, so the task carries a reference, not the arrays. Only the first
            ``generation.validation_logs`` are loaded here, when a program must be written.
            Ignored (everything runs here) with ``candidates`` or a custom ``runner``.
        load: log id → log, for ``logs`` given as ids.
        record: called with each log's result and the program's SHA-256 where the log was
            mined (a worker, with an executor), e.g. to commit it to the store at once.

    Raises:
        ValueError: no logs, or no program and no synthesizer.
        BackendError: a model call failed.
    """
    cfg = config or MiningConfig()
    if not logs:
        raise ValueError("mine_logs needs at least one log")
    n_valid = cfg.generation.validation_logs
    contexts = [_resolve(log, load, cfg) for log in logs[:n_valid]]
    generation: GenerationReport | None = None
    consensus: ConsensusReport | None = None
    generation_s = 0.0
    attempts = 0
    if program is not None:
        source = ProgramSource.GIVEN
    else:
        bank = tuple(examples) if examples is not None else load_examples(cfg.generation.examples_files)
        hit = bank_program(description, bank) if use_bank else None
        if hit is not None:
            source, program = ProgramSource.BANK, hit.program
        elif synthesizer is None:
            raise ValueError(
                f"no program for {description!r}: the example bank has none and no language model "
                "is configured"
            )
        else:
            source = ProgramSource.GENERATED
            validation = contexts[: cfg.generation.validation_logs]
            writer = synthesizer if isinstance(synthesizer, ProgramSynthesizer) else synthesizer()
            gen_cfg = cfg.generation
            if gen_cfg.consensus_samples > 1:
                consensus = configured_consensus(description, writer, validation, cfg, runner)
                generation = consensus.generation
                assert generation is not None
                program = consensus.program
            else:
                generation = generate_program(
                    description, writer, validation, config=cfg, cache=cache, runner=runner, force=force
                )
                program = generation.program
            attempts = generation.attempts_used
            generation_s = 0.0 if generation.from_cache else generation.generation_s + generation.validation_s
            if consensus is not None:
                generation_s += consensus.seconds
    run_in_process = trusted if trusted is not None else source is ProgramSource.BANK
    if program is None:
        assert generation is not None
        return QueryReport(
            description, source, GenerationStatus.MANUAL_REVIEW, None, attempts, generation_s, 0.0,
            len(logs), (), (), generation, candidates is not None,
        )  # fmt: skip
    t_exec = time.perf_counter()
    task = MineLogTask(load, cfg, program, run_in_process, description, record)
    distributed = executor is not None and executor.name != "local" and candidates is None and runner is None
    if distributed:
        assert executor is not None
        items = [x.log if isinstance(x, LogContext) else x for x in logs]  # ids stay ids: loaded by workers
        keys = [x if isinstance(x, str) else x.log_id for x in items]
        outcomes = executor.map(
            task, items, keys=keys, on_outcome=lambda o: on_log(o.key) if on_log else None
        )
        results = [o.value if o.value is not None else _failed_item(o.key, o.error) for o in outcomes]
    else:
        run = runner or _runner(run_in_process, cfg)
        results = []
        for i, log in enumerate(logs):
            ctx = contexts[i] if i < len(contexts) else _resolve(log, load, cfg)
            tracklets = candidates.get(ctx.log_id) if candidates is not None else None
            result = _run_one(run, program, ctx, tracklets, description)
            if record is not None:
                record(result, program_sha256(program))
            results.append(result)
            if on_log is not None:
                on_log(ctx.log_id)
    matches = [r for r in results if isinstance(r, LogMatches)]
    failures = [r for r in results if isinstance(r, LogFailure)]
    return QueryReport(
        description=description,
        source=source,
        status=GenerationStatus.OK,
        program=program,
        attempts_used=attempts,
        generation_s=generation_s,
        execution_s=time.perf_counter() - t_exec,
        n_logs=len(logs),
        matches=tuple(matches),
        failures=tuple(failures),
        generation=generation,
        filtered=candidates is not None,
        consensus=consensus,
    )


def _run_one(
    run: ProgramRunner,
    program: str,
    ctx: LogContext,
    tracklets: CandidateTracklets | None,
    description: str,
) -> LogMatches | LogFailure:
    """Run the program on one log (restricted to the CLIP candidates when given)."""
    t0 = time.perf_counter()
    target, cells = ctx, None
    if tracklets is not None:
        target, cells = restrict_context(ctx, candidate_cells(ctx.log, tracklets))
    result = run(program, target, description)
    if result.error is not None or result.scenario is None:
        error = result.error or ProgramError(ErrorKind.INVALID_OUTPUT, "the program returned no scenario")
        return LogFailure(ctx.log_id, error)
    scenario = result.scenario if cells is None else result.scenario.restrict(cells)
    return LogMatches.from_scenario(scenario, description, program, time.perf_counter() - t0)


def _failed_item(log_id: str, error: str) -> LogFailure:
    """A log whose worker gave no result (the log could not be loaded, the worker died)."""
    return LogFailure(log_id, ProgramError(ErrorKind.RUNTIME, f"the log could not be mined: {error}"))


@dataclass(frozen=True)
class MineLogTask:
    """The worker side of mining: run one program on one log (picklable).

    Attributes:
        load: log id → log, for items given as ids (``None`` when items are logs).
        config: mining configuration.
        program: the program text.
        trusted: run in-process (bank programs) instead of in the sandbox.
        description: the description mined.
        record: called with the result in the worker (e.g. commit it to the store).
    """

    load: Callable[[str], Log] | None
    config: MiningConfig
    program: str
    trusted: bool
    description: str
    record: Callable[[LogMatches | LogFailure, str], None] | None = None

    def __call__(self, log: str | Log) -> LogMatches | LogFailure:
        """Mine one log (loaded here when given by id) and record the result."""
        if isinstance(log, str):
            if self.load is None:
                raise ValueError("a log given by id needs a load function")
            log = self.load(log)
        ctx = LogContext(log, self.config)
        result = _run_one(_runner(self.trusted, self.config), self.program, ctx, None, self.description)
        if self.record is not None:
            self.record(result, program_sha256(self.program))
        return result


def av2_submission(
    report: QueryReport,
    raw_logs: Mapping[str, Log],
    *,
    timestamps: Mapping[str, Sequence[int]] | None = None,
) -> dict[tuple[str, str], list[dict[str, Any]]]:
    """The Argoverse 2 submission entries of a query: one frame list per log of ``raw_logs``.

    Logs where the program failed or found nothing, and every log of a query under manual
    review, get frames without referred objects (an empty answer), so every evaluation
    timestamp of every log has a frame.

    Args:
        report: the query's result.
        raw_logs: the RAW logs (unsmoothed boxes) of the mined logs, by log id.
        timestamps: evaluation timestamps per log id (e.g. the ground truth's); default the
            2 Hz subsampling (:func:`~scenariominer.mine.export.evaluation_timestamps`).

    Raises:
        KeyError: a log with matches has no raw log.
    """
    out: dict[tuple[str, str], list[dict[str, Any]]] = {}
    found = {m.log_id: m for m in report.matches}
    missing = sorted(set(found) - set(raw_logs))
    if missing:
        raise KeyError(
            f"no raw log for {missing[0]}; the export needs the unsmoothed boxes of every mined log"
        )
    for log_id, raw in raw_logs.items():
        matches = found.get(log_id) or LogMatches(
            log_id, report.description, report.program_sha256, raw.timestamps_ns, raw.track_ids,
            raw.categories, np.zeros(raw.valid.shape, dtype=bool), np.zeros((0, 3), dtype=np.int64),
        )  # fmt: skip
        ts = None if timestamps is None or log_id not in timestamps else timestamps[log_id]
        out[(log_id, report.description)] = av2_frames(matches, raw, timestamps_ns=ts)
    return out


def make_synthesizer(
    config: Config | None = None, *, leave_one_out: bool = True, usage: UsageCounter | None = None
) -> ProgramSynthesizer:
    """The configured program writer: chat client (``[llm]``), embedder (``[embedding]``), bank.

    ``usage`` counts the calls and tokens of both models (for the command's usage table).

    Raises:
        ModelNotAvailableError: the model file or the packages carrying it are missing.
        ExampleBankError: a bank file in ``mining.generation.examples_files`` is unreadable.
    """
    from scenariominer.config import load_config
    from scenariominer.llm.factory import make_chat_client, make_embedder
    from scenariominer.mine.synthesis import ExampleSelector

    cfg = config or load_config()
    gen = cfg.mining.generation
    selector = ExampleSelector(load_examples(gen.examples_files), make_embedder(cfg, usage=usage))
    return ProgramSynthesizer(make_chat_client(cfg, usage=usage), selector, gen, leave_one_out=leave_one_out)


def clip_candidates(
    description: str,
    logs: Sequence[Log],
    frames_root: str | Path,
    config: MiningConfig | None = None,
    *,
    encoder: CropEncoder | None = None,
    keywords: KeywordSet | None = None,
) -> dict[str, CandidateTracklets]:
    """Candidate tracklets per log from camera crops (the coarse stage).

    ``frames_root`` is either one log's camera-frame folder (its crop table may carry a
    ``log_id`` column) or a folder with one sub-folder per log id. Logs without camera frames
    get no entry (they are mined whole).

    Args:
        description: the query; its keywords are extracted with spaCy unless given.
        logs: the logs being mined.
        frames_root: camera-frame folder (see :mod:`scenariominer.mine.clip_filter`).
        config: ``clip`` settings (model path, top K, margin).
        encoder: crop/text encoder (default: CLIP from ``clip.model_path``).
        keywords: the keywords to match (default :func:`~scenariominer.mine.keywords.extract_keywords`).

    Raises:
        ClipModelError: ``mining.clip.model_path`` is empty or not a CLIP model folder.
        CameraFrameError: a crop table or image is unreadable.
    """
    from scenariominer.mine.clip_filter import CROPS_FILES, CropTable, candidate_tracklets, rank_crops
    from scenariominer.mine.keywords import extract_keywords

    cfg = (config or MiningConfig()).clip
    root = Path(frames_root)
    enc: CropEncoder = encoder or ClipEncoder.from_pretrained(cfg.model_path, batch_size=cfg.batch_size)
    words = keywords or extract_keywords(description)
    single = any((root / n).is_file() for n in CROPS_FILES)
    out: dict[str, CandidateTracklets] = {}
    for log in logs:
        folder = root if single else root / log.log_id
        if not any((folder / n).is_file() for n in CROPS_FILES):
            continue
        crops = CropTable.read(folder, log.log_id)
        ranked = rank_crops(words, crops, enc, cfg)
        out[log.log_id] = candidate_tracklets(log.log_id, crops, ranked, cfg.tracklet_margin_s)
    return out
