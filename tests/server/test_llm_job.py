"""A mining job whose program the real embedded model writes, through the server (slow)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import httpx
import pytest


@pytest.mark.slow
def test_mine_job_with_the_embedded_model(servers: Any, built_store: Any, tmp_path: Path) -> None:
    # One model answer at most: the job ends with a program or under manual review either way.
    config = tmp_path / "config.toml"
    config.write_text(built_store.config.read_text() + "[mining.generation]\nmax_attempts = 1\n")
    with (
        servers.start(servers.settings(config_path=config)) as server,
        httpx.Client(base_url=server.url) as c,
    ):
        _run(c)


def _run(client: httpx.Client) -> None:
    # "lingering" is no phrase the rules know: the model reads the description and writes the program
    body = {"description": "a pedestrian lingering near the ego vehicle", "use_bank": False}
    job = client.post("/api/jobs/mine", json=body).json()
    final: dict[str, Any] = {}
    with client.stream("GET", f"/api/jobs/{job['id']}/events", timeout=1800) as resp:
        for line in resp.iter_lines():
            if line.startswith("data: ") and '"kind"' in line:
                final = json.loads(line[6:])
    assert final["state"] == "succeeded", final["error"]
    result = final["result"]
    assert result["source"] == "generated"
    if result["status"] == "ok":  # the model's program ran in the sandbox on every log
        assert result["program"] and "output_scenario" in result["program"]
        assert result["summary"]["n_logs"] == 4
        logs = {log["log_id"] for log in client.get("/api/logs").json()}
        assert {o["log_id"] for o in result["referred_objects"]} <= logs
    else:  # the loop gave up: no program, flagged for review
        assert result["status"] == "manual_review" and result["program"] is None
