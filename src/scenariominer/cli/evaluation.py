"""The ``eval`` command group: ``eval braking`` (seed 000's Tables IV-VI), ``eval mining`` and ``nl2prog``."""

from __future__ import annotations

import math
from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer

from scenariominer.cli._common import ConfigOpt, JsonOpt, StoreOpt, console, load_cfg
from scenariominer.cli.progress import progress_bar
from scenariominer.cli.text import safe
from scenariominer.errors import EvaluationError

if TYPE_CHECKING:
    from collections.abc import Iterable

    from scenariominer.api.evaluation import BrakingSet
    from scenariominer.config import Config
    from scenariominer.eval.braking import BrakingEvaluation
    from scenariominer.eval.mining import MiningEvaluation
    from scenariominer.eval.nl2prog import Nl2ProgEvaluation

app = typer.Typer(name="eval", help="Evaluate pipelines against labelled data.", no_args_is_help=True)


def _num(x: float, digits: int = 2) -> str:
    return "-" if math.isnan(x) else f"{x:.{digits}f}"


def render_braking(ev: BrakingEvaluation) -> None:
    """Print the KeyIdent, known-category and free-text retrieval tables."""
    from rich.table import Table

    out = console()
    status = ", ".join(f"{k}: {v}" for k, v in sorted(ev.llm_status.items())) or "-"
    out.print(
        f"{ev.n_logs} labelled log(s) evaluated ({ev.n_logs_not_analyzed} not analysed), "
        f"{ev.n_labels} label(s), {ev.n_events} event(s); LLM answers: {status}"
    )
    t4 = Table(title="KeyIdent (Table IV)", title_justify="left")
    for col in ("category", "labels", "found", "precision", "recall"):
        t4.add_column(col, justify="left" if col == "category" else "right", no_wrap=True)
    for r in ev.keyident:
        overall = r.category == "overall"
        t4.add_row(
            safe(r.category),
            str(r.n_labels),
            str(r.n_found),
            _num(ev.keyident_overall.precision) if overall else "-",
            _num(r.recall),
            style="bold" if overall else None,
        )
    out.print(t4)
    t5 = Table(title="Known categories by judge (Table V)", title_justify="left")
    for col in ("category", "judge", "precision", "recall", "F1", "TP", "FP", "FN"):
        t5.add_column(col, justify="left" if col in ("category", "judge") else "right", no_wrap=True)
    for c in ev.classification:
        for i, judge in enumerate(ev.judges):
            p = c.scores[judge]
            t5.add_row(
                safe(c.category) if i == 0 else "",
                safe(judge),
                _num(p.precision),
                _num(p.recall),
                _num(p.f1),
                str(p.tp),
                str(p.fp),
                str(p.fn),
                style="bold" if c.category == "overall" else None,
                end_section=i == len(ev.judges) - 1,
            )
    out.print(t5)
    if ev.pedestrians_as_obj_crossing:
        peds = ", ".join(f"{safe(j)} {n}/{of}" for j, (n, of) in ev.pedestrians_as_obj_crossing.items())
        out.print(f"pedestrian guests classed obj_crossing: {peds}")
    if ev.by_method:
        _render_by_method(ev)
    if ev.retrieval:
        k_p, k_r = ev.retrieval[0].k_precision, ev.retrieval[0].k_recall
        t6 = Table(title=f"Free-text retrieval, {safe(ev.embedding_model)} (Table VI)", title_justify="left")
        for col in ("category", "query", "relevant", f"P@{k_p}", f"R@{k_r}"):
            t6.add_column(col, justify="right" if col in ("relevant", f"P@{k_p}", f"R@{k_r}") else "left")
        for row in ev.retrieval:
            t6.add_row(
                safe(row.category),
                safe(row.query),
                str(row.n_relevant),
                _num(row.precision_at_k),
                _num(row.recall_at_k),
            )
        out.print(t6)


