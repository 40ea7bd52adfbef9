"""Request and response models of the HTTP API (pydantic), with limits on sizes and counts.

Responses are built from the use cases' typed results by the ``from_*`` functions here; NaN and
infinite measures become ``null``.
"""

import math
from typing import Any, Literal

from pydantic import BaseModel, ConfigDict, Field

from scenariominer.schema import Judge

__all__ = [
    "AnalyzeJob",
    "ErrorBody",
    "EventModel",
    "IngestJob",
    "JobModel",
    "LogModel",
    "MineJob",
    "SceneModel",
    "SynthJob",
]

#: Longest identifier (log, track, event, category) a request may carry.
MAX_ID_CHARS = 300
#: Longest path a request may carry.
MAX_PATH_CHARS = 4096
#: Most paths or log ids in one request.
MAX_ITEMS = 1000

PathStr = Field(min_length=1, max_length=MAX_PATH_CHARS)


class _Strict(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)


class ErrorBody(BaseModel):
    """Every error answer: a message a person can act on (never a traceback)."""

    error: str


def finite(value: float) -> float | None:
    """``value``, or ``None`` when it is NaN or infinite."""
    return value if math.isfinite(value) else None


class LogModel(BaseModel):
    """One stored log (metadata and analysed events per category)."""

    log_id: str
    dataset: str
    source_path: str | None
    has_map: bool
    n_tracks: int
    n_timestamps: int
    n_frames: int
    duration_s: float
    start_timestamp_ns: int
    categories: dict[str, int]
    notes: list[str]
    ingested_at: str
    n_events: int
    event_categories: dict[str, int]


class EventModel(BaseModel):
    """One analysed braking event (category, explanation, criticality)."""

    event_id: str
    log_id: str
    guest_id: str
    guest_category: str
    start_ns: int
    end_ns: int
    start_s: float
    end_s: float
    closest_ns: int
    category: str
    baseline_category: str
    rule_candidates: str
    judge: str
    llm_status: str
    explanation: str
    description: str
    tag_description: str
    min_ttc_s: float | None
    min_distance_m: float | None
    pet_s: float | None
    headway_s: float | None
    peak_decel_mps2: float | None
    score: float | None = None


class SceneModel(BaseModel):
    """One scenario as arrays: N tracks x T timestamps in the city frame, with map outlines and tags."""

    log_id: str
    event: EventModel | None
    t_s: list[float] = Field(description="(T,) seconds from the first timestamp shown")
    timestamps_ns: list[int]
    track_ids: list[str]
    categories: list[str]
    ego_index: int
    key_index: int = Field(description="row of the event's key object, -1 without an event")
    x_m: list[list[float | None]]
    y_m: list[list[float | None]]
    yaw_rad: list[list[float | None]]
    length_m: list[list[float | None]]
    width_m: list[list[float | None]]
    lanes: list[list[list[float]]] = Field(description="lane polygons, each (K, 2) x/y in metres")
    crossings: list[list[list[float]]] = Field(description="pedestrian-crossing polygons, each (K, 2)")
    tags: dict[str, list[str | None]] = Field(description="per tag family, the key object's (T,) tags")


class JobModel(BaseModel):
    """A job: its state, latest progress, and result or error."""

    id: str
    kind: str
    params: dict[str, Any]
    state: Literal["queued", "running", "succeeded", "failed", "cancelled", "interrupted"]
    created_at: str
    started_at: str | None
    finished_at: str | None
    progress: dict[str, Any] | None
    result: Any
    error: str | None


class IngestJob(_Strict):
    """Ingest log sources (paths inside the server's data roots)."""

    paths: list[str] = Field(min_length=1, max_length=64)
    force: bool = False


class AnalyzeJob(_Strict):
    """Analyse braking events of some or all logs."""

    log_ids: list[str] | None = Field(default=None, max_length=MAX_ITEMS)
    llm: bool = Field(default=True, description="false: rules only, no model loaded")
    limit: int | None = Field(default=None, ge=0, le=100_000)
    force: bool = False
    judge: Judge | None = None


class MineJob(_Strict):
    """A mining query: a description in plain English, optionally with a program to run (sandboxed)."""

    description: str = Field(min_length=1, max_length=2000)
    program: str | None = Field(default=None, max_length=20_000)
    use_bank: bool = True


class SynthJob(_Strict):
    """Write labelled synthetic logs into a folder inside the data roots."""

    out_dir: str = PathStr
    n: int = Field(ge=1, le=1000)
    seed: int = Field(default=0, ge=0)


class SimulateHighwayJob(_Strict):
    """Simulate highway traffic with SUMO into highD-format recordings (a folder inside the data roots)."""

    out_dir: str = PathStr
    recordings: int = Field(default=6, ge=1, le=100)
    minutes: float = Field(default=10.0, gt=0, le=240)
    seed: int = Field(default=1, ge=0)
    overwrite: bool = False


