"""Many writer processes on one store at once: one catalog, per-log files, nothing lost or mixed.

Real OS processes (``spawn``) start together at a barrier and write into ONE store:

* ingesters, each with its own disjoint logs: ``replace_source`` of two-log sources, derived tables
  for every log, a re-ingest of one source with changed content (which drops that source's derived
  tables), then new tables for the changed logs and a rewrite of one table;
* upserters, all doing keyed ``upsert_table_rows`` into the SAME table of the SAME log: their own
  keys, a replacement and a deletion of one of them, and one key they all overwrite;
* a reader checking, while the others write, that every read is one whole committed state.

Afterwards the store must hold exactly the expected logs, rows and files.
"""

from __future__ import annotations

import multiprocessing as mp
import operator
import time
import traceback
from collections import Counter
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pyarrow as pa

from scenariominer.data.log import Log, build_log
from scenariominer.store import ScenarioStore, UnknownTableError

N_INGESTERS = 4
SOURCES_EACH = 3  # two logs per source
LOGS_EACH = 2 * SOURCES_EACH
N_UPSERTERS = 3
KEYS_EACH = 8
HUB = "hub"  # the one log every upserter writes to
T0_NS = 1_600_000_000_000_000_000
DT_NS = 100_000_000
JOIN_TIMEOUT_S = 120.0


# ---------------------------------------------------------------------- the data each writer writes


def log_id(writer: int, i: int) -> str:
    return f"w{writer}/log {i}"  # a slash and a space: the directory name is percent-encoded


def make_log(lid: str, rev: int) -> Log:
    """Ego and one car; positions depend on the log id and on ``rev`` (a re-ingest changes them)."""
    n_t = 5 + sum(map(ord, lid)) % 4
    offset = float(sum(map(ord, lid)) % 97) + 1000.0 * rev
    frames = np.arange(n_t)
    return build_log(
        log_id=lid,
        track_id=["ego"] * n_t + ["car"] * n_t,
        category=["EGO_VEHICLE"] * n_t + ["REGULAR_VEHICLE"] * n_t,
        timestamp_ns=np.concatenate([T0_NS + frames * DT_NS] * 2),
        fields={
            "x_m": np.concatenate([offset + 1.0 * frames, offset + 20.0 + 1.5 * frames]),
            "y_m": np.concatenate([np.zeros(n_t), np.full(n_t, 3.5)]),
            "yaw_rad": np.zeros(2 * n_t),
            "length_m": np.full(2 * n_t, 4.5),
            "width_m": np.full(2 * n_t, 1.9),
        },
        ego_track_id="ego",
        source="<concurrent test>",
        dataset="synthetic",
    )


def n_events(lid: str) -> int:
    return 2 + sum(map(ord, lid)) % 3


def events(lid: str, rev: int) -> pa.Table:
    n = n_events(lid)
    return pa.table(
        {
            "event_id": [f"e{j}" for j in range(n)],
            "rev": pa.array([rev] * n, pa.int64()),
            "t_ns": pa.array([T0_NS + j * DT_NS for j in range(n)], pa.int64()),
        }
    )


def final_log_rev(i: int) -> int:
    return 1 if i < 2 else 0  # source 0 (logs 0 and 1) is re-ingested with changed content


def final_events_rev(i: int) -> int:
    return 1 if i < 2 or i == LOGS_EACH - 1 else 0  # rewritten after the re-ingest / replaced once


def has_tags(i: int) -> bool:
    return i >= 2  # the re-ingest dropped logs 0 and 1's tables; only events are written again


def result_rows(key: str, n: int, writer: int, rev: int) -> pa.Table:
    return pa.table(
        {
            "key": [key] * n,
            "writer": pa.array([writer] * n, pa.int64()),
            "rev": pa.array([rev] * n, pa.int64()),
            "row": pa.array(list(range(n)), pa.int64()),
        }
    )


def expected_results() -> dict[str, tuple[int, int, int]]:
    """key -> (rows, writer, rev) in the hub's ``results`` table ("shared" is checked apart)."""
    out = {}
    for u in range(N_UPSERTERS):
        out[f"u{u}-k0"] = (1, u, 1)  # replaced by a one-row version
        for k in range(2, KEYS_EACH):  # k1 was deleted
            out[f"u{u}-k{k}"] = (2, u, 0)
    return out


