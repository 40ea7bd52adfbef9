"""Command ``simulate urban``: SUMO braking scenarios written as labelled Argoverse 2 logs."""

from __future__ import annotations

import json
from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer

from scenariominer.cli._common import JsonOpt, console, err_console
from scenariominer.cli.progress import progress_bar
from scenariominer.cli.text import safe

if TYPE_CHECKING:
    from scenariominer.sim.urban import UrbanSetResult


def _report_json(report: UrbanSetResult) -> str:
    return json.dumps(
        {
            "out_dir": str(report.out_dir),
            "labels_csv": str(report.labels_csv),
            "seconds": report.seconds,
            "rejected_draws": report.rejections,
            "logs": [
                {
                    "index": r.index,
                    "category": r.category.value,
                    "ok": r.ok,
                    "error": r.error,
                    "log_id": r.log_id,
                    "guest_id": r.guest_id,
                    "noise": r.noise,
                    "style": r.style,
                    "attempts": r.attempts,
                    "tracks": r.n_tracks,
                    "sim_s": r.sim_s,
                }
                for r in report.logs
            ],
        }
    )


def render_report(report: UrbanSetResult) -> None:
    """Print one row per log (failures on stderr), the rejected draws and the totals."""
    from rich.table import Table

    for r in report.logs:
        if not r.ok:
            err_console().print(f"[red]failed[/red] log {r.index:03d}: {safe(r.error)}", soft_wrap=True)
    table = Table(title=f"simulated urban braking logs in {safe(report.out_dir)}", title_justify="left")
    for name in ("#", "category", "noise", "driver", "draws", "tracks", "log id", "s"):
        table.add_column(
            name, justify="left" if name in ("category", "noise", "driver", "log id") else "right"
        )
    for r in report.logs:
        if r.ok:
            table.add_row(
                f"{r.index:03d}", r.category.value, r.noise, r.style, str(r.attempts), str(r.n_tracks),
                safe(r.log_id[:8]), f"{r.sim_s:.1f}",
            )  # fmt: skip
    out = console()
    out.print(table)
    for reason, count in sorted(report.rejections.items(), key=lambda kv: -kv[1]):
        out.print(f"  redrawn {count}x: {safe(reason)}", highlight=False, soft_wrap=True)
    written = len(report.logs) - report.n_failed
    out.print(
        f"{written} log(s) written, {report.n_failed} failed, in {report.seconds:.1f} s; labels in "
        f"{safe(report.labels_csv)}. Ingest with: scenariominer ingest {safe(report.out_dir)}",
        highlight=False,
        soft_wrap=True,
    )


def urban(
    out: Annotated[Path, typer.Option("--out", "-o", help="Output folder for the logs and labels.csv.")],
    n: Annotated[int, typer.Option("--n", help="Number of logs (categories cycle).")] = 40,
    seed: Annotated[int, typer.Option(help="Seed of the whole set (same seed, same files).")] = 0,
    noise: Annotated[
        str,
        typer.Option(help="Tracker-like noise: none, low, medium, high, or mixed (cycles low/medium/high)."),
    ] = "mixed",
    category: Annotated[
        list[str] | None,
        typer.Option(
            "--category",
            help="Only these categories (repeatable): ped_crossing, left_oppo, cut_in, lead_brake, "
            "obj_crossing, right_ped, approach_stop.",
        ),
    ] = None,
    overwrite: Annotated[
        bool,
        typer.Option("--overwrite", help="Replace an earlier set in OUT (the logs its labels.csv lists)."),
    ] = False,
    keep_sumo: Annotated[
        bool,
        typer.Option("--keep-sumo-output", help="Keep each log's SUMO network and routes in OUT/sumo/NNN/."),
    ] = False,
    json_out: JsonOpt = False,
) -> None:
    """Simulate urban braking scenarios with SUMO and write them as labelled Argoverse 2 logs.

    Writes OUT/<log_id>/ (annotations, ego poses, vector map; read by `scenariominer ingest`)
    and OUT/labels.csv naming the road user that forced the ego to brake (read by `scenariominer
    eval braking`; see docs/simulate.md). A log that fails is reported and the others are
    written; the exit status is 1 when any failed.
    """
    from scenariominer import api
    from scenariominer.sim.urban import UrbanSettings

    settings = UrbanSettings(n=n, seed=seed, noise=noise, categories=tuple(category or ()))
    request = api.UrbanSimRequest(
        out_dir=out, settings=settings, overwrite=overwrite, keep_sumo_outputs=keep_sumo
    )
    with progress_bar(not json_out) as bar:
        report = api.simulate_urban(request, progress=bar)
    if json_out:
        console().print_json(_report_json(report))
    else:
        render_report(report)
    if report.n_failed:
        raise typer.Exit(1)


def register(app: typer.Typer) -> None:
    """Add the ``urban`` command to the ``simulate`` group."""
    app.command("urban")(urban)
