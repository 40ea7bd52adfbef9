"""The ``eval`` command group: ``eval braking`` prints the braking paper's Tables IV-VI.

A thin Typer layer over :func:`scenariominer.eval.braking.evaluate_braking`.
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Annotated

import typer
from rich.console import Console
from rich.table import Table

from scenariominer.config import ConfigError, load_config
from scenariominer.eval.braking import BrakingEvaluation, LabelFileError, evaluate_braking, read_labels
from scenariominer.explain.categories import CategoryFileError, load_categories
from scenariominer.explain.search import NoEventsError
from scenariominer.llm.errors import LLMError
from scenariominer.llm.factory import make_embedder
from scenariominer.store import EmbeddingMismatchError, ScenarioStore, StoreError, resolve_store_path

__all__ = ["app", "render_braking"]

app = typer.Typer(name="eval", help="Evaluate pipelines against labelled data.", no_args_is_help=True)
console = Console()
err_console = Console(stderr=True)


def _num(x: float) -> str:
    return "-" if math.isnan(x) else f"{x:.2f}"


def render_braking(ev: BrakingEvaluation) -> None:
    """Print the KeyIdent, known-category and free-text retrieval tables."""
    status = ", ".join(f"{k}: {v}" for k, v in sorted(ev.llm_status.items())) or "-"
    console.print(
        f"{ev.n_logs} labelled log(s) evaluated ({ev.n_logs_not_analyzed} not analysed), "
        f"{ev.n_labels} label(s), {ev.n_events} event(s); LLM answers: {status}"
    )
    t4 = Table(title="KeyIdent (Table IV)", title_justify="left")
    for col in ("category", "labels", "found", "precision", "recall"):
        t4.add_column(col, justify="left" if col == "category" else "right", no_wrap=True)
    for r in ev.keyident:
        overall = r.category == "overall"
        t4.add_row(
            r.category,
            str(r.n_labels),
            str(r.n_found),
            _num(ev.keyident_overall.precision) if overall else "-",
            _num(r.recall),
            style="bold" if overall else None,
        )
    console.print(t4)
    t5 = Table(title="Known categories, baseline / LLM (Table V)", title_justify="left")
    for col in ("category", "precision", "recall", "F1", "TP", "FP", "FN"):
        t5.add_column(col, justify="left" if col == "category" else "right", no_wrap=True)
    for c in ev.classification:
        b, m = c.baseline, c.llm
        t5.add_row(
            c.category,
            f"{_num(b.precision)} / {_num(m.precision)}",
            f"{_num(b.recall)} / {_num(m.recall)}",
            f"{_num(b.f1)} / {_num(m.f1)}",
            f"{b.tp} / {m.tp}",
            f"{b.fp} / {m.fp}",
            f"{b.fn} / {m.fn}",
            style="bold" if c.category == "overall" else None,
        )
    console.print(t5)
    if ev.retrieval:
        k_p, k_r = ev.retrieval[0].k_precision, ev.retrieval[0].k_recall
        t6 = Table(title=f"Free-text retrieval, {ev.embedding_model} (Table VI)", title_justify="left")
        for col in ("category", "query", "relevant", f"P@{k_p}", f"R@{k_r}"):
            t6.add_column(col, justify="right" if col in ("relevant", f"P@{k_p}", f"R@{k_r}") else "left")
        for row in ev.retrieval:
            t6.add_row(
                row.category, row.query, str(row.n_relevant), _num(row.precision_at_k), _num(row.recall_at_k)
            )
        console.print(t6)


@app.command()
def braking(
    labels: Annotated[
        Path, typer.Option("--labels", "-l", help="CSV with log_id, guest_id, scenario_category.")
    ],
    store: Annotated[
        Path | None,
        typer.Option(
            "--store", "-s", help="Store directory (default: $SCENARIOMINER_STORE or the per-user dir)."
        ),
    ] = None,
    config: Annotated[Path | None, typer.Option("--config", "-c", help="TOML configuration file.")] = None,
    categories: Annotated[
        Path | None,
        typer.Option("--categories", help="TOML file of the categories the store was analysed with."),
    ] = None,
    retrieval: Annotated[
        bool, typer.Option(help="Also evaluate free-text retrieval (embeds the query sentences).")
    ] = True,
    complete_only: Annotated[
        bool, typer.Option("--complete-only", help="Evaluate only logs whose events all have an LLM answer.")
    ] = False,
    json_out: Annotated[bool, typer.Option("--json", help="Print the results as JSON.")] = False,
) -> None:
    """Evaluate braking events against labels: KeyIdent, baseline vs LLM per category, text retrieval."""
    try:
        cfg = load_config(config)
    except ConfigError as exc:
        err_console.print(f"[red]config error:[/red] {exc}")
        raise typer.Exit(2) from None
    try:
        st = ScenarioStore.open(resolve_store_path(store, cfg.store.path), create=False)
        rows = read_labels(labels)
        category_set = load_categories(categories or cfg.explain.categories_file)
        embedder = make_embedder(cfg) if retrieval else None
        ev = evaluate_braking(st, rows, embedder, categories=category_set, only_complete=complete_only)
    except (
        StoreError,
        LabelFileError,
        CategoryFileError,
        NoEventsError,
        EmbeddingMismatchError,
        LLMError,
    ) as exc:
        err_console.print(f"[red]error:[/red] {exc}")
        raise typer.Exit(1) from None
    if json_out:
        console.print_json(json.dumps(ev.to_json_dict()))
    else:
        render_braking(ev)
