"""Trained embedders and their embeddings in the store (corpus tables).

``represent_models`` (schema 1), key: model id ``vrae-<loss>-<data hash 8>-<settings hash 6>``.
JSON: ``loss``, ``config`` (the :class:`~scenariominer.config.represent.EmbedderConfig` fields),
``data_hash`` (:func:`~.vrae.windows_data_hash` of the training windows), ``window_config`` (hash
of the window settings it was trained on) and ``window_settings`` (those settings), ``n_windows``,
``n_agents``, ``n_steps``, ``loss_history``, ``seconds``, ``trained_at``.
Blob: :meth:`TrajectoryEmbedder.to_bytes`.

``represent_embeddings`` (schema 1), key ``<model id>|<log id>``. JSON: ``model_id``, ``log_id``,
``window_ids``. Blob: ``.npy`` float32 ``(n windows, latent_dim)``, rows in ``window_ids`` order.
Embedding a new log writes that log's row only.
"""

from __future__ import annotations

import dataclasses
import hashlib
import io
import json
from collections.abc import Sequence
from dataclasses import dataclass
from datetime import UTC, datetime
from typing import Any

import numpy as np
from numpy.typing import NDArray

from scenariominer.config.represent import WindowConfig
from scenariominer.represent.errors import UnknownModelError
from scenariominer.represent.vrae import TrajectoryEmbedder
from scenariominer.represent.window_table import window_config_from, window_config_hash
from scenariominer.store import ScenarioStore

__all__ = [
    "EMBEDDINGS_TABLE",
    "MODELS_TABLE",
    "ModelRecord",
    "embedded_logs",
    "list_models",
    "load_embeddings",
    "load_model",
    "model_id_for",
    "save_embeddings",
    "save_model",
]

MODELS_TABLE = "represent_models"
EMBEDDINGS_TABLE = "represent_embeddings"
SCHEMA = 1


@dataclass(frozen=True)
class ModelRecord:
    """A stored embedder's description (without its weights).

    Attributes:
        model_id: its key.
        loss: ``hausdorff`` or ``mse``.
        data_hash: hash of the training windows.
        window_config: hash of the window settings it expects.
        n_windows: training windows.
        n_agents: agents per window.
        n_steps: steps per window.
        final_loss: last epoch's mean training loss.
        seconds: training wall time.
        trained_at: ISO time of training (UTC).
        window_settings: the window settings it expects (:class:`WindowConfig` fields).
    """

    model_id: str
    loss: str
    data_hash: str
    window_config: str
    n_windows: int
    n_agents: int
    n_steps: int
    final_loss: float
    seconds: float
    trained_at: str
    window_settings: dict[str, Any]

    def windows(self) -> WindowConfig:
        """The window settings the model expects."""
        return window_config_from(self.window_settings)


def model_id_for(embedder: TrajectoryEmbedder) -> str:
    """The key a fitted embedder is stored under (same settings and data: same id)."""
    cfg = json.dumps(dataclasses.asdict(embedder.config), sort_keys=True)
    settings = hashlib.sha256(cfg.encode()).hexdigest()[:6]
    return f"vrae-{embedder.config.loss}-{embedder.data_hash_[:8]}-{settings}"


def save_model(store: ScenarioStore, embedder: TrajectoryEmbedder, window_config: WindowConfig) -> str:
    """Store a fitted embedder trained on windows cut with ``window_config``; returns its model id."""
    model_id = model_id_for(embedder)
    summary = embedder.summary_
    row = {
        "loss": embedder.config.loss,
        "config": dataclasses.asdict(embedder.config),
        "data_hash": embedder.data_hash_,
        "window_config": window_config_hash(window_config),
        "window_settings": dataclasses.asdict(window_config),
        "n_windows": summary.n_windows if summary else 0,
        "n_agents": embedder.n_agents_,
        "n_steps": embedder.n_steps_,
        "loss_history": list(summary.loss_history) if summary else [],
        "seconds": summary.seconds if summary else 0.0,
        "trained_at": datetime.now(UTC).isoformat(),
    }
    store.corpus(MODELS_TABLE, SCHEMA).upsert({model_id: row}, {model_id: embedder.to_bytes()})
    return model_id