# ---------------------------------------------------------------------- workers (run in child processes)


def _run(name: str, barrier: Any, queue: Any, body: Callable[[], dict[str, Any]]) -> None:
    try:
        barrier.wait(60)
        start = time.monotonic()
        report = body()
        queue.put({"name": name, "start": start, "end": time.monotonic(), **report})
    except BaseException:
        barrier.abort()  # the others fail now instead of waiting for this one
        queue.put({"name": name, "error": traceback.format_exc()})
        raise


def _ingester(root: str, writer: int, barrier: Any, queue: Any) -> None:
    store = ScenarioStore.open(root, create=False)

    def body() -> dict[str, Any]:
        ids = [log_id(writer, i) for i in range(LOGS_EACH)]
        for s in range(SOURCES_EACH):
            pair = ids[2 * s : 2 * s + 2]
            store.replace_source(f"src-{writer}-{s}", "h0", [make_log(lid, 0) for lid in pair])
            for lid in pair:  # two tables in one atomic step
                tags = pa.table({"tag": [f"tag-{lid}"]})
                store.write_tables(lid, {"events": events(lid, 0), "tags": tags})
        # Re-ingest source 0 with changed content: its logs get new files and lose their tables.
        store.replace_source(f"src-{writer}-0", "h1", [make_log(lid, 1) for lid in ids[:2]])
        for lid in ids[:2]:
            store.write_table(lid, "events", events(lid, 1))
        store.write_table(ids[-1], "events", events(ids[-1], 1))  # replaces the rev-0 table
        return {}

    _run(f"ingester {writer}", barrier, queue, body)


def _upserter(root: str, writer: int, barrier: Any, queue: Any) -> None:
    store = ScenarioStore.open(root, create=False)

    def body() -> dict[str, Any]:
        for k in range(KEYS_EACH):  # one transaction per key: the upserters interleave
            store.upsert_table_rows(HUB, "results", result_rows(f"u{writer}-k{k}", 2, writer, 0), "key")
            if k == KEYS_EACH // 2:
                store.upsert_table_rows(HUB, "results", result_rows("shared", writer + 1, writer, 0), "key")
        store.upsert_table_rows(HUB, "results", result_rows(f"u{writer}-k0", 1, writer, 1), "key")
        empty = result_rows("", 0, writer, 0)
        store.upsert_table_rows(HUB, "results", empty, "key", keys=[f"u{writer}-k1"])
        return {}

    _run(f"upserter {writer}", barrier, queue, body)


def _check_results_snapshot(table: pa.Table) -> None:
    """One committed state of the hub's results: every key's rows come from one upsert."""
    keys = table.column("key").to_pylist()
    writers = table.column("writer").to_pylist()
    revs = table.column("rev").to_pylist()
    rows_of: dict[str, list[tuple[int, int]]] = {}
    for key, w, r in zip(keys, writers, revs, strict=True):
        rows_of.setdefault(key, []).append((w, r))
    for key, rows in rows_of.items():
        assert len(set(rows)) == 1, (key, rows)  # never two upserts' rows under one key
        w, r = rows[0]
        if key == "shared":
            assert len(rows) == w + 1, (key, rows)
        else:
            assert key.startswith(f"u{w}-") and len(rows) == (1 if r == 1 else 2), (key, rows)


def _reader(root: str, barrier: Any, queue: Any, stop: Any) -> None:
    store = ScenarioStore.open(root, create=False)
    expected = {
        log_id(w, i): (make_log(log_id(w, i), 0), make_log(log_id(w, i), 1))
        for w in range(N_INGESTERS)
        for i in range(LOGS_EACH)
    }

    def body() -> dict[str, Any]:
        reads = 0
        while not stop.is_set():
            try:
                results = store.read_table("results", [HUB])
            except UnknownTableError:
                pass  # no upsert committed yet
            else:
                _check_results_snapshot(results)
            ids = [i for i in store.log_ids() if i != HUB]
            if ids:
                lid = ids[reads % len(ids)]
                loaded = store.load_log(lid)
                assert any(np.array_equal(loaded.x_m, e.x_m) for e in expected[lid]), lid
            # Per-log event counts over all logs through DuckDB: each log's table is whole.
            if "events" in store.table_names():
                counts = store.sql("SELECT log_id, count(*) AS n FROM events GROUP BY log_id").to_pylist()
                for row in counts:
                    assert row["n"] == n_events(row["log_id"]), row
            reads += 1
        return {"reads": reads}

    _run("reader", barrier, queue, body)


