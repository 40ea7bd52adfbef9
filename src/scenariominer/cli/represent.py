"""The ``embed`` command group (windows, train, apply, cluster, plot) and ``similar``."""

from __future__ import annotations

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
    load_cfg,
    with_exec,
)
from scenariominer.cli.progress import progress_bar
from scenariominer.cli.text import safe

if TYPE_CHECKING:
    from scenariominer.represent.pipeline import WindowsReport
    from scenariominer.represent.similar import SimilarResult
    from scenariominer.represent.stages import ApplyReport, ClusterReport, TrainReport

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
    executor: ExecutorOpt = None,
    workers: WorkersOpt = None,
    ray_address: RayAddressOpt = None,
) -> None:
    """Cut stored logs into windows of an agent and its nearest road users (only new or changed logs)."""
    import dataclasses
    import json

    from scenariominer import api

    cfg = with_exec(load_cfg(config), executor, workers, ray_address)
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


ModelOpt = Annotated[str | None, typer.Option("--model", help="Model id (default: the latest trained).")]
LossOpt = Annotated[
    str | None, typer.Option("--loss", help="Reconstruction loss: hausdorff (the paper's) or mse (baseline).")
]


def _json(report: object) -> None:
    import dataclasses
    import json

    console().print_json(json.dumps(dataclasses.asdict(report), default=str))  # type: ignore[call-overload]


def render_train_report(report: TrainReport) -> None:
    """Print the stored model and its training losses."""
    m, s = report.model, report.summary
    console().print(
        f"model {safe(m.model_id)}: {m.loss} loss, {s.n_windows} windows of {report.n_logs} logs "
        f"({m.n_agents} agents x {m.n_steps} steps), {len(s.loss_history)} epochs in {s.seconds:.1f} s; "
        f"loss {s.loss_history[0]:.4f} -> {s.loss_history[-1]:.4f}",
        highlight=False,
    )
    for note in report.notes:
        console().print(f"[yellow]note:[/yellow] {safe(note)}", highlight=False, soft_wrap=True)


@app.command("train")
def train(
    store: StoreOpt = None,
    config: ConfigOpt = None,
    loss: LossOpt = None,
    epochs: Annotated[int | None, typer.Option(help="Passes over the windows.")] = None,
    seed: Annotated[int | None, typer.Option(help="Training seed.")] = None,
    json_out: JsonOpt = False,
) -> None:
    """Train the trajectory autoencoder on the stored windows; store it and their embeddings."""
    from scenariominer import api

    cfg = load_cfg(config)
    st = api.open_existing_store(store, cfg)
    request = api.TrainRequest(loss=loss, epochs=epochs, seed=seed)
    with progress_bar(not json_out) as bar:
        report = api.train_embedder(st, request, cfg, progress=bar)
    if json_out:
        _json(report)
        return
    render_train_report(report)


def render_apply_report(report: ApplyReport) -> None:
    """Print what was embedded and assigned."""
    out = console()
    if report.n_logs_cut or report.failed_logs:
        out.print(
            f"cut windows of {report.n_logs_cut} new logs with the model's settings"
            + (f"; {len(report.failed_logs)} could not be cut" if report.failed_logs else ""),
            highlight=False,
        )
    out.print(
        f"model {safe(report.model_id)}: embedded {report.n_windows_embedded} windows of "
        f"{report.n_logs_embedded} new or changed logs",
        highlight=False,
    )
    if report.clustering_id:
        out.print(
            f"assigned {report.n_windows_assigned} windows to clustering {safe(report.clustering_id)} "
            f"without re-clustering ({report.n_assigned_noise} outliers)",
            highlight=False,
        )
    if report.skipped_logs:
        out.print(
            f"skipped {len(report.skipped_logs)} logs whose windows were cut with other settings than "
            "the model's (re-cut them or train a new model)",
            highlight=False,
        )


@app.command("apply")
def apply(
    store: StoreOpt = None,
    config: ConfigOpt = None,
    model: ModelOpt = None,
    loss: LossOpt = None,
    json_out: JsonOpt = False,
) -> None:
    """Embed windows of new logs with a trained model (no retraining) and assign them to its clusters."""
    from scenariominer import api

    cfg = load_cfg(config)
    st = api.open_existing_store(store, cfg)
    with progress_bar(not json_out) as bar:
        report = api.apply_embedder(st, api.ApplyRequest(model_id=model, loss=loss), cfg, progress=bar)
    if json_out:
        _json(report)
        return
    render_apply_report(report)


