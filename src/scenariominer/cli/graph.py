"""``graph build``, ``ask`` and ``eval retrieval``: the scenario knowledge graph (seed 001, 3.3-3.4)."""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer

from scenariominer.cli._common import ConfigOpt, JsonOpt, StoreOpt, console, load_cfg
from scenariominer.cli.progress import progress_bar
from scenariominer.cli.text import safe

if TYPE_CHECKING:
    from scenariominer.api.graph import AskAnswer
    from scenariominer.eval.scenario_retrieval import RetrievalEvaluation
    from scenariominer.represent.graph_build import GraphBuildReport

app = typer.Typer(name="graph", help="Scenario descriptions and knowledge graph.", no_args_is_help=True)

ModelOpt = Annotated[str | None, typer.Option("--model", help="Embedder whose clusters the graph uses.")]
LossOpt = Annotated[str | None, typer.Option("--loss", help="Pick the latest model of this loss.")]


@app.callback()
def _group() -> None:
    """Scenario descriptions and knowledge graph (seed 001)."""


def _json(obj: object) -> None:
    import dataclasses
    import json

    console().print_json(json.dumps(dataclasses.asdict(obj), default=str))  # type: ignore[call-overload]


def render_build(r: GraphBuildReport) -> None:
    """Print the graph's size and what was computed now."""
    out = console()
    for log_id, why in r.failed:
        out.print(f"[red]failed[/red] {safe(log_id)}: {safe(why)}", highlight=False)
    for subject, why in r.failed_summaries:
        out.print(f"[yellow]no summary[/yellow] {safe(subject)}: {safe(why)}", highlight=False)
    levels = ", ".join(str(n) for n in r.communities_per_level)
    out.print(
        f"graph {safe(r.graph_id)}: {r.n_samples} samples of {r.n_logs} logs "
        f"({r.n_logs_built} described now), "
        f"{r.n_entities} entities, {r.n_relationships} relationships, communities per level {levels}; "
        f"{r.n_summaries} LLM summaries ({r.n_llm_calls} asked now)",
        highlight=False,
    )


@app.command("build")
def build(
    store: StoreOpt = None,
    config: ConfigOpt = None,
    model: ModelOpt = None,
    loss: LossOpt = None,
    no_summaries: Annotated[
        bool, typer.Option("--no-summaries", help="Skip the language-model summaries and reports.")
    ] = False,
    json_out: JsonOpt = False,
) -> None:
    """Describe the windows, build the knowledge graph and its communities, summarise clusters."""
    from scenariominer import api

    cfg = load_cfg(config)
    st = api.open_existing_store(store, cfg)
    request = api.GraphBuildRequest(model_id=model, loss=loss, summaries=not no_summaries)
    with progress_bar(not json_out) as bar:
        report = api.build_graph(st, request, cfg, progress=bar)
    if json_out:
        _json(report)
        return
    render_build(report)


def _others(track_ids: Sequence[str], agent_id: str, shown: int = 4) -> str:
    """How many road users share the sample with its agent, and the first ids in short (``--json``: all).

    Six full Argoverse 2 track ids folded into a column made each sample a dozen lines tall.
    """
    others = [t for t in track_ids if t != agent_id]
    if not others:
        return "0"
    more = " …" if len(others) > shown else ""
    return f"{len(others)}: " + " ".join(t[:8] for t in others[:shown]) + more


def render_answer(a: AskAnswer) -> None:
    """Print the ranked samples, the answer and its citations."""
    from rich.table import Table

    r = a.result
    out = console()
    table = Table(title=f"samples for: {safe(r.question)} (graph {safe(r.graph_id)})", title_justify="left")
    for col in ("#", "log", "track", "time [s]", "frames", "cluster", "road users around", "score"):
        table.add_column(col, overflow="fold")
    for s in r.samples:
        frames = f"{s.start_frame}-{s.end_frame}" if s.start_frame is not None else "-"
        table.add_row(
            str(s.rank),
            safe(s.log_id),
            safe(s.agent_id),
            f"{s.start_s:.1f}-{s.end_s:.1f}",
            frames,
            "-" if s.cluster is None else str(s.cluster),
            safe(_others(s.track_ids, s.agent_id)),
            f"{s.score:.3f}",
        )
    out.print(table)
    if r.answer:
        out.print(safe(r.answer), highlight=False)
        cites = [
            f"Samples ({', '.join(r.cited_samples)})" if r.cited_samples else "",
            f"Entities ({', '.join(r.cited_entities)})" if r.cited_entities else "",
            f"Relationships ({', '.join(r.cited_relationships)})" if r.cited_relationships else "",
            f"Reports ({', '.join(r.cited_reports)})" if r.cited_reports else "",
        ]
        out.print(safe("[Data: " + "; ".join(c for c in cites if c) + "]"), highlight=False)
        if r.invalid_citations:
            out.print(f"[yellow]cited outside the context:[/yellow] {safe(', '.join(r.invalid_citations))}")
    out.print(
        f"retrieval {r.retrieval_ms:.1f} ms, question embedding {r.embed_ms:.1f} ms, "
        f"answer {r.llm_s:.1f} s ({safe(r.llm_status)})",
        highlight=False,
    )
    if a.picture is not None:
        out.print(f"picture: {safe(a.picture)}", highlight=False)


