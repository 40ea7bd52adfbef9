"""Command ``mine`` (program-based scenario mining, seed 003)."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer

from scenariominer.cli._common import (
    ConfigOpt,
    ExecutorOpt,
    JsonOpt,
    RayAddressOpt,
    WorkersOpt,
    console,
    err_console,
    load_cfg,
    with_exec,
)
from scenariominer.cli.text import safe
from scenariominer.schema import ExportFormat

if TYPE_CHECKING:
    from scenariominer.mine.query import QueryReport


def _seconds(t_ns: int, t0_ns: int) -> str:
    return f"{(t_ns - t0_ns) * 1e-9:.1f}"


def render_query(report: QueryReport) -> None:
    """Print a query's matches (log, track, time span) and its timing summary."""
    import numpy as np
    from rich.table import Table
    from rich.text import Text

    from scenariominer.cli.text import plain
    from scenariominer.mine.query import ProgramSource

    out = console()
    if report.generation is not None and not report.generation.from_cache:
        for attempt in report.generation.attempts:
            verdict = (
                "[green]ok[/green]"
                if attempt.error is None
                else f"[red]{safe(attempt.error.feedback())}[/red]"
            )
            if attempt.index == 0:
                out.print(
                    f"program built from the plan: {attempt.execution_s:.2f} s checks: {verdict}",
                    soft_wrap=True,
                )
                continue
            out.print(
                f"attempt {attempt.index}: {attempt.generation_s:.1f} s generation, "
                f"{attempt.execution_s:.2f} s checks: {verdict}",
                soft_wrap=True,
            )
    plan = report.generation.plan if report.generation is not None else None
    if plan:
        from scenariominer.mine.plan import plan_text

        if "error" in plan:
            out.print(f"[yellow]plan:[/yellow] not formed ({safe(str(plan['error']))})", soft_wrap=True)
        else:
            out.print("[bold]plan[/bold] (how the description was read):")
            out.print(Text(plain(plan_text(plan))), highlight=False)
            if plan.get("reworded"):
                out.print(
                    "[yellow]reworded:[/yellow] the phrase rules read the model's plain rewording "
                    "of the description (shown above); check that it says what you meant",
                    soft_wrap=True,
                )
            if plan.get("unread"):
                out.print(
                    f"[yellow]read in part:[/yellow] {len(plan['unread'])} word(s) of the description "
                    "were left out (listed above); check that the matches are what you meant",
                    soft_wrap=True,
                )
    if report.program is not None:
        out.print(f"[bold]program[/bold] ({report.source.value}, sha256 {report.program_sha256[:12]}):")
        out.print(Text(plain(report.program.rstrip())), highlight=False)
        if report.source is ProgramSource.BANK:
            out.print(
                "[yellow]note:[/yellow] a hand-written program of the example bank, not a generated one; "
                "a score on the log it was written for shows that execution and export are exact, "
                "not that generation works (use --no-bank for the model's own program)",
                soft_wrap=True,
            )
    c = report.consensus
    if c is not None:
        valid = sum(1 for x in c.candidates if x.ok)
        agreed = "-" if c.confidence != c.confidence else f"{c.confidence:.2f}"
        flag = " [yellow]review: the candidates disagree or too few ran[/yellow]" if c.needs_review else ""
        out.print(
            f"consensus: {valid} of {len(c.candidates)} candidate programs ran; the chosen one's mean "
            f"agreement with the others {agreed}{flag}",
            soft_wrap=True,
        )
    table = Table(title=f"matches of {safe(repr(report.description))}", title_justify="left")
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
                safe(m.log_id),
                safe(m.track_ids[row]),
                safe(m.categories[row]),
                str(ts.size),
                _seconds(int(ts[0]), t0),
                _seconds(int(ts[-1]), t0),
                str(len(rel_rows)) if related.any() else "-",
            )
    if table.row_count:
        out.print(table)
    else:
        out.print(f"no match of {safe(repr(report.description))} in {report.n_logs} log(s)", soft_wrap=True)
    for failure in report.failures:
        err_console().print(
            f"[red]failed[/red] on {safe(failure.log_id)}: {safe(failure.error.feedback())}", soft_wrap=True
        )
    s = report.summary()
    out.print(
        f"program {s['status']} ({s['source']}, {_attempts(int(s['attempts_used']))}); "
        f"generation {s['generation_s']:.1f} s, execution {s['execution_s']:.2f} s over {s['n_logs']}"
        f" log(s); {s['n_matching_logs']} log(s) match, {s['n_failed_logs']} failed",
        soft_wrap=True,
    )


def _attempts(n: int) -> str:
    """How many times the model was asked ("no model call" for a program the phrase rules built)."""
    return "no model call" if n == 0 else f"{n} attempt(s)"


def read_program_file(path: Path) -> str:
    """The text of a program file.

    Raises:
        MiningError: the file cannot be read or is not UTF-8 text.
    """
    from scenariominer.errors import MiningError

    try:
        data = path.read_bytes()
    except OSError as exc:
        raise MiningError(f"cannot read program file {path}: {exc.strerror or exc}") from None
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise MiningError(
            f"program file {path} is not UTF-8 text (byte {exc.start}: {data[exc.start : exc.start + 1]!r}); "
            "save it as UTF-8"
        ) from None


def mine(
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
    json_out: JsonOpt = False,
    executor: ExecutorOpt = None,
    workers: WorkersOpt = None,
    ray_address: RayAddressOpt = None,
    config: ConfigOpt = None,
) -> None:
    """Find a described scenario in driving logs with a (generated) mining program.

    Exit status: 0 when the query ran, 1 when the program failed on every log or the model loop
    gave up (manual review), 2 for unusable input.
    """
    import json
    from dataclasses import replace

    from scenariominer import api
    from scenariominer.errors import MiningError
    from scenariominer.llm.usage import UsageCounter, print_usage
    from scenariominer.mine.loop import GenerationStatus

    cfg = with_exec(load_cfg(config), executor, workers, ray_address)
    if clip_model is not None:
        clip = replace(cfg.mining.clip, model_path=str(clip_model))
        cfg = replace(cfg, mining=replace(cfg.mining, clip=clip))
    if export is not None and out is None:
        raise MiningError("--export needs --out FILE")
    if not logs and store is None:
        raise MiningError("give --logs PATH (repeatable), --store DIR, or both")
    program = read_program_file(program_file) if program_file is not None else None
    st = api.open_store(store, cfg) if store is not None else None
    request = api.MineRequest(
        description,
        logs=list(logs or []),
        store=st,
        program=program,
        use_bank=not no_bank,
        camera_frames=camera_frames,
        export_av2=out if export is ExportFormat.AV2 else None,
        align_to=align_to,
        force=force,
    )
    usage = UsageCounter()
    result = api.mine(request, cfg, usage)
    report = result.report
    if json_out:
        console().print_json(json.dumps(report.summary()))
    else:
        render_query(report)
        if result.export_path is not None:
            console().print(f"wrote {safe(result.export_path)}", soft_wrap=True)
        print_usage(usage.report(), console())
    if result.all_failed:
        err_console().print(
            f"[red]the program failed on every log ({len(report.failures)})[/red]", soft_wrap=True
        )
        raise typer.Exit(1)
    if report.status is GenerationStatus.MANUAL_REVIEW:
        raise typer.Exit(1)


def register(app: typer.Typer) -> None:
    """Add the ``mine`` command to ``app``."""
    app.command("mine")(mine)
