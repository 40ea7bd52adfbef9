"""The FastAPI application: routes over :mod:`scenariominer.api`, errors as JSON, token, web UI.

Every route calls one use case of :mod:`scenariominer.api` (never the store or a stage directly)
and turns its typed result into a response model of :mod:`scenariominer.server.models`. Long
work (ingest, analyze, mine, embed, evaluations) is submitted to the :class:`JobManager` and
followed over Server-Sent Events at ``/api/jobs/{id}/events``.
"""

import asyncio
import hmac
import json
import logging
import shutil
import tempfile
import threading
from collections.abc import AsyncIterator, Callable
from contextlib import asynccontextmanager
from dataclasses import asdict
from importlib import resources
from pathlib import Path
from typing import Annotated, Any

import anyio

from scenariominer._optional import require

require("fastapi", extra="server", purpose="the scenario browser (scenariominer serve)")

from fastapi import APIRouter, Depends, FastAPI, HTTPException, Query, Request  # noqa: E402
from fastapi.exceptions import RequestValidationError  # noqa: E402
from fastapi.responses import FileResponse, JSONResponse, StreamingResponse  # noqa: E402
from fastapi.security import HTTPAuthorizationCredentials, HTTPBearer  # noqa: E402
from fastapi.staticfiles import StaticFiles  # noqa: E402
from pydantic import BaseModel  # noqa: E402
from starlette.background import BackgroundTask  # noqa: E402
from starlette.exceptions import HTTPException as StarletteHTTPException  # noqa: E402

from scenariominer import api  # noqa: E402
from scenariominer.config import Config, load_config  # noqa: E402
from scenariominer.errors import ScenarioMinerError  # noqa: E402
from scenariominer.schema import SortKey  # noqa: E402
from scenariominer.server import models as m  # noqa: E402
from scenariominer.server.jobs import FINAL_STATES, Job, JobManager, QueueFullError  # noqa: E402
from scenariominer.server.settings import PathOutsideRootsError, ServerSettings, confine_path  # noqa: E402

__all__ = ["create_app"]

log = logging.getLogger("scenariominer.server")

#: Seconds an event stream waits for a job's next event before sending a keep-alive comment.
SSE_POLL_S = 2.0


def _event_model(record: Any, score: float | None = None) -> m.EventModel:
    return m.EventModel(
        event_id=record.event_id,
        log_id=record.log_id,
        guest_id=record.guest_id,
        guest_category=record.guest_category,
        start_ns=record.start_ns,
        end_ns=record.end_ns,
        start_s=record.start_s,
        end_s=record.end_s,
        closest_ns=record.closest_ns,
        category=record.category,
        baseline_category=record.baseline_category,
        rule_candidates=record.rule_candidates,
        judge=record.judge,
        llm_status=record.llm_status,
        explanation=record.explanation,
        description=record.llm_description,
        tag_description=record.tag_description,
        min_ttc_s=m.finite(record.min_ttc_s),
        min_distance_m=m.finite(record.min_distance_m),
        pet_s=m.finite(record.pet_s),
        headway_s=m.finite(record.headway_s),
        peak_decel_mps2=m.finite(record.peak_decel_mps2),
        score=None if score is None else m.finite(score),
    )


def _log_model(entry: Any) -> m.LogModel:
    meta = entry.meta
    return m.LogModel(
        log_id=meta.log_id,
        dataset=meta.dataset,
        source_path=meta.source_path,
        has_map=meta.map_dir is not None,
        n_tracks=meta.n_tracks,
        n_timestamps=meta.n_timestamps,
        n_frames=meta.n_frames,
        duration_s=meta.duration_s,
        start_timestamp_ns=meta.start_timestamp_ns,
        categories=dict(meta.categories),
        notes=list(meta.notes),
        ingested_at=meta.ingested_at.isoformat(),
        n_events=entry.n_events,
        event_categories=entry.event_categories,
    )


def _rows(values: Any) -> list[list[float | None]]:
    return [[float(v) if v == v else None for v in row] for row in values.tolist()]


