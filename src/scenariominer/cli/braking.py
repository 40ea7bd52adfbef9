"""Commands ``analyze``, ``search`` and ``show`` (why-braking, seed 000)."""

from __future__ import annotations

import math
from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer

from scenariominer.cli._common import (
    ConfigOpt,
    ExecutorOpt,
    JsonOpt,
    RayAddressOpt,
    StoreOpt,
    WorkersOpt,
    console,
    err_console,
    load_cfg,
    with_exec,
)
from scenariominer.cli.text import safe
from scenariominer.schema import Judge, SortKey

if TYPE_CHECKING:
    from scenariominer.explain.pipeline import AnalyzeReport
    from scenariominer.explain.search import SearchHit


def _fmt(value: float, unit: str = "", digits: int = 1) -> str:
    if math.isnan(value):
        return "-"
    if math.isinf(value):
        return "none"
    return f"{value:.{digits}f}{unit}"


def render_analyze_report(report: AnalyzeReport) -> None:
    """Print what an analysis run did: failures first, then a summary."""
    from rich.table import Table

    from scenariominer.explain.pipeline import LogStatus

    for r in report.logs:
        if r.status is LogStatus.FAILED:
            err_console().print(f"[red]failed[/red] {safe(r.log_id)}: {safe(r.error)}", soft_wrap=True)
    skipped = [r for r in report.logs if r.status is LogStatus.NO_EGO_MOTION]
    for r in skipped[:10]:
        note = safe("; ".join(r.notes)[-160:])
        console().print(f"[yellow]no ego motion[/yellow] {safe(r.log_id)}: {note}", soft_wrap=True)
    table = Table(title="braking analysis", show_header=False, title_justify="left")
    table.add_row("logs analysed", str(report.n_analyzed))
    table.add_row("logs unchanged (skipped)", str(report.n_unchanged))
    table.add_row("logs without ego motion", str(len(skipped)))
    table.add_row("logs failed", str(report.n_failed))
    table.add_row("events stored", str(report.n_events))
    table.add_row("fresh LLM classifications", str(report.n_llm_calls))
    table.add_row("invalid LLM answers", str(report.n_invalid))
    table.add_row("pending (limit reached)", str(report.n_pending))
    table.add_row(
        "LLM time", f"{report.llm_seconds:.1f} s ({_fmt(report.mean_llm_latency_s, ' s')} per event)"
    )
    table.add_row("total time", f"{report.seconds:.1f} s")
    table.add_row("fingerprint", report.fingerprint)
    console().print(table)
    if report.n_pending:
        console().print(f"{report.n_pending} event(s) are pending; run `analyze` again to classify them.")


def analyze(
    store: StoreOpt = None,
    config: ConfigOpt = None,
    limit: Annotated[
        int | None,
        typer.Option("--limit", min=0, help="At most this many fresh LLM calls in this run (0: rules only)."),
    ] = None,
    force: Annotated[bool, typer.Option(help="Re-analyse logs whose stored results are current.")] = False,
    categories: Annotated[
        Path | None,
        typer.Option("--categories", help="TOML file of scenario categories (name = definition)."),
    ] = None,
    log: Annotated[
        list[str] | None, typer.Option("--log", help="Analyse only this log (repeatable).")
    ] = None,
    judge: Annotated[
        Judge | None,
        typer.Option(
            "--judge",
            help="Who decides the category: hybrid (rules where one rule holds, the LLM otherwise; "
            "the LLM writes the explanation), llm, or rules (no model). Default: explain.judge.",
        ),
    ] = None,
    llm: Annotated[
        bool,
        typer.Option(
            "--llm/--no-llm", help="--no-llm: rules only, at once, no model loaded (= --judge rules)."
        ),
    ] = True,
    json_out: JsonOpt = False,
    executor: ExecutorOpt = None,
    workers: WorkersOpt = None,
    ray_address: RayAddressOpt = None,
) -> None:
    """Find braking events, describe, measure and classify them, and embed them.

    Rule results are stored for every log first; the LLM's part follows log by log, so an
    interrupted run keeps what it finished and a re-run continues (answers already given are cached).
    """
    from scenariominer import api
    from scenariominer.cli.progress import progress_bar
    from scenariominer.llm.usage import UsageCounter, print_usage

    cfg = with_exec(load_cfg(config), executor, workers, ray_address)
    st = api.open_existing_store(store, cfg)
    chosen = "rules" if not llm else (judge.value if judge is not None else None)
    request = api.AnalyzeRequest(
        log_ids=log, limit=limit, force=force, categories_file=categories, judge=chosen
    )
    usage = UsageCounter()
    with progress_bar(not json_out) as bar:
        report = api.analyze(st, request, cfg, progress=bar, usage=usage)
    if json_out:
        console().print_json(report.to_json())
    else:
        render_analyze_report(report)
        print_usage(usage.report(), console())
    if report.n_failed and not (report.n_analyzed or report.n_unchanged):
        raise typer.Exit(1)


