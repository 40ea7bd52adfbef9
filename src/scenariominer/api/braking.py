"""Use cases of the why-braking method (seed 000): ``analyze``, ``search`` and ``show``.

Each function takes a store, a typed request and the configuration, builds the backends the
configuration names, calls the stage in :mod:`scenariominer.explain` and returns its typed result.
Nothing here prints.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from scenariominer.api._exec import executor_for
from scenariominer.config import Config
from scenariominer.explain.categories import RESERVED_NAMES, load_categories
from scenariominer.explain.pipeline import AnalyzeReport, analyze_store
from scenariominer.explain.search import SearchHit, SearchQuery, search_events
from scenariominer.explain.show import show_event
from scenariominer.llm.factory import make_chat_client, make_embedder
from scenariominer.llm.usage import UsageCounter
from scenariominer.progress import Progress
from scenariominer.store import ScenarioStore

if TYPE_CHECKING:
    from scenariominer.exec import Executor

__all__ = ["AnalyzeRequest", "ShowRequest", "analyze", "search", "show"]


@dataclass(frozen=True)
class AnalyzeRequest:
    """Which logs to analyse and how.

    Attributes:
        log_ids: only these logs (``None``: every log in the store).
        limit: at most this many fresh LLM calls in this run; 0 runs the rules only (no model is
            loaded) and leaves the events pending for a later run.
        force: re-analyse logs whose stored results are current.
        categories_file: TOML file of scenario categories (overrides ``explain.categories_file``).
        judge: who decides the categories (``hybrid``, ``llm``, ``rules``; overrides
            ``explain.judge``). ``rules`` loads no model: every event is complete at once.
    """

    log_ids: Sequence[str] | None = None
    limit: int | None = None
    force: bool = False
    categories_file: Path | None = None
    judge: str | None = None


def analyze(
    store: ScenarioStore,
    request: AnalyzeRequest,
    config: Config,
    progress: Progress | None = None,
    usage: UsageCounter | None = None,
    executor: Executor | None = None,
) -> AnalyzeReport:
    """Find braking events, describe, measure and classify them with the LLM, and embed them.

    The rules stage of each log runs on ``executor`` (default: ``config.exec``); the LLM stage
    runs in this process.

    Raises:
        ExplainError: an unusable category file.
        LLMError: the model or the embedder cannot be loaded or answered unusably.
        StoreError, DataError: the store or a stored log is unreadable.
    """
    cfg = config
    if request.categories_file is not None:
        explain = dataclasses.replace(cfg.explain, categories_file=str(request.categories_file))
        cfg = dataclasses.replace(cfg, explain=explain)
    if request.judge is not None:
        cfg = dataclasses.replace(cfg, explain=dataclasses.replace(cfg.explain, judge=request.judge))
    categories = load_categories(cfg.explain.categories_file)
    embedder = make_embedder(cfg, usage=usage)
    no_model = request.limit == 0 or cfg.explain.judge == "rules"
    client = None if no_model else make_chat_client(cfg, usage=usage)
    try:
        with executor_for(cfg, executor) as runner:
            return analyze_store(
                store,
                cfg,
                client,
                embedder,
                log_ids=request.log_ids,
                progress=progress,
                force=request.force,
                limit=request.limit,
                categories=categories,
                executor=runner,
            )
    finally:
        if client is not None:
            client.close()


def search(store: ScenarioStore, query: SearchQuery, config: Config) -> list[SearchHit]:
    """Braking events by category and/or free text (the embedder is loaded for text queries only).

    Raises:
        ExplainError: the store holds no analysed events.
        EmbeddingMismatchError: the stored vectors come from another embedding model.
    """
    embedder = make_embedder(config) if query.text is not None else None
    known = (*load_categories(config.explain.categories_file).names, *RESERVED_NAMES)
    return search_events(store, query, embedder, known_categories=known)


@dataclass(frozen=True)
class ShowRequest:
    """What to draw: a log, one of its events (``None``: the hardest braking) and the PNG path."""

    log_id: str
    out: Path | None = None
    event_id: str | None = None

    def out_path(self) -> Path:
        """The PNG to write: ``out``, or one named after the event in the current folder.

        An event id already starts with its log id (``<log>:<guest>:<start_ns>``), so the name is
        the event id with ``_`` for ``:`` (``<log>_event.png`` for the hardest braking).
        """
        if self.out is not None:
            return self.out
        if self.event_id is None:
            return Path(f"{self.log_id}_event.png")
        name = self.event_id
        if not name.startswith(f"{self.log_id}:"):
            name = f"{self.log_id}:{name}"
        return Path(f"{name.replace(':', '_')}.png")


def show(store: ScenarioStore, request: ShowRequest, config: Config) -> Path:
    """Draw a bird's-eye-view PNG of a braking event; returns the file written.

    Raises:
        ExplainError: no events, or no such event in the log.
        StoreError: no such log.
    """
    return show_event(store, request.log_id, request.out_path(), request.event_id, config.explain)
