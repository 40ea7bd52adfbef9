"""Which route serves each use case of :mod:`scenariominer.api` (and why a few are not served).

The OpenAPI test checks every entry against ``/openapi.json`` and that every public function of
:mod:`scenariominer.api` is listed in one of the two tables, so a new use case cannot be missed.
"""

from __future__ import annotations

__all__ = ["NOT_SERVED", "USE_CASE_ROUTES"]

#: api function → (HTTP method, path) of the route that calls it.
USE_CASE_ROUTES: dict[str, tuple[str, str]] = {
    "info": ("GET", "/api/info"),
    "store_check": ("GET", "/api/store/check"),
    "list_logs": ("GET", "/api/logs"),
    "log_events": ("GET", "/api/logs/{log_id}/events"),
    "search": ("GET", "/api/search"),
    "scene": ("GET", "/api/scene/{log_id}"),
    "show": ("GET", "/api/show/{log_id}"),
    "similar": ("GET", "/api/similar"),
    "ingest": ("POST", "/api/jobs/ingest"),
    "synth": ("POST", "/api/jobs/synth"),
    "analyze": ("POST", "/api/jobs/analyze"),
    "mine": ("POST", "/api/jobs/mine"),
    "build_windows": ("POST", "/api/jobs/embed/windows"),
    "train_embedder": ("POST", "/api/jobs/embed/train"),
    "apply_embedder": ("POST", "/api/jobs/embed/apply"),
    "cluster_windows": ("POST", "/api/jobs/embed/cluster"),
    "plot_embeddings": ("POST", "/api/jobs/embed/plot"),
    "llm_check": ("POST", "/api/jobs/llm-check"),
    "evaluate_braking": ("POST", "/api/jobs/eval/braking"),
    "evaluate_mining": ("POST", "/api/jobs/eval/mining"),
    "evaluate_nl2prog": ("POST", "/api/jobs/eval/nl2prog"),
    "cbr_list": ("GET", "/api/cbr/cases"),
    "cbr_show": ("GET", "/api/cbr/cases/{case_id}"),
    "cbr_add": ("POST", "/api/cbr/cases"),
    "cbr_remove": ("POST", "/api/cbr/cases/remove"),
    "cbr_build": ("POST", "/api/jobs/cbr/build"),
    "recommend": ("POST", "/api/jobs/recommend"),
    "evaluate_cbr": ("POST", "/api/jobs/eval/cbr"),
    "simulate_highway": ("POST", "/api/jobs/simulate/highway"),
    "simulate_urban": ("POST", "/api/jobs/simulate/urban"),
    "build_graph": ("POST", "/api/jobs/graph/build"),
    "ask": ("POST", "/api/jobs/ask"),
    "evaluate_retrieval": ("POST", "/api/jobs/eval/retrieval"),
}

#: api functions without a route, and why.
NOT_SERVED: dict[str, str] = {
    "open_store": "a helper (the server opens its one store at start)",
    "open_existing_store": "a helper (the server opens its one store at start)",
    "find_sample_av2": "a helper for the demo command",
    "load_logs": "a helper of mine",
    "raw_logs_for": "a helper of mine's export",
    "store_report": "a helper of mine",
    "serve": "the model server: a server of its own (`scenariominer llm serve`)",
    "serve_settings": "the model server's settings",
    "store_vacuum": "deletes files: left to an operator at the command line",
    "open_case_base": "a helper of the case base",
    "evaluate_braking_sets": "compares several stores; the server has one (its eval braking job scores it)",
}
