"""The HTTP API against a real uvicorn server on loopback over a small real store."""

from __future__ import annotations

import json
import time
from typing import Any

import httpx
import pytest

from scenariominer import api
from scenariominer.config import load_config

MINE_PROGRAM = (
    'vehicles = get_objects_of_category(log_dir, category="VEHICLE")\n'
    "output_scenario(vehicles, description, log_dir, output_dir)\n"
)


def _events(client: httpx.Client, job_id: str) -> list[tuple[str, dict[str, Any]]]:
    """Every Server-Sent Event of a job until its ``end`` event."""
    out: list[tuple[str, dict[str, Any]]] = []
    with client.stream("GET", f"/api/jobs/{job_id}/events", timeout=120) as resp:
        assert resp.status_code == 200
        assert resp.headers["content-type"].startswith("text/event-stream")
        kind, data = "message", ""
        for line in resp.iter_lines():
            if line.startswith("event: "):
                kind = line[7:]
            elif line.startswith("data: "):
                data += line[6:]
            elif line == "" and data:
                out.append((kind, json.loads(data)))
                if kind == "end":
                    break
                kind, data = "message", ""
    return out


def _wait_state(client: httpx.Client, job_id: str, states: set[str], timeout_s: float = 60) -> dict[str, Any]:
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        job: dict[str, Any] = client.get(f"/api/jobs/{job_id}").json()
        if job["state"] in states:
            return job
        time.sleep(0.1)
    raise AssertionError(f"job {job_id} never reached {states}")


def test_logs_list_matches_the_store(
    client: httpx.Client, built_store: Any, hostile_ids: tuple[str, str]
) -> None:
    logs = client.get("/api/logs").json()
    store = api.open_existing_store(built_store.root, load_config(built_store.config))
    assert sorted(log["log_id"] for log in logs) == sorted(store.log_ids())
    assert hostile_ids[0] in {log["log_id"] for log in logs}  # returned verbatim, not mangled
    synth = [log for log in logs if log["dataset"] == "av2"]
    assert len(synth) == 3 and all(log["has_map"] for log in synth)
    assert sum(log["n_events"] for log in logs) == len(store.read_table("events"))


