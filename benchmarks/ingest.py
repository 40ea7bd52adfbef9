"""Ingestion throughput: N synthetic Argoverse 2-format logs into a fresh store.

Prints logs/s and frames/s for
  * the baseline: reading + validating + preprocessing every log in memory (no store writes),
  * a full ingest into a fresh store (read, preprocess, atomic Parquet writes, catalog),
  * an incremental re-ingest of the unchanged set (content hashing only),
with ratios against the baseline measured in the same run, and the process's peak memory.

    python benchmarks/ingest.py --n 50
"""

from __future__ import annotations

import argparse
import resource
import tempfile
import time
from pathlib import Path

from scenariominer import api
from scenariominer.config import Config
from scenariominer.data.preprocess import preprocess
from scenariominer.data.sources import discover_sources, reader_for


def _rate(count: float, seconds: float) -> str:
    return f"{count / seconds:10,.1f}" if seconds > 0 else "       inf"


def main() -> None:
    parser = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument("--n", type=int, default=50, help="number of synthetic logs")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--keep", type=Path, default=None, help="keep data and store in this folder")
    args = parser.parse_args()

    work = args.keep or Path(tempfile.mkdtemp(prefix="sm-bench-ingest-"))
    data = work / "synth"
    t = time.perf_counter()
    api.synth(data, args.n, seed=args.seed)
    print(f"generated {args.n} logs in {time.perf_counter() - t:.1f} s (not timed below)")
    config = Config()

    # Baseline: adapter + preprocessing only.
    t = time.perf_counter()
    frames = 0
    sources = discover_sources([data])
    for src in sources:
        for log in reader_for(src).read(src, config):
            frames += preprocess(log, config.preprocess).n_frames
    base_s = time.perf_counter() - t

    store = api.open_store(work / "store")
    t = time.perf_counter()
    report = api.ingest([data], store, config)
    full_s = time.perf_counter() - t
    assert report.n_ingested == args.n, report.failed

    t = time.perf_counter()
    again = api.ingest([data], store, config)
    skip_s = time.perf_counter() - t
    assert again.n_skipped == args.n

    peak_mb = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print(f"{'stage':<34}{'seconds':>9}{'logs/s':>11}{'frames/s':>13}{'vs baseline':>13}")
    rows = [
        ("baseline: read+preprocess (memory)", base_s, base_s),
        ("ingest into fresh store", full_s, base_s),
        ("re-ingest unchanged (skip)", skip_s, base_s),
    ]
    for name, sec, ref in rows:
        print(f"{name:<34}{sec:9.2f}{_rate(args.n, sec):>11}{_rate(frames, sec):>13}{sec / ref:12.2f}x")
    print(
        f"frames: {frames:,}  store size: {report.store.size_bytes / 1e6:.1f} MB  peak RSS: {peak_mb:,.0f} MB"
    )
    print(f"data and store in {work}")


if __name__ == "__main__":
    main()
