"""Commands ``cbr add/list/show/remove/build``, ``recommend`` and ``eval cbr`` (seed 002)."""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer

from scenariominer.cli._common import ConfigOpt, JsonOpt, StoreOpt, console, load_cfg
from scenariominer.cli.text import safe

if TYPE_CHECKING:
    from scenariominer.cbr.cases import AddReport, Case
    from scenariominer.cbr.rollout import RolloutOutcome
    from scenariominer.config import Config
    from scenariominer.eval.cbr import CbrEvaluation
    from scenariominer.store import ScenarioStore

app = typer.Typer(
    name="cbr", help="The case base of evasive manoeuvres (case-based reasoning).", no_args_is_help=True
)


def _store(store: Path | None, config: Path | None, create: bool = False) -> tuple[ScenarioStore, Config]:
    from scenariominer import api

    cfg = load_cfg(config)
    st = api.open_store(store, cfg) if create else api.open_existing_store(store, cfg)
    return st, cfg


def render_add(report: AddReport) -> None:
    """Print what an add stored, skipped as near-duplicate and rejected."""
    out = console()
    out.print(f"added {len(report.added)} case(s)", highlight=False)
    for d in report.duplicates[:20]:
        out.print(
            f"[yellow]near-duplicate[/yellow] {safe(d.case_id)} of {safe(d.existing_id)} "
            f"(caption cosine {d.similarity:.3f}); not stored",
            soft_wrap=True,
        )
    if len(report.duplicates) > 20:
        out.print(f"... {len(report.duplicates) - 20} more near-duplicates")
    for row, why in report.rejected[:20]:
        out.print(f"[red]rejected[/red] {safe(row)}: {safe(why)}", soft_wrap=True)


@app.command("add")
def add(
    file: Annotated[Path | None, typer.Argument(help="CSV or JSONL file of cases (see docs/cbr.md).")] = None,
    log: Annotated[str | None, typer.Option("--log", help="Log of an analysed event to add.")] = None,
    event: Annotated[
        str | None, typer.Option("--event", help="Event id (default: the hardest braking).")
    ] = None,
    manoeuvre: Annotated[
        str | None, typer.Option("--manoeuvre", "-m", help="The confirmed manoeuvre (name or label).")
    ] = None,
    justification: Annotated[str, typer.Option("--justification", help="Why it resolves the risk.")] = "",
    risk_type: Annotated[
        str | None, typer.Option("--risk-type", help="Override the mapped risk type.")
    ] = None,
    store: StoreOpt = None,
    config: ConfigOpt = None,
    json_out: JsonOpt = False,
) -> None:
    """Store confirmed cases from a file or an analysed event; near-duplicates are reported, not stored."""
    from scenariominer import api

    st, cfg = _store(store, config, create=file is not None)
    request = api.CbrAddRequest(file, log, event, manoeuvre, justification, risk_type)
    report = api.cbr_add(st, request, cfg)
    if json_out:
        console().print_json(json.dumps(report.to_json_dict()))
    else:
        render_add(report)
    if not report.added and report.rejected:
        raise typer.Exit(1)


@app.command("list")
def list_cases(
    risk_type: Annotated[str | None, typer.Option("--risk-type", help="Only this risk type.")] = None,
    store: StoreOpt = None,
    config: ConfigOpt = None,
    json_out: JsonOpt = False,
) -> None:
    """List the stored cases (id, risk type, manoeuvre, caption)."""
    from scenariominer import api

    st, cfg = _store(store, config)
    cases = api.cbr_list(st, cfg, risk_type)
    if json_out:
        console().print_json(json.dumps([c.to_json_dict() for c in cases]))
        return
    out = console()
    out.print(f"{len(cases)} case(s)")
    if not cases and risk_type is None:
        out.print("the case base is empty: `scenariominer cbr build` makes one, `cbr add` adds cases")
    for c in cases:
        cap = c.caption if len(c.caption) <= 90 else c.caption[:87] + "..."
        out.print(
            f"{safe(c.case_id)}  {safe(c.risk_type)}  {safe(c.manoeuvre)}  {safe(cap)}", highlight=False
        )