# ---------------------------------------------------------------------- the test


def test_concurrent_writer_processes_keep_one_consistent_store(tmp_path: Path) -> None:
    root = tmp_path / "store"
    store = ScenarioStore.open(root)
    store.replace_source("hub-src", "h", [make_log(HUB, 0)])

    ctx = mp.get_context("spawn")
    n_writers = N_INGESTERS + N_UPSERTERS
    barrier = ctx.Barrier(n_writers + 1)
    queue = ctx.Queue()
    stop = ctx.Event()
    writers = [ctx.Process(target=_ingester, args=(str(root), w, barrier, queue)) for w in range(N_INGESTERS)]
    writers += [
        ctx.Process(target=_upserter, args=(str(root), w, barrier, queue)) for w in range(N_UPSERTERS)
    ]
    reader = ctx.Process(target=_reader, args=(str(root), barrier, queue, stop))
    for p in [*writers, reader]:
        p.start()
    reports = []
    try:
        for _ in writers:
            reports.append(queue.get(timeout=JOIN_TIMEOUT_S))
        stop.set()
        reports.append(queue.get(timeout=JOIN_TIMEOUT_S))
    finally:
        stop.set()
        for p in [*writers, reader]:
            p.join(JOIN_TIMEOUT_S)
            if p.is_alive():
                p.kill()
    errors = [f"{r['name']}:\n{r['error']}" for r in reports if "error" in r]
    assert not errors, "\n".join(errors)
    assert [p.exitcode for p in [*writers, reader]] == [0] * (n_writers + 1)

    # The writers really ran at the same time: some instant lies inside every writer's phase.
    phases = [r for r in reports if r["name"] != "reader"]
    assert max(r["start"] for r in phases) < min(r["end"] for r in phases), phases
    reader_report = next(r for r in reports if r["name"] == "reader")
    assert reader_report["reads"] >= 1

    store = ScenarioStore.open(root, create=False)
    all_ids = [log_id(w, i) for w in range(N_INGESTERS) for i in range(LOGS_EACH)]

    # Every log exactly once, each under the source that wrote it.
    ids = store.log_ids()
    assert ids == sorted([HUB, *all_ids])
    assert Counter(store.sql("SELECT log_id FROM meta").column("log_id").to_pylist()) == Counter(ids)
    for w in range(N_INGESTERS):
        for s in range(SOURCES_EACH):
            assert store.logs_of_source(f"src-{w}-{s}") == sorted([log_id(w, 2 * s), log_id(w, 2 * s + 1)])
    hashes = {r.source_key: r.content_hash for r in store.sources()}
    assert hashes == {"hub-src": "h"} | {
        f"src-{w}-{s}": "h1" if s == 0 else "h0" for w in range(N_INGESTERS) for s in range(SOURCES_EACH)
    }

    # Reading back gives the data last written, for every log.
    for w in range(N_INGESTERS):
        for i in range(LOGS_EACH):
            lid = log_id(w, i)
            loaded, want = store.load_log(lid), make_log(lid, final_log_rev(i))
            np.testing.assert_array_equal(loaded.timestamps_ns, want.timestamps_ns)
            np.testing.assert_array_equal(loaded.track_ids, want.track_ids)
            np.testing.assert_array_equal(loaded.x_m, want.x_m, err_msg=lid)
            np.testing.assert_array_equal(loaded.y_m, want.y_m, err_msg=lid)
            assert store.log_meta(lid).n_frames == want.n_frames

    # Derived tables: exactly the expected rows, per log.
    ev = store.read_table("events").to_pylist()
    want_ev = [
        {"log_id": log_id(w, i), **row}
        for w in range(N_INGESTERS)
        for i in range(LOGS_EACH)
        for row in events(log_id(w, i), final_events_rev(i)).to_pylist()
    ]
    by_event = operator.itemgetter("log_id", "event_id")
    assert sorted(ev, key=by_event) == sorted(want_ev, key=by_event)
    tags = store.read_table("tags").to_pylist()
    assert sorted(r["log_id"] for r in tags) == sorted(
        log_id(w, i) for w in range(N_INGESTERS) for i in range(LOGS_EACH) if has_tags(i)
    )
    assert all(r["tag"] == f"tag-{r['log_id']}" for r in tags)
    n_ev = store.sql("SELECT count(*) AS n FROM events").column("n").to_pylist()
    assert n_ev == [len(want_ev)]

    # The concurrent upserts into one log's table: no lost update, replacements and deletes applied.
    results = store.read_table("results", [HUB])
    _check_results_snapshot(results)
    groups: dict[str, list[dict[str, Any]]] = {}
    for row in results.to_pylist():
        groups.setdefault(row["key"], []).append(row)
    shared = groups.pop("shared")
    assert len(shared) == shared[0]["writer"] + 1 and shared[0]["writer"] in range(N_UPSERTERS)
    got = {k: (len(rows), rows[0]["writer"], rows[0]["rev"]) for k, rows in groups.items()}
    assert got == expected_results()
    info = store.info()
    assert info.n_logs == 1 + N_INGESTERS * LOGS_EACH
    assert info.table_logs == {
        "events": N_INGESTERS * LOGS_EACH,
        "results": 1,
        "tags": N_INGESTERS * (LOGS_EACH - 2),
    }

    # On disk: no orphan, no missing file, no staging left behind, one version folder per log.
    check = store.check(staging_max_age_s=0.0)
    assert (check.missing_files, check.orphaned_files, check.stale_staging) == ((), (), ())
    assert check.ok and check.n_logs == len(ids)
    versions = sorted(p for p in (root / "logs").glob("*/*") if p.is_dir())
    assert len(versions) == len(ids)
    staging = root / ".staging"
    assert not staging.exists() or list(staging.iterdir()) == []


