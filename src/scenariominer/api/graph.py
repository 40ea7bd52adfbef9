"""Use cases of the scenario knowledge graph (seed 001, sections 3.3-3.4): build, ask, evaluate retrieval.

Each function takes a store, a typed request and the configuration and returns a typed result;
nothing here prints. The text embedder is ``[embedding]`` (:func:`~scenariominer.llm.factory.make_embedder`)
and the language model ``[llm]`` (:func:`~scenariominer.llm.factory.make_chat_client`).
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from pathlib import Path

from scenariominer.config import Config
from scenariominer.eval.scenario_retrieval import RetrievalEvaluation
from scenariominer.progress import Progress
from scenariominer.represent.ask import AskResult
from scenariominer.represent.graph_build import GraphBuildReport
from scenariominer.store import ScenarioStore

__all__ = [
    "AskAnswer",
    "AskRequest",
    "GraphBuildRequest",
    "RetrievalEvalRequest",
    "ask",
    "build_graph",
    "evaluate_retrieval",
]


@dataclass(frozen=True)
class GraphBuildRequest:
    """Which graph to build.

    Attributes:
        model_id: embedder whose latest clustering the samples carry (default: the latest model,
            with ``loss`` if given; ``windows`` when the store has no model).
        loss: ``hausdorff`` or ``mse`` to pick the latest model of that loss.
        summaries: ask the language model for cluster summaries, contrasts and community reports.
        resolutions: Leiden resolutions, coarse to fine (default ``(0.5, 0.85, 1.0)``).
    """

    model_id: str | None = None
    loss: str | None = None
    summaries: bool = True
    resolutions: tuple[float, ...] | None = None


def build_graph(
    store: ScenarioStore, request: GraphBuildRequest, config: Config, progress: Progress | None = None
) -> GraphBuildReport:
    """Describe new or changed windowed logs, extend the graph, recompute communities, summarise.

    Raises:
        ModelNotAvailableError: the embedder (or, with summaries, the language model) is missing.
    """
    from scenariominer.llm.factory import make_chat_client, make_embedder
    from scenariominer.represent.graph_build import GraphSettings, build_store_graph, resolve_graph_id

    settings = GraphSettings()
    if request.resolutions:
        settings = replace(settings, resolutions=tuple(float(r) for r in request.resolutions))
    graph_id = resolve_graph_id(store, request.model_id, request.loss)
    embedder = make_embedder(config)
    client = make_chat_client(config) if request.summaries else None
    try:
        return build_store_graph(store, graph_id, embedder, client, settings, progress)
    finally:
        if client is not None:
            client.close()


@dataclass(frozen=True)
class AskRequest:
    """A question to the graph.

    Attributes:
        question: natural-language question.
        model_id: graph of this embedder (default as in :class:`GraphBuildRequest`).
        loss: pick the latest model of this loss.
        k: samples returned.
        graph: use the graph (False: plain vector search over the descriptions).
        answer: ask the language model for an answer with citations.
        picture: write a PNG of the top samples here.
    """

    question: str
    model_id: str | None = None
    loss: str | None = None
    k: int = 5
    graph: bool = True
    answer: bool = True
    picture: Path | None = None


@dataclass(frozen=True)
class AskAnswer:
    """Result of :func:`ask`: the ranked samples and answer, and the picture's path (if written)."""

    result: AskResult
    picture: Path | None


def ask(store: ScenarioStore, request: AskRequest, config: Config) -> AskAnswer:
    """Answer a question over the stored graph: ranked samples, cited answer, picture.

    Raises:
        ConfigError: ``k`` below 1 or an empty question.
        GraphNotBuiltError: the graph is not built.
        ModelNotAvailableError: the embedder (or, with ``answer``, the language model) is missing.
    """
    from scenariominer.config import ConfigError
    from scenariominer.llm.factory import make_chat_client, make_embedder
    from scenariominer.represent.ask import AskSettings, ask_graph, open_graph, write_samples_picture
    from scenariominer.represent.graph_build import resolve_graph_id
    from scenariominer.represent.window_table import load_windows

    if request.k < 1:
        raise ConfigError(f"k must be at least 1, got {request.k}")
    if not request.question.strip():
        raise ConfigError("the question is empty")
    og = open_graph(store, resolve_graph_id(store, request.model_id, request.loss))
    embedder = make_embedder(config)
    client = make_chat_client(config) if request.answer else None
    try:
        result = ask_graph(
            og.graph,
            og.index,
            request.question,
            embedder,
            client,
            AskSettings(k=request.k, graph=request.graph),
            og.summaries,
        )
    finally:
        if client is not None:
            client.close()
    picture = None
    if request.picture is not None and result.samples:
        windows = load_windows(store, window_ids=[s.window_id for s in result.samples])
        picture = write_samples_picture(windows, result.samples, request.picture)
    return AskAnswer(result, picture)


@dataclass(frozen=True)
class RetrievalEvalRequest:
    """What to evaluate.

    Attributes:
        queries: query file (default: the shipped ``highway_queries.toml``).
        losses: evaluate the graph of the latest model of each loss (those that exist).
        model_ids: evaluate these models' graphs instead.
        k_max: ranking depth scored (Recall@k up to it).
        answers: also ask the language model for each query's answer (time reported apart).
    """

    queries: Path | None = None
    losses: tuple[str, ...] = ("hausdorff", "mse")
    model_ids: tuple[str, ...] = ()
    k_max: int = 100
    answers: bool = False


def evaluate_retrieval(
    store: ScenarioStore, request: RetrievalEvalRequest, config: Config, progress: Progress | None = None
) -> RetrievalEvaluation:
    """prec@5 grid, Recall@k and nDCG@k of graph vs vector retrieval for each embedding's graph.

    Raises:
        RuleError: the query file is malformed.
        GraphNotBuiltError: no graph to evaluate.
    """
    from scenariominer.eval.scenario_retrieval import evaluate_retrieval as run
    from scenariominer.eval.scenario_retrieval import load_queries
    from scenariominer.llm.factory import make_chat_client, make_embedder
    from scenariominer.represent.graph import graph_logs
    from scenariominer.represent.graph_store import GraphNotBuiltError
    from scenariominer.represent.model_table import list_models

    queries = load_queries(request.queries)
    graphs: dict[str, str] = {}
    if request.model_ids:
        graphs = {m: m for m in request.model_ids}
    else:
        models = list_models(store)
        for loss in request.losses:
            mine = [m for m in models if m.loss == loss]
            if mine:
                graphs[loss] = mine[0].model_id
        if not graphs:
            graphs["windows"] = "windows"
    graphs = {k: v for k, v in graphs.items() if graph_logs(store, v)}
    if not graphs:
        raise GraphNotBuiltError("no graph to evaluate; build one first (scenariominer graph build)")
    embedder = make_embedder(config)
    client = make_chat_client(config) if request.answers else None
    try:
        return run(store, graphs, embedder, queries, k_max=request.k_max, client=client, progress=progress)
    finally:
        if client is not None:
            client.close()