def render_case(case: Case) -> None:
    """Print every field of a case."""
    out = console()
    for k, v in case.to_json_dict().items():
        out.print(f"[bold]{k}[/bold]: {safe(v)}", highlight=False, soft_wrap=True)


@app.command("show")
def show(
    case_id: Annotated[str, typer.Argument(help="Case id.")],
    store: StoreOpt = None,
    config: ConfigOpt = None,
    json_out: JsonOpt = False,
) -> None:
    """Show one stored case."""
    from scenariominer import api

    st, cfg = _store(store, config)
    case = api.cbr_show(st, cfg, case_id)
    if json_out:
        console().print_json(json.dumps(case.to_json_dict()))
    else:
        render_case(case)


@app.command("remove")
def remove(
    case_ids: Annotated[list[str], typer.Argument(help="Case id(s).")],
    store: StoreOpt = None,
    config: ConfigOpt = None,
) -> None:
    """Delete cases from the case base."""
    from scenariominer import api

    st, cfg = _store(store, config)
    n = api.cbr_remove(st, cfg, case_ids)
    console().print(f"removed {n} of {len(case_ids)} case(s)")
    if n < len(case_ids):
        raise typer.Exit(1)


@app.command("build")
def build(
    per_type: Annotated[
        int, typer.Option("--per-type", min=2, help="Cases per risk type (both splits).")
    ] = 110,
    holdout: Annotated[
        int, typer.Option("--holdout", min=0, help="Cases per risk type held out (never in the case base).")
    ] = 10,
    seed: Annotated[int, typer.Option("--seed", help="Random seed of the scenes.")] = 0,
    store: StoreOpt = None,
    config: ConfigOpt = None,
    json_out: JsonOpt = False,
) -> None:
    """Build the labelled synthetic case set (replaces the case base and its hold-out split)."""
    from scenariominer import api

    st, cfg = _store(store, config, create=True)
    report = api.cbr_build(st, api.CbrBuildRequest(per_type, holdout, seed), cfg)
    if json_out:
        console().print_json(json.dumps(report.to_json_dict()))
        return
    out = console()
    out.print(
        f"case base: {report.n_case_base} cases, hold-out: {report.n_holdout} cases "
        f"({report.n_drawn} scenes drawn, {len(report.add.duplicates)} near-duplicates skipped, "
        f"{report.seconds:.1f} s)"
    )
    for rt, counts in report.labels.items():
        labels = ", ".join(f"{k} {v}" for k, v in sorted(counts.items(), key=lambda kv: -kv[1]))
        out.print(f"  {rt}: {labels}", highlight=False)


def _num(x: float, unit: str = "") -> str:
    if math.isnan(x):
        return "-"
    if math.isinf(x):
        return "none"
    return f"{x:.2f}{unit}"


def _outcome_line(o: RolloutOutcome) -> str:
    verdict = f"COLLISION at {o.first_collision_s:.1f} s" if o.collision else "avoided"
    return (
        f"{o.manoeuvre:<34} {verdict:<22} min dist {_num(o.min_distance_m, ' m'):>9}  "
        f"min TTC {_num(o.min_ttc_s, ' s'):>8}  closest {o.closest_id}"
    )


