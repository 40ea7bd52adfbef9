"""What a job's worker process runs: one :mod:`scenariominer.api` call, its progress and its result.

:func:`run_job` is the target of the worker process (started with ``spawn``): it opens the store,
loads the configuration, calls the use case the job names with a :class:`QueueProgress` sink, and
sends ``(job_id, kind, payload)`` messages back over a multiprocessing queue: ``progress`` while it
runs, then exactly one ``result`` or ``error``. Results are turned into plain JSON here (:func:`plain`).
"""

from __future__ import annotations

import dataclasses
import datetime as _dt
import enum
import math
import sys
import traceback
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any, Protocol

import numpy as np

__all__ = ["JOB_KINDS", "EventSink", "QueueProgress", "mine_result_json", "picture_path", "plain", "run_job"]


class EventSink(Protocol):
    """The part of a multiprocessing queue the worker uses."""

    def put(self, obj: Any) -> None:
        """Send one message to the server."""
        ...


class QueueProgress:
    """A :class:`~scenariominer.progress.Progress` sink that sends each step's state to the server."""

    def __init__(self, job_id: str, events: EventSink) -> None:
        self._job_id = job_id
        self._events = events
        self._step = ""
        self._total: int | None = None
        self._done = 0

    @property
    def job_id(self) -> str:
        """The job this sink reports for."""
        return self._job_id

    def _send(self, message: str | None = None) -> None:
        payload = {"step": self._step, "total": self._total, "done": self._done, "message": message}
        self._events.put((self._job_id, "progress", payload))

    def start(self, description: str, total: int | None) -> None:
        """Begin a step."""
        self._step, self._total, self._done = description, total, 0
        self._send()

    def advance(self, n: int = 1, message: str | None = None) -> None:
        """Count ``n`` more units done."""
        self._done += n
        self._send(message)

    def finish(self) -> None:
        """End the step."""
        self._send("finished")


def plain(value: Any, _depth: int = 0) -> Any:
    """``value`` as JSON-safe Python (dataclasses, paths, enums, numpy, dates; NaN and inf become None)."""
    if _depth > 12:
        return str(value)
    if isinstance(value, float | np.floating):
        return float(value) if math.isfinite(value) else None
    if isinstance(value, bool | int | str) or value is None:
        return value
    if isinstance(value, np.integer | np.bool_):
        return value.item()
    if isinstance(value, enum.Enum):
        return plain(value.value, _depth + 1)
    if isinstance(value, Path | _dt.datetime | _dt.date):
        return value.isoformat() if not isinstance(value, Path) else str(value)
    if isinstance(value, np.ndarray):
        return plain(value.tolist(), _depth + 1)
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return {f.name: plain(getattr(value, f.name), _depth + 1) for f in dataclasses.fields(value)}
    if isinstance(value, Mapping):
        return {str(k): plain(v, _depth + 1) for k, v in value.items()}
    if isinstance(value, list | tuple | set | frozenset):
        return [plain(v, _depth + 1) for v in value]
    return str(value)


def mine_result_json(result: Any, max_objects: int = 500) -> dict[str, Any]:
    """What the mining page shows of an :class:`~scenariominer.api.MineResult`.

    The program, where it came from, its review flag and confidence, and per log the referred
    objects (track id, category, first/last timestamp, timestamp count), at most ``max_objects``.
    """
    report = result.report
    consensus = report.consensus
    objects: list[dict[str, Any]] = []
    for m in report.matches:
        for row in np.flatnonzero(m.referred.any(axis=1)).tolist()[: max(0, max_objects - len(objects))]:
            ts = m.timestamps_ns[m.referred[row]]
            objects.append(
                {
                    "log_id": m.log_id,
                    "track_id": str(m.track_ids[row]),
                    "category": str(m.categories[row]),
                    "first_ns": int(ts[0]),
                    "last_ns": int(ts[-1]),
                    "n_timestamps": int(ts.size),
                    "timestamps_ns": [int(t) for t in ts[:400]],
                }
            )
    return {
        "summary": plain(report.summary()),
        "program": report.program,
        "source": report.source.value,
        "status": report.status.value,
        "needs_review": bool(consensus.needs_review) if consensus is not None else None,
        "confidence": plain(consensus.confidence) if consensus is not None else None,
        "referred_objects": objects,
        "failures": [{"log_id": f.log_id, "error": f.error.feedback()} for f in report.failures],
        "stored_logs": list(result.stored_logs),
    }


def _ingest(p: Mapping[str, Any], store: Any, cfg: Any, progress: QueueProgress) -> Any:
    from scenariominer import api

    report = api.ingest(p["paths"], store, cfg, force=p.get("force", False), progress=progress)
    return {
        "n_ingested": report.n_ingested,
        "n_skipped": report.n_skipped,
        "n_logs_ingested": report.n_logs_ingested,
        "n_frames_ingested": report.n_frames_ingested,
        "failed": [{"source": r.key, "error": r.error} for r in report.failed],
        "seconds": report.seconds,
    }