def render_hits(hits: list[SearchHit], title: str) -> None:
    """Print search results, one block per event (readable in a narrow terminal)."""
    out = console()
    out.print(f"[bold]{safe(title)}[/bold]", soft_wrap=True)
    for i, h in enumerate(hits, start=1):
        e = h.event
        score = "" if math.isnan(h.score) else f"  score {h.score:.3f}"
        out.print(
            f"[bold]{i}. {safe(e.category)}[/bold]{score}  (baseline: {safe(e.baseline_category)})\n"
            f"   event {safe(e.event_id)}  log {safe(e.log_id)}  {e.start_s:.1f}-{e.end_s:.1f} s\n"
            f"   guest {safe(e.guest_id)} ({safe(e.guest_category)})\n"
            f"   min TTC {_fmt(e.min_ttc_s, ' s')}  peak decel {_fmt(e.peak_decel_mps2, ' m/s²')}  "
            f"PET {_fmt(e.pet_s, ' s')}  headway {_fmt(e.headway_s, ' s')}",
            highlight=False,
            soft_wrap=True,
        )
        text = e.explanation or e.llm_description
        shown = f"   {safe(text)}" if text else f"   [dim](LLM: {safe(e.llm_status)})[/dim]"
        out.print(shown, highlight=False, soft_wrap=True)
        out.print(
            f"   [dim]scenariominer show {safe(e.log_id)} --event {safe(e.event_id)}[/dim]", soft_wrap=True
        )


def search(
    query: Annotated[
        str | None, typer.Argument(help="Free-text scenario description (cosine search).")
    ] = None,
    category: Annotated[str | None, typer.Option("--category", help="LLM category to match.")] = None,
    k: Annotated[int | None, typer.Option("--k", min=1, help="Number of results.")] = None,
    min_decel: Annotated[
        float | None, typer.Option("--min-decel", help="Minimum peak deceleration of the ego (m/s²).")
    ] = None,
    max_ttc: Annotated[
        float | None, typer.Option("--max-ttc", help="Maximum minimum time-to-collision (s).")
    ] = None,
    sort: Annotated[SortKey | None, typer.Option("--sort", help="Order of the results.")] = None,
    store: StoreOpt = None,
    config: ConfigOpt = None,
    json_out: JsonOpt = False,
) -> None:
    """Search braking events by category and/or by a free-text description."""
    import json

    from scenariominer import api
    from scenariominer.explain.search import SearchQuery

    cfg = load_cfg(config)
    q = SearchQuery(query, category, k or cfg.explain.search_k, min_decel, max_ttc, sort)
    hits = api.search(api.open_existing_store(store, cfg), q, cfg)
    if json_out:
        console().print_json(json.dumps([h.to_json_dict() for h in hits]))
        return
    what = " and ".join(
        x for x in (f'"{query}"' if query else "", f"category {category}" if category else "") if x
    )
    render_hits(hits, f"{len(hits)} event(s) for {what or 'any category'}")


def show(
    log_id: Annotated[str, typer.Argument(metavar="LOG", help="Log id.")],
    event: Annotated[
        str | None,
        typer.Option("--event", help="Event id, <guest>:<start_ns> or guest id (default: hardest braking)."),
    ] = None,
    out: Annotated[Path | None, typer.Option("--out", "-o", help="PNG file to write.")] = None,
    store: StoreOpt = None,
    config: ConfigOpt = None,
) -> None:
    """Draw a bird's-eye-view PNG of a braking event (ego red, guest orange, others grey)."""
    from scenariominer import api

    cfg = load_cfg(config)
    path = api.show(api.open_existing_store(store, cfg), api.ShowRequest(log_id, out, event), cfg)
    console().print(f"wrote {safe(path)}", soft_wrap=True)


def register(app: typer.Typer) -> None:
    """Add this module's commands to ``app``."""
    for command in (analyze, search, show):
        app.command(command.__name__)(command)
