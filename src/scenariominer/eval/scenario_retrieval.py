"""Scenario retrieval evaluation (seed 001, section 5.3 and its future work): prec@5, Recall@k, nDCG@k.

The queries (``highway_queries.toml``, shipped beside this module, or a file with the same layout)
follow Table 1: categories ``general``, ``infrastructure``, ``ego``, ``interaction``,
``combination`` at levels 1-3. A window is relevant to a query when the query's rule holds on the
window's ground truth (:mod:`.highway_truth`, from the recording's columns); windows without
ground truth (logs that are not highD-format recordings) are never relevant.

Each design ranks every window of its graph for each query: ``graph`` (descriptions, entities,
relationships and LLM summaries fused; :class:`~scenariominer.represent.ask.GraphIndex`) and
``vector`` (descriptions only), for each embedding's graph (Hausdorff, MSE).
"""

from __future__ import annotations

import ast
import math
import operator
import tomllib
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, replace
from importlib import resources
from pathlib import Path
from typing import Any

import numpy as np

from scenariominer import errors as _errors
from scenariominer.eval.highway_truth import TRUTH_FIELDS
from scenariominer.eval.metrics import precision_at_k, recall_at_k

__all__ = [
    "CATEGORIES",
    "QUERIES_FILE",
    "QueryScore",
    "RetrievalEvaluation",
    "RetrievalQuery",
    "RuleError",
    "compile_rule",
    "design_summary",
    "evaluate_retrieval",
    "load_queries",
    "ndcg_at_k",
    "score_ranking",
    "store_window_truth",
]

QUERIES_FILE = "highway_queries.toml"
CATEGORIES = ("general", "infrastructure", "ego", "interaction", "combination")


class RuleError(_errors.ScenarioMinerError, ValueError):
    """A query's relevance rule or the query file is malformed."""


@dataclass(frozen=True)
class RetrievalQuery:
    """One evaluation query.

    Attributes:
        query_id: unique id.
        category: one of :data:`CATEGORIES`.
        level: 1-3 (detail).
        text: the natural-language query.
        rule: boolean expression over :data:`~.highway_truth.TRUTH_FIELDS`.
        split: ``dev`` (may be used to choose settings) or ``test``.
    """

    query_id: str
    category: str
    level: int
    text: str
    rule: str
    split: str = "test"


_BINARY: dict[type, Callable[[Any, Any], Any]] = {
    ast.Add: operator.add,
    ast.Sub: operator.sub,
    ast.Mult: operator.mul,
    ast.Div: operator.truediv,
}
_COMPARE: dict[type, Callable[[Any, Any], Any]] = {
    ast.Eq: operator.eq,
    ast.NotEq: operator.ne,
    ast.Lt: operator.lt,
    ast.LtE: operator.le,
    ast.Gt: operator.gt,
    ast.GtE: operator.ge,
}


def compile_rule(rule: str) -> Callable[[Mapping[str, float]], bool]:
    """A checked relevance rule as a function of a truth dict.

    Raises:
        RuleError: syntax outside the allowed subset or an unknown field.
    """
    try:
        tree = ast.parse(rule, mode="eval")
    except SyntaxError as exc:
        raise RuleError(f"rule {rule!r} is not an expression: {exc.msg}") from None

    def ev(node: ast.AST, truth: Mapping[str, float]) -> Any:
        if isinstance(node, ast.Expression):
            return ev(node.body, truth)
        if isinstance(node, ast.BoolOp):
            vals = (bool(ev(v, truth)) for v in node.values)
            return all(vals) if isinstance(node.op, ast.And) else any(vals)
        if isinstance(node, ast.UnaryOp) and isinstance(node.op, ast.Not):
            return not ev(node.operand, truth)
        if isinstance(node, ast.UnaryOp) and isinstance(node.op, ast.USub):
            return -ev(node.operand, truth)
        if isinstance(node, ast.BinOp) and type(node.op) in _BINARY:
            return _BINARY[type(node.op)](ev(node.left, truth), ev(node.right, truth))
        if isinstance(node, ast.Compare):
            left = ev(node.left, truth)
            for op, comp in zip(node.ops, node.comparators, strict=True):
                right = ev(comp, truth)
                if not _COMPARE[type(op)](left, right):
                    return False
                left = right
            return True
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id == "abs":
            return abs(ev(node.args[0], truth))
        if isinstance(node, ast.Name):
            return truth[node.id]
        if isinstance(node, ast.Constant) and isinstance(node.value, int | float):
            return node.value
        raise RuleError(f"rule {rule!r}: {type(node).__name__} is not allowed")

    for node in ast.walk(tree):
        if isinstance(node, ast.Name) and node.id not in TRUTH_FIELDS and node.id != "abs":
            raise RuleError(f"rule {rule!r}: unknown field {node.id!r} (known: {', '.join(TRUTH_FIELDS)})")
        if isinstance(node, ast.Compare) and any(type(op) not in _COMPARE for op in node.ops):
            raise RuleError(f"rule {rule!r}: comparison not allowed")
    ev(tree, dict.fromkeys(TRUTH_FIELDS, 0.0))  # syntax subset check on a neutral truth

    def judge(truth: Mapping[str, float]) -> bool:
        return bool(ev(tree, truth))

    return judge


