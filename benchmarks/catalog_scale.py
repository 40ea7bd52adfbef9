"""Store at scale: catalog queries on stores of 100, 1,000 and 10,000 tiny synthetic logs.

One store is grown to each size in turn (every log its own source by default, as one writer per log
would write it, plus a small derived ``events`` table per log); the build rate (logs/s) is printed
per step. At each size, every query below is timed (median of ``--repeats`` after one warm-up call,
warm page cache):

  log_ids(), info(), log_meta(one id), load_log(one id), read_table("events", [one id]),
  read_table("events") over every log, sql("SELECT count(*) FROM events"),
  sql(... FROM meta ...) over every log's metadata.

The table gives the time at each size, the ratio 10k/100 (about 1 for a query that looks up one log,
about 100 for one that reads every log) and the 10k time as a multiple of two floors measured in the
same run: one raw ``pyarrow.parquet.read_table`` of a log's tracks file and one SQLite primary-key
lookup in the catalog (fresh connection). ``python -c pass`` start-up is printed for scale.

    .venv/bin/python benchmarks/catalog_scale.py                 # 100, 1000, 10000 (a few minutes)
    .venv/bin/python benchmarks/catalog_scale.py --quick         # 100, 1000
    .venv/bin/python benchmarks/catalog_scale.py --sizes 100 2000 --workers 2 --out /tmp/cat
"""

from __future__ import annotations

import argparse
import contextlib
import os
import shutil
import sqlite3
import statistics
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from concurrent.futures import ProcessPoolExecutor
from multiprocessing import get_context
from pathlib import Path
from typing import Any

import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq

from scenariominer.data.log import Log, build_log
from scenariominer.store import ScenarioStore

T0_NS = 1_700_000_000_000_000_000
DT_NS = 100_000_000
N_FRAMES = 5
CATEGORIES = ("REGULAR_VEHICLE", "PEDESTRIAN", "BICYCLIST")


def log_id(i: int) -> str:
    return f"log-{i:06d}"


def tiny_log(i: int) -> Log:
    """Ego plus one road user over ``N_FRAMES`` frames (a second one on every third log)."""
    n_tracks = 3 if i % 3 == 0 else 2
    frames = np.arange(N_FRAMES)
    tid, cat, ts, x, y = [], [], [], [], []
    for k in range(n_tracks):
        tid += ["ego" if k == 0 else f"t{k}"] * N_FRAMES
        cat += ["EGO_VEHICLE" if k == 0 else CATEGORIES[(i + k) % len(CATEGORIES)]] * N_FRAMES
        ts += (T0_NS + i * 10**9 + frames * DT_NS).tolist()
        x += (10.0 * k + (1.0 + 0.1 * k) * frames + i % 7).tolist()
        y += [3.5 * k] * N_FRAMES
    n = len(tid)
    return build_log(
        log_id=log_id(i),
        track_id=tid,
        category=cat,
        timestamp_ns=ts,
        fields={
            "x_m": np.asarray(x),
            "y_m": np.asarray(y),
            "yaw_rad": np.zeros(n),
            "length_m": np.full(n, 4.5),
            "width_m": np.full(n, 1.9),
        },
        ego_track_id="ego",
        source=f"<bench {i}>",
        dataset="synthetic",
    )


def events(i: int) -> pa.Table:
    n = 1 + i % 4
    return pa.table(
        {
            "event": [("hard_brake", "cut_in", "lane_change")[j % 3] for j in range(n)],
            "t_start_ns": pa.array([T0_NS + j * DT_NS for j in range(n)], pa.int64()),
            "score": pa.array([0.1 * (j + 1) for j in range(n)], pa.float64()),
        }
    )


def build_range(root: str, start: int, stop: int, per_source: int) -> int:
    """Ingest logs ``start..stop-1`` (``per_source`` logs per source) and their ``events`` tables."""
    store = ScenarioStore.open(root, create=False)
    for first in range(start, stop, per_source):
        idx = range(first, min(first + per_source, stop))
        store.replace_source(f"src-{first:06d}", "h", [tiny_log(i) for i in idx])
        store.write_table_batch("events", {log_id(i): events(i) for i in idx})
    return stop - start


