"""Commands ``analyze``, ``search`` and ``show``: a thin Typer layer over :mod:`scenariominer.explain`.

:func:`register` adds the commands to an application (the root ``scenariominer`` command);
each parses options, calls one library function and renders the result with Rich.
"""

from __future__ import annotations

import dataclasses
import json
import math
from pathlib import Path
from typing import Annotated

import typer
from rich.console import Console
from rich.table import Table

from scenariominer.config import Config, ConfigError, load_config
from scenariominer.data.log import LogFormatError
from scenariominer.explain.categories import CategoryFileError, load_categories
from scenariominer.explain.pipeline import AnalyzeReport, LogStatus, analyze_store
from scenariominer.explain.search import NoEventsError, SearchHit, SearchQuery, SortKey, search_events
from scenariominer.explain.show import UnknownEventError, show_event
from scenariominer.llm.errors import LLMError
from scenariominer.llm.factory import make_chat_client, make_embedder
from scenariominer.progress import RichProgress
from scenariominer.store import ScenarioStore, StoreError, resolve_store_path

__all__ = ["register"]

console = Console()
err_console = Console(stderr=True)

StoreOpt = Annotated[
    Path | None,
    typer.Option(
        "--store", "-s", help="Store directory (default: $SCENARIOMINER_STORE or the per-user data dir)."
    ),
]
ConfigOpt = Annotated[Path | None, typer.Option("--config", "-c", help="TOML configuration file.")]


def _config(path: Path | None) -> Config:
    try:
        return load_config(path)
    except ConfigError as exc:
        err_console.print(f"[red]config error:[/red] {exc}")
        raise typer.Exit(2) from None


def _fail(exc: Exception, code: int = 1) -> typer.Exit:
    err_console.print(f"[red]error:[/red] {exc}")
    return typer.Exit(code)


def _open_store(path: Path | None, cfg: Config) -> ScenarioStore:
    try:
        return ScenarioStore.open(resolve_store_path(path, cfg.store.path), create=False)
    except StoreError as exc:
        raise _fail(exc) from None


def _fmt(value: float, unit: str = "", digits: int = 1) -> str:
    if math.isnan(value):
        return "-"
    if math.isinf(value):
        return "none"
    return f"{value:.{digits}f}{unit}"


def render_analyze_report(report: AnalyzeReport) -> None:
    """Print what an analysis run did: failures first, then a summary."""
    for r in report.logs:
        if r.status is LogStatus.FAILED:
            err_console.print(f"[red]failed[/red] {r.log_id}: {r.error}")
    skipped = [r for r in report.logs if r.status is LogStatus.NO_EGO_MOTION]
    for r in skipped[:10]:
        console.print(f"[yellow]no ego motion[/yellow] {r.log_id}: {'; '.join(r.notes)[-160:]}")
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
    console.print(table)
    if report.n_pending:
        console.print(f"{report.n_pending} event(s) are pending; run `analyze` again to classify them.")


def analyze(
    store: StoreOpt = None,
    config: ConfigOpt = None,
    limit: Annotated[
        int | None, typer.Option("--limit", min=0, help="At most this many fresh LLM calls in this run.")
    ] = None,
    force: Annotated[bool, typer.Option(help="Re-analyse logs whose stored results are current.")] = False,
    categories: Annotated[
        Path | None,
        typer.Option("--categories", help="TOML file of scenario categories (name = definition)."),
    ] = None,
    log: Annotated[
        list[str] | None, typer.Option("--log", help="Analyse only this log (repeatable).")
    ] = None,
    json_out: Annotated[bool, typer.Option("--json", help="Print the report as JSON.")] = False,
) -> None:
    """Find braking events, describe, measure and classify them with the LLM, and embed them."""
    cfg = _config(config)
    if categories is not None:
        cfg = dataclasses.replace(
            cfg, explain=dataclasses.replace(cfg.explain, categories_file=str(categories))
        )
    st = _open_store(store, cfg)
    try:
        cats = load_categories(cfg.explain.categories_file)
        embedder = make_embedder(cfg)
        client = None if limit == 0 else make_chat_client(cfg)
    except (CategoryFileError, LLMError) as exc:
        raise _fail(exc) from None
    bar = None if json_out else RichProgress()
    try:
        report = analyze_store(
            st, cfg, client, embedder, log_ids=log, progress=bar, force=force, limit=limit, categories=cats
        )
    except (StoreError, LLMError, LogFormatError) as exc:
        raise _fail(exc) from None
    finally:
        if bar is not None:
            bar.close()
        if client is not None:
            client.close()
    if json_out:
        console.print_json(report.to_json())
    else:
        render_analyze_report(report)
    if report.n_failed and not (report.n_analyzed or report.n_unchanged):
        raise typer.Exit(1)


def render_hits(hits: list[SearchHit], title: str) -> None:
    """Print search results, one block per event (readable in a narrow terminal)."""
    console.print(f"[bold]{title}[/bold]")
    for i, h in enumerate(hits, start=1):
        e = h.event
        score = "" if math.isnan(h.score) else f"  score {h.score:.3f}"
        console.print(
            f"[bold]{i}. {e.category}[/bold]{score}  (baseline: {e.baseline_category})\n"
            f"   log {e.log_id}  {e.start_s:.1f}-{e.end_s:.1f} s\n"
            f"   guest {e.guest_id} ({e.guest_category})\n"
            f"   min TTC {_fmt(e.min_ttc_s, ' s')}  peak decel {_fmt(e.peak_decel_mps2, ' m/s²')}  "
            f"PET {_fmt(e.pet_s, ' s')}  headway {_fmt(e.headway_s, ' s')}",
            highlight=False,
        )
        text = e.explanation or e.llm_description
        console.print(f"   {text}" if text else f"   [dim](LLM: {e.llm_status})[/dim]", highlight=False)


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
    json_out: Annotated[bool, typer.Option("--json", help="Print the results as JSON.")] = False,
) -> None:
    """Search braking events by category and/or by a free-text description."""
    cfg = _config(config)
    try:
        q = SearchQuery(query, category, k or cfg.explain.search_k, min_decel, max_ttc, sort)
    except ValueError as exc:
        raise _fail(exc, 2) from None
    st = _open_store(store, cfg)
    try:
        embedder = make_embedder(cfg) if query is not None else None
        hits = search_events(st, q, embedder)
    except (NoEventsError, StoreError, LLMError, ValueError) as exc:
        raise _fail(exc) from None
    if json_out:
        console.print_json(json.dumps([h.to_json_dict() for h in hits]))
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
    cfg = _config(config)
    st = _open_store(store, cfg)
    target = out or Path(f"{log_id}_{(event or 'event').replace(':', '_')}.png")
    try:
        path = show_event(st, log_id, target, event, cfg.explain)
    except (NoEventsError, UnknownEventError, StoreError, KeyError) as exc:
        raise _fail(exc) from None
    console.print(f"wrote {path}")


def register(app: typer.Typer) -> None:
    """Add the ``analyze``, ``search`` and ``show`` commands to ``app``."""
    app.command("analyze")(analyze)
    app.command("search")(search)
    app.command("show")(show)
