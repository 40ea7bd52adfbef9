"""Commands ``ingest``, ``info``, ``synth`` and ``demo``."""

from __future__ import annotations

import re
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

if TYPE_CHECKING:
    from scenariominer.api.corpus import IngestReport
    from scenariominer.store import StoreInfo


def render_store_info(info: StoreInfo, title: str = "Scenario store") -> None:
    """Print a store summary: logs, tracks, frames, duration, categories, derived tables."""
    from rich.table import Table

    table = Table(title=f"{title}: {safe(info.root)}", show_header=False, title_justify="left")
    table.add_row("logs", f"{info.n_logs:,}")
    table.add_row("tracks", f"{info.n_tracks:,}")
    table.add_row("frames (track observations)", f"{info.n_frames:,}")
    table.add_row("timestamps", f"{info.n_timestamps:,}")
    table.add_row("duration", f"{info.total_duration_s:,.1f} s ({info.total_duration_s / 3600:.2f} h)")
    datasets = ", ".join(f"{k}: {v}" for k, v in sorted(info.datasets.items()))
    table.add_row("datasets", safe(datasets) or "-")
    table.add_row("derived tables", safe(", ".join(info.tables)) or "-")
    table.add_row("size on disk", f"{info.size_bytes / 1e6:,.1f} MB")
    console().print(table)
    if info.categories:
        cats = Table(title="tracks per category", title_justify="left")
        cats.add_column("category")
        cats.add_column("tracks", justify="right")
        for name, count in sorted(info.categories.items(), key=lambda kv: -kv[1]):
            cats.add_row(safe(name), f"{count:,}")
        console().print(cats)


def render_ingest_report(report: IngestReport) -> None:
    """Print what an ingestion run did, failures first."""
    for failed in report.failed:
        err_console().print(f"[red]failed[/red] {safe(failed.key)}: {safe(failed.error)}", soft_wrap=True)
    # Repairs are grouped by kind (numbers and examples ignored) so a large batch stays readable;
    # each group shows one real note, never a template with placeholders.
    kinds: dict[str, list[tuple[str, str]]] = {}
    for r in report.sources:
        for note in r.notes:
            log_id, _, text = note.partition(": ")
            kind = re.sub(r"\(e\.g\..*\)", "", re.sub(r"\d+", "#", text)).strip()
            kinds.setdefault(kind, []).append((log_id, text))
    for _kind, notes in sorted(kinds.items()):
        log_id, text = notes[0]
        n_logs = len({lid for lid, _ in notes})
        console().print(
            f"[yellow]repaired[/yellow] {n_logs} log(s), e.g. {safe(log_id)}: {safe(text)}", soft_wrap=True
        )
    fps = report.n_frames_ingested / report.seconds if report.seconds > 0 else 0.0
    console().print(
        f"ingested {report.n_ingested} source(s) ({report.n_logs_ingested} logs, "
        f"{report.n_frames_ingested:,} frames, {fps:,.0f} frames/s), skipped {report.n_skipped} unchanged, "
        f"failed {len(report.failed)} in {report.seconds:.1f} s"
    )
    render_store_info(report.store)


def ingest(
    paths: Annotated[
        list[Path], typer.Argument(help="AV2 log folders or dataset roots, highD recordings, tabular files.")
    ],
    store: StoreOpt = None,
    config: ConfigOpt = None,
    force: Annotated[bool, typer.Option(help="Re-ingest unchanged sources too.")] = False,
    json_out: JsonOpt = False,
    executor: ExecutorOpt = None,
    workers: WorkersOpt = None,
    ray_address: RayAddressOpt = None,
) -> None:
    """Ingest driving logs into the scenario store (incremental, atomic per log).

    A path or source that fails is reported and the others are still ingested; the exit status is
    1 when anything failed, 0 otherwise.
    """
    from scenariominer import api
    from scenariominer.cli.progress import progress_bar

    cfg = with_exec(load_cfg(config), executor, workers, ray_address)
    st = api.open_store(store, cfg)
    with progress_bar(not json_out) as bar:
        report = api.ingest(paths, st, cfg, force=force, progress=bar)
    if json_out:
        console().print_json(report.to_json())
    else:
        render_ingest_report(report)
    if report.failed:  # the rest of the batch landed; the exit status still says something failed
        raise typer.Exit(1)


def info(store: StoreOpt = None, config: ConfigOpt = None, json_out: JsonOpt = False) -> None:
    """Summarise what the scenario store holds (never creates a store)."""
    import json
    from dataclasses import asdict

    from scenariominer import api

    summary = api.info(api.open_existing_store(store, load_cfg(config)))
    if json_out:
        console().print_json(json.dumps(asdict(summary), default=str))
    else:
        render_store_info(summary)