def _analyze(p: Mapping[str, Any], store: Any, cfg: Any, progress: QueueProgress) -> Any:
    from scenariominer import api

    judge = "rules" if not p.get("llm", True) else p.get("judge")
    request = api.AnalyzeRequest(
        log_ids=p.get("log_ids"), limit=p.get("limit"), force=p.get("force", False), judge=judge
    )
    return api.analyze(store, request, cfg, progress=progress)


def _mine(p: Mapping[str, Any], store: Any, cfg: Any, progress: QueueProgress) -> Any:
    from scenariominer import api

    request = api.MineRequest(
        p["description"], store=store, program=p.get("program"), use_bank=p.get("use_bank", True)
    )
    progress.start("mine", None)
    result = api.mine(request, cfg)
    progress.finish()
    return mine_result_json(result)


def _synth(p: Mapping[str, Any], store: Any, cfg: Any, progress: QueueProgress) -> Any:
    from scenariominer import api

    return api.synth(p["out_dir"], p["n"], seed=p.get("seed", 0), progress=progress)


def _simulate_highway(p: Mapping[str, Any], store: Any, cfg: Any, progress: QueueProgress) -> Any:
    from scenariominer import api
    from scenariominer.sim.highway_scenario import HighwaySettings

    settings = HighwaySettings(recordings=p["recordings"], minutes=p["minutes"], seed=p["seed"])
    request = api.HighwaySimRequest(Path(p["out_dir"]), settings, overwrite=p.get("overwrite", False))
    return api.simulate_highway(request, progress=progress)


def _simulate_urban(p: Mapping[str, Any], store: Any, cfg: Any, progress: QueueProgress) -> Any:
    from scenariominer import api
    from scenariominer.sim.urban import UrbanSettings

    settings = UrbanSettings(n=p["n"], seed=p["seed"], noise=p["noise"])
    request = api.UrbanSimRequest(Path(p["out_dir"]), settings, overwrite=p.get("overwrite", False))
    return api.simulate_urban(request, progress=progress)


def _graph_build(p: Mapping[str, Any], store: Any, cfg: Any, progress: QueueProgress) -> Any:
    from scenariominer import api

    request = api.GraphBuildRequest(model_id=p.get("model_id"), loss=p.get("loss"), summaries=p["summaries"])
    return api.build_graph(store, request, cfg, progress=progress)


def _ask(p: Mapping[str, Any], store: Any, cfg: Any, progress: QueueProgress) -> Any:
    from scenariominer import api

    out = picture_path(store.root, progress.job_id)
    out.parent.mkdir(parents=True, exist_ok=True)
    request = api.AskRequest(
        question=p["question"],
        model_id=p.get("model_id"),
        loss=p.get("loss"),
        k=p["k"],
        graph=p["graph"],
        answer=p["answer"],
        picture=out,
    )
    return api.ask(store, request, cfg)


def _eval_retrieval(p: Mapping[str, Any], store: Any, cfg: Any, progress: QueueProgress) -> Any:
    from scenariominer import api

    request = api.RetrievalEvalRequest(losses=tuple(p["losses"]), k_max=p["k_max"], answers=p["answers"])
    return api.evaluate_retrieval(store, request, cfg, progress=progress)


def _embed_windows(p: Mapping[str, Any], store: Any, cfg: Any, progress: QueueProgress) -> Any:
    from scenariominer import api

    return api.build_windows(
        store, api.WindowsRequest(log_ids=p.get("log_ids"), rebuild=p.get("rebuild", False)), cfg, progress
    )


def _embed_train(p: Mapping[str, Any], store: Any, cfg: Any, progress: QueueProgress) -> Any:
    from scenariominer import api

    request = api.TrainRequest(loss=p.get("loss"), epochs=p.get("epochs"), seed=p.get("seed"))
    return api.train_embedder(store, request, cfg, progress)


def _embed_apply(p: Mapping[str, Any], store: Any, cfg: Any, progress: QueueProgress) -> Any:
    from scenariominer import api

    return api.apply_embedder(store, api.ApplyRequest(model_id=p.get("model_id")), cfg, progress)


def _embed_cluster(p: Mapping[str, Any], store: Any, cfg: Any, progress: QueueProgress) -> Any:
    from scenariominer import api

    request = api.ClusterRequest(model_id=p.get("model_id"), min_cluster_size=p.get("min_cluster_size"))
    return api.cluster_windows(store, request, cfg, progress)


def _embed_plot(p: Mapping[str, Any], store: Any, cfg: Any, progress: QueueProgress) -> Any:
    from scenariominer import api

    return api.plot_embeddings(
        store, api.PlotRequest(Path(p["out_dir"]), model_id=p.get("model_id")), cfg, progress
    )


