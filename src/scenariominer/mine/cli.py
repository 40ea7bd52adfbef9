"""Command-line layer of scenario mining: ``scenariominer mine`` and ``scenariominer eval mining``.

Thin Typer functions over :mod:`scenariominer.mine.api` and :mod:`scenariominer.eval.mining`:
they parse options, call the API, and print with Rich. The main application attaches them with
:func:`register` (``mine``) and ``eval_app.command("mining")(mining_command)``.
"""

from __future__ import annotations

import json
import math
from enum import StrEnum
from pathlib import Path
from typing import Annotated

import numpy as np
import typer
from rich.console import Console
from rich.table import Table

from scenariominer.config import Config, ConfigError, load_config
from scenariominer.data.log import LogFormatError
from scenariominer.eval.mining import MiningEvaluation, MiningEvaluationError, evaluate_mining_files
from scenariominer.llm.errors import LLMError
from scenariominer.mine import api
from scenariominer.mine.clip_filter import CameraFrameError, ClipModelError
from scenariominer.mine.export import SubmissionFormatError, read_av2_submission, write_av2_submission
from scenariominer.mine.loop import GenerationStatus, ProgramCache
from scenariominer.mine.programs import ExampleBankError
from scenariominer.store import ScenarioStore, StoreError, resolve_store_path

__all__ = ["ExportFormat", "mine_command", "mining_command", "register", "render_evaluation", "render_query"]

console = Console()
err_console = Console(stderr=True)


class ExportFormat(StrEnum):
    """Output formats of ``mine --export``."""

    AV2 = "av2"
    """The Argoverse 2 scenario-mining submission pickle."""


def _config(path: Path | None) -> Config:
    try:
        return load_config(path)
    except ConfigError as exc:
        err_console.print(f"[red]config error:[/red] {exc}", soft_wrap=True)
        raise typer.Exit(2) from None


def _fail(exc: Exception, code: int = 1) -> typer.Exit:
    err_console.print(f"[red]error:[/red] {exc}", soft_wrap=True)
    return typer.Exit(code)


def _seconds(t_ns: int, t0_ns: int) -> str:
    return f"{(t_ns - t0_ns) * 1e-9:.1f}"


def render_query(report: api.QueryReport) -> None:
    """Print a query's matches (log, track, time span) and its timing summary."""
    if report.generation is not None and not report.generation.from_cache:
        for attempt in report.generation.attempts:
            verdict = (
                "[green]ok[/green]" if attempt.error is None else f"[red]{attempt.error.feedback()}[/red]"
            )
            console.print(
                f"attempt {attempt.index}: {attempt.generation_s:.1f} s generation, "
                f"{attempt.execution_s:.2f} s checks: {verdict}",
                soft_wrap=True,
            )
    if report.program is not None:
        console.print(f"[bold]program[/bold] ({report.source.value}, sha256 {report.program_sha256[:12]}):")
        console.print(report.program.rstrip(), markup=False, highlight=False)
    table = Table(title=f"matches of {report.description!r}", title_justify="left")
    for col in ("log", "track", "category", "timestamps", "from s", "to s", "related"):
        table.add_column(
            col, justify="right" if col in ("timestamps", "from s", "to s", "related") else "left"
        )
    for m in report.matches:
        t0 = int(m.timestamps_ns[0]) if m.timestamps_ns.size else 0
        related = m.related
        for row in np.flatnonzero(m.referred.any(axis=1)).tolist():
            ts = m.timestamps_ns[m.referred[row]]
            rel_rows = {int(r) for a, _, r in m.relations if int(a) == row}
            table.add_row(
                m.log_id,
                str(m.track_ids[row]),
                str(m.categories[row]),
                str(ts.size),
                _seconds(int(ts[0]), t0),
                _seconds(int(ts[-1]), t0),
                str(len(rel_rows)) if related.any() else "-",
            )
    console.print(table)
    for failure in report.failures:
        err_console.print(
            f"[red]failed[/red] on {failure.log_id}: {failure.error.feedback()}", soft_wrap=True
        )
    s = report.summary()
    console.print(
        f"status {s['status']} ({s['source']}, {s['attempts_used']} attempt(s)); "
        f"generation {s['generation_s']:.1f} s, execution {s['execution_s']:.2f} s over {s['n_logs']}"
        f" log(s); "
        f"{s['n_matching_logs']} log(s) match, {s['n_failed_logs']} failed",
        soft_wrap=True,
    )


