"""One function per use case: what the command line, the HTTP server and a user's script call.

Every function takes typed arguments (a request dataclass where there are several options) and
returns a typed result; none prints. Progress goes through :class:`scenariominer.progress.Progress`.

==================  ===============================================  ============================
use case            function                                         module
==================  ===============================================  ============================
ingest              :func:`ingest`                                   :mod:`.corpus`
info                :func:`info` (store opened without creating it)  :mod:`.corpus`
synth               :func:`synth`                                    :mod:`.corpus`
store check         :func:`store_check`                              :mod:`.corpus`
store vacuum        :func:`store_vacuum`                             :mod:`.corpus`
analyze             :func:`analyze`                                  :mod:`.braking`
search              :func:`search`                                   :mod:`.braking`
show                :func:`show`                                     :mod:`.braking`
mine                :func:`mine`                                     :mod:`.mining`
eval braking        :func:`evaluate_braking`                         :mod:`.evaluation`
eval braking --also :func:`evaluate_braking_sets` (:class:`BrakingSet`)  :mod:`.evaluation`
eval mining         :func:`evaluate_mining`                          :mod:`.evaluation`
eval nl2prog        :func:`evaluate_nl2prog`                         :mod:`.evaluation`
llm check           :func:`llm_check`                                :mod:`.models`
llm serve           :func:`serve` (:func:`serve_settings`)          :mod:`.models`
embed windows       :func:`build_windows`                            :mod:`.represent`
embed train         :func:`train_embedder`                           :mod:`.represent`
embed apply         :func:`apply_embedder`                           :mod:`.represent`
embed cluster       :func:`cluster_windows`                          :mod:`.represent`
embed plot          :func:`plot_embeddings`                          :mod:`.represent`
similar             :func:`similar`                                  :mod:`.represent`
browse logs         :func:`list_logs`, :func:`log_events`            :mod:`.browse`
browse scene        :func:`scene` (:class:`SceneRequest`)            :mod:`.browse`
cbr add             :func:`cbr_add`                                  :mod:`.cbr`
cbr list            :func:`cbr_list`                                 :mod:`.cbr`
cbr show            :func:`cbr_show`                                 :mod:`.cbr`
cbr remove          :func:`cbr_remove`                               :mod:`.cbr`
cbr build           :func:`cbr_build`                                :mod:`.cbr`
recommend           :func:`recommend`                                :mod:`.cbr`
eval cbr            :func:`evaluate_cbr`                             :mod:`.cbr`
graph build         :func:`build_graph`                              :mod:`.graph`
ask                 :func:`ask`                                      :mod:`.graph`
eval retrieval      :func:`evaluate_retrieval`                       :mod:`.graph`
simulate highway    :func:`simulate_highway`                         :mod:`.sim_highway`
simulate urban      :func:`simulate_urban`                           :mod:`.sim_urban`
==================  ===============================================  ============================

Names are imported lazily on first use, so ``import scenariominer.api`` is cheap.
"""

from __future__ import annotations

import importlib
from typing import Any

_EXPORTS: dict[str, str] = {
    "IngestReport": "corpus",
    "SourceResult": "corpus",
    "find_sample_av2": "corpus",
    "info": "corpus",
    "ingest": "corpus",
    "open_existing_store": "corpus",
    "open_store": "corpus",
    "synth": "corpus",
    "store_check": "corpus",
    "store_vacuum": "corpus",
    "AnalyzeRequest": "braking",
    "ShowRequest": "braking",
    "analyze": "braking",
    "search": "braking",
    "show": "braking",
    "MineRequest": "mining",
    "MineResult": "mining",
    "load_logs": "mining",
    "mine": "mining",
    "raw_logs_for": "mining",
    "store_report": "mining",
    "BrakingEvalRequest": "evaluation",
    "BrakingSet": "evaluation",
    "MiningEvalRequest": "evaluation",
    "Nl2ProgEvalRequest": "evaluation",
    "evaluate_braking": "evaluation",
    "evaluate_braking_sets": "evaluation",
    "evaluate_mining": "evaluation",
    "evaluate_nl2prog": "evaluation",
    "LLMCheckResult": "models",
    "llm_check": "models",
    "serve": "models",
    "serve_settings": "models",
    "WindowsRequest": "represent",
    "build_windows": "represent",
    "TrainRequest": "represent",
    "ApplyRequest": "represent",
    "ClusterRequest": "represent",
    "PlotRequest": "represent",
    "SimilarRequest": "represent",
    "train_embedder": "represent",
    "apply_embedder": "represent",
    "cluster_windows": "represent",
    "plot_embeddings": "represent",
    "similar": "represent",
    "LogEntry": "browse",
    "Scene": "browse",
    "SceneRequest": "browse",
    "list_logs": "browse",
    "log_events": "browse",
    "scene": "browse",
    "CbrAddRequest": "cbr",
    "CbrBuildRequest": "cbr",
    "CbrEvalRequest": "cbr",
    "RecommendRequest": "cbr",
    "RecommendResult": "cbr",
    "cbr_add": "cbr",
    "cbr_build": "cbr",
    "cbr_list": "cbr",
    "cbr_remove": "cbr",
    "cbr_show": "cbr",
    "evaluate_cbr": "cbr",
    "open_case_base": "cbr",
    "recommend": "cbr",
    "AskAnswer": "graph",
    "AskRequest": "graph",
    "GraphBuildRequest": "graph",
    "RetrievalEvalRequest": "graph",
    "ask": "graph",
    "build_graph": "graph",
    "evaluate_retrieval": "graph",
    "HighwaySimReport": "sim_highway",
    "HighwaySimRequest": "sim_highway",
    "simulate_highway": "sim_highway",
    "UrbanSimReport": "sim_urban",
    "UrbanSimRequest": "sim_urban",
    "simulate_urban": "sim_urban",
}

__all__ = sorted(_EXPORTS)


def __getattr__(name: str) -> Any:
    module = _EXPORTS.get(name)
    if module is None:
        raise AttributeError(f"module 'scenariominer.api' has no attribute {name!r}")
    value = getattr(importlib.import_module(f"scenariominer.api.{module}"), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_EXPORTS))