def load_queries(path: Path | None = None) -> list[RetrievalQuery]:
    """The queries of ``path`` (default: the shipped file).

    Raises:
        RuleError: malformed file, duplicate ids, unknown category/level, or a bad rule.
    """
    if path is None:
        text = resources.files(__package__).joinpath(QUERIES_FILE).read_text(encoding="utf-8")
        source = QUERIES_FILE
    else:
        try:
            text = Path(path).read_text(encoding="utf-8")
        except OSError as exc:
            raise RuleError(f"cannot read query file {path}: {exc.strerror}") from None
        source = str(path)
    try:
        doc = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise RuleError(f"{source}: {exc}") from None
    out: list[RetrievalQuery] = []
    for i, raw in enumerate(doc.get("query", [])):
        try:
            q = RetrievalQuery(
                str(raw["id"]),
                str(raw["category"]),
                int(raw["level"]),
                str(raw["text"]),
                str(raw["rule"]),
                str(raw.get("split", "test")),
            )
        except KeyError as exc:
            raise RuleError(f"{source}: query {i + 1} lacks {exc.args[0]!r}") from None
        if q.category not in CATEGORIES or q.level not in (1, 2, 3) or q.split not in ("dev", "test"):
            raise RuleError(
                f"{source}: query {q.query_id!r} has category/level/split {q.category}/{q.level}/{q.split}"
            )
        compile_rule(q.rule)
        out.append(q)
    ids = [q.query_id for q in out]
    if len(set(ids)) != len(ids):
        raise RuleError(f"{source}: duplicate query ids")
    if not out:
        raise RuleError(f"{source}: no [[query]] entries")
    return out


def ndcg_at_k(ranked: Sequence[str], relevant: set[str], k: int) -> float:
    """Binary-gain nDCG of the first ``k`` ranked items; NaN when nothing is relevant.

    DCG = sum over ranks r (1-based) of rel_r / log2(r + 1); the ideal ranking puts
    ``min(k, |relevant|)`` relevant items first.
    """
    if k < 1:
        raise ValueError(f"k must be at least 1, got {k}")
    if not relevant:
        return math.nan
    gains = np.asarray([1.0 if x in relevant else 0.0 for x in ranked[:k]])
    discounts = 1.0 / np.log2(np.arange(2, k + 2))
    ideal = discounts[: min(k, len(relevant))].sum()
    return float((gains * discounts[: gains.size]).sum() / ideal)


@dataclass(frozen=True)
class QueryScore:
    """Scores of one ranking for one query.

    Attributes:
        query_id: the query.
        design: e.g. ``hausdorff/graph``.
        n_relevant: windows with ground truth that satisfy the rule.
        precision_at_5: prec@5.
        recall: k -> Recall@k (NaN without relevant windows).
        ndcg: k -> nDCG@k.
        top: the first five window ids.
    """

    query_id: str
    design: str
    n_relevant: int
    precision_at_5: float
    recall: dict[int, float]
    ndcg: dict[int, float]
    top: tuple[str, ...]