def mine_command(
    description: Annotated[str, typer.Argument(help="The scenario to find, in plain English.")],
    logs: Annotated[
        list[Path] | None,
        typer.Option(
            "--logs", "-l", help="AV2 log folders or roots, highD recordings, tabular files (repeatable)."
        ),
    ] = None,
    store: Annotated[
        Path | None,
        typer.Option(
            "--store",
            "-s",
            help="Store directory: logs are ingested into it (with --logs) and results saved.",
        ),
    ] = None,
    export: Annotated[
        ExportFormat | None, typer.Option("--export", help="Also write the results in this format.")
    ] = None,
    out: Annotated[Path | None, typer.Option("--out", "-o", help="File for --export.")] = None,
    program_file: Annotated[
        Path | None, typer.Option("--program", help="Run this program file instead of generating one.")
    ] = None,
    no_bank: Annotated[
        bool, typer.Option("--no-bank", help="Do not use a hand-written bank program with this description.")
    ] = False,
    camera_frames: Annotated[
        Path | None,
        typer.Option(
            "--camera-frames", help="Camera-frame crops (see docs/mining.md): enables the CLIP filter."
        ),
    ] = None,
    clip_model: Annotated[
        Path | None,
        typer.Option("--clip-model", help="Local CLIP model folder (overrides mining.clip.model_path)."),
    ] = None,
    align_to: Annotated[
        Path | None,
        typer.Option(
            "--align-to", help="Ground-truth pickle whose evaluation timestamps the AV2 export uses."
        ),
    ] = None,
    force: Annotated[bool, typer.Option("--force", help="Regenerate even if the program is cached.")] = False,
    json_out: Annotated[bool, typer.Option("--json", help="Print the per-query summary as JSON.")] = False,
    config: Annotated[Path | None, typer.Option("--config", "-c", help="TOML configuration file.")] = None,
) -> None:
    """Find a described scenario in driving logs with a (generated) mining program."""
    cfg = _config(config)
    if clip_model is not None:
        from dataclasses import replace

        cfg = replace(
            cfg, mining=replace(cfg.mining, clip=replace(cfg.mining.clip, model_path=str(clip_model)))
        )
    if export is not None and out is None:
        raise _fail(ValueError("--export needs --out FILE"), 2)
    if not logs and store is None:
        raise _fail(ValueError("give --logs PATH (repeatable), --store DIR, or both"), 2)
    program = None
    if program_file is not None:
        try:
            program = program_file.read_text(encoding="utf-8")
        except OSError as exc:
            raise _fail(ValueError(f"cannot read {program_file}: {exc.strerror or exc}"), 2) from None
    try:
        st = ScenarioStore.open(resolve_store_path(store, cfg.store.path)) if store is not None else None
        mined = api.load_logs(list(logs or []), st, cfg)
        if not mined:
            raise _fail(ValueError("no logs to mine"), 1)
        candidates = (
            api.clip_candidates(description, mined, camera_frames, cfg.mining)
            if camera_frames is not None
            else None
        )
        cache = ProgramCache.in_dir(cfg.llm.cache_dir) if cfg.mining.generation.cache_programs else None
        report = api.mine_logs(
            description,
            mined,
            config=cfg.mining,
            program=program,
            synthesizer=lambda: api.make_synthesizer(cfg),
            examples=None,
            use_bank=not no_bank,
            cache=cache,
            candidates=candidates,
            force=force,
        )
        if st is not None:
            api.store_report(st, report)
        if export is ExportFormat.AV2:
            assert out is not None
            timestamps = None
            if align_to is not None:
                gt = read_av2_submission(align_to)
                timestamps = {
                    log_id: [int(f["timestamp_ns"]) for f in frames] for (log_id, _), frames in gt.items()
                }
            submission = api.av2_submission(report, api.raw_logs_for(mined, cfg), timestamps=timestamps)
            write_av2_submission(submission, out)
    except (
        LogFormatError,
        StoreError,
        LLMError,
        ExampleBankError,
        ClipModelError,
        CameraFrameError,
        SubmissionFormatError,
        ValueError,
        KeyError,
    ) as exc:
        raise _fail(exc) from None
    if json_out:
        console.print_json(json.dumps(report.summary()))
    else:
        render_query(report)
        if export is not None:
            console.print(f"wrote {out}")
    if report.status is GenerationStatus.MANUAL_REVIEW:
        raise typer.Exit(1)


def register(app: typer.Typer) -> None:
    """Add the ``mine`` command to the main application."""
    app.command("mine")(mine_command)


# ---------------------------------------------------------------------- eval mining


def _num(x: float) -> str:
    return "-" if math.isnan(x) else f"{x:.3f}"


def render_evaluation(ev: MiningEvaluation) -> None:
    """Print the official scores and the paper's F1 scores."""
    table = Table(title=f"scenario mining, {len(ev.pairs)} (log, description) pair(s)", title_justify="left")
    table.add_column("metric")
    table.add_column("value", justify="right")
    table.add_row("HOTA-Temporal", _num(ev.hota_temporal))
    table.add_row("HOTA-Track", _num(ev.hota_track))
    table.add_row("timestamp balanced accuracy", _num(ev.timestamp_balanced_accuracy))
    table.add_row("log balanced accuracy", _num(ev.log_balanced_accuracy))
    table.add_row("timestamp F1", _num(ev.timestamp_f1))
    table.add_row("log F1", _num(ev.log_f1))
    console.print(table)
    tc, lc = ev.timestamp_counts, ev.log_counts
    console.print(
        f"timestamps: TP {tc.tp}, FP {tc.fp}, FN {tc.fn}, TN {tc.tn}; "
        f"logs: TP {lc.tp}, FP {lc.fp}, FN {lc.fn}, TN {lc.tn}"
    )


def mining_command(
    pred: Annotated[
        Path, typer.Option("--pred", help="Prediction pickle (scenariominer mine --export av2).")
    ],
    gt: Annotated[
        Path, typer.Option("--gt", help="Ground-truth pickle of the Argoverse 2 scenario-mining task.")
    ],
    dataset_dir: Annotated[
        Path | None,
        typer.Option(
            "--dataset-dir", help="Folder with <log_id>/map and poses, for the region-of-interest filter."
        ),
    ] = None,
    max_range_m: Annotated[
        int, typer.Option(help="Evaluate boxes within this distance of the ego (m).")
    ] = 50,
    out: Annotated[
        Path | None, typer.Option("--out", help="Folder for the evaluator's JSON and plots.")
    ] = None,
    json_out: Annotated[bool, typer.Option("--json", help="Print the scores as JSON.")] = False,
) -> None:
    """Score a scenario-mining prediction with the official Argoverse 2 evaluator (plus F1)."""
    try:
        ev = evaluate_mining_files(pred, gt, dataset_dir, max_range_m=max_range_m, out_dir=out)
    except MiningEvaluationError as exc:
        raise _fail(exc) from None
    if json_out:
        console.print_json(json.dumps(ev.as_dict()))
    else:
        render_evaluation(ev)