def grow(root: Path, start: int, stop: int, per_source: int, workers: int) -> float:
    """Add logs ``start..stop-1``; returns seconds."""
    t = time.perf_counter()
    if workers <= 1:
        build_range(str(root), start, stop, per_source)
    else:
        n = stop - start
        step = -(-n // (workers * 8))  # about 8 chunks per worker, whole sources each
        step = -(-step // per_source) * per_source
        bounds = [(a, min(a + step, stop)) for a in range(start, stop, step)]
        with ProcessPoolExecutor(workers, mp_context=get_context("spawn")) as pool:
            futures = [pool.submit(build_range, str(root), a, b, per_source) for a, b in bounds]
            assert sum(f.result() for f in futures) == n
    return time.perf_counter() - t


def median_s(fn: Callable[[], Any], repeats: int) -> float:
    fn()  # warm-up: imports, DuckDB connection, page cache
    times = []
    for _ in range(repeats):
        t = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t)
    return statistics.median(times)


def queries(store: ScenarioStore, n: int) -> dict[str, Callable[[], Any]]:
    one = log_id(n // 2)
    return {
        "log_ids()": store.log_ids,
        "info()": store.info,
        "log_meta(one id)": lambda: store.log_meta(one),
        "load_log(one id)": lambda: store.load_log(one),
        "read_table(events, [one id])": lambda: store.read_table("events", [one]),
        "read_table(events) all logs": lambda: store.read_table("events"),
        "sql count(*) FROM events": lambda: store.sql("SELECT count(*) FROM events"),
        "sql GROUP BY dataset FROM meta": lambda: store.sql(
            "SELECT dataset, count(*), sum(n_frames) FROM meta GROUP BY dataset"
        ),
    }


def check_answers(store: ScenarioStore, n: int) -> None:
    """The queries must answer correctly, not only quickly."""
    assert len(store.log_ids()) == n
    info = store.info()
    assert info.n_logs == n and info.table_logs == {"events": n}
    n_events = sum(1 + i % 4 for i in range(n))
    assert store.read_table("events").num_rows == n_events
    assert store.sql("SELECT count(*) AS c FROM events").column("c").to_pylist() == [n_events]
    one = log_id(n // 2)
    assert store.read_table("events", [one]).num_rows == 1 + (n // 2) % 4
    assert store.load_log(one).n_frames == store.log_meta(one).n_frames


def floors(store: ScenarioStore, n: int, repeats: int) -> dict[str, float]:
    one = log_id(n // 2)
    catalog = store.root / "catalog.sqlite"
    with contextlib.closing(sqlite3.connect(catalog)) as con:
        rel_dir = con.execute("SELECT dir FROM logs WHERE log_id = ?", (one,)).fetchone()[0]
    tracks = store.root / rel_dir / "tracks.parquet"

    def lookup() -> None:
        with contextlib.closing(sqlite3.connect(catalog)) as con:
            con.execute("SELECT meta FROM logs WHERE log_id = ?", (one,)).fetchone()

    return {
        "raw read": median_s(lambda: pq.read_table(tracks), repeats),
        "sqlite PK lookup": median_s(lookup, repeats),
    }


def _label(n: int) -> str:
    return f"{n // 1000}k" if n >= 1000 and n % 1000 == 0 else f"{n:,}"


def report(
    results: dict[int, dict[str, float]], base: dict[int, dict[str, float]], sizes: list[int], repeats: int
) -> None:
    """Print ms per query and size, the ratio largest/smallest, and the largest size vs the floors."""
    small, big = sizes[0], sizes[-1]
    floor_read, floor_pk = base[big]["raw read"], base[big]["sqlite PK lookup"]
    ratio = f"{_label(big)}/{_label(small)}"
    heads = "".join(f"{_label(n) + ' logs':>12}" for n in sizes)
    print(f"\nmedian ms of {repeats} runs (warm page cache); last columns: {_label(big)} time / floor")
    print(f"{'query':<32}{heads}{ratio:>10}{'/ read':>9}{'/ PK':>9}")
    for name in results[small]:
        cells = "".join(f"{results[n][name] * 1e3:12.2f}" for n in sizes)
        t_big = results[big][name]
        growth = t_big / results[small][name]
        print(f"{name:<32}{cells}{growth:10.1f}{t_big / floor_read:9.1f}{t_big / floor_pk:9.1f}")
    floors_named = {"raw read": "floor: pq.read_table(tracks)", "sqlite PK lookup": "floor: sqlite PK lookup"}
    for key, name in floors_named.items():
        cells = "".join(f"{base[n][key] * 1e3:12.2f}" for n in sizes)
        print(f"{name:<32}{cells}{base[big][key] / base[small][key]:10.1f}")


def main() -> None:
    parser = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument("--sizes", type=int, nargs="+", default=[100, 1_000, 10_000])
    parser.add_argument("--quick", action="store_true", help="sizes 100 and 1000 only")
    parser.add_argument("--repeats", type=int, default=5, help="timed repeats per query (median)")
    parser.add_argument("--logs-per-source", type=int, default=1, help="logs per replace_source call")
    parser.add_argument("--workers", type=int, default=1, help="writer processes for the build")
    parser.add_argument(
        "--out", type=Path, default=None, help="build the store in DIR/store (replaced) and keep it"
    )
    args = parser.parse_args()
    sizes = sorted(set([100, 1_000] if args.quick else args.sizes))

    work = args.out or Path(tempfile.mkdtemp(prefix="sm-bench-catalog-"))
    root = work / "store"
    if root.exists():
        shutil.rmtree(root)
    store = ScenarioStore.open(root)
    startup_s = median_s(lambda: subprocess.run([sys.executable, "-c", "pass"], check=True), 5)

    results: dict[int, dict[str, float]] = {}
    base: dict[int, dict[str, float]] = {}
    have = 0
    print(
        f"{'build step':<22}{'logs':>8}{'seconds':>9}{'logs/s':>9}   (writer processes: {args.workers}, "
        f"{args.logs_per_source} log(s) per source, an events table per log)"
    )
    for n in sizes:
        sec = grow(root, have, n, args.logs_per_source, args.workers)
        print(f"{f'{have:,} -> {n:,}':<22}{n - have:>8,}{sec:9.1f}{(n - have) / sec:9.0f}", flush=True)
        have = n
        check_answers(store, n)
        results[n] = {name: median_s(fn, args.repeats) for name, fn in queries(store, n).items()}
        base[n] = floors(store, n, args.repeats)

    report(results, base, sizes, args.repeats)
    size_mb = sum(f.stat().st_size for f in root.rglob("*") if f.is_file()) / 1e6
    catalog_mb = (root / "catalog.sqlite").stat().st_size / 1e6
    print(
        f"\npython -c pass start-up: {startup_s * 1e3:.0f} ms   store: {sizes[-1]:,} logs, {size_mb:.1f} MB, "
        f"catalog {catalog_mb:.1f} MB   cores: {len(os.sched_getaffinity(0))}"
    )
    if args.out is None:
        shutil.rmtree(work)
    else:
        print(f"store kept in {root}")


if __name__ == "__main__":
    main()