class SimulateUrbanJob(_Strict):
    """Simulate labelled braking scenarios with SUMO into AV2 logs (a folder inside the data roots)."""

    out_dir: str = PathStr
    n: int = Field(default=40, ge=1, le=1000)
    seed: int = Field(default=0, ge=0)
    noise: str = Field(default="mixed", pattern="^(none|low|medium|high|mixed)$")
    overwrite: bool = False


class GraphBuildJob(_Strict):
    """Describe the windows, build the knowledge graph, its communities and (optionally) LLM summaries."""

    model_id: str | None = Field(default=None, max_length=MAX_ID_CHARS)
    loss: str | None = Field(default=None, pattern="^(hausdorff|mse)$")
    summaries: bool = True


class AskJob(_Strict):
    """A natural-language question over the knowledge graph."""

    question: str = Field(min_length=1, max_length=2000)
    model_id: str | None = Field(default=None, max_length=MAX_ID_CHARS)
    loss: str | None = Field(default=None, pattern="^(hausdorff|mse)$")
    k: int = Field(default=5, ge=1, le=50)
    graph: bool = Field(default=True, description="false: plain vector search over the descriptions")
    answer: bool = Field(default=True, description="false: rank only, no model loaded")


class EvalRetrievalJob(_Strict):
    """Score graph and vector retrieval against the simulator's ground truth (shipped queries)."""

    losses: list[str] = Field(default=["hausdorff", "mse"], min_length=1, max_length=2)
    k_max: int = Field(default=100, ge=5, le=10_000)
    answers: bool = False


class EmbedWindowsJob(_Strict):
    """Cut trajectory windows of some or all logs."""

    log_ids: list[str] | None = Field(default=None, max_length=MAX_ITEMS)
    rebuild: bool = False


class EmbedTrainJob(_Strict):
    """Train the trajectory autoencoder on the stored windows."""

    loss: Literal["hausdorff", "mse"] | None = None
    epochs: int | None = Field(default=None, ge=1, le=10_000)
    seed: int | None = Field(default=None, ge=0)


class EmbedModelJob(_Strict):
    """Apply a trained model to the windows (or cluster its embeddings)."""

    model_id: str | None = Field(default=None, max_length=MAX_ID_CHARS)
    min_cluster_size: int | None = Field(default=None, ge=2, le=100_000)


class EmbedPlotJob(_Strict):
    """Plot the embeddings into a folder inside the data roots."""

    out_dir: str = PathStr
    model_id: str | None = Field(default=None, max_length=MAX_ID_CHARS)


class LlmCheckJob(_Strict):
    """Check that the configured chat model and/or embedder answer."""

    chat: bool = True
    embeddings: bool = False


class EvalBrakingJob(_Strict):
    """Evaluate the stored braking categories against a labels CSV inside the data roots."""

    labels: str = PathStr
    retrieval: bool = True


class EvalMiningJob(_Strict):
    """Score an Argoverse 2 mining submission against ground truth (both inside the data roots)."""

    pred: str = PathStr
    gt: str = PathStr


class EvalNl2ProgJob(_Strict):
    """Score program generation on the description set."""

    split: Literal["dev", "holdout", "published", "challenge", "all"] = "holdout"
    limit: int | None = Field(default=None, ge=1, le=1000)


class CbrAddBody(_Strict):
    """Add cases: from a CSV/JSONL file inside the data roots, or one analysed event with its manoeuvre."""

    file: str | None = Field(default=None, min_length=1, max_length=MAX_PATH_CHARS)
    log_id: str | None = Field(default=None, max_length=MAX_ID_CHARS)
    event_id: str | None = Field(default=None, max_length=MAX_ID_CHARS)
    manoeuvre: str | None = Field(default=None, max_length=MAX_ID_CHARS)
    justification: str = Field(default="", max_length=4000)
    risk_type: str | None = Field(default=None, max_length=MAX_ID_CHARS)


class CbrRemoveBody(_Strict):
    """Cases to delete."""

    case_ids: list[str] = Field(min_length=1, max_length=MAX_ITEMS)


class CbrBuildJob(_Strict):
    """Build the labelled synthetic case set (replaces the case base)."""

    per_type: int = Field(default=110, ge=1, le=10_000)
    holdout_per_type: int = Field(default=10, ge=0, le=1000)
    seed: int = Field(default=0, ge=0)


class RecommendJob(_Strict):
    """Recommend an evasive manoeuvre for an analysed event (the LLM), with its rollout check."""

    log_id: str = Field(min_length=1, max_length=MAX_ID_CHARS)
    event_id: str | None = Field(default=None, max_length=MAX_ID_CHARS)
    k: int | None = Field(default=None, ge=0, le=20)
    risk_type: str | None = Field(default=None, max_length=MAX_ID_CHARS)


class EvalCbrJob(_Strict):
    """Run (or continue) the case-based reasoning evaluation grid."""

    per_type: int | None = Field(default=None, ge=1, le=10_000)
    ks: list[int] = Field(default=[0, 1, 3, 5], min_length=1, max_length=10)
    time_budget_s: float | None = Field(default=None, gt=0, le=7 * 24 * 3600)
    text_metrics: bool = True
