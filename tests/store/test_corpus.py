"""Corpus-level tables and keyed upserts: concurrent writers in separate processes lose nothing."""

from __future__ import annotations

import multiprocessing as mp
from pathlib import Path

import numpy as np
import pyarrow as pa
import pytest

from scenariominer.data.log import build_log
from scenariominer.store import CorpusSchemaError, InvalidNameError, ScenarioStore

N_WRITERS = 4
ROWS_EACH = 25


def _write_corpus_rows(root: str, writer: int) -> None:
    table = ScenarioStore.open(Path(root), create=False).corpus("windows")
    for i in range(ROWS_EACH):  # one transaction per row: the writers interleave
        table.upsert({f"w{writer}-{i}": {"writer": writer, "i": i}})
    table.upsert({"shared": {"writer": writer}})  # every writer overwrites one common key


def _upsert_log_rows(root: str, writer: int) -> None:
    store = ScenarioStore.open(Path(root), create=False)
    for i in range(5):
        rows = pa.table({"key": [f"d{writer}"] * 3, "value": [writer * 100 + i] * 3})
        store.upsert_table_rows("L", "mining_results", rows, "key")


def test_rows_are_versioned_keyed_and_replaced(tmp_path: Path) -> None:
    store = ScenarioStore.open(tmp_path / "s")
    table = store.corpus("cases", schema_version=2)
    assert table.info().version == 0 and table.get("a") is None
    assert table.upsert({"a": {"x": 1}, "b": {"x": 2}}, blobs={"b": b"\x00\x01"}) == 1
    assert table.upsert({"a": {"x": 3}}) == 2
    rows = {r.key: r for r in table.rows(with_blobs=True)}
    assert rows["a"].data == {"x": 3} and rows["a"].version == 2
    assert rows["b"].data == {"x": 2} and rows["b"].blob == b"\x00\x01" and rows["b"].version == 1
    assert table.rows(["b"])[0].blob is None  # blobs only when asked for
    assert table.delete(["a", "missing"]) == 1 and table.keys() == ["b"]
    info = store.corpus_tables()[0]
    assert (info.name, info.schema_version, info.version, info.n_rows) == ("cases", 2, 3, 1)
    with pytest.raises(CorpusSchemaError, match="schema version 2"):
        store.corpus("cases", schema_version=3)
    with pytest.raises(InvalidNameError):
        store.corpus("Bad Name")
    with pytest.raises(ValueError, match="JSON"):
        table.upsert({"c": {"x": object()}})
    assert table.keys() == ["b"]  # a failed write changes nothing


def test_concurrent_writers_in_separate_processes_lose_no_row(tmp_path: Path) -> None:
    root = tmp_path / "s"
    ScenarioStore.open(root).corpus("windows")
    ctx = mp.get_context("spawn")
    procs = [ctx.Process(target=_write_corpus_rows, args=(str(root), w)) for w in range(N_WRITERS)]
    for p in procs:
        p.start()
    for p in procs:
        p.join(120)
        assert p.exitcode == 0
    table = ScenarioStore.open(root).corpus("windows")
    keys = table.keys()
    assert len(keys) == N_WRITERS * ROWS_EACH + 1
    assert {f"w{w}-{i}" for w in range(N_WRITERS) for i in range(ROWS_EACH)} <= set(keys)
    assert table.info().version == N_WRITERS * (ROWS_EACH + 1)  # every write committed once
    assert table.get("shared") is not None


def test_concurrent_keyed_upserts_into_one_log_table_keep_every_writer(tmp_path: Path) -> None:
    root = tmp_path / "s"
    store = ScenarioStore.open(root)
    log = build_log(
        log_id="L",
        track_id=["ego", "ego"],
        category=["EGO_VEHICLE", "EGO_VEHICLE"],
        timestamp_ns=[0, 100_000_000],
        fields={
            "x_m": [0.0, 1.0],
            "y_m": [0.0, 0.0],
            "yaw_rad": [0.0, 0.0],
            "length_m": [4.0, 4.0],
            "width_m": [2.0, 2.0],
        },  # fmt: skip
        ego_track_id="ego",
        source="<test>",
    )
    store.replace_source("src", "h", [log])
    ctx = mp.get_context("spawn")
    procs = [ctx.Process(target=_upsert_log_rows, args=(str(root), w)) for w in range(N_WRITERS)]
    for p in procs:
        p.start()
    for p in procs:
        p.join(120)
        assert p.exitcode == 0
    table = store.read_table("mining_results", ["L"])
    keys = np.asarray(table.column("key").to_pylist())
    values = np.asarray(table.column("value").to_pylist())
    for w in range(N_WRITERS):  # each writer's last upsert survives, with all its rows
        assert (keys == f"d{w}").sum() == 3
        assert set(values[keys == f"d{w}"].tolist()) == {w * 100 + 4}
    # an empty upsert with explicit keys deletes those keys' rows
    store.upsert_table_rows("L", "mining_results", table.slice(0, 0).drop_columns(["log_id"]), "key", ["d0"])
    assert "d0" not in store.read_table("mining_results", ["L"]).column("key").to_pylist()