def _scene_model(scene: Any) -> m.SceneModel:
    ts = scene.timestamps_ns
    t0 = int(ts[0]) if ts.size else 0
    return m.SceneModel(
        log_id=scene.log_id,
        event=_event_model(scene.event) if scene.event is not None else None,
        t_s=[(int(t) - t0) * 1e-9 for t in ts.tolist()],
        timestamps_ns=[int(t) for t in ts.tolist()],
        track_ids=[str(t) for t in scene.track_ids.tolist()],
        categories=[str(c) for c in scene.categories.tolist()],
        ego_index=scene.ego_index,
        key_index=scene.key_index,
        x_m=_rows(scene.x_m),
        y_m=_rows(scene.y_m),
        yaw_rad=_rows(scene.yaw_rad),
        length_m=_rows(scene.length_m),
        width_m=_rows(scene.width_m),
        lanes=[p.round(2).tolist() for p in scene.lanes],
        crossings=[p.round(2).tolist() for p in scene.crossings],
        tags=scene.tags,
    )


def _job_model(job: Job) -> m.JobModel:
    return m.JobModel(**asdict(job))


def _status_of(exc: BaseException) -> int:
    if isinstance(exc, PathOutsideRootsError):
        return 403
    if isinstance(exc, QueueFullError):
        return 429
    if isinstance(exc, LookupError):
        return 404
    return 400


def _error(status: int, message: str) -> JSONResponse:
    return JSONResponse({"error": message}, status_code=status)


def _install_error_handlers(app: FastAPI) -> None:
    """Every error as ``{"error": message}``; a bug's traceback goes to the log, not the client."""

    @app.exception_handler(StarletteHTTPException)
    async def _http(_: Request, exc: StarletteHTTPException) -> JSONResponse:
        return JSONResponse({"error": str(exc.detail)}, status_code=exc.status_code, headers=exc.headers)

    @app.exception_handler(RequestValidationError)
    async def _invalid(_: Request, exc: RequestValidationError) -> JSONResponse:
        parts = []
        for err in exc.errors()[:10]:
            where = ".".join(str(p) for p in err.get("loc", ()) if p != "body")
            parts.append(f"{where}: {err.get('msg', 'invalid')}")
        return _error(422, "invalid request: " + "; ".join(parts))

    @app.exception_handler(ScenarioMinerError)
    async def _user(_: Request, exc: ScenarioMinerError) -> JSONResponse:
        return _error(_status_of(exc), str(exc))

    @app.exception_handler(ValueError)
    async def _value(_: Request, exc: ValueError) -> JSONResponse:
        return _error(400, str(exc))

    @app.exception_handler(Exception)
    async def _bug(_: Request, exc: Exception) -> JSONResponse:
        log.error("internal error", exc_info=exc)
        return _error(500, f"internal error ({type(exc).__name__}); the server log has the details")


def _token_check(token: str | None) -> Callable[..., None]:
    bearer = HTTPBearer(auto_error=False, description="the token given to `scenariominer serve --token`")

    def check(credentials: Annotated[HTTPAuthorizationCredentials | None, Depends(bearer)]) -> None:
        if token is None:
            return
        given = credentials.credentials if credentials is not None else ""
        if not hmac.compare_digest(given.encode(), token.encode()):
            raise HTTPException(401, "missing or wrong bearer token", headers={"WWW-Authenticate": "Bearer"})

    return check


def create_app(settings: ServerSettings, config: Config | None = None) -> FastAPI:
    """The scenario browser's application for ``settings`` (the store must exist).

    Raises:
        NotAStoreError: there is no store at ``settings.store_path``.
    """
    cfg = config or load_config(settings.config_path)
    store = api.open_existing_store(settings.store_path, cfg)
    jobs = JobManager(
        settings.jobs_db_path,
        settings.store_path,
        settings.config_path,
        workers=settings.workers,
        max_queued=settings.max_queued,
    )

    @asynccontextmanager
    async def lifespan(_: FastAPI) -> AsyncIterator[None]:
        try:
            yield
        finally:
            await asyncio.to_thread(jobs.close)

    app = FastAPI(
        title="scenariominer",
        summary="Scenario browser: logs, braking events, search, mining and jobs over the use cases.",
        version=_version(),
        lifespan=lifespan,
        responses={400: {"model": m.ErrorBody}, 401: {"model": m.ErrorBody}, 404: {"model": m.ErrorBody}},
    )
    app.state.jobs = jobs
    app.state.settings = settings
    _install_error_handlers(app)
    router = APIRouter(prefix="/api", dependencies=[Depends(_token_check(settings.token))])
    _add_read_routes(router, store, cfg, settings)
    _add_cbr_routes(router, store, cfg, settings)
    _add_job_routes(router, jobs, settings)
    app.include_router(router)
    static = resources.files("scenariominer.server") / "static"
    app.mount("/static", StaticFiles(directory=str(static)), name="static")

    @app.get("/", include_in_schema=False)
    def index() -> FileResponse:
        return FileResponse(str(static / "index.html"), headers={"Content-Security-Policy": _CSP})

    return app


