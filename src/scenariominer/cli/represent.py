"""The ``embed`` command group (windows, train, apply, cluster, plot) and ``similar``."""

from __future__ import annotations

from typing import TYPE_CHECKING, Annotated

import typer

from scenariominer.cli._common import ConfigOpt, JsonOpt, StoreOpt, console, load_cfg
from scenariominer.cli.progress import progress_bar
from scenariominer.cli.text import safe

if TYPE_CHECKING:
    from scenariominer.represent.pipeline import WindowsReport

app = typer.Typer(name="embed", help="Trajectory windows, embeddings and clusters.", no_args_is_help=True)


@app.callback()
def _group() -> None:
    """Trajectory windows, embeddings and clusters (seed 001)."""


def render_windows_report(report: WindowsReport) -> None:
    """Print the per-log outcome and the totals."""
    out = console()
    for r in report.failed:
        out.print(f"[red]failed[/red] {safe(r.log_id)}: {safe(r.error)}", highlight=False)
    n_current = sum(r.status == "current" for r in report.logs)
    n_lanes = sum(r.has_lanes for r in report.logs if r.status == "built")
    out.print(
        f"{report.n_windows} windows from {len(report.logs)} logs: {report.n_built} cut now "
        f"({n_lanes} with lane ids), {n_current} already current, {len(report.failed)} failed "
        f"(settings {report.config_hash})",
        highlight=False,
    )


@app.command("windows")
def windows(
    store: StoreOpt = None,
    config: ConfigOpt = None,
    log: Annotated[list[str] | None, typer.Option("--log", help="Only this log (repeatable).")] = None,
    length: Annotated[
        list[float] | None,
        typer.Option("--length", help="Window length in seconds (repeatable: multi-scale)."),
    ] = None,
    overlap: Annotated[
        float | None, typer.Option(help="Fraction shared by consecutive windows, 0..1.")
    ] = None,
    agents: Annotated[str | None, typer.Option(help="Chosen agents: ego or vehicles.")] = None,
    rebuild: Annotated[
        bool, typer.Option("--rebuild", help="Re-cut logs whose windows are current.")
    ] = False,
    json_out: JsonOpt = False,
) -> None:
    """Cut stored logs into windows of an agent and its nearest road users (only new or changed logs)."""
    import dataclasses
    import json

    from scenariominer import api

    cfg = load_cfg(config)
    st = api.open_existing_store(store, cfg)
    request = api.WindowsRequest(
        log_ids=log or None, lengths_s=length or None, overlap=overlap, agents=agents, rebuild=rebuild
    )
    with progress_bar(not json_out) as bar:
        report = api.build_windows(st, request, cfg, progress=bar)
    if json_out:
        console().print_json(json.dumps(dataclasses.asdict(report)))
        return
    render_windows_report(report)


def register(root: typer.Typer) -> None:
    """Add the ``embed`` group and the ``similar`` command to the root app."""
    root.add_typer(app, name="embed", help="Trajectory windows, embeddings and clusters (seed 001).")
