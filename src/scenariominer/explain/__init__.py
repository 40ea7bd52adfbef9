"""LLM scenario understanding and dual-path retrieval of braking events (braking paper, III-D, III-E).

* :mod:`~scenariominer.explain.categories` - the categories the LLM chooses from (paper's or a file).
* :mod:`~scenariominer.explain.prompts` - the versioned prompt texts.
* :mod:`~scenariominer.explain.classify` - one description → ``{description, category, explanation}``.
* :mod:`~scenariominer.explain.baseline` - the rule-based baseline classifier.
* :mod:`~scenariominer.explain.pipeline` - :func:`analyze_store`, the whole stage over a store.
* :mod:`~scenariominer.explain.search` - retrieval by category and by free text.
* :mod:`~scenariominer.explain.show` - a bird's-eye-view picture of an event.
"""

from scenariominer.explain.baseline import baseline_category
from scenariominer.explain.categories import CategoryDef, CategoryFileError, CategorySet, load_categories
from scenariominer.explain.classify import Classification, ClassificationStatus, classify_description
from scenariominer.explain.pipeline import AnalyzeReport, LogAnalysis, LogStatus, analyze_log, analyze_store
from scenariominer.explain.prompts import PROMPT_VERSION, build_messages
from scenariominer.explain.records import EventRecord
from scenariominer.explain.search import NoEventsError, SearchHit, SearchQuery, SortKey, search_events
from scenariominer.explain.show import UnknownEventError, render_event, show_event

__all__ = [
    "PROMPT_VERSION",
    "AnalyzeReport",
    "CategoryDef",
    "CategoryFileError",
    "CategorySet",
    "Classification",
    "ClassificationStatus",
    "EventRecord",
    "LogAnalysis",
    "LogStatus",
    "NoEventsError",
    "SearchHit",
    "SearchQuery",
    "SortKey",
    "UnknownEventError",
    "analyze_log",
    "analyze_store",
    "baseline_category",
    "build_messages",
    "classify_description",
    "load_categories",
    "render_event",
    "search_events",
    "show_event",
]
