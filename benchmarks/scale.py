"""Throughput of the corpus-wide stages per executor: 1 worker against 2, and the cost per 1,000 logs.

For N synthetic Argoverse 2-format logs, each executor runs, on a fresh store:
  * ingest (read, validate, preprocess, commit),
  * analyze with the rules judge (tags, events, facts, embeddings, commit; no LLM),
  * mine with a bank program (trusted, in-process in the worker) and with a user program (sandboxed),
and the script prints seconds, logs/s and the ratio of each executor to the 1-worker process pool,
plus two baselines measured in the same run: reading every Feather file of the logs with pyarrow
(the floor of any ingest) and ``python -c pass`` (a process start). The last table projects the
cost of 1,000 logs per stage from the measured per-log time of the 2-worker pool: core-seconds per
1,000 logs and wall minutes on W workers (per-log cost × 1,000 / W, assuming the stage stays
per-log independent, which it is: one item per log, no shared state but the catalog commit).

    python benchmarks/scale.py --n 40             # local, process x1, process x2
    python benchmarks/scale.py --n 40 --ray       # and a private 2-CPU Ray cluster
    python benchmarks/scale.py --embedder default # the configured sentence-transformers embedder
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

import pyarrow.feather as feather

from scenariominer import api
from scenariominer.config import Config, load_config
from scenariominer.exec import InlineExecutor, ProcessExecutor
from scenariominer.exec.base import Executor
from scenariominer.mine.programs import load_examples

BANK = "vehicle braking hard"
SANDBOXED = "vehicle following another vehicle"
STAGES = ("ingest", "analyze", "mine (bank)", "mine (sandbox)")


def _timed(fn: Callable[[], object]) -> float:
    t = time.perf_counter()
    fn()
    return time.perf_counter() - t


def _run(root: Path, logs: Path, config: Config, executor: Executor, n: int) -> dict[str, float]:
    store = api.open_store(root, config)
    out: dict[str, float] = {}
    out["ingest"] = _timed(lambda: api.ingest([logs], store, config, executor=executor))
    assert len(store.log_ids()) == n
    request = api.AnalyzeRequest(judge="rules")
    out["analyze"] = _timed(lambda: api.analyze(store, request, config, executor=executor))
    program = next(e.program for e in load_examples(()) if e.description == SANDBOXED)
    for stage, description, text in [("mine (bank)", BANK, None), ("mine (sandbox)", SANDBOXED, program)]:
        req = api.MineRequest(description, store=store, program=text)
        out[stage] = _timed(lambda req=req: api.mine(req, config, executor=executor))  # type: ignore[misc]
    return out


def _config(work: Path, embedder: str) -> Config:
    path = work / "bench.toml"
    text = "[exec]\nmin_items = 1\n"
    if embedder == "hashing":
        text += '[embedding]\nbackend = "hashing"\nhashing_dim = 384\n'
    path.write_text(text)
    return load_config(path)


def main() -> None:
    parser = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument("--n", type=int, default=40, help="number of synthetic logs")
    parser.add_argument("--ray", action="store_true", help="also run on a private local Ray cluster (2 CPUs)")
    parser.add_argument(
        "--embedder", choices=["hashing", "default"], default="hashing",
        help="hashing: model-free (measures the pipeline); default: the configured sentence-transformers",
    )  # fmt: skip
    parser.add_argument("--workers", type=int, default=8, help="W of the projection (workers of a cluster)")
    parser.add_argument(
        "--real-log", type=Path, default=Path(__file__).resolve().parents[2] / "shared/data/av2",
        help="real Argoverse 2 log(s) whose per-log cost (in process) is compared with a synthetic log's",
    )  # fmt: skip
    args = parser.parse_args()

    work = Path(tempfile.mkdtemp(prefix="sm-bench-scale-"))
    logs = work / "logs"
    api.synth(logs, args.n, seed=3)
    config = _config(work, args.embedder)
    print(f"{args.n} synthetic logs, {os.cpu_count()} cores, embedder {args.embedder}; work folder {work}")

    files = sorted(logs.rglob("*.feather"))
    for f in files:
        feather.read_table(f)
    read_s = _timed(lambda: [feather.read_table(f) for f in files])
    start_s = _timed(lambda: subprocess.run([sys.executable, "-c", "pass"], check=True))
    print(f"baselines: raw Feather read of all logs {read_s:.3f} s; python -c pass {start_s:.3f} s\n")

    executors: list[tuple[str, Callable[[], Executor]]] = [
        ("local", InlineExecutor),
        ("process x1", lambda: ProcessExecutor(1, min_items=1)),
        ("process x2", lambda: ProcessExecutor(2, min_items=1)),
    ]
    if args.ray:
        from scenariominer.exec.ray_executor import RayExecutor

        executors.append(
            ("ray x2", lambda: RayExecutor("", 2, init_kwargs={"object_store_memory": 200 * 2**20}))
        )
    results: dict[str, dict[str, float]] = {}
    for name, make in executors:
        executor = make()
        try:
            results[name] = _run(work / name.replace(" ", "-"), logs, config, executor, args.n)
        finally:
            executor.close()
        print(f"  {name}: " + ", ".join(f"{s} {results[name][s]:.2f} s" for s in STAGES), flush=True)

    print(f"\n{'stage':<16}" + "".join(f"{n:>22}" for n in results) + f"{'x2 / x1':>10}")
    for stage in STAGES:
        cells = "".join(
            f"{results[n][stage]:>9.2f} s {args.n / results[n][stage]:>6.1f} l/s" for n in results
        )
        ratio = results["process x1"][stage] / results["process x2"][stage]
        print(f"{stage:<16}{cells}{ratio:>9.2f}x")
    total = {n: sum(r.values()) for n, r in results.items()}
    print(f"{'all stages':<16}" + "".join(f"{total[n]:>9.2f} s {'':>10}" for n in results), end="")
    print(f"{total['process x1'] / total['process x2']:>9.2f}x")
    ingest_x = results["process x2"]["ingest"] / read_s
    print(f"\ningest on process x2 / raw read of the files: {ingest_x:.1f}x")

    print(
        "\nprojection per 1,000 logs (from process x2: per-log wall time x 2 workers = core-seconds per log)"
    )
    print(f"{'stage':<16}{'core-s / 1k logs':>18}{f'wall min on {args.workers} workers':>26}")
    for stage in STAGES:
        core_s = results["process x2"][stage] * 2 / args.n * 1000
        print(f"{stage:<16}{core_s:>18.0f}{core_s / args.workers / 60:>26.1f}")
    if args.real_log.exists():
        _real_log_costs(work, args.real_log, logs, config)
    if args.ray:
        import ray

        ray.shutdown()


def _real_log_costs(work: Path, real: Path, synth: Path, config: Config) -> None:
    """Per-log ingest and rules-analysis time in process, a real log against one synthetic log (warm)."""
    one_synth = next(p for p in sorted(synth.iterdir()) if p.is_dir())
    print(f"\nper-log cost in process (warm), real log(s) under {real} against one synthetic log:")
    for name, source in [("synthetic", one_synth), ("real", real)]:
        costs = []
        for attempt in range(2):  # the first pays the imports; the second is reported
            store = api.open_store(work / f"{name}-{attempt}", config)
            t = time.perf_counter()
            api.ingest([source], store, config, executor=InlineExecutor())
            ingest_s = time.perf_counter() - t
            t = time.perf_counter()
            api.analyze(store, api.AnalyzeRequest(judge="rules"), config, executor=InlineExecutor())
            analyze_s = time.perf_counter() - t
            n_logs, n_cells = len(store.log_ids()), store.info().n_frames
            costs = [ingest_s / n_logs, analyze_s / n_logs]
        print(f"  {name:<10} {n_cells / n_logs:>8,.0f} cells/log  ingest {costs[0] * 1000:6.0f} ms/log  "
              f"analyze {costs[1] * 1000:6.0f} ms/log")  # fmt: skip


if __name__ == "__main__":
    main()