def render_braking_sets(results: list[tuple[str, BrakingEvaluation]], method: str) -> None:
    """One table with a column per set: KeyIdent, Table V F1 per judge and category, noise levels.

    Args:
        results: ``(set name, evaluation)`` in column order.
        method: the configured key-object method, whose recall per noise level is shown.
    """
    from rich.table import Table

    evs = [ev for _, ev in results]
    t = Table(title="Braking evaluation, sets side by side", title_justify="left")
    t.add_column("measure", no_wrap=True)
    for set_name, _ in results:
        t.add_column(safe(set_name), justify="right", no_wrap=True)
    t.add_row("labelled logs evaluated", *(str(ev.n_logs) for ev in evs))
    t.add_row("events", *(str(ev.n_events) for ev in evs))
    t.add_row("KeyIdent recall", *(_num(ev.keyident_overall.recall) for ev in evs))
    t.add_row("KeyIdent precision", *(_num(ev.keyident_overall.precision) for ev in evs), end_section=True)
    for cat in _union([r.category for r in ev.keyident if r.category != "overall"] for ev in evs):
        t.add_row(f"KeyIdent recall {safe(cat)}", *(_keyident_recall(ev, cat) for ev in evs))
    t.rows[-1].end_section = True
    judges = _union(list(ev.judges) for ev in evs)
    for cat in _union([c.category for c in ev.classification] for ev in evs):
        for judge in judges:
            t.add_row(f"F1 {safe(judge)} {safe(cat)}", *(_f1(ev, cat, judge) for ev in evs))
    t.rows[-1].end_section = True
    levels = _union([m.noise_level for m in ev.by_method if m.method == method] for ev in evs)
    for level in (lv for lv in levels if lv != "all"):  # "all" is the KeyIdent recall above
        t.add_row(
            f"KeyIdent recall ({safe(method)}), noise {safe(level)}",
            *(_noise_recall(ev, method, level) for ev in evs),
        )
    console().print(t)


def _union(lists: Iterable[list[str]]) -> list[str]:
    return list(dict.fromkeys(k for ks in lists for k in ks))


def _keyident_recall(ev: BrakingEvaluation, category: str) -> str:
    return next((_num(r.recall) for r in ev.keyident if r.category == category), "-")


def _f1(ev: BrakingEvaluation, category: str, judge: str) -> str:
    hit = [c.scores[judge] for c in ev.classification if c.category == category and judge in c.scores]
    return _num(hit[0].f1) if hit else "-"


def _noise_recall(ev: BrakingEvaluation, method: str, level: str) -> str:
    hit = [m for m in ev.by_method if m.method == method and m.noise_level == level]
    return _num(hit[0].overall.recall) if hit else "-"


def _render_by_method(ev: BrakingEvaluation) -> None:
    """KeyIdent recall per category by method, then overall recall per noise level by method."""
    from rich.table import Table

    out = console()
    methods = list(dict.fromkeys(m.method for m in ev.by_method))
    by = {(m.method, m.noise_level): m for m in ev.by_method}
    t = Table(title="KeyIdent recall by method (logs tagged again)", title_justify="left")
    t.add_column("category", no_wrap=True)
    for method in methods:
        t.add_column(safe(method), justify="right", no_wrap=True)
    for i, row in enumerate(by[(methods[0], "all")].rows):
        t.add_row(
            safe(row.category),
            *(_num(by[(m, "all")].rows[i].recall) for m in methods),
            style="bold" if row.category == "overall" else None,
        )
    t.add_row("precision", *(_num(by[(m, "all")].overall.precision) for m in methods))
    out.print(t)
    levels = [lv for lv in dict.fromkeys(m.noise_level for m in ev.by_method) if lv != "all"]
    if levels:
        tn = Table(title="KeyIdent recall by noise level", title_justify="left")
        tn.add_column("noise", no_wrap=True)
        for method in methods:
            tn.add_column(safe(method), justify="right", no_wrap=True)
        for level in levels:
            tn.add_row(safe(level), *(_num(by[(m, level)].overall.recall) for m in methods))
        out.print(tn)


def _num3(x: float) -> str:
    return _num(x, 3)


def render_evaluation(ev: MiningEvaluation) -> None:
    """Print the official scores and the paper's F1 scores."""
    from rich.table import Table

    out = console()
    table = Table(title=f"scenario mining, {len(ev.pairs)} (log, description) pair(s)", title_justify="left")
    table.add_column("metric")
    table.add_column("value", justify="right")
    table.add_row("HOTA-Temporal", _num3(ev.hota_temporal))
    table.add_row("HOTA-Track", _num3(ev.hota_track))
    table.add_row("timestamp balanced accuracy", _num3(ev.timestamp_balanced_accuracy))
    table.add_row("log balanced accuracy", _num3(ev.log_balanced_accuracy))
    table.add_row("timestamp F1", _num3(ev.timestamp_f1))
    table.add_row("log F1", _num3(ev.log_f1))
    out.print(table)
    tc, lc = ev.timestamp_counts, ev.log_counts
    out.print(
        f"timestamps: TP {tc.tp}, FP {tc.fp}, FN {tc.fn}, TN {tc.tn}; "
        f"logs: TP {lc.tp}, FP {lc.fp}, FN {lc.fn}, TN {lc.tn}"
    )