#: The UI loads only its own files: no inline script, no other origin.
_CSP = (
    "default-src 'self'; img-src 'self' data: blob:; style-src 'self'; script-src 'self'; object-src 'none'"
)


def _version() -> str:
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("scenariominer")
    except PackageNotFoundError:
        return "0"


def _add_read_routes(router: APIRouter, store: Any, cfg: Config, settings: ServerSettings) -> None:
    limit = settings.max_results
    # Reads run in the thread pool; more than a few at once only contend for the cores and the GIL.
    gate = threading.BoundedSemaphore(settings.read_concurrency)
    draw_lock = threading.Lock()

    @router.get("/health", tags=["store"])
    def health() -> dict[str, str]:
        """Liveness: the server answers."""
        return {"status": "ok"}

    @router.get("/info", tags=["store"])
    def info() -> dict[str, Any]:
        """What the store holds (use case ``info``)."""
        from scenariominer.server.worker import plain

        result: dict[str, Any] = plain(api.info(store))
        return result

    @router.get("/store/check", tags=["store"])
    def store_check() -> dict[str, Any]:
        """Leftovers of killed writers and missing files (use case ``store check``; changes nothing)."""
        from scenariominer.server.worker import plain

        result: dict[str, Any] = plain(api.store_check(store.root, cfg))
        return result

    @router.get("/logs", tags=["logs"])
    def logs(
        offset: Annotated[int, Query(ge=0)] = 0, count: Annotated[int, Query(ge=1, le=limit)] = 100
    ) -> list[m.LogModel]:
        """The stored logs with their metadata and analysed events per category."""
        with gate:
            entries = api.list_logs(store)
        return [_log_model(e) for e in entries[offset : offset + count]]

    @router.get("/logs/{log_id}", tags=["logs"])
    def log_detail(log_id: Annotated[str, _id_path()]) -> m.LogModel:
        """One log's metadata."""
        for entry in api.list_logs(store):
            if entry.meta.log_id == log_id:
                return _log_model(entry)
        raise HTTPException(404, f"log {log_id!r} is not in the store")

    @router.get("/logs/{log_id}/events", tags=["events"])
    def events(log_id: Annotated[str, _id_path()]) -> list[m.EventModel]:
        """The analysed braking events of one log, in time order."""
        return [_event_model(r) for r in api.log_events(store, log_id)[:limit]]

    @router.get("/search", tags=["events"])
    def search(
        text: Annotated[
            str | None, Query(min_length=1, max_length=500, description="free-text description")
        ] = None,
        category: Annotated[str | None, Query(max_length=m.MAX_ID_CHARS)] = None,
        k: Annotated[int, Query(ge=1, le=limit)] = 50,
        min_decel_mps2: Annotated[float | None, Query(ge=0, le=100)] = None,
        max_ttc_s: Annotated[float | None, Query(ge=0, le=1000)] = None,
        sort: SortKey | None = None,
    ) -> list[m.EventModel]:
        """Braking events by category, free text and criticality (use case ``search``)."""
        from scenariominer.explain.search import SearchQuery

        query = SearchQuery(text, category or None, k, min_decel_mps2, max_ttc_s, sort)
        with gate:
            hits = api.search(store, query, cfg)
        return [_event_model(h.event, h.score) for h in hits]

    @router.get("/scene/{log_id}", tags=["events"])
    def scene(
        log_id: Annotated[str, _id_path()],
        event_id: Annotated[str | None, Query(max_length=m.MAX_ID_CHARS)] = None,
        max_timestamps: Annotated[int, Query(ge=2, le=2000)] = 400,
    ) -> m.SceneModel:
        """One scenario as arrays for the bird's-eye view: tracks, map lanes and crossings, tags."""
        with gate:
            scene = api.scene(store, api.SceneRequest(log_id, event_id, max_timestamps))
        return _scene_model(scene)

    @router.get("/show/{log_id}", tags=["events"], response_class=FileResponse)
    def show(
        log_id: Annotated[str, _id_path()],
        event_id: Annotated[str | None, Query(max_length=m.MAX_ID_CHARS)] = None,
    ) -> FileResponse:
        """The bird's-eye-view PNG of an event (use case ``show``)."""
        folder = Path(tempfile.mkdtemp(prefix="scenariominer-show-"))
        try:
            with draw_lock:  # matplotlib's pyplot is not thread-safe
                path = api.show(store, api.ShowRequest(log_id, folder / "event.png", event_id), cfg)
        except BaseException:
            shutil.rmtree(folder, ignore_errors=True)
            raise
        return FileResponse(
            str(path), media_type="image/png", background=BackgroundTask(shutil.rmtree, folder, True)
        )

    @router.get("/similar", tags=["represent"])
    def similar(
        log_id: Annotated[str, Query(min_length=1, max_length=m.MAX_ID_CHARS)],
        track_id: Annotated[str, Query(min_length=1, max_length=m.MAX_ID_CHARS)],
        t_s: Annotated[float, Query(ge=0, le=1e6)],
        k: Annotated[int, Query(ge=1, le=limit)] = 10,
    ) -> dict[str, Any]:
        """Windows whose trajectory embeddings are nearest to an agent's window (use case ``similar``)."""
        from scenariominer.server.worker import plain

        result: dict[str, Any] = plain(api.similar(store, api.SimilarRequest(log_id, track_id, t_s, k), cfg))
        return result