def test_search_by_category_and_criticality(client: httpx.Client) -> None:
    everything = client.get("/api/search", params={"k": 500}).json()
    assert everything, "the synthetic logs have braking events"
    category = everything[0]["category"]
    hits = client.get("/api/search", params={"category": category}).json()
    assert hits and all(h["category"] == category for h in hits)
    threshold = sorted(h["peak_decel_mps2"] for h in everything)[len(everything) // 2]
    hard = client.get("/api/search", params={"min_decel_mps2": threshold, "k": 500}).json()
    assert {h["event_id"] for h in hard} == {
        h["event_id"] for h in everything if h["peak_decel_mps2"] >= threshold
    }
    by_ttc = client.get("/api/search", params={"sort": "ttc", "k": 500}).json()
    ttcs = [h["min_ttc_s"] for h in by_ttc if h["min_ttc_s"] is not None]
    assert ttcs == sorted(ttcs)


def test_free_text_search_ranks_by_score(client: httpx.Client) -> None:
    hits = client.get("/api/search", params={"text": "a vehicle cuts in front of the ego", "k": 3}).json()
    assert 1 <= len(hits) <= 3
    scores = [h["score"] for h in hits]
    assert all(s is not None for s in scores) and scores == sorted(scores, reverse=True)


def test_scene_has_tracks_map_and_tags_of_the_event(client: httpx.Client) -> None:
    hit = client.get("/api/search", params={"k": 1}).json()[0]
    scene = client.get(f"/api/scene/{hit['log_id']}", params={"event_id": hit["event_id"]}).json()
    n, t = len(scene["track_ids"]), len(scene["t_s"])
    assert n >= 2 and t >= 2
    assert all(len(row) == t for row in scene["x_m"]) and len(scene["x_m"]) == n
    assert scene["track_ids"][scene["key_index"]] == hit["guest_id"]
    assert scene["categories"][scene["ego_index"]] == "EGO_VEHICLE"
    assert scene["lanes"], "synthetic AV2 logs carry a vector map"
    assert scene["event"]["event_id"] == hit["event_id"]
    assert set(scene["tags"]) >= {"longitude", "collision", "position", "ego_longitude"}
    assert all(len(v) == t for v in scene["tags"].values())
    start_ns, end_ns = scene["timestamps_ns"][0], scene["timestamps_ns"][-1]
    assert start_ns <= hit["start_ns"] <= hit["end_ns"] <= end_ns


def test_show_returns_the_png_of_the_use_case(client: httpx.Client) -> None:
    hit = client.get("/api/search", params={"k": 1}).json()[0]
    resp = client.get(f"/api/show/{hit['log_id']}", params={"event_id": hit["event_id"]})
    assert resp.status_code == 200 and resp.headers["content-type"] == "image/png"
    assert resp.content[:8] == b"\x89PNG\r\n\x1a\n"


@pytest.mark.parametrize(
    ("path", "params", "status", "needle"),
    [
        ("/api/logs/no-such-log/events", {}, 404, "no-such-log"),
        ("/api/scene/no-such-log", {}, 404, "no-such-log"),
        ("/api/search", {"k": 0}, 422, "k"),
        ("/api/search", {"text": "x" * 501}, 422, "text"),
        ("/api/jobs/feedface", {}, 404, "feedface"),
    ],
)
def test_errors_are_json_messages(
    client: httpx.Client, path: str, params: dict[str, Any], status: int, needle: str
) -> None:
    resp = client.get(path, params=params)
    assert resp.status_code == status
    body = resp.json()
    assert set(body) == {"error"} and needle in body["error"]
    assert "Traceback" not in body["error"]


def test_unknown_event_of_a_known_log_is_404(client: httpx.Client) -> None:
    log_id = client.get("/api/search", params={"k": 1}).json()[0]["log_id"]
    resp = client.get(f"/api/scene/{log_id}", params={"event_id": "nope"})
    assert resp.status_code == 404 and "nope" in resp.json()["error"]


def test_oversized_and_unknown_fields_are_refused(client: httpx.Client) -> None:
    resp = client.post("/api/jobs/mine", json={"description": "x" * 2001})
    assert resp.status_code == 422 and "description" in resp.json()["error"]
    resp = client.post("/api/jobs/analyze", json={"llm": False, "rm_rf": True})
    assert resp.status_code == 422 and "rm_rf" in resp.json()["error"]
    resp = client.post("/api/jobs/ingest", json={"paths": ["a"] * 65})
    assert resp.status_code == 422


def test_paths_outside_the_data_roots_are_refused(client: httpx.Client, built_store: Any) -> None:
    n_jobs = len(client.get("/api/jobs").json())
    resp = client.post("/api/jobs/ingest", json={"paths": ["/etc"]})
    assert resp.status_code == 403 and "outside" in resp.json()["error"]
    escape = built_store.data_root / "escape"
    if not escape.exists():
        escape.symlink_to("/etc")
    resp = client.post("/api/jobs/ingest", json={"paths": [str(escape)]})  # a link out of the root
    assert resp.status_code == 403
    resp = client.post("/api/jobs/synth", json={"out_dir": str(built_store.data_root / ".." / "out"), "n": 1})
    assert resp.status_code == 403
    assert len(client.get("/api/jobs").json()) == n_jobs  # nothing was queued


def test_analyze_job_streams_progress_over_sse(client: httpx.Client) -> None:
    job = client.post("/api/jobs/analyze", json={"llm": False, "force": True}).json()
    assert job["state"] == "queued"
    events = _events(client, job["id"])
    kinds = [k for k, _ in events]
    states = [d["state"] for k, d in events if k == "state"]
    assert states[0] == "queued" and "running" in states and states[-1] == "succeeded"
    progress = [d for k, d in events if k == "progress" and d["step"] == "analyze"]
    done = [p["done"] for p in progress]
    assert done == sorted(done) and done[-1] == progress[0]["total"] == 4  # the four logs
    assert kinds[-1] == "end" and events[-1][1]["result"]["fingerprint"]


def test_mine_job_runs_a_given_program_in_the_sandbox(client: httpx.Client) -> None:
    job = client.post("/api/jobs/mine", json={"description": "any vehicle", "program": MINE_PROGRAM}).json()
    final = _events(client, job["id"])[-1][1]
    assert final["state"] == "succeeded", final["error"]
    result = final["result"]
    assert result["program"] == MINE_PROGRAM and result["source"] == "given"
    categories = {o["category"] for o in result["referred_objects"]}
    assert "REGULAR_VEHICLE" in categories and "PEDESTRIAN" not in categories  # the logs hold both
    assert set(result["stored_logs"]) >= {o["log_id"] for o in result["referred_objects"]}


def test_a_program_escaping_the_sandbox_fails_that_job_only(client: httpx.Client, tmp_path: Any) -> None:
    marker = tmp_path / "pwned"
    program = f"import os\nos.system('touch {marker}')\n"
    job = client.post("/api/jobs/mine", json={"description": "escape", "program": program}).json()
    final = _events(client, job["id"])[-1][1]
    assert final["state"] == "failed"  # refused by the sandbox's checks before any log, once
    assert "the program was not run" in final["error"] and "import" in final["error"]
    assert not marker.exists()
    assert client.get("/api/health").json() == {"status": "ok"}


def test_cancel_a_running_job(client: httpx.Client, built_store: Any) -> None:
    out = built_store.data_root / "cancelled-synth"
    job = client.post("/api/jobs/synth", json={"out_dir": str(out), "n": 1000}).json()
    _wait_state(client, job["id"], {"running"})
    cancelled = client.post(f"/api/jobs/{job['id']}/cancel").json()
    assert cancelled["state"] in {"running", "cancelled"}
    final = _wait_state(client, job["id"], {"cancelled", "succeeded", "failed"})
    assert final["state"] == "cancelled"
    assert len(list(out.glob("*"))) < 1000


def test_openapi_covers_the_use_cases(client: httpx.Client) -> None:
    from scenariominer.server.use_cases import NOT_SERVED, USE_CASE_ROUTES

    schema = client.get("/openapi.json").json()
    operations = {(method.upper(), path) for path, item in schema["paths"].items() for method in item}
    for use_case, route in USE_CASE_ROUTES.items():
        assert route in operations, f"use case {use_case} has no route {route}"
    functions = {n for n in api.__all__ if n[0].islower()}
    assert functions <= set(USE_CASE_ROUTES) | set(NOT_SERVED), (
        functions - set(USE_CASE_ROUTES) - set(NOT_SERVED)
    )


def test_case_base_add_list_show_remove(client: httpx.Client) -> None:
    hit = client.get("/api/search", params={"k": 1}).json()[0]
    body = {"log_id": hit["log_id"], "event_id": hit["event_id"], "manoeuvre": "emergency_braking"}
    added = client.post("/api/cbr/cases", json=body | {"justification": "<b>brake</b>"}).json()
    assert len(added["added"]) == 1, added
    case_id = added["added"][0]
    listed = client.get("/api/cbr/cases").json()
    assert case_id in {c["case_id"] for c in listed}
    case = client.get(f"/api/cbr/cases/{case_id}").json()
    assert case["event_id"] == hit["event_id"] and case["manoeuvre"] == "emergency_braking"
    assert case["justification"] == "<b>brake</b>"
    bad = client.post("/api/cbr/cases", json=body | {"manoeuvre": "teleport"})
    assert bad.status_code == 200 and not bad.json()["added"]  # the batch answers; the case is rejected
    assert "teleport" in bad.json()["rejected"][0][1]
    outside = client.post("/api/cbr/cases", json={"file": "/etc/passwd"})
    assert outside.status_code == 403
    assert client.post("/api/cbr/cases/remove", json={"case_ids": [case_id]}).json() == {"removed": 1}
    assert case_id not in {c["case_id"] for c in client.get("/api/cbr/cases").json()}


def test_graph_build_and_ask_jobs_rank_windows_and_draw_them(client: httpx.Client) -> None:
    # windows of the synthetic AV2 logs, their graph (no LLM summaries), then a ranked question
    for path, body in (
        ("/api/jobs/embed/windows", {}),
        ("/api/jobs/graph/build", {"summaries": False}),
    ):
        job = client.post(path, json=body).json()
        done = _wait_state(client, job["id"], {"succeeded", "failed"}, timeout_s=300)
        assert done["state"] == "succeeded", done["error"]
    built = done["result"]
    assert built["n_samples"] > 0 and built["n_llm_calls"] == 0
    job = client.post(
        "/api/jobs/ask", json={"question": "the ego brakes behind a car", "k": 2, "answer": False}
    )
    done = _wait_state(client, job.json()["id"], {"succeeded", "failed"}, timeout_s=120)
    assert done["state"] == "succeeded", done["error"]
    samples = done["result"]["result"]["samples"]
    assert [s["rank"] for s in samples] == [1, 2]
    assert done["result"]["result"]["llm_status"] == "no model"
    picture = client.get(f"/api/jobs/{job.json()['id']}/picture")
    assert picture.status_code == 200 and picture.content[:8] == b"\x89PNG\r\n\x1a\n"
    refused = client.post("/api/jobs/ask", json={"question": "x", "k": 0})
    assert refused.status_code == 422


def test_simulate_urban_job_writes_a_labelled_log_inside_the_data_roots(
    client: httpx.Client, built_store: Any
) -> None:
    outside = client.post("/api/jobs/simulate/urban", json={"out_dir": "/tmp/elsewhere", "n": 1})
    assert outside.status_code == 403
    assert client.post("/api/jobs/simulate/highway", json={"out_dir": "/etc/x"}).status_code == 403
    assert client.post("/api/jobs/simulate/urban", json={"out_dir": "x", "noise": "loud"}).status_code == 422
    out = built_store.data_root / "sumo-urban"
    job = client.post("/api/jobs/simulate/urban", json={"out_dir": str(out), "n": 1, "noise": "none"}).json()
    done = _wait_state(client, job["id"], {"succeeded", "failed"}, timeout_s=300)
    assert done["state"] == "succeeded", done["error"]
    assert (out / "labels.csv").is_file()
    assert len((out / "labels.csv").read_text().strip().splitlines()) == 2  # header + one log