def ask(
    question: Annotated[str, typer.Argument(help="What to look for, in plain words.")],
    k: Annotated[int, typer.Option("-k", help="Samples to return.")] = 5,
    store: StoreOpt = None,
    config: ConfigOpt = None,
    model: ModelOpt = None,
    loss: LossOpt = None,
    vector_only: Annotated[
        bool, typer.Option("--vector-only", help="Plain vector search over the descriptions (no graph).")
    ] = False,
    no_answer: Annotated[bool, typer.Option("--no-answer", help="Rank only; no language model.")] = False,
    picture: Annotated[Path | None, typer.Option("--picture", help="Write a PNG of the top samples.")] = None,
    json_out: JsonOpt = False,
) -> None:
    """Find samples for a natural-language question, answered with entity/relationship/report citations."""
    from scenariominer import api

    cfg = load_cfg(config)
    st = api.open_existing_store(store, cfg)
    request = api.AskRequest(
        question=question,
        model_id=model,
        loss=loss,
        k=k,
        graph=not vector_only,
        answer=not no_answer,
        picture=picture,
    )
    answer = api.ask(st, request, cfg)
    if json_out:
        _json(answer)
        return
    render_answer(answer)


def _pct(x: float) -> str:
    return "-" if math.isnan(x) else f"{100 * x:.1f}"


def render_retrieval(ev: RetrievalEvaluation) -> None:
    """Print the prec@5 grid (Fig. 4 layout) per design and the summary table."""
    from rich.table import Table

    from scenariominer.eval.scenario_retrieval import CATEGORIES, design_summary

    out = console()
    out.print(
        f"{len(ev.queries)} queries ({sum(q.split == 'dev' for q in ev.queries)} dev), "
        f"{ev.n_windows} windows, "
        f"{ev.n_with_truth} with ground truth; graphs: "
        + ", ".join(
            f"{safe(k)}={safe(v)} ({ev.llm_summaries.get(k, 0)} LLM summaries)" for k, v in ev.graphs.items()
        ),
        highlight=False,
    )
    if ev.skipped:
        out.print(f"not scored (no relevant window): {safe(', '.join(ev.skipped))}", highlight=False)
    for d in ev.designs:
        grid = ev.grid(d)
        t = Table(title=f"prec@5 [%] {safe(d)}", title_justify="left")
        t.add_column("category")
        for lv in (1, 2, 3):
            t.add_column(f"L{lv}", justify="right")
        for c in CATEGORIES:
            t.add_row(c, *(_pct(grid.get((c, lv), math.nan)) for lv in (1, 2, 3)))
        out.print(t)
    s = Table(title="averages over scored queries (paper: prec@5 80.2 %)", title_justify="left")
    rows = design_summary(ev)
    for col in rows[0] if rows else []:
        s.add_column(col, justify="left" if col == "design" else "right", no_wrap=col == "design")
    for row in rows:
        s.add_row(*(safe(v) if isinstance(v, str) else _pct(v) for v in row.values()))
    out.print(s)
    out.print(
        "retrieval per query: " + ", ".join(f"{safe(d)} {ms:.1f} ms" for d, ms in ev.retrieval_ms.items()),
        highlight=False,
    )
    if ev.answers:
        mean_s = sum(a[3] for a in ev.answers) / len(ev.answers)
        out.print(f"{len(ev.answers)} LLM answers, {mean_s:.1f} s each on average", highlight=False)


def eval_retrieval(
    store: StoreOpt = None,
    config: ConfigOpt = None,
    queries: Annotated[Path | None, typer.Option("--queries", help="Query file (TOML).")] = None,
    model: Annotated[
        list[str] | None, typer.Option("--model", help="Evaluate this model's graph (repeatable).")
    ] = None,
    k_max: Annotated[int, typer.Option("--k-max", help="Ranking depth scored.")] = 100,
    answers: Annotated[bool, typer.Option("--answers", help="Also time the LLM's answer per query.")] = False,
    json_out: JsonOpt = False,
) -> None:
    """prec@5 grid, Recall@k and nDCG@k: graph vs vector retrieval, Hausdorff vs MSE embedding."""
    from scenariominer import api

    cfg = load_cfg(config)
    st = api.open_existing_store(store, cfg)
    request = api.RetrievalEvalRequest(
        queries=queries, model_ids=tuple(model or ()), k_max=k_max, answers=answers
    )
    with progress_bar(not json_out) as bar:
        ev = api.evaluate_retrieval(st, request, cfg, progress=bar)
    if json_out:
        _json(ev)
        return
    render_retrieval(ev)


def register(root: typer.Typer) -> None:
    """Add ``graph``, ``ask`` and ``eval retrieval`` to the command tree."""
    from scenariominer.cli import evaluation

    root.add_typer(app, name="graph")
    root.command("ask")(ask)
    evaluation.app.command("retrieval")(eval_retrieval)