def score_ranking(
    query_id: str,
    design: str,
    ranked: Sequence[str],
    relevant: set[str],
    ks: Sequence[int] = (5, 10, 50, 100),
) -> QueryScore:
    """prec@5, Recall@k and nDCG@k of one ranking."""
    return QueryScore(
        query_id,
        design,
        len(relevant),
        precision_at_k(list(ranked), relevant, 5),
        {k: recall_at_k(list(ranked), relevant, k) for k in ks},
        {k: ndcg_at_k(ranked, relevant, k) for k in ks},
        tuple(ranked[:5]),
    )


@dataclass(frozen=True)
class RetrievalEvaluation:
    """Result of a retrieval evaluation.

    Attributes:
        queries: the queries.
        designs: design names (``<graph label>/<graph|vector>``).
        scores: one per (design, query with at least one relevant window).
        skipped: ids of queries without any relevant window (not scored).
        n_windows: windows ranked (per design).
        n_with_truth: windows with ground truth.
        graphs: label -> graph id.
        llm_summaries: label -> LLM summaries in that graph.
        retrieval_ms: design -> mean retrieval time per query, milliseconds.
        answers: ``(design, query id, answer text, LLM seconds)`` when answers were asked.
    """

    queries: tuple[RetrievalQuery, ...]
    designs: tuple[str, ...]
    scores: tuple[QueryScore, ...]
    skipped: tuple[str, ...]
    n_windows: int
    n_with_truth: int
    graphs: dict[str, str]
    llm_summaries: dict[str, int]
    retrieval_ms: dict[str, float]
    answers: tuple[tuple[str, str, str, float], ...] = ()

    def grid(self, design: str, split: str | None = None) -> dict[tuple[str, int], float]:
        """(category, level) -> mean prec@5 of ``design`` (only ``split`` queries if given)."""
        split_of = {q.query_id: q for q in self.queries}
        cells: dict[tuple[str, int], list[float]] = {}
        for s in self.scores:
            q = split_of[s.query_id]
            if s.design == design and (split is None or q.split == split):
                cells.setdefault((q.category, q.level), []).append(s.precision_at_5)
        return {k: float(np.mean(v)) for k, v in cells.items()}

    def mean(self, design: str, metric: str, split: str | None = None, k: int = 5) -> float:
        """Mean over scored queries of ``precision_at_5``, ``recall`` or ``ndcg`` (at ``k``)."""
        split_of = {q.query_id: q.split for q in self.queries}
        vals = []
        for s in self.scores:
            if s.design != design or (split is not None and split_of[s.query_id] != split):
                continue
            vals.append(s.precision_at_5 if metric == "precision_at_5" else getattr(s, metric)[k])
        return float(np.nanmean(vals)) if vals else math.nan


def design_summary(ev: RetrievalEvaluation) -> list[dict[str, float | str]]:
    """One row per design: prec@5 (all, test), Recall@k and nDCG@k means."""
    rows: list[dict[str, float | str]] = []
    for d in ev.designs:
        row: dict[str, float | str] = {
            "design": d,
            "prec@5": ev.mean(d, "precision_at_5"),
            "prec@5 test": ev.mean(d, "precision_at_5", "test"),
        }
        for k in (5, 10, 50, 100):
            row[f"R@{k}"] = ev.mean(d, "recall", k=k)
        for k in (5, 10):
            row[f"nDCG@{k}"] = ev.mean(d, "ndcg", k=k)
        rows.append(row)
    return rows


def with_split(q: RetrievalQuery, split: str) -> RetrievalQuery:
    """``q`` moved to ``split``."""
    return replace(q, split=split)