def _llm_check(p: Mapping[str, Any], store: Any, cfg: Any, progress: QueueProgress) -> Any:
    from scenariominer import api

    return api.llm_check(cfg, chat=p.get("chat", True), embeddings=p.get("embeddings", False))


def _eval_braking(p: Mapping[str, Any], store: Any, cfg: Any, progress: QueueProgress) -> Any:
    from scenariominer import api

    request = api.BrakingEvalRequest(labels=Path(p["labels"]), retrieval=p.get("retrieval", True))
    return api.evaluate_braking(store, request, cfg, progress=progress)


def _eval_mining(p: Mapping[str, Any], store: Any, cfg: Any, progress: QueueProgress) -> Any:
    from scenariominer import api

    return api.evaluate_mining(api.MiningEvalRequest(pred=Path(p["pred"]), gt=Path(p["gt"])))


def _eval_nl2prog(p: Mapping[str, Any], store: Any, cfg: Any, progress: QueueProgress) -> Any:
    from scenariominer import api

    request = api.Nl2ProgEvalRequest(split=p.get("split", "holdout"), limit=p.get("limit"))
    return api.evaluate_nl2prog(request, cfg, progress=progress)


def _cbr_build(p: Mapping[str, Any], store: Any, cfg: Any, progress: QueueProgress) -> Any:
    from scenariominer import api

    request = api.CbrBuildRequest(p["per_type"], p["holdout_per_type"], p["seed"])
    return api.cbr_build(store, request, cfg)


def _recommend(p: Mapping[str, Any], store: Any, cfg: Any, progress: QueueProgress) -> Any:
    from scenariominer import api

    out = picture_path(store.root, progress.job_id)
    out.parent.mkdir(parents=True, exist_ok=True)
    request = api.RecommendRequest(
        p["log_id"], p.get("event_id"), out, k=p.get("k"), risk_type=p.get("risk_type")
    )
    return api.recommend(store, request, cfg)


def _eval_cbr(p: Mapping[str, Any], store: Any, cfg: Any, progress: QueueProgress) -> Any:
    from scenariominer import api

    out = picture_path(store.root, progress.job_id)
    request = api.CbrEvalRequest(
        per_type=p.get("per_type"),
        ks=tuple(p.get("ks", (0, 1, 3, 5))),
        time_budget_s=p.get("time_budget_s"),
        text_metrics=p.get("text_metrics", True),
        picture=out,
    )
    return api.evaluate_cbr(store, request, cfg, progress=progress)


def picture_path(store_root: Path, job_id: str) -> Path:
    """Where a job's picture (the rollout check of ``recommend``, the top samples of ``ask``) is written."""
    return Path(store_root) / "server" / "pictures" / f"{job_id}.png"


_Runner = Callable[[Mapping[str, Any], Any, Any, QueueProgress], Any]

#: Job kind → the function that runs it in the worker.
_RUNNERS: dict[str, _Runner] = {
    "ingest": _ingest,
    "analyze": _analyze,
    "mine": _mine,
    "synth": _synth,
    "embed_windows": _embed_windows,
    "embed_train": _embed_train,
    "embed_apply": _embed_apply,
    "embed_cluster": _embed_cluster,
    "embed_plot": _embed_plot,
    "llm_check": _llm_check,
    "eval_braking": _eval_braking,
    "eval_mining": _eval_mining,
    "eval_nl2prog": _eval_nl2prog,
    "cbr_build": _cbr_build,
    "recommend": _recommend,
    "eval_cbr": _eval_cbr,
    "simulate_highway": _simulate_highway,
    "simulate_urban": _simulate_urban,
    "graph_build": _graph_build,
    "ask": _ask,
    "eval_retrieval": _eval_retrieval,
}

#: Every job kind the server runs.
JOB_KINDS = tuple(_RUNNERS)


def run_job(
    job_id: str,
    kind: str,
    params: Mapping[str, Any],
    store_path: str,
    config_path: str | None,
    events: EventSink,
) -> None:
    """Run one job to its end and report it over ``events`` (the worker process's target).

    A :class:`~scenariominer.errors.ScenarioMinerError` (or ``ValueError``/``OSError``) is the
    user's to fix and is sent as its message; anything else is a bug: the traceback goes to this
    process's stderr (the server log) and the message names the exception type.
    """
    from scenariominer import api
    from scenariominer.config import load_config
    from scenariominer.errors import ScenarioMinerError

    try:
        cfg = load_config(config_path)
        store = api.open_existing_store(store_path, cfg)
        result = _RUNNERS[kind](params, store, cfg, QueueProgress(job_id, events))
        payload = result if isinstance(result, dict) else plain(result)
        events.put((job_id, "result", plain(payload)))
    except (ScenarioMinerError, ValueError, OSError) as exc:
        events.put((job_id, "error", f"{type(exc).__name__}: {exc}"))
    except Exception as exc:
        traceback.print_exc(file=sys.stderr)
        events.put((job_id, "error", f"internal error {type(exc).__name__}: {exc} (see the server log)"))