# ---------------------------------------------------------------------- creating the store concurrently

N_OPENERS = 4
CREATE_ROUNDS = 6


def _create_and_ingest(base: str, writer: int, barrier: Any, queue: Any) -> None:
    """In each round, open a store that does not exist yet (all openers at once) and ingest one log."""
    try:
        for r in range(CREATE_ROUNDS):
            barrier.wait(60)
            store = ScenarioStore.open(Path(base) / f"round{r}")  # create=True: whoever comes first creates
            lid = f"round{r}-w{writer}"
            store.replace_source(f"src-{lid}", "h", [make_log(lid, 0)])
        queue.put({"name": f"opener {writer}"})
    except BaseException:
        barrier.abort()
        queue.put({"name": f"opener {writer}", "error": traceback.format_exc()})
        raise


def test_writers_that_all_create_the_store_at_once_share_one_store(tmp_path: Path) -> None:
    ctx = mp.get_context("spawn")
    barrier = ctx.Barrier(N_OPENERS)
    queue = ctx.Queue()
    procs = [
        ctx.Process(target=_create_and_ingest, args=(str(tmp_path), w, barrier, queue))
        for w in range(N_OPENERS)
    ]
    for p in procs:
        p.start()
    try:
        reports = [queue.get(timeout=JOIN_TIMEOUT_S) for _ in procs]
    finally:
        for p in procs:
            p.join(JOIN_TIMEOUT_S)
            if p.is_alive():
                p.kill()
    errors = [f"{r['name']}:\n{r['error']}" for r in reports if "error" in r]
    assert not errors, "\n".join(errors)
    for r in range(CREATE_ROUNDS):
        store = ScenarioStore.open(tmp_path / f"round{r}", create=False)
        assert store.log_ids() == sorted(f"round{r}-w{w}" for w in range(N_OPENERS))
        check = store.check(staging_max_age_s=0.0)
        assert (check.missing_files, check.orphaned_files, check.stale_staging) == ((), (), ())
        names = sorted(p.name for p in store.root.iterdir())  # no marker temp file left behind
        assert [n for n in names if n != ".staging"] == ["catalog.sqlite", "logs", "store.json"]
        assert not (store.root / ".staging").exists() or list((store.root / ".staging").iterdir()) == []