def _add_cbr_routes(router: APIRouter, store: Any, cfg: Config, settings: ServerSettings) -> None:
    from scenariominer.server.worker import plain

    @router.get("/cbr/cases", tags=["cbr"])
    def cbr_list(
        risk_type: Annotated[str | None, Query(max_length=m.MAX_ID_CHARS)] = None,
    ) -> list[dict[str, Any]]:
        """The stored cases (of one risk type), in id order (use case ``cbr list``)."""
        cases: list[dict[str, Any]] = plain(api.cbr_list(store, cfg, risk_type)[: settings.max_results])
        return cases

    @router.get("/cbr/cases/{case_id}", tags=["cbr"])
    def cbr_show(case_id: Annotated[str, _id_path()]) -> dict[str, Any]:
        """One stored case (use case ``cbr show``)."""
        case: dict[str, Any] = plain(api.cbr_show(store, cfg, case_id))
        return case

    @router.post("/cbr/cases", tags=["cbr"])
    def cbr_add(body: m.CbrAddBody) -> dict[str, Any]:
        """Add cases from a file inside the data roots, or an event with its manoeuvre (``cbr add``)."""
        file = confine_path(body.file, settings.data_roots) if body.file is not None else None
        request = api.CbrAddRequest(
            file, body.log_id, body.event_id, body.manoeuvre, body.justification, body.risk_type
        )
        report: dict[str, Any] = plain(api.cbr_add(store, request, cfg))
        return report

    @router.post("/cbr/cases/remove", tags=["cbr"])
    def cbr_remove(body: m.CbrRemoveBody) -> dict[str, int]:
        """Delete cases (use case ``cbr remove``); answers how many existed."""
        return {"removed": api.cbr_remove(store, cfg, body.case_ids)}


def _id_path() -> Any:
    from fastapi import Path as PathParam

    return PathParam(min_length=1, max_length=m.MAX_ID_CHARS)


