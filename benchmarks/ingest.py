"""Ingestion throughput: N synthetic Argoverse 2-format logs into a fresh store.

Prints seconds, logs/s/core and frames/s, as ratios to the raw Feather read of the same files
(pyarrow reading every ``.feather`` file, the floor any ingest pays) measured in the same run
(a second floor also parses each log's vector-map JSON, which an ingest must read to validate), for
  * a cold ingest: ``scenariominer ingest`` in a fresh process (start-up and imports included),
  * reading + validating + preprocessing every log in memory (no store writes),
  * a warm ingest into a fresh store in this process (read, preprocess, Parquet writes, catalog),
    the best of three runs (as the in-memory pass; single passes vary by a third here), and the
    same with a process pool (wall-clock seconds; logs/s/core divides by every core),
  * an incremental re-ingest of the unchanged set (content hashing only),
the peak memory of this process and of the cold ingest, and the process CPU time per log of each
step (read, preprocess, store), which varies far less than wall-clock seconds on a busy machine.

    python benchmarks/ingest.py --n 50
    python benchmarks/ingest.py --n 50 --copies-of ../shared/data/av2/3b3570b4-7b0b-3268-a571-b0889dbf40b6

``--copies-of LOG`` ingests N copies of a real Argoverse 2 log (each under its own log id) instead
of synthetic logs: a real log holds about 14 times the rows of a synthetic one (13,820 against
about 950), so per-log fixed costs weigh less and the per-row work shows.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import shutil
import subprocess
import sys
import tempfile
import time
import uuid
from collections.abc import Callable
from pathlib import Path

import pyarrow.feather as feather

from scenariominer import api
from scenariominer.config import Config
from scenariominer.data.ingest import _BATCH_SOURCES
from scenariominer.data.preprocess import preprocess
from scenariominer.data.sources import discover_sources, reader_for
from scenariominer.exec import make_executor


def _rate(count: float, seconds: float) -> str:
    return f"{count / seconds:10,.1f}" if seconds > 0 else "       inf"


def _best_of(n: int, run: Callable[[], object], clock: Callable[[], float] = time.perf_counter) -> float:
    """The shortest of ``n`` calls of ``run`` timed by ``clock`` (seconds)."""
    times = []
    for _ in range(n):
        t = clock()
        run()
        times.append(clock() - t)
    return min(times)


def _copy_log(log_dir: Path, out: Path, n: int) -> None:
    """``n`` copies of an AV2 log folder, each renamed (folder and map files) to a new log id."""
    for i in range(n):
        log_id = str(uuid.UUID(int=i + 1))
        target = out / log_id
        shutil.copytree(log_dir, target)
        for f in (target / "map").iterdir():
            f.rename(f.with_name(f.name.replace(log_dir.name, log_id)))


def main() -> None:
    parser = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument("--n", type=int, default=50, help="number of synthetic logs")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--keep", type=Path, default=None, help="keep data and store in this folder")
    parser.add_argument("--copies-of", type=Path, default=None, help="a real AV2 log folder to copy N times")
    args = parser.parse_args()

    work = args.keep or Path(tempfile.mkdtemp(prefix="sm-bench-ingest-"))
    data = work / "logs"
    t = time.perf_counter()
    if args.copies_of is not None:
        _copy_log(args.copies_of, data, args.n)
        print(f"copied {args.copies_of.name} {args.n} times in {time.perf_counter() - t:.1f} s (not timed)")
    else:
        api.synth(data, args.n, seed=args.seed)
        print(f"generated {args.n} synthetic logs in {time.perf_counter() - t:.1f} s (not timed below)")
    config = Config()

    # The floor: pyarrow reading every Feather file, warm page cache, the fastest of 5 passes (a
    # single pass of 50-100 ms varies by half between runs, and every ratio below divides by it).
    files = sorted(data.rglob("*.feather"))
    for f in files:
        feather.read_table(f)
    passes = []
    for _ in range(5):
        t = time.perf_counter()
        for f in files:
            feather.read_table(f)
        passes.append(time.perf_counter() - t)
    raw_s = min(passes)
    # Every file a log consists of, read and parsed: the Feather tables plus the vector-map JSON
    # (an ingest validates the map, so it must at least parse it).
    maps = sorted(data.rglob("log_map_archive_*.json"))
    t = time.perf_counter()
    for f in files:
        feather.read_table(f)
    for m in maps:
        json.loads(m.read_bytes())
    raw_all_s = time.perf_counter() - t

    # Cold: the command in a fresh process, as a user runs it.
    exe = Path(sys.executable).parent / "scenariominer"
    t = time.perf_counter()
    cold = subprocess.run(
        ["/usr/bin/time", "-f", "%M", str(exe), "ingest", str(data), "--store", str(work / "cold"), "--json"],
        capture_output=True, text=True, check=True,
    )  # fmt: skip
    cold_s = time.perf_counter() - t
    cold_peak_mb = int(cold.stderr.strip().splitlines()[-1]) / 1024
    assert json.loads(cold.stdout)["store"]["n_logs"] == args.n

    # Adapter + preprocessing only: one pass warms this process's imports and caches, then the
    # best of three (single passes vary by a third on a shared 2-core machine).
    def read_and_preprocess() -> int:
        count = 0
        for src in discover_sources([data]):
            for log in reader_for(src).read(src, config):
                count += preprocess(log, config.preprocess).n_frames
        return count

    frames = read_and_preprocess()
    base_s = _best_of(3, read_and_preprocess)

    # Warm ingest into a fresh store each time, the best of three.
    stores = iter(range(3))

    def ingest_fresh() -> api.IngestReport:
        report = api.ingest([data], api.open_store(work / f"store{next(stores)}"), config)
        assert report.n_ingested == args.n, report.failed
        return report

    full_s = _best_of(3, ingest_fresh)

    # The same with a process pool of one worker per core (what a large batch gets by default;
    # worker start-up included, so small batches gain little).
    def ingest_pool() -> None:
        pool = make_executor(config.exec, "process")
        try:
            report = api.ingest([data], api.open_store(work / f"store{next(stores)}"), config, executor=pool)
        finally:
            pool.close()
        assert report.n_ingested == args.n, report.failed

    stores = iter(range(3, 6))
    pool_s = _best_of(3, ingest_pool)

    t = time.perf_counter()
    report = api.ingest([data], api.open_store(work / "store0"), config)
    skip_s = time.perf_counter() - t
    assert report.n_skipped == args.n

    steps = _cpu_per_step(data, config, work / "steps")

    peak_mb = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    cores = len(os.sched_getaffinity(0))
    print(f"{'stage':<38}{'seconds':>9}{'logs/s/core':>13}{'frames/s':>13}{'vs raw read':>13}")
    rows = [
        ("raw Feather read (pyarrow)", raw_s),
        ("raw read of every file (+ map JSON)", raw_all_s),
        ("cold ingest (fresh process, CLI)", cold_s),
        ("read + preprocess in memory", base_s),
        ("warm ingest into a fresh store", full_s),
        (f"  the same, {config.exec.workers or cores} worker processes", pool_s),
        ("re-ingest unchanged (skip)", skip_s),
    ]
    for name, sec in rows:
        per_core = _rate(args.n / cores, sec)
        print(f"{name:<38}{sec:9.2f}{per_core:>13}{_rate(frames, sec):>13}{sec / raw_s:12.1f}x")
    print(
        f"frames: {frames:,}  store size: {report.store.size_bytes / 1e6:.1f} MB  cores: {cores}  "
        f"peak RSS: this process {peak_mb:,.0f} MB, cold ingest {cold_peak_mb:,.0f} MB"
    )
    print(
        "CPU ms per log, best of 5 (robust to a busy machine): "
        + ", ".join(f"{name} {ms:.1f}" for name, ms in steps.items())
    )
    print(f"data and store in {work}")


def _cpu_per_step(data: Path, config: Config, out: Path) -> dict[str, float]:
    """Process CPU milliseconds per log of each ingest step, the best of 5 passes each.

    Wall-clock seconds on a shared machine vary by up to a half within minutes; CPU time of this
    process varies far less, so a change to one step shows here first.
    """
    sources = discover_sources([data])

    def best_ms(run: Callable[[], object]) -> float:
        return _best_of(5, run, time.process_time) * 1e3 / len(sources)

    raws = [log for src in sources for log in reader_for(src).read(src, config)]
    logs = [preprocess(log, config.preprocess) for log in raws]
    stores = iter(range(5))

    def store_all() -> None:
        # as the ingest loop commits when reading runs ahead of the writer: batches of sources
        store = api.open_store(out / str(next(stores)))
        items = [(src.key, "benchmark", [log]) for src, log in zip(sources, logs, strict=True)]
        for start in range(0, len(items), _BATCH_SOURCES):
            store.replace_sources(items[start : start + _BATCH_SOURCES])

    return {
        "read": best_ms(lambda: [log for src in sources for log in reader_for(src).read(src, config)]),
        "preprocess": best_ms(lambda: [preprocess(log, config.preprocess) for log in raws]),
        "store": best_ms(store_all),
    }


if __name__ == "__main__":
    main()
