"""Load test of the scenario browser: concurrent searches against a real `scenariominer serve`.

Builds a synthetic store (``--logs`` labelled logs, ingested and analysed by the rules), starts the
server as a subprocess on loopback, answers every query once sequentially (the baseline, and the
expected answer), then fires ``--concurrency`` searches at once with httpx and prints p50/p95/max
latency, throughput, errors and answers that differ from the sequential ones (nothing may be lost).

Queries mix the category path, criticality filters, sorting and free text (the configured
``hashing`` embedder, so the figure is the server's, not an embedding model's).

    .venv/bin/python benchmarks/server_load.py --logs 24 --concurrency 50 --rounds 3
"""

from __future__ import annotations

import argparse
import asyncio
import socket
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

import httpx
import numpy as np

from scenariominer import api
from scenariominer.config import load_config


def build_store(base: Path, n_logs: int) -> tuple[Path, Path]:
    config = base / "config.toml"
    config.write_text(
        f'[embedding]\nbackend = "hashing"\ncache_dir = "{base / "cache"}"\n'
        f'[llm]\ncache_dir = "{base / "cache"}"\n',
        encoding="utf-8",
    )
    cfg = load_config(config)
    api.synth(base / "synth", n_logs, seed=1)
    store = api.open_store(base / "store", cfg)
    api.ingest([base / "synth"], store, cfg)
    api.analyze(store, api.AnalyzeRequest(judge="rules"), cfg)
    return store.root, config


def start_server(store: Path, config: Path) -> tuple[subprocess.Popen[bytes], str]:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    exe = str(Path(sys.executable).with_name("scenariominer"))
    cmd = [exe, "serve", "--store", str(store), "--config", str(config), "--port", str(port)]
    proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    url = f"http://127.0.0.1:{port}"
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline:
        try:
            if httpx.get(url + "/api/health", timeout=1).status_code == 200:
                return proc, url
        except httpx.TransportError:
            time.sleep(0.2)
    proc.kill()
    raise SystemExit("the server did not start")


def queries(categories: list[str], n: int) -> list[dict[str, Any]]:
    kinds: list[dict[str, Any]] = [{"k": 100}]
    kinds += [{"category": c, "k": 100} for c in categories]
    kinds += [{"min_decel_mps2": 1.0, "sort": "decel", "k": 50}, {"max_ttc_s": 3.0, "sort": "ttc", "k": 50}]
    kinds += [
        {"text": t, "k": 10} for t in ("a car cuts in front", "pedestrian crossing", "lead vehicle brakes")
    ]
    return [kinds[i % len(kinds)] for i in range(n)]


async def run_one(client: httpx.AsyncClient, params: dict[str, Any]) -> tuple[float, int, list[str]]:
    t0 = time.perf_counter()
    resp = await client.get("/api/search", params=params)
    dt = time.perf_counter() - t0
    ids = [h["event_id"] for h in resp.json()] if resp.status_code == 200 else []
    return dt, resp.status_code, ids


async def load(url: str, batch: list[dict[str, Any]]) -> tuple[list[tuple[float, int, list[str]]], float]:
    limits = httpx.Limits(max_connections=len(batch), max_keepalive_connections=len(batch))
    async with httpx.AsyncClient(base_url=url, timeout=120, limits=limits) as client:
        t0 = time.perf_counter()
        results = await asyncio.gather(*(run_one(client, q) for q in batch))
        return list(results), time.perf_counter() - t0


def main() -> None:
    parser = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument("--logs", type=int, default=24, help="synthetic logs in the store")
    parser.add_argument("--concurrency", type=int, default=50, help="searches fired at once")
    parser.add_argument("--rounds", type=int, default=3, help="bursts of --concurrency searches")
    args = parser.parse_args()

    with tempfile.TemporaryDirectory(prefix="scenariominer-load-") as tmp:
        store, config = build_store(Path(tmp), args.logs)
        proc, url = start_server(store, config)
        try:
            with httpx.Client(base_url=url, timeout=120) as c:
                logs = c.get("/api/logs").json()
                categories = sorted({k for log in logs for k in log["event_categories"]})
                batch = queries(categories, args.concurrency)
                expected, sequential = {}, []
                for q in batch:  # one at a time: the baseline latency and the expected answers
                    t0 = time.perf_counter()
                    resp = c.get("/api/search", params=q)
                    sequential.append(time.perf_counter() - t0)
                    expected[repr(sorted(q.items()))] = [h["event_id"] for h in resp.json()]
            latencies: list[float] = []
            errors = mismatches = 0
            wall = 0.0
            for _ in range(args.rounds):
                results, seconds = asyncio.run(load(url, batch))
                wall += seconds
                for q, (dt, status, ids) in zip(batch, results, strict=True):
                    latencies.append(dt)
                    errors += status != 200
                    mismatches += status == 200 and ids != expected[repr(sorted(q.items()))]
        finally:
            proc.terminate()
            proc.wait(timeout=60)

    events = sum(log["n_events"] for log in logs)
    lat_ms = np.array(latencies) * 1e3
    seq_ms = np.array(sequential) * 1e3
    n = len(latencies)
    p50, p95 = np.percentile(lat_ms, 50), np.percentile(lat_ms, 95)
    distinct = len(set(map(repr, batch)))
    print(f"store: {len(logs)} synthetic logs, {events} braking events; {distinct} distinct queries")
    s50, s95 = np.percentile(seq_ms, 50), np.percentile(seq_ms, 95)
    print(f"sequential (baseline): p50 {s50:.1f} ms, p95 {s95:.1f} ms")
    print(
        f"{args.concurrency} concurrent x {args.rounds} rounds ({n} searches): p50 {p50:.1f} ms, "
        f"p95 {p95:.1f} ms, max {lat_ms.max():.1f} ms; {n / wall:.1f} searches/s"
    )
    print(f"p50 ratio concurrent/sequential: {p50 / s50:.1f}x")
    print(f"errors: {errors}; answers different from the sequential ones: {mismatches}")
    if errors or mismatches:
        raise SystemExit(1)


if __name__ == "__main__":
    main()