def _add_job_routes(router: APIRouter, jobs: JobManager, settings: ServerSettings) -> None:
    roots = settings.data_roots

    def submit(kind: str, body: BaseModel, path_fields: tuple[str, ...] = ()) -> m.JobModel:
        params = body.model_dump(mode="json")
        for name in path_fields:
            value = params[name]
            params[name] = (
                [str(confine_path(v, roots)) for v in value]
                if isinstance(value, list)
                else str(confine_path(value, roots))
            )
        return _job_model(jobs.submit(kind, params))

    @router.post("/jobs/ingest", tags=["jobs"], status_code=202)
    def ingest(body: m.IngestJob) -> m.JobModel:
        """Ingest log sources (use case ``ingest``); paths must lie inside the data roots."""
        return submit("ingest", body, ("paths",))

    @router.post("/jobs/analyze", tags=["jobs"], status_code=202)
    def analyze(body: m.AnalyzeJob) -> m.JobModel:
        """Find, describe and classify braking events (use case ``analyze``)."""
        return submit("analyze", body)

    @router.post("/jobs/mine", tags=["jobs"], status_code=202)
    def mine(body: m.MineJob) -> m.JobModel:
        """Mine the store for a description (use case ``mine``); a given program runs in the sandbox."""
        return submit("mine", body)

    @router.post("/jobs/synth", tags=["jobs"], status_code=202)
    def synth(body: m.SynthJob) -> m.JobModel:
        """Write labelled synthetic logs (use case ``synth``) into a folder inside the data roots."""
        return submit("synth", body, ("out_dir",))

    @router.post("/jobs/embed/windows", tags=["jobs"], status_code=202)
    def embed_windows(body: m.EmbedWindowsJob) -> m.JobModel:
        """Cut trajectory windows (use case ``embed windows``)."""
        return submit("embed_windows", body)

    @router.post("/jobs/embed/train", tags=["jobs"], status_code=202)
    def embed_train(body: m.EmbedTrainJob) -> m.JobModel:
        """Train the trajectory autoencoder (use case ``embed train``)."""
        return submit("embed_train", body)

    @router.post("/jobs/embed/apply", tags=["jobs"], status_code=202)
    def embed_apply(body: m.EmbedModelJob) -> m.JobModel:
        """Embed the windows with a trained model (use case ``embed apply``)."""
        return submit("embed_apply", body)

    @router.post("/jobs/embed/cluster", tags=["jobs"], status_code=202)
    def embed_cluster(body: m.EmbedModelJob) -> m.JobModel:
        """Cluster the window embeddings (use case ``embed cluster``)."""
        return submit("embed_cluster", body)

    @router.post("/jobs/embed/plot", tags=["jobs"], status_code=202)
    def embed_plot(body: m.EmbedPlotJob) -> m.JobModel:
        """Plot the embeddings (use case ``embed plot``) into a folder inside the data roots."""
        return submit("embed_plot", body, ("out_dir",))

    @router.post("/jobs/llm-check", tags=["jobs"], status_code=202)
    def llm_check(body: m.LlmCheckJob) -> m.JobModel:
        """Check the configured model and embedder answer (use case ``llm check``)."""
        return submit("llm_check", body)

    @router.post("/jobs/eval/braking", tags=["jobs"], status_code=202)
    def eval_braking(body: m.EvalBrakingJob) -> m.JobModel:
        """Evaluate braking categories against labels (use case ``eval braking``)."""
        return submit("eval_braking", body, ("labels",))

    @router.post("/jobs/eval/mining", tags=["jobs"], status_code=202)
    def eval_mining(body: m.EvalMiningJob) -> m.JobModel:
        """Score a mining submission against ground truth (use case ``eval mining``)."""
        return submit("eval_mining", body, ("pred", "gt"))

    @router.post("/jobs/eval/nl2prog", tags=["jobs"], status_code=202)
    def eval_nl2prog(body: m.EvalNl2ProgJob) -> m.JobModel:
        """Score program generation (use case ``eval nl2prog``)."""
        return submit("eval_nl2prog", body)

    @router.post("/jobs/cbr/build", tags=["jobs"], status_code=202)
    def cbr_build(body: m.CbrBuildJob) -> m.JobModel:
        """Build the labelled synthetic case set (use case ``cbr build``)."""
        return submit("cbr_build", body)

    @router.post("/jobs/recommend", tags=["jobs"], status_code=202)
    def recommend(body: m.RecommendJob) -> m.JobModel:
        """Recommend a manoeuvre for an event (use case ``recommend``); picture at /api/jobs/{id}/picture."""
        return submit("recommend", body)

    @router.post("/jobs/eval/cbr", tags=["jobs"], status_code=202)
    def eval_cbr(body: m.EvalCbrJob) -> m.JobModel:
        """Run and score the CBR grid (use case ``eval cbr``); its picture at /api/jobs/{id}/picture."""
        return submit("eval_cbr", body)

    @router.post("/jobs/simulate/highway", tags=["jobs"], status_code=202)
    def simulate_highway(body: m.SimulateHighwayJob) -> m.JobModel:
        """Simulate highway traffic with SUMO (use case ``simulate highway``) into a data-root folder."""
        return submit("simulate_highway", body, ("out_dir",))

    @router.post("/jobs/simulate/urban", tags=["jobs"], status_code=202)
    def simulate_urban(body: m.SimulateUrbanJob) -> m.JobModel:
        """Simulate labelled braking scenarios (use case ``simulate urban``) into a data-root folder."""
        return submit("simulate_urban", body, ("out_dir",))

    @router.post("/jobs/graph/build", tags=["jobs"], status_code=202)
    def graph_build(body: m.GraphBuildJob) -> m.JobModel:
        """Describe windows, build the knowledge graph and its summaries (use case ``graph build``)."""
        return submit("graph_build", body)

    @router.post("/jobs/ask", tags=["jobs"], status_code=202)
    def ask(body: m.AskJob) -> m.JobModel:
        """Answer a question over the graph (use case ``ask``); top samples at /api/jobs/{id}/picture."""
        return submit("ask", body)

    @router.post("/jobs/eval/retrieval", tags=["jobs"], status_code=202)
    def eval_retrieval(body: m.EvalRetrievalJob) -> m.JobModel:
        """Score graph vs vector retrieval against simulator truth (use case ``eval retrieval``)."""
        return submit("eval_retrieval", body)

    @router.get("/jobs/{job_id}/picture", tags=["jobs"], response_class=FileResponse)
    def job_picture(job_id: Annotated[str, _id_path()]) -> FileResponse:
        """The picture a finished job drew.

        ``recommend``: the rollout check; ``ask``: the top samples; ``eval cbr``: the grid.
        """
        from scenariominer.server.worker import picture_path

        job = jobs.get(job_id)
        path = picture_path(settings.store_path, job.id)
        if job.state != "succeeded" or not path.is_file():
            raise HTTPException(404, f"job {job_id} has no picture")
        return FileResponse(str(path), media_type="image/png")

    @router.get("/jobs", tags=["jobs"])
    def list_jobs(count: Annotated[int, Query(ge=1, le=settings.max_results)] = 100) -> list[m.JobModel]:
        """The newest jobs, newest first."""
        return [_job_model(j) for j in jobs.recent(count)]

    @router.get("/jobs/{job_id}", tags=["jobs"])
    def job(job_id: Annotated[str, _id_path()]) -> m.JobModel:
        """One job: state, latest progress, result or error."""
        return _job_model(jobs.get(job_id))

    @router.post("/jobs/{job_id}/cancel", tags=["jobs"])
    def cancel(job_id: Annotated[str, _id_path()]) -> m.JobModel:
        """Cancel a queued or running job."""
        return _job_model(jobs.cancel(job_id))

    @router.get(
        "/jobs/{job_id}/events",
        tags=["jobs"],
        response_class=StreamingResponse,
        responses={200: {"content": {"text/event-stream": {}}, "description": "Server-Sent Events"}},
    )
    async def job_events(job_id: Annotated[str, _id_path()], request: Request) -> StreamingResponse:
        """The job's events as Server-Sent Events (``state``, ``progress``), ending with its final state."""
        jobs.get(job_id)  # 404 before the stream starts

        async def stream() -> AsyncIterator[str]:
            seq = 0
            while not await request.is_disconnected():
                events, job = await anyio.to_thread.run_sync(jobs.events_after, job_id, seq, SSE_POLL_S)
                for event in events:
                    seq = event.seq
                    yield f"id: {event.seq}\nevent: {event.type}\ndata: {json.dumps(event.data)}\n\n"
                if not events and job.state not in FINAL_STATES:
                    yield ": keep-alive\n\n"
                if job.state in FINAL_STATES and not events:
                    final = _job_model(job).model_dump_json()
                    yield f"event: end\ndata: {final}\n\n"
                    return

        return StreamingResponse(
            stream(), media_type="text/event-stream", headers={"Cache-Control": "no-cache"}
        )
