"""The ``scenariominer`` command: a thin Typer layer over :mod:`scenariominer.api`.

Each command parses options, calls one API function, and renders the result with Rich.
No pipeline logic lives here.
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer
from rich.console import Console
from rich.table import Table

from scenariominer import api
from scenariominer.config import Config, ConfigError, load_config
from scenariominer.data.log import LogFormatError
from scenariominer.progress import RichProgress
from scenariominer.store import StoreError, StoreInfo

app = typer.Typer(
    name="scenariominer",
    help="Turn recorded driving logs into a searchable, explainable scenario database.",
    no_args_is_help=True,
    pretty_exceptions_enable=False,
)
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


def _fail(exc: Exception) -> typer.Exit:
    err_console.print(f"[red]error:[/red] {exc}")
    return typer.Exit(1)


def render_store_info(info: StoreInfo, title: str = "Scenario store") -> None:
    """Print a store summary: logs, tracks, frames, duration, categories, derived tables."""
    table = Table(title=f"{title}: {info.root}", show_header=False, title_justify="left")
    table.add_row("logs", f"{info.n_logs:,}")
    table.add_row("tracks", f"{info.n_tracks:,}")
    table.add_row("frames (track observations)", f"{info.n_frames:,}")
    table.add_row("timestamps", f"{info.n_timestamps:,}")
    table.add_row("duration", f"{info.total_duration_s:,.1f} s ({info.total_duration_s / 3600:.2f} h)")
    table.add_row("datasets", ", ".join(f"{k}: {v}" for k, v in sorted(info.datasets.items())) or "-")
    table.add_row("derived tables", ", ".join(info.tables) or "-")
    table.add_row("size on disk", f"{info.size_bytes / 1e6:,.1f} MB")
    console.print(table)
    if info.categories:
        cats = Table(title="tracks per category", title_justify="left")
        cats.add_column("category")
        cats.add_column("tracks", justify="right")
        for name, count in sorted(info.categories.items(), key=lambda kv: -kv[1]):
            cats.add_row(name, f"{count:,}")
        console.print(cats)


def render_ingest_report(report: api.IngestReport) -> None:
    """Print what an ingestion run did, failures first."""
    for failed in report.failed:
        err_console.print(f"[red]failed[/red] {failed.key}: {failed.error}")
    notes = [n for r in report.sources for n in r.notes]
    for note in notes[:10]:
        console.print(f"[yellow]repaired[/yellow] {note}")
    if len(notes) > 10:
        console.print(f"[yellow]... {len(notes) - 10} more repair note(s)[/yellow]")
    fps = report.n_frames_ingested / report.seconds if report.seconds > 0 else 0.0
    console.print(
        f"ingested {report.n_ingested} source(s) ({report.n_logs_ingested} logs, "
        f"{report.n_frames_ingested:,} frames, {fps:,.0f} frames/s), skipped {report.n_skipped} unchanged, "
        f"failed {len(report.failed)} in {report.seconds:.1f} s"
    )
    render_store_info(report.store)


@app.command()
def ingest(
    paths: Annotated[
        list[Path], typer.Argument(help="AV2 log folders or dataset roots, highD recordings, tabular files.")
    ],
    store: StoreOpt = None,
    config: ConfigOpt = None,
    force: Annotated[bool, typer.Option(help="Re-ingest unchanged sources too.")] = False,
    json_out: Annotated[bool, typer.Option("--json", help="Print the report as JSON.")] = False,
) -> None:
    """Ingest driving logs into the scenario store (incremental, atomic per log)."""
    cfg = _config(config)
    try:
        st = api.open_store(store, cfg)
        bar = RichProgress()
        try:
            report = api.ingest(paths, st, cfg, force=force, progress=bar)
        finally:
            bar.close()
    except (LogFormatError, StoreError) as exc:
        raise _fail(exc) from None
    if json_out:
        console.print_json(report.to_json())
    else:
        render_ingest_report(report)
    if report.failed and not report.n_ingested and not report.n_skipped:
        raise typer.Exit(1)


@app.command()
def info(store: StoreOpt = None, config: ConfigOpt = None) -> None:
    """Summarise what the scenario store holds."""
    cfg = _config(config)
    try:
        render_store_info(api.info(api.open_store(store, cfg)))
    except StoreError as exc:
        raise _fail(exc) from None


def main() -> None:
    """Console-script entry point."""
    app()


if __name__ == "__main__":  # pragma: no cover
    main()