@app.command("braking")
def braking(
    labels: Annotated[
        Path, typer.Option("--labels", "-l", help="CSV with log_id, guest_id, scenario_category.")
    ],
    store: StoreOpt = None,
    config: ConfigOpt = None,
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
    judges: Annotated[
        str,
        typer.Option(
            "--judges",
            help="Also score these judges side by side (comma-separated: llm, hybrid); each re-judges "
            "the stored events with the configured model.",
        ),
    ] = "",
    methods: Annotated[
        bool,
        typer.Option(help="Also give KeyIdent recall per key-object method (tags, counterfactual, combined)"),
    ] = True,
    also: Annotated[
        list[str] | None,
        typer.Option(
            "--also",
            help="Another labelled set to evaluate side by side, as NAME=STORE,LABELS (repeatable); "
            "prints one table with a column per set.",
        ),
    ] = None,
    name: Annotated[
        str, typer.Option("--name", help="Name of the --store/--labels set in the side-by-side table.")
    ] = "",
    json_out: JsonOpt = False,
) -> None:
    """Evaluate braking events against labels: KeyIdent, rules / LLM / hybrid per category, retrieval.

    With `--also NAME=STORE,LABELS` (repeatable) every set is evaluated with the same settings and
    one table shows them side by side, e.g. the tuning split beside a SUMO-made hold-out.
    """
    import json

    from scenariominer import api
    from scenariominer.llm.usage import UsageCounter, print_usage

    cfg = load_cfg(config)
    wanted = tuple(j.strip() for j in judges.split(",") if j.strip())
    request = api.BrakingEvalRequest(labels, categories, retrieval, complete_only, wanted, methods)
    usage = UsageCounter()
    if also:
        sets = [api.BrakingSet(name or labels.parent.name, api.open_existing_store(store, cfg), labels)]
        sets += [_braking_set(spec, cfg) for spec in also]
        with progress_bar(not json_out) as bar:
            results = api.evaluate_braking_sets(sets, request, cfg, bar, usage)
        if json_out:
            console().print_json(json.dumps({"sets": {n: ev.to_json_dict() for n, ev in results}}))
        else:
            render_braking_sets(results, cfg.tags.keyident.method)
        return
    with progress_bar(not json_out) as bar:
        ev = api.evaluate_braking(api.open_existing_store(store, cfg), request, cfg, bar, usage)
    if json_out:
        console().print_json(json.dumps(ev.to_json_dict()))
    else:
        render_braking(ev)
        if wanted:
            print_usage(usage.report(), console())


def _braking_set(spec: str, cfg: Config) -> BrakingSet:
    """``NAME=STORE,LABELS`` as a set (the store must exist)."""
    from scenariominer import api

    set_name, eq, rest = spec.partition("=")
    store_path, comma, labels_path = rest.rpartition(",")
    if not (eq and comma and set_name.strip() and store_path and labels_path):
        raise EvaluationError(f"--also takes NAME=STORE,LABELS, got {spec!r}")
    found: BrakingSet = api.BrakingSet(
        set_name.strip(), api.open_existing_store(store_path, cfg), Path(labels_path)
    )
    return found


@app.command("mining")
def mining(
    pred: Annotated[
        Path, typer.Option("--pred", help="Prediction pickle (scenariominer mine --export av2).")
    ],
    gt: Annotated[
        Path, typer.Option("--gt", help="Ground-truth pickle of the Argoverse 2 scenario-mining task.")
    ],
    dataset_dir: Annotated[
        Path | None,
        typer.Option(
            "--dataset-dir", help="Folder with <log_id>/map and poses, for the region-of-interest filter."
        ),
    ] = None,
    max_range_m: Annotated[
        int, typer.Option(help="Evaluate boxes within this distance of the ego (m).")
    ] = 50,
    out: Annotated[
        Path | None, typer.Option("--out", help="Folder for the evaluator's JSON and plots.")
    ] = None,
    json_out: JsonOpt = False,
) -> None:
    """Score a scenario-mining prediction with the official Argoverse 2 evaluator (plus F1)."""
    import json

    from scenariominer import api

    ev = api.evaluate_mining(api.MiningEvalRequest(pred, gt, dataset_dir, max_range_m, out))
    if json_out:
        console().print_json(json.dumps(ev.as_dict()))
    else:
        render_evaluation(ev)


