"""The ``store`` command group: check the store for leftovers and damage, and clean it."""

from __future__ import annotations

import typer

from scenariominer.cli._common import ConfigOpt, JsonOpt, StoreOpt, console, load_cfg
from scenariominer.cli.text import safe

app = typer.Typer(name="store", help="Check and clean the scenario store.", no_args_is_help=True)


@app.command("check")
def check(store: StoreOpt = None, config: ConfigOpt = None, json_out: JsonOpt = False) -> None:
    """List leftovers of killed writers and missing files (changes nothing); exit 1 if damaged."""
    import json
    from dataclasses import asdict

    from scenariominer import api

    report = api.store_check(store, load_cfg(config))
    if json_out:
        console().print_json(json.dumps({**asdict(report), "ok": report.ok}))
    else:
        out = console()
        out.print(f"store {safe(report.root)}: {report.n_logs} log(s)", soft_wrap=True)
        for title, items in (
            ("missing files (re-ingest these logs)", report.missing_files),
            ("orphaned files (removed by `store vacuum`)", report.orphaned_files),
            ("stale staging (removed by `store vacuum`)", report.stale_staging),
        ):
            out.print(f"{title}: {len(items)}")
            for item in items[:20]:
                out.print(f"  {safe(item)}", soft_wrap=True)
        out.print(f"corpus tables: {safe(', '.join(report.corpus_tables)) or '-'}")
    if not report.ok:
        raise typer.Exit(1)


@app.command("vacuum")
def vacuum(store: StoreOpt = None, config: ConfigOpt = None) -> None:
    """Remove leftovers of killed writers; committed data is never touched."""
    from scenariominer import api

    removed = api.store_vacuum(store, load_cfg(config))
    console().print(f"removed {removed} leftover path(s)")