def render_cluster_report(report: ClusterReport) -> None:
    """Print the clusters found and how lane-change windows fall across them."""
    sizes = ", ".join(str(s) for s in report.sizes[:30]) + (" ..." if len(report.sizes) > 30 else "")
    out = console()
    out.print(
        f"clustering {safe(report.clustering_id)}: {report.n_clusters} clusters and {report.n_noise} "
        f"outliers among {report.n_windows} windows; sizes {sizes}",
        highlight=False,
    )
    if report.n_with_lanes:
        with_lc = [(i, n) for i, n in enumerate(report.lane_change_by_cluster) if n]
        majority = [i for i, n in with_lc if 2 * n > report.sizes[i]]
        out.print(
            f"lane-change windows: {report.n_lane_change} of {report.n_with_lanes} with lane ids; "
            f"{report.lane_change_noise} outliers, the rest in {len(with_lc)} clusters; "
            f"{len(majority)} clusters are mostly lane changes, holding "
            f"{sum(report.lane_change_by_cluster[i] for i in majority)}",
            highlight=False,
        )


@app.command("cluster")
def cluster(
    store: StoreOpt = None,
    config: ConfigOpt = None,
    model: ModelOpt = None,
    loss: LossOpt = None,
    min_cluster_size: Annotated[int | None, typer.Option(help="HDBSCAN min_cluster_size.")] = None,
    min_samples: Annotated[
        int | None, typer.Option(help="HDBSCAN min_samples (0: = min_cluster_size).")
    ] = None,
    selection: Annotated[str | None, typer.Option(help="HDBSCAN cluster selection: eom or leaf.")] = None,
    json_out: JsonOpt = False,
) -> None:
    """Cluster every embedded window of a model with HDBSCAN (noise kept as outliers)."""
    from scenariominer import api

    cfg = load_cfg(config)
    st = api.open_existing_store(store, cfg)
    request = api.ClusterRequest(
        model_id=model,
        loss=loss,
        min_cluster_size=min_cluster_size,
        min_samples=min_samples,
        selection=selection,
    )
    with progress_bar(not json_out) as bar:
        report = api.cluster_windows(st, request, cfg, progress=bar)
    if json_out:
        _json(report)
        return
    render_cluster_report(report)


@app.command("plot")
def plot(
    out: Annotated[Path, typer.Option("--out", help="Folder for the PNG files.")],
    store: StoreOpt = None,
    config: ConfigOpt = None,
    model: ModelOpt = None,
    loss: LossOpt = None,
    json_out: JsonOpt = False,
) -> None:
    """Write t-SNE projections coloured by cluster and by scenario features (PNG)."""
    from scenariominer import api

    cfg = load_cfg(config)
    st = api.open_existing_store(store, cfg)
    with progress_bar(not json_out) as bar:
        report = api.plot_embeddings(
            st, api.PlotRequest(out_dir=out, model_id=model, loss=loss), cfg, progress=bar
        )
    if json_out:
        _json(report)
        return
    console().print(
        f"{report.n_windows} windows of model {safe(report.model_id)}, {report.n_clusters} clusters: "
        f"wrote {len(report.files)} files to {safe(out)}",
        highlight=False,
    )


def render_similar(result: SimilarResult) -> None:
    """Print the query window and the hits as a table."""
    from rich.table import Table

    q = result.query
    table = Table(
        title=f"nearest to {safe(q.log_id)} track {safe(q.track_id)} {q.start_s:.1f}-{q.end_s:.1f} s "
        f"(model {safe(result.model_id)}, {result.searched} windows)",
        title_justify="left",
    )
    for col in ("#", "log", "track", "time [s]", "distance"):
        table.add_column(col, overflow="fold")
    for i, h in enumerate(result.hits, 1):
        table.add_row(
            str(i), safe(h.log_id), safe(h.track_id), f"{h.start_s:.1f}-{h.end_s:.1f}", f"{h.distance:.4f}"
        )
    console().print(table)


def similar(
    log: Annotated[str, typer.Argument(help="Log id of the example.")],
    track: Annotated[str, typer.Option("--track", help="Track id of the example's agent.")],
    t: Annotated[float, typer.Option("--t", help="Moment, seconds since the log's first timestamp.")],
    k: Annotated[int, typer.Option("-k", help="Number of windows to return.")] = 10,
    store: StoreOpt = None,
    config: ConfigOpt = None,
    model: ModelOpt = None,
    json_out: JsonOpt = False,
) -> None:
    """Nearest windows in embedding space to an agent's window (query by example)."""
    from scenariominer import api

    cfg = load_cfg(config)
    st = api.open_existing_store(store, cfg)
    result = api.similar(st, api.SimilarRequest(log_id=log, track_id=track, t_s=t, k=k, model_id=model), cfg)
    if json_out:
        _json(result)
        return
    render_similar(result)


def register(root: typer.Typer) -> None:
    """Add the ``embed`` group and the ``similar`` command to the root app."""
    root.add_typer(app, name="embed", help="Trajectory windows, embeddings and clusters (seed 001).")
    root.command("similar")(similar)