def _jaccard_cell(x: float | None) -> str:
    return "-" if x is None else _num3(x)


def render_nl2prog(ev: Nl2ProgEvaluation, title: str) -> None:
    """Print the per-description table, the summary, the per-family table and the failures."""
    from rich.table import Table

    out = console()
    table = Table(title=title, title_justify="left")
    for col in ("description", "split", "runnable", "mean Jaccard", "seconds"):
        table.add_column(col, justify="left" if col in ("description", "split") else "right")
    for s in ev.descriptions:
        table.add_row(
            safe(s.description),
            safe(s.split),
            "yes" if s.runnable else "[red]no[/red]",
            _jaccard_cell(s.mean_jaccard),
            f"{s.seconds:.1f}",
        )
    out.print(table)
    n = len(ev.descriptions)
    agree, empty = ev.empty_cells
    out.print(
        f"{n} description(s) on {len(ev.log_ids)} log(s): runnable {ev.n_runnable}/{n} "
        f"({_num(100 * ev.runnable_share, 0)}%); mean Jaccard {_jaccard_cell(ev.mean_jaccard)} over "
        f"{ev.n_scored_cells} (description, log) cell(s) where the reference finds something; "
        f"where it finds nothing the candidate agrees in {agree}/{empty}; {ev.seconds:.1f} s",
        soft_wrap=True,
    )
    readers = ev.by_reader()
    labels = {
        "rules": "read by the phrase rules",
        "reworded": "from the model's rewording",
        "partial": "in part (some words left out)",
        "reworded-partial": "from the model's rewording, in part",
        "model": "read by the model",
    }
    if readers["rules"].n_descriptions or readers["partial"].n_descriptions:
        shown = [name for name in labels if name in ("rules", "model") or readers[name].n_descriptions]
        parts = [
            f"{labels[name]}: {readers[name].n_descriptions}/{n}, mean Jaccard "
            f"{_jaccard_cell(readers[name].mean_jaccard)} over {readers[name].n_scored_cells} cell(s)"
            for name in shown
        ]
        out.print("; ".join(parts), soft_wrap=True)
    if ev.n_reference_failures:
        out.print(
            f"[yellow]note:[/yellow] the reference failed in {ev.n_reference_failures} cell(s) "
            "(e.g. a log without a map); those are not scored",
            soft_wrap=True,
        )
    families = Table(title="per family", title_justify="left")
    for col in ("family", "descriptions", "runnable", "scored cells", "mean Jaccard"):
        families.add_column(col, justify="left" if col == "family" else "right")
    for f in ev.per_family().values():
        families.add_row(
            safe(f.family),
            str(f.n_descriptions),
            str(f.n_runnable),
            str(f.n_scored_cells),
            _jaccard_cell(f.mean_jaccard),
        )
    out.print(families)
    for s in ev.descriptions:
        if not s.runnable:
            out.print(f"not runnable: {safe(repr(s.description))}: {safe(s.error or '')}", soft_wrap=True)