def recommend(
    log_id: Annotated[str, typer.Argument(metavar="LOG", help="Log id.")],
    event: Annotated[
        str | None,
        typer.Option("--event", help="Event id, <guest>:<start_ns> or guest id (default: hardest braking)."),
    ] = None,
    out: Annotated[Path | None, typer.Option("--out", "-o", help="PNG of the rollout check.")] = None,
    k: Annotated[int | None, typer.Option("--k", min=0, help="Few-shot cases (default cbr.k).")] = None,
    selection: Annotated[str | None, typer.Option("--selection", help="similarity or random.")] = None,
    risk_aware: Annotated[
        bool | None, typer.Option("--risk-aware/--risk-unaware", help="Show the risk type in the prompt.")
    ] = None,
    risk_type: Annotated[
        str | None, typer.Option("--risk-type", help="Override the mapped risk type.")
    ] = None,
    store: StoreOpt = None,
    config: ConfigOpt = None,
    json_out: JsonOpt = False,
) -> None:
    """Recommend an evasive manoeuvre for an analysed event, with its rollout check and a picture."""
    from scenariominer import api
    from scenariominer.cbr.rollout import RECORDED
    from scenariominer.llm.usage import UsageCounter

    st, cfg = _store(store, config)
    request = api.RecommendRequest(log_id, event, out, k, selection, risk_aware, risk_type)
    result = api.recommend(st, request, cfg, UsageCounter())
    if json_out:
        console().print_json(json.dumps(result.to_json_dict()))
        return
    rec, o = result.recommendation, console()
    o.print(
        f"[bold]event[/bold] {safe(rec.event_id)}  risk type {safe(result.query.risk_type)}", soft_wrap=True
    )
    o.print(f"[bold]caption[/bold] {safe(result.query.caption)}", soft_wrap=True, highlight=False)
    o.print(f"[bold]recommendation[/bold] {safe(rec.manoeuvre)}  ({rec.settings.label})", highlight=False)
    for key in ("road_context", "other_vehicle_position", "other_vehicle_action", "event_context"):
        o.print(f"  {key}: {safe(rec.answer.get(key, ''))}", soft_wrap=True, highlight=False)
    o.print(f"[bold]justification[/bold] {safe(rec.answer.get('justification', ''))}", soft_wrap=True)
    shown = ", ".join(f"{r.case.case_id} ({_num(r.score)})" for r in rec.retrieved) or "none (zero-shot)"
    o.print(f"[bold]retrieved cases[/bold] {safe(shown)}", soft_wrap=True, highlight=False)
    o.print("[bold]rollout check[/bold] (from the manoeuvre start, other road users on their recorded paths)")
    o.print("  " + safe(_outcome_line(result.outcomes[RECORDED])), highlight=False, soft_wrap=True)
    recommended = safe(_outcome_line(result.outcomes[rec.manoeuvre]))
    o.print(f"  {recommended}  <- recommended", highlight=False, soft_wrap=True)
    for note in result.notes:
        o.print(f"[yellow]note:[/yellow] {safe(note)}", soft_wrap=True, highlight=False)
    o.print(
        f"model time {rec.latency_s:.1f} s{' (cached)' if rec.cached else ''}, total {result.seconds:.1f} s; "
        f"wrote {safe(result.picture)}",
        soft_wrap=True,
    )