def synth(
    out: Annotated[
        Path, typer.Option("--out", "-o", help="Output folder (one AV2 log folder per scenario).")
    ],
    n: Annotated[int, typer.Option("--n", "-n", min=1, help="Number of labelled logs.")] = 40,
    seed: Annotated[int, typer.Option(help="Random seed (log i depends only on seed and i).")] = 0,
    category: Annotated[
        list[str] | None, typer.Option("--category", help="Only these scenario categories (repeatable).")
    ] = None,
) -> None:
    """Generate labelled synthetic scenarios in the Argoverse 2 format plus OUT/labels.csv."""
    from rich.table import Table

    from scenariominer import api
    from scenariominer.cli.progress import progress_bar

    with progress_bar() as bar:
        result = api.synth(out, n, seed=seed, categories=category or None, progress=bar)
    counts: dict[str, int] = {}
    for label in result.labels:
        counts[str(label.scenario_category)] = counts.get(str(label.scenario_category), 0) + 1
    title = f"{len(result.log_dirs)} synthetic logs in {safe(result.out_dir)}"
    table = Table(title=title, title_justify="left")
    table.add_column("category")
    table.add_column("logs", justify="right")
    for name, count in sorted(counts.items()):
        table.add_row(name, str(count))
    console().print(table)
    console().print(f"labels: {safe(result.labels_csv)}")


def demo(
    out: Annotated[Path, typer.Option("--out", "-o", help="Working folder for the demo.")] = Path("demo-out"),
    n: Annotated[int, typer.Option("--n", "-n", min=1, help="Synthetic logs to generate.")] = 24,
    llm_events: Annotated[
        int,
        typer.Option("--llm-events", min=0, help="Braking events the embedded LLM classifies (slow on CPU)."),
    ] = 6,
    av2: Annotated[
        list[Path] | None,
        typer.Option("--av2", help="Argoverse 2 logs to ingest (default: the shared sample)."),
    ] = None,
    config: ConfigOpt = None,
) -> None:
    """Run the main job on the embedded defaults.

    Generates a labelled synthetic set, ingests it with the Argoverse 2 sample log into a fresh
    store, explains braking events with the embedded LLM, searches them both ways, draws one,
    and mines the sample log for "vehicle with a bicycle to its right" scored by the official metric.
    The demo is a guided tour of the other commands: each step calls one of them.
    """
    from scenariominer import api
    from scenariominer.cli import braking, evaluation, mining
    from scenariominer.schema import ExportFormat

    load_cfg(config)  # fail early on a bad file
    av2_paths = list(av2 or [])
    if not av2_paths:
        sample = api.find_sample_av2()
        if sample is None:
            err_console().print(
                "[yellow]no Argoverse 2 sample beside the checkout; using synthetic data only[/yellow]"
            )
        else:
            av2_paths.append(sample)
    out.mkdir(parents=True, exist_ok=True)
    store = out / "store"
    rule = console().rule
    rule("[bold]1. synthetic labelled scenarios")
    synth(out=out / "synth", n=n, seed=0, category=None)
    rule("[bold]2. ingestion (validate, interpolate, smooth, store)")
    ingest(paths=[*av2_paths, out / "synth"], store=store, config=config, force=False, json_out=False)
    rule(f"[bold]3. why braking: tags, key objects, LLM explanations (first {llm_events} events)")
    braking.analyze(store=store, config=config, limit=llm_events)
    rule("[bold]4. dual-path retrieval")
    braking.search(query=None, category="cut_in", store=store, config=config, k=5)
    braking.search(
        query="The lead vehicle suddenly brakes, requiring the ego vehicle to brake.",
        store=store,
        config=config,
        k=5,
    )
    rule("[bold]5. program-based mining on the Argoverse 2 sample")
    pred = out / "mining-predictions.pkl"
    for path in av2_paths:
        mining.mine(
            "vehicle with a bicycle to its right",
            logs=[path],
            store=store,
            export=ExportFormat.AV2,
            out=pred,
            config=config,
        )
        gts = sorted(path.glob("scenario_mining_gt_*.pkl")) if path.is_dir() else []
        if gts and pred.is_file():
            rule("[bold]6. official Argoverse 2 scenario-mining metrics")
            try:
                evaluation.mining(pred=pred, gt=gts[0], dataset_dir=path, out=out / "mining-eval")
            except typer.Exit:
                err_console().print("[yellow]evaluation skipped (install the av2eval extra)[/yellow]")
    console().print(f"\ndemo outputs in {safe(out)}: store/, synth/labels.csv, mining-predictions.pkl")


def register(app: typer.Typer) -> None:
    """Add this module's commands to ``app``."""
    for command in (ingest, info, synth, demo):
        app.command(command.__name__)(command)