@app.command("nl2prog")
def nl2prog(
    split: Annotated[
        str,
        typer.Option(
            "--split",
            help="Descriptions to score: holdout, published (RefAV's wording, held out), challenge "
            "(the AV2 2025 challenge's wording, held out), fresh ... fresh99 (others' wording, each held "
            "out and scored once), dev or all.",
        ),
    ] = "holdout",
    limit: Annotated[
        int | None, typer.Option("--limit", min=0, help="Score at most N descriptions (in set order).")
    ] = None,
    logs: Annotated[
        list[Path] | None,
        typer.Option(
            "--logs",
            help="Log folder or file to score on; repeat for several (default: the Argoverse 2 "
            "sample log beside the checkout).",
        ),
    ] = None,
    no_bank_similar: Annotated[
        bool,
        typer.Option(
            "--no-bank-similar",
            help="Leave the bank entries most similar to each description out of its few-shot examples.",
        ),
    ] = False,
    samples: Annotated[
        int | None,
        typer.Option(
            "--samples",
            min=1,
            help="Candidate programs per description, chosen by agreement of their outputs "
            "(default: mining.generation.consensus_samples).",
        ),
    ] = None,
    grammar: Annotated[
        bool | None,
        typer.Option(
            "--grammar/--no-grammar",
            help="Decode under the program grammar built from the predicates' signatures "
            "(default: mining.generation.grammar).",
        ),
    ] = None,
    plan: Annotated[
        bool | None,
        typer.Option(
            "--plan/--no-plan",
            help="Read each description into a structured plan before writing its program "
            "(default: mining.generation.plan).",
        ),
    ] = None,
    plan_program: Annotated[
        bool | None,
        typer.Option(
            "--plan-program/--no-plan-program",
            help="With --plan, first try the program built from the plan by fixed rules "
            "(default: mining.generation.plan_program).",
        ),
    ] = None,
    plan_rules: Annotated[
        bool | None,
        typer.Option(
            "--plan-rules/--no-plan-rules",
            help="With --plan, read each description with the phrase rules first; the model "
            "reads only those with a word the rules do not know (default: mining.generation.plan_rules).",
        ),
    ] = None,
    plan_partial: Annotated[
        bool | None,
        typer.Option(
            "--plan-partial/--no-plan-partial",
            help="With --plan-rules, let the phrase rules read a description in part (the words they "
            "do not know left out and listed) when they read its subject, before asking the model "
            "(default: mining.generation.plan_partial).",
        ),
    ] = None,
    plan_reword: Annotated[
        bool | None,
        typer.Option(
            "--plan-reword/--no-plan-reword",
            help="With --plan-rules, have the model put a description the rules cannot read in full "
            "in plain words, and use the rules' full reading of those words when it keeps the "
            "description's numbers and road users (default: mining.generation.plan_reword).",
        ),
    ] = None,
    reword_tries: Annotated[
        int | None,
        typer.Option(
            "--reword-tries",
            min=1,
            help="With --plan-reword, how many rewordings to ask for at most: after one the rules "
            "read only in part, the model is asked for a simpler one without the words they left out "
            "(default: mining.generation.plan_reword_tries).",
        ),
    ] = None,
    config: ConfigOpt = None,
    json_out: JsonOpt = False,
) -> None:
    """Score generated programs against hand-written references (Jaccard of referred track-timestamps)."""
    import dataclasses
    import json

    from scenariominer import api
    from scenariominer.llm.usage import UsageCounter, print_usage

    cfg = load_cfg(config)
    gen = cfg.mining.generation
    if samples is not None:
        gen = dataclasses.replace(gen, consensus_samples=samples)
    if grammar is not None:
        gen = dataclasses.replace(gen, grammar=grammar)
    if plan is not None:
        gen = dataclasses.replace(gen, plan=plan)
    if plan_program is not None:
        gen = dataclasses.replace(gen, plan_program=plan_program)
    if plan_rules is not None:
        gen = dataclasses.replace(gen, plan_rules=plan_rules)
    if plan_partial is not None:
        gen = dataclasses.replace(gen, plan_partial=plan_partial)
    if plan_reword is not None:
        gen = dataclasses.replace(gen, plan_reword=plan_reword)
    if reword_tries is not None:
        gen = dataclasses.replace(gen, plan_reword_tries=reword_tries)
    cfg = dataclasses.replace(cfg, mining=dataclasses.replace(cfg.mining, generation=gen))
    request = api.Nl2ProgEvalRequest(split, limit, tuple(logs or ()), no_bank_similar)
    usage = UsageCounter()
    with progress_bar(not json_out) as bar:
        ev = api.evaluate_nl2prog(request, cfg, bar, usage)
    if json_out:
        doc = {"split": split, "without_similar_bank": no_bank_similar, **ev.to_json_dict()}
        console().print_json(json.dumps(doc))
        return
    variant = "without the most similar bank entries" if no_bank_similar else "with the whole bank"
    render_nl2prog(ev, f"description -> program, {split} split, few-shot examples {variant}")
    print_usage(usage.report(), console())