def store_window_truth(store: Any, samples: Sequence[Mapping[str, Any]]) -> dict[str, dict[str, float]]:
    """Ground truth of each sample (window records of a stored graph) from its highD recording.

    Samples of logs that are not highD-format recordings (no frames, or no readable recording)
    get none. One recording is read once, whatever the number of its logs.
    """
    from scenariominer.data.log import LogFormatError
    from scenariominer.eval.highway_truth import load_recording_truth, window_truth

    paths: dict[str, str | None] = {}
    out: dict[str, dict[str, float]] = {}
    for s in samples:
        log_id = str(s["log_id"])
        if s.get("start_frame") is None:
            continue
        if log_id not in paths:
            meta = store.log_meta(log_id)
            paths[log_id] = str(meta.source_path) if meta.dataset == "highd" and meta.source_path else None
        path = paths[log_id]
        if path is None:
            continue
        try:
            rec = load_recording_truth(path)
            truth = window_truth(rec, int(str(s["agent_id"])), int(s["start_frame"]), int(s["end_frame"]))
        except (LogFormatError, OSError, ValueError):
            paths[log_id] = None
            continue
        if truth is not None:
            out[str(s["window_id"])] = truth
    return out


def evaluate_retrieval(
    store: Any,
    graph_ids: Mapping[str, str],
    embedder: Any,
    queries: Sequence[RetrievalQuery],
    *,
    k_max: int = 100,
    client: Any = None,
    progress: Any = None,
) -> RetrievalEvaluation:
    """Rank every window of each graph for each query with both designs and score the rankings.

    Args:
        store: the scenario store.
        graph_ids: label (e.g. ``hausdorff``) -> graph id.
        embedder: the text embedder the graphs were built with.
        queries: the queries.
        k_max: ranking depth scored.
        client: when given, the graph design's top samples are also answered by the model (its
            time is reported separately; the answers do not change the ranking).
        progress: progress sink.
    """
    import time

    from scenariominer.progress import NullProgress
    from scenariominer.represent.ask import AskSettings, ask_graph, open_graph

    bar = progress or NullProgress()
    judges = {q.query_id: compile_rule(q.rule) for q in queries}
    qvecs = embedder.embed([q.text for q in queries]).vectors
    truth: dict[str, dict[str, float]] = {}
    scores: list[QueryScore] = []
    designs: list[str] = []
    timing: dict[str, float] = {}
    n_summaries: dict[str, int] = {}
    answers: list[tuple[str, str, str, float]] = []
    skipped: set[str] = set()
    n_windows = 0
    bar.start("retrieval queries", total=len(graph_ids) * len(queries))
    for label, gid in graph_ids.items():
        og = open_graph(store, gid)
        n_summaries[label] = len(og.summaries)
        missing = [s for s in og.graph.samples if str(s["window_id"]) not in truth]
        truth.update(store_window_truth(store, missing))
        ids = [str(s["window_id"]) for s in og.graph.samples]
        n_windows = max(n_windows, len(ids))
        relevant = {
            q.query_id: {w for w in ids if w in truth and judges[q.query_id](truth[w])} for q in queries
        }
        for mode in ("graph", "vector"):
            design = f"{label}/{mode}"
            designs.append(design)
            settings = AskSettings(k=k_max, graph=mode == "graph")
            spent = 0.0
            for q, v in zip(queries, qvecs, strict=True):
                t0 = time.perf_counter()
                found = og.index.search(v, settings)
                spent += time.perf_counter() - t0
                if not relevant[q.query_id]:
                    skipped.add(q.query_id)
                    continue
                ranked = [og.index.sample_ids[i] for i in found.samples.tolist()]
                scores.append(score_ranking(q.query_id, design, ranked, relevant[q.query_id]))
            timing[design] = spent / max(len(queries), 1) * 1e3
        if client is not None:
            for q in queries:
                res = ask_graph(og.graph, og.index, q.text, embedder, client, AskSettings(), og.summaries)
                answers.append((f"{label}/graph", q.query_id, res.answer, res.llm_s))
                bar.advance()
        else:
            bar.advance(len(queries))
    return RetrievalEvaluation(
        queries=tuple(queries),
        designs=tuple(designs),
        scores=tuple(scores),
        skipped=tuple(sorted(skipped)),
        n_windows=n_windows,
        n_with_truth=len(truth),
        graphs=dict(graph_ids),
        llm_summaries=n_summaries,
        retrieval_ms=timing,
        answers=tuple(answers),
    )