def _record(key: str, d: dict[str, object]) -> ModelRecord:
    history = d.get("loss_history") or []
    settings = d.get("window_settings")
    assert isinstance(history, list)
    return ModelRecord(
        model_id=key,
        loss=str(d["loss"]),
        data_hash=str(d["data_hash"]),
        window_config=str(d["window_config"]),
        n_windows=int(str(d["n_windows"])),
        n_agents=int(str(d["n_agents"])),
        n_steps=int(str(d["n_steps"])),
        final_loss=float(history[-1]) if history else float("nan"),
        seconds=float(str(d["seconds"])),
        trained_at=str(d["trained_at"]),
        window_settings=dict(settings) if isinstance(settings, dict) else {},
    )


def list_models(store: ScenarioStore) -> list[ModelRecord]:
    """Every stored embedder, most recently trained first."""
    rows = store.corpus(MODELS_TABLE, SCHEMA).rows()
    records = [_record(r.key, dict(r.data)) for r in rows]
    return sorted(records, key=lambda m: m.trained_at, reverse=True)


def load_model(
    store: ScenarioStore, model_id: str | None = None, loss: str | None = None
) -> tuple[ModelRecord, TrajectoryEmbedder]:
    """A stored embedder: by id, or the most recently trained one (with ``loss``, if given).

    Raises:
        UnknownModelError: no such model (the message lists the stored ones).
    """
    models = list_models(store)
    if model_id is None:
        candidates = [m for m in models if loss is None or m.loss == loss]
        if not candidates:
            which = f"with the {loss} loss " if loss else ""
            raise UnknownModelError(f"no embedder {which}in the store; train one (scenariominer embed train)")
        model_id = candidates[0].model_id
    row = store.corpus(MODELS_TABLE, SCHEMA).get(model_id)
    if row is None or row.blob is None:
        known = ", ".join(m.model_id for m in models) or "none"
        raise UnknownModelError(f"no embedder {model_id!r} in the store (stored: {known})")
    return _record(row.key, dict(row.data)), TrajectoryEmbedder.from_bytes(row.blob)


def save_embeddings(
    store: ScenarioStore,
    model_id: str,
    log_ids: NDArray[np.str_],
    window_ids: NDArray[np.str_],
    z: NDArray[np.float32],
) -> None:
    """Store embeddings ``z`` ``(W, D)`` of windows ``window_ids`` (from ``log_ids``), one row per log."""
    rows: dict[str, dict[str, object]] = {}
    blobs: dict[str, bytes] = {}
    for log_id in sorted(set(log_ids.tolist())):
        sel = np.flatnonzero(log_ids == log_id)
        buf = io.BytesIO()
        np.save(buf, np.ascontiguousarray(z[sel], dtype=np.float32))
        key = f"{model_id}|{log_id}"
        rows[key] = {"model_id": model_id, "log_id": log_id, "window_ids": window_ids[sel].tolist()}
        blobs[key] = buf.getvalue()
    if rows:
        store.corpus(EMBEDDINGS_TABLE, SCHEMA).upsert(rows, blobs)


def embedded_logs(store: ScenarioStore, model_id: str, log_ids: Sequence[str]) -> dict[str, tuple[str, ...]]:
    """For each of ``log_ids`` embedded with ``model_id``: the window ids embedded."""
    keys = [f"{model_id}|{log_id}" for log_id in log_ids]
    rows = store.corpus(EMBEDDINGS_TABLE, SCHEMA).rows(keys)
    return {str(r.data["log_id"]): tuple(r.data["window_ids"]) for r in rows}


def load_embeddings(
    store: ScenarioStore, model_id: str, log_ids: Sequence[str]
) -> tuple[NDArray[np.str_], NDArray[np.str_], NDArray[np.float32]]:
    """Window ids ``(W,)``, log ids ``(W,)`` and embeddings ``(W, D)`` of ``model_id`` for ``log_ids``.

    Rows are sorted by window id.
    """
    keys = [f"{model_id}|{log_id}" for log_id in log_ids]
    rows = store.corpus(EMBEDDINGS_TABLE, SCHEMA).rows(keys, with_blobs=True)
    if not rows:
        return np.empty(0, dtype=str), np.empty(0, dtype=str), np.empty((0, 0), dtype=np.float32)
    wids = np.asarray([w for r in rows for w in r.data["window_ids"]], dtype=str)
    lids = np.asarray([r.data["log_id"] for r in rows for _ in r.data["window_ids"]], dtype=str)
    z = np.concatenate([np.load(io.BytesIO(r.blob or b"")) for r in rows]).astype(np.float32)
    order = np.argsort(wids, kind="stable")
    return wids[order], lids[order], z[order]