def render_eval(ev: CbrEvaluation) -> None:
    """Print the accuracy table (Tables 3-6 layout), the text metrics and the rollout success."""
    from rich.table import Table

    acc = Table(
        title=f"CBR evasive manoeuvre micro-accuracy on the hold-out split ({ev.model})", title_justify="left"
    )
    acc.add_column("configuration", no_wrap=True)
    for rt in ev.risk_types:
        acc.add_column(rt.replace("_", " "), justify="right", min_width=4)
    acc.add_column("overall", justify="right")
    for i, c in enumerate((*ev.configs, *ev.baselines)):
        if i == len(ev.configs):
            acc.add_section()  # the model-free baselines below the line
        acc.add_row(
            safe(c.label) + ("" if c.complete else " *"),
            *[_num(c.per_type.get(rt, math.nan)) for rt in ev.risk_types],
            _num(c.accuracy),
        )
    console().print(acc)
    run = Table(title="answers and rollout check", title_justify="left")
    run.add_column("configuration", no_wrap=True)
    for head in ("answered", "invalid", "rollout success", "s / recommendation"):
        run.add_column(head, justify="right")
    for i, c in enumerate((*ev.configs, *ev.baselines)):
        if i == len(ev.configs):
            run.add_section()
        run.add_row(
            safe(c.label) + ("" if c.complete else " *"),
            f"{c.n_answered}/{c.n_cases}",
            str(c.n_invalid),
            _num(c.rollout_success),
            _num(c.seconds_per_call),
        )
    console().print(run)
    metrics = sorted({m for c in ev.configs for f in c.text.values() for m in f})
    if metrics:
        txt = Table(title="text metrics (x100) against the hold-out references", title_justify="left")
        txt.add_column("configuration", no_wrap=True)
        for f in ("event_context", "justification"):
            for m in metrics:
                txt.add_column(f"{f[:5]} {m}", justify="right")
        for c in ev.configs:
            cells = [
                _num(c.text.get(f, {}).get(m, math.nan))
                for f in ("event_context", "justification")
                for m in metrics
            ]
            txt.add_row(c.label, *cells)
        console().print(txt)
    for n in ev.metric_notes:
        console().print(f"[yellow]{safe(n)}[/yellow]", soft_wrap=True)
    unfinished = any(not c.complete for c in ev.configs)
    console().print(
        f"hold-out {ev.n_holdout} cases, case base {ev.n_case_base} cases; {ev.fresh_calls} fresh model "
        f"calls, {ev.seconds:.0f} s. Below the line, no model: baseline/majority answers the case base's "
        "most frequent manoeuvre of the risk type, baseline/vote the most frequent among the most similar "
        "cases."
        + (" * = not every hold-out case answered yet (run again to continue)." if unfinished else ""),
        soft_wrap=True,
    )


def eval_cbr(
    per_type: Annotated[
        int | None, typer.Option("--per-type", min=1, help="Hold-out cases per risk type (default: all).")
    ] = None,
    ks: Annotated[str, typer.Option("--ks", help="Shots to compare, comma-separated.")] = "0,1,3,5",
    configs: Annotated[
        str | None, typer.Option("--configs", help="Only these configurations (e.g. aware/similarity/k3).")
    ] = None,
    time_budget: Annotated[
        float | None,
        typer.Option("--time-budget", min=0, help="Stop asking the model after this many seconds."),
    ] = None,
    text: Annotated[
        bool, typer.Option("--text-metrics/--no-text-metrics", help="BLEU/ROUGE/METEOR/CIDEr.")
    ] = True,
    picture: Annotated[
        Path | None,
        typer.Option("--picture", help="Write a PNG of accuracy and rollout success per configuration."),
    ] = None,
    store: StoreOpt = None,
    config: ConfigOpt = None,
    json_out: JsonOpt = False,
) -> None:
    """Evaluate CBR recommendations on the hold-out split (resumable: answers are kept in the store)."""
    from scenariominer import api
    from scenariominer.cli.progress import progress_bar
    from scenariominer.llm.usage import UsageCounter

    st, cfg = _store(store, config)
    wanted = tuple(x.strip() for x in configs.split(",") if x.strip()) if configs else None
    shots = tuple(int(x) for x in ks.split(",") if x.strip())
    request = api.CbrEvalRequest(per_type, shots, wanted, time_budget, text, picture)
    with progress_bar(not json_out) as bar:
        ev = api.evaluate_cbr(st, request, cfg, bar, UsageCounter())
    if json_out:
        console().print_json(json.dumps(ev.to_json_dict()))
    else:
        render_eval(ev)
        if ev.picture is not None:
            console().print(f"wrote {safe(str(ev.picture))}", soft_wrap=True, highlight=False)


def register(root: typer.Typer) -> None:
    """Add ``cbr``, ``recommend`` and ``eval cbr`` to the command tree."""
    from scenariominer.cli import evaluation

    root.add_typer(app, name="cbr")
    root.command("recommend")(recommend)
    evaluation.app.command("cbr")(eval_cbr)
