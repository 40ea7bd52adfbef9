"""The scenario store: lossless round trips, incremental and atomic ingestion, derived tables, SQL."""

from __future__ import annotations

import json
import os
import threading
import time
from pathlib import Path

import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq
import pytest

import scenariominer.store as store_pkg
from scenariominer.config import Config, PreprocessConfig
from scenariominer.data.log import STATE_FIELDS, Log, build_log
from scenariominer.data.preprocess import preprocess
from scenariominer.store import (
    InvalidLogError,
    InvalidNameError,
    LogConflictError,
    NotAStoreError,
    QueryError,
    ScenarioStore,
    StoreVersionError,
    UnknownLogError,
    UnknownTableError,
    default_store_path,
    resolve_store_path,
)

T0_NS = 1_600_000_000_000_000_000
DT_NS = 100_000_000  # 10 Hz


def make_log(
    log_id: str,
    *,
    n_t: int = 6,
    x0: float = 0.0,
    n_peds: int = 1,
    source: str = "<test>",
    source_hash: str = "",
    map_dir: Path | None = None,
) -> Log:
    """Ego and one car over all ``n_t`` frames; each pedestrian misses frame 0 and frame 3.

    n_frames = 2 * n_t + n_peds * (n_t - 2).
    """
    frames = np.arange(n_t)
    ped_frames = frames[(frames != 0) & (frames != 3)]
    tracks = [("ego", "EGO_VEHICLE", frames, 2.0), ("car1", "REGULAR_VEHICLE", frames, 1.5)]
    tracks += [(f"ped{i}", "PEDESTRIAN", ped_frames, 0.2 * (i + 1)) for i in range(n_peds)]
    tid, cat, ts, x, y, yaw = [], [], [], [], [], []
    for k, (name, category, fr, speed) in enumerate(tracks):
        tid += [name] * len(fr)
        cat += [category] * len(fr)
        ts += (T0_NS + fr * DT_NS).tolist()
        x += (x0 + 5.0 * k + speed * 0.1 * fr).tolist()
        y += (0.5 * k + 0.01 * fr**2).tolist()
        yaw += (0.3 * k - 0.05 * fr).tolist()
    xa = np.asarray(x)
    return build_log(
        log_id=log_id,
        track_id=tid,
        category=cat,
        timestamp_ns=ts,
        fields={
            "x_m": xa,
            "y_m": np.asarray(y),
            "yaw_rad": np.asarray(yaw),
            "length_m": np.full_like(xa, 4.5),
            "width_m": np.full_like(xa, 1.9),
        },
        ego_track_id=None,
        source=source,
        dataset="synthetic",
        map_dir=map_dir,
        source_hash=source_hash,
    )


def assert_logs_equal(a: Log, b: Log) -> None:
    assert a.log_id == b.log_id
    np.testing.assert_array_equal(a.timestamps_ns, b.timestamps_ns)
    np.testing.assert_array_equal(a.track_ids, b.track_ids)
    np.testing.assert_array_equal(a.categories, b.categories)
    np.testing.assert_array_equal(a.valid, b.valid)
    for name in STATE_FIELDS:
        if name == "yaw_rad":
            # build_log re-wraps headings into (-pi, pi]; that can move a value by one ulp.
            np.testing.assert_allclose(a.yaw_rad, b.yaw_rad, rtol=0, atol=1e-15)
        else:
            np.testing.assert_array_equal(getattr(a, name), getattr(b, name), err_msg=name)
    assert (a.dataset, a.source_path, a.map_dir, a.source_hash, a.notes, a.ego_index) == (
        b.dataset,
        b.source_path,
        b.map_dir,
        b.source_hash,
        b.notes,
        b.ego_index,
    )


@pytest.fixture()
def store(tmp_path: Path) -> ScenarioStore:
    return ScenarioStore.open(tmp_path / "store")


def version_dirs(store: ScenarioStore) -> list[Path]:
    return sorted(p for p in (store.root / "logs").glob("*/*") if p.is_dir())


def staging_entries(store: ScenarioStore) -> list[Path]:
    staging = store.root / ".staging"
    return sorted(staging.iterdir()) if staging.exists() else []


def tags_table(labels: list[str]) -> pa.Table:
    return pa.table({"tag": labels, "t_start_ns": pa.array([T0_NS] * len(labels), pa.int64())})


# ---------------------------------------------------------------------- public API


def test_every_exported_name_exists() -> None:
    missing = [name for name in store_pkg.__all__ if not hasattr(store_pkg, name)]
    assert missing == []
    assert len(set(store_pkg.__all__)) == len(store_pkg.__all__)


# ---------------------------------------------------------------------- round trip


def test_round_trip_restores_every_array_and_the_metadata(store: ScenarioStore, tmp_path: Path) -> None:
    log = make_log(
        "L1", source=str(tmp_path / "raw" / "L1.feather"), source_hash="abc", map_dir=tmp_path / "map"
    )
    log = log.replace(notes=("dropped 2 row(s) with NaN position",))
    assert store.replace_source("src-1", "h1", [log]) == ["L1"]
    loaded = store.load_log("L1")
    assert_logs_equal(loaded, log)
    assert loaded.source_path == tmp_path / "raw" / "L1.feather"
    assert loaded.map_dir == tmp_path / "map"


def test_round_trip_of_a_preprocessed_log_keeps_interpolated_cells_and_derivatives(
    store: ScenarioStore,
) -> None:
    raw = make_log("P", n_t=30, n_peds=2)
    log = preprocess(raw, PreprocessConfig())
    assert log.n_frames > raw.n_frames  # the gap at frame 3 was filled
    store.replace_source("src", "h", [log])
    assert_logs_equal(store.load_log("P"), log)


def test_the_real_av2_sample_log_round_trips(store: ScenarioStore, av2_log_dir: Path) -> None:
    from scenariominer.data.adapters.av2 import Av2Reader, av2_source

    config = Config()
    log = preprocess(next(Av2Reader().read(av2_source(av2_log_dir), config)), config.preprocess)
    store.replace_source(str(av2_log_dir), "h", [log])
    assert_logs_equal(store.load_log(log.log_id), log)
    n_peds = store.sql("SELECT count(DISTINCT track_id) AS n FROM tracks WHERE category = 'PEDESTRIAN'")
    assert n_peds.column("n").to_pylist() == [log.category_counts()["PEDESTRIAN"]]
    map_dir = store.log_meta(log.log_id).map_dir
    assert map_dir is not None and Path(map_dir).resolve() == (av2_log_dir / "map").resolve()


def test_round_trip_keeps_a_non_canonical_track_order(store: ScenarioStore) -> None:
    log = make_log("L", n_peds=2).select_tracks(np.array([0, 3, 1, 2]))
    assert log.track_ids.tolist() == ["ego", "ped1", "car1", "ped0"]
    store.replace_source("src", "h", [log])
    assert store.load_log("L").track_ids.tolist() == ["ego", "ped1", "car1", "ped0"]


def test_any_log_id_becomes_a_safe_directory_name(store: ScenarioStore) -> None:
    odd = [make_log("run 1/ü"), make_log(".hidden"), make_log("..")]
    store.replace_source("src", "h", odd)
    assert sorted(p.name for p in (store.root / "logs").iterdir()) == [
        "%2E.",
        "%2Ehidden",
        "run%201%2F%C3%BC",
    ]
    for log in odd:
        assert_logs_equal(store.load_log(log.log_id), log)


def test_meta_json_describes_the_log(store: ScenarioStore) -> None:
    store.replace_source("src", "h", [make_log("L", n_t=6, n_peds=2)])
    (meta_file,) = (store.root / "logs").glob("L/*/meta.json")
    meta = json.loads(meta_file.read_text())
    assert meta["log_id"] == "L"
    assert meta["source_key"] == "src"
    assert meta["n_tracks"] == 4
    assert meta["n_timestamps"] == 6
    assert meta["n_frames"] == 2 * 6 + 2 * 4
    assert meta["duration_s"] == pytest.approx(0.5)
    assert meta["categories"] == {"EGO_VEHICLE": 1, "PEDESTRIAN": 2, "REGULAR_VEHICLE": 1}


# ---------------------------------------------------------------------- incremental ingestion


def test_needs_ingest_is_true_only_for_new_or_changed_content(store: ScenarioStore) -> None:
    assert store.needs_ingest("src", "h1")
    store.replace_source("src", "h1", [make_log("A")])
    assert not store.needs_ingest("src", "h1")
    assert store.needs_ingest("src", "h2")
    assert store.needs_ingest("other", "h1")
    assert store.logs_of_source("src") == ["A"]


def test_changed_content_replaces_rows_and_drops_stale_derived_tables(store: ScenarioStore) -> None:
    store.replace_source("src", "h1", [make_log("A"), make_log("B")])
    store.write_table("A", "tags", tags_table(["a"]))
    store.write_table("B", "tags", tags_table(["b"]))
    store.replace_source("src", "h2", [make_log("A"), make_log("B", x0=100.0)])
    xmin = store.sql("SELECT log_id, min(x_m) AS xmin FROM tracks GROUP BY 1 ORDER BY 1").to_pydict()
    assert xmin == {"log_id": ["A", "B"], "xmin": [0.0, 100.0]}
    # A did not change: its tags survive; B's tags were computed from old data and are gone.
    assert store.read_table("tags").column("log_id").to_pylist() == ["A"]
    assert store.log_meta("A").source_key == "src"
    assert len(version_dirs(store)) == 2  # B's old version was deleted


def test_unchanged_log_keeps_its_files_but_gets_the_new_metadata(store: ScenarioStore) -> None:
    store.replace_source("src", "h1", [make_log("A", source_hash="h1")])
    before = version_dirs(store)
    store.replace_source("src", "h2", [make_log("A", source_hash="h2")])
    assert version_dirs(store) == before
    assert store.log_meta("A").source_hash == "h2"
    assert store.load_log("A").source_hash == "h2"
    assert json.loads((before[0] / "meta.json").read_text())["source_hash"] == "h2"


def test_a_source_that_now_yields_fewer_logs_loses_the_others(store: ScenarioStore) -> None:
    store.replace_source("src", "h1", [make_log("A"), make_log("B"), make_log("C")])
    store.replace_source("src", "h2", [make_log("A"), make_log("C", x0=1.0)])
    assert store.log_ids() == ["A", "C"]
    assert store.logs_of_source("src") == ["A", "C"]
    assert store.sql("SELECT DISTINCT log_id FROM tracks ORDER BY 1").column("log_id").to_pylist() == [
        "A",
        "C",
    ]
    assert not (store.root / "logs" / "B").exists()
    store.replace_source("src", "h3", [])
    assert store.log_ids() == []
    assert not store.needs_ingest("src", "h3")


def test_a_log_id_belongs_to_one_source(store: ScenarioStore) -> None:
    store.replace_source("src-1", "h", [make_log("A")])
    with pytest.raises(LogConflictError, match="already belongs to source src-1"):
        store.replace_source("src-2", "h", [make_log("A", x0=5.0)])
    assert store.sql("SELECT min(x_m) AS x FROM tracks").column("x").to_pylist() == [0.0]


def test_repeated_log_ids_in_one_source_are_refused(store: ScenarioStore) -> None:
    with pytest.raises(InvalidLogError, match="more than once"):
        store.replace_source("src", "h", [make_log("A"), make_log("A")])
    assert store.log_ids() == []


def test_a_log_that_cannot_round_trip_is_refused_before_anything_is_written(store: ScenarioStore) -> None:
    bad = make_log("A")
    vx = bad.vx_mps.copy()
    vx[1, 2] = np.nan
    with pytest.raises(
        InvalidLogError, match=r"vx_mps is not finite in 1 valid cell\(s\), e.g. track 'car1'"
    ):
        store.replace_source("src", "h", [make_log("B"), bad.replace(vx_mps=vx)])
    assert store.log_ids() == []
    assert store.needs_ingest("src", "h")


def test_a_batch_of_sources_lands_in_one_transaction_and_a_bad_source_stays_out_alone(
    store: ScenarioStore,
) -> None:
    store.replace_source("old", "h0", [make_log("A")])
    generation = store._generation()
    bad = make_log("C")
    vx = bad.vx_mps.copy()
    vx[1, 2] = np.nan
    outcomes = store.replace_sources(
        [
            ("s1", "h1", [make_log("B"), make_log("B2")]),
            ("s2", "h2", [bad.replace(vx_mps=vx)]),  # cannot round-trip
            ("s3", "h3", [make_log("A", x0=5.0)]),  # A belongs to source "old"
            ("s4", "h4", [make_log("D")]),
            ("s5", "h5", [make_log("D", x0=9.0), make_log("E")]),  # D is s4's by the time s5 switches
            ("s6", "h6", [make_log("F", n_peds=2)]),
        ]
    )
    assert outcomes[0] == ["B", "B2"] and outcomes[3] == ["D"] and outcomes[5] == ["F"]
    assert isinstance(outcomes[1], InvalidLogError)
    assert isinstance(outcomes[2], LogConflictError) and "already belongs to source old" in str(outcomes[2])
    assert isinstance(outcomes[4], LogConflictError) and "already belongs to source s4" in str(outcomes[4])
    assert store._generation() == generation + 1  # one catalog transaction for the whole batch
    assert store.log_ids() == ["A", "B", "B2", "D", "F"]  # s5's E went back with its D
    assert store.logs_of_source("old") == ["A"]
    for log in (make_log("A"), make_log("D"), make_log("F", n_peds=2)):
        assert_logs_equal(store.load_log(log.log_id), log)
    assert [store.needs_ingest(k, h) for k, h in [("s1", "h1"), ("s2", "h2"), ("s5", "h5")]] == [
        False,
        True,
        True,
    ]
    check = store.check()  # no files left behind by the sources kept out
    assert (check.orphaned_files, check.missing_files, check.stale_staging) == ((), (), ())


# ---------------------------------------------------------------------- atomicity


def _fail_on_call(n: int, real):  # type: ignore[no-untyped-def]
    calls = {"n": 0}

    def wrapper(*args, **kwargs):  # type: ignore[no-untyped-def]
        calls["n"] += 1
        if calls["n"] == n:
            raise OSError(28, "No space left on device")
        return real(*args, **kwargs)

    return wrapper


def test_failure_while_writing_a_source_leaves_the_previous_state(
    store: ScenarioStore, monkeypatch: pytest.MonkeyPatch
) -> None:
    old = [make_log("A"), make_log("B")]
    store.replace_source("src", "h1", old)
    before_dirs = version_dirs(store)
    monkeypatch.setattr(pq, "write_table", _fail_on_call(2, pq.write_table))
    with pytest.raises(OSError, match="No space left"):
        store.replace_source("src", "h2", [make_log("A", x0=9.0), make_log("B", x0=9.0), make_log("C")])
    monkeypatch.undo()
    assert store.log_ids() == ["A", "B"]
    assert not store.needs_ingest("src", "h1")
    assert store.sql("SELECT min(x_m) AS x FROM tracks").column("x").to_pylist() == [0.0]
    for log in old:
        assert_logs_equal(store.load_log(log.log_id), log)
    assert version_dirs(store) == before_dirs
    assert staging_entries(store) == []


def test_failure_while_switching_a_source_in_leaves_the_previous_state(
    store: ScenarioStore, monkeypatch: pytest.MonkeyPatch
) -> None:
    store.replace_source("src", "h1", [make_log("A"), make_log("B")])
    before_dirs = version_dirs(store)
    real_replace = os.replace
    moved_dirs = {"n": 0}

    def replace(src: str | Path, dst: str | Path) -> None:
        if Path(src).is_dir():  # staged version directories move into logs/ inside the commit step
            moved_dirs["n"] += 1
            if moved_dirs["n"] == 2:
                raise OSError(5, "Input/output error")
        real_replace(src, dst)

    monkeypatch.setattr(os, "replace", replace)
    with pytest.raises(OSError, match="Input/output error"):
        store.replace_source("src", "h2", [make_log("A", x0=9.0), make_log("B", x0=9.0)])
    monkeypatch.undo()
    assert moved_dirs["n"] == 2  # A's new version had been moved in, then was rolled back
    assert store.sql("SELECT min(x_m) AS x FROM tracks").column("x").to_pylist() == [0.0]
    assert not store.needs_ingest("src", "h1")
    assert version_dirs(store) == before_dirs
    assert staging_entries(store) == []


def test_readers_see_a_whole_source_before_or_after_a_rewrite(tmp_path: Path) -> None:
    writer = ScenarioStore.open(tmp_path / "s")
    reader = ScenarioStore.open(tmp_path / "s")  # a second handle, as another process would have
    v1 = [make_log("A", n_t=10), make_log("B", n_t=10), make_log("C", n_t=10)]
    v2 = [make_log("A", n_t=14, x0=100.0), make_log("B", n_t=14, x0=100.0)]

    def expected(logs: list[Log]) -> dict[str, list[object]]:
        return {
            "log_id": [log.log_id for log in logs],
            "n": [log.n_frames for log in logs],
            "xmin": [float(np.nanmin(log.x_m)) for log in logs],
        }

    states = [expected(v1), expected(v2)]
    writer.replace_source("src", "h0", v1)
    done = threading.Event()
    errors: list[BaseException] = []

    def write() -> None:
        try:
            for i in range(1, 7):
                writer.replace_source("src", f"h{i}", v2 if i % 2 else v1)
        except BaseException as exc:  # pragma: no cover - reported below
            errors.append(exc)
        finally:
            done.set()

    seen: list[int] = []
    thread = threading.Thread(target=write)
    thread.start()
    while not done.is_set():
        got = reader.sql(
            "SELECT log_id, count(*) AS n, min(x_m) AS xmin FROM tracks GROUP BY log_id ORDER BY log_id"
        ).to_pydict()
        assert got in states, got
        seen.append(states.index(got))
    thread.join()
    assert errors == []
    assert len(seen) > 0
    assert reader.log_ids() == ["A", "B", "C"]


# ---------------------------------------------------------------------- derived tables


def test_derived_tables_round_trip_and_join_across_logs(store: ScenarioStore) -> None:
    store.replace_source("src", "h", [make_log("A"), make_log("B", n_peds=3)])
    store.write_table("A", "tags", tags_table(["follow", "cut_in"]))
    store.write_table(
        "B", "tags", tags_table(["follow"]).append_column("confidence", pa.array([0.5], pa.float64()))
    )
    tags = store.read_table("tags")
    assert tags.column_names == ["log_id", "tag", "t_start_ns", "confidence"]
    assert tags.to_pydict()["tag"] == ["follow", "cut_in", "follow"]
    assert tags.column("confidence").to_pylist() == [None, None, 0.5]
    assert store.read_table("tags", log_ids=["B"]).num_rows == 1
    joined = store.sql(
        "SELECT t.log_id, count(*) AS n_tags, any_value(m.categories['PEDESTRIAN']) AS n_peds "
        "FROM tags t JOIN meta m USING (log_id) GROUP BY 1 ORDER BY 1"
    ).to_pydict()
    assert joined == {"log_id": ["A", "B"], "n_tags": [2, 1], "n_peds": [1, 3]}
    assert store.table_names() == ["tags"]


def test_rewriting_a_derived_table_replaces_it(store: ScenarioStore) -> None:
    store.replace_source("src", "h", [make_log("A")])
    store.write_table("A", "tags", tags_table(["x", "y"]))
    store.write_table("A", "tags", tags_table(["z"]))
    assert store.read_table("tags").column("tag").to_pylist() == ["z"]
    assert len(list((store.root / "logs").glob("A/*/tags.*.parquet"))) == 1


def test_write_tables_is_all_or_nothing(store: ScenarioStore, monkeypatch: pytest.MonkeyPatch) -> None:
    store.replace_source("src", "h", [make_log("A")])
    monkeypatch.setattr(pq, "write_table", _fail_on_call(2, pq.write_table))
    with pytest.raises(OSError):
        store.write_tables("A", {"tags": tags_table(["a"]), "events": tags_table(["brake"])})
    monkeypatch.undo()
    assert store.table_names() == []
    store.write_tables("A", {"tags": tags_table(["a"]), "events": tags_table(["brake"])})
    assert store.table_names() == ["events", "tags"]


def test_write_table_batch_writes_many_logs_in_one_commit(
    store: ScenarioStore, monkeypatch: pytest.MonkeyPatch
) -> None:
    store.replace_source("src", "h", [make_log("A"), make_log("B"), make_log("C")])
    batch = {"A": tags_table(["a1", "a2"]), "B": tags_table([]), "C": tags_table(["c"])}
    monkeypatch.setattr(pq, "write_table", _fail_on_call(3, pq.write_table))
    with pytest.raises(OSError):
        store.write_table_batch("tags", batch)
    monkeypatch.undo()
    assert store.table_names() == []  # nothing of a failed batch is visible
    store.write_table_batch("tags", batch)
    assert store.read_table("tags").column("log_id").to_pylist() == ["A", "A", "C"]
    # B was processed and found nothing: it holds an empty table, unlike a log never processed.
    assert store.sql("SELECT log_id, tables FROM meta ORDER BY log_id").column("tables").to_pylist() == [
        ["tags"],
        ["tags"],
        ["tags"],
    ]
    with pytest.raises(UnknownLogError, match="'Z'"):
        store.write_table_batch("tags", {"A": tags_table(["x"]), "Z": tags_table(["z"])})
    assert store.read_table("tags", log_ids=["A"]).column("tag").to_pylist() == ["a1", "a2"]


def test_read_table_returns_tracks_and_meta_too(store: ScenarioStore) -> None:
    store.replace_source("src", "h", [make_log("A"), make_log("B", n_peds=0)])
    tracks = store.read_table("tracks", log_ids=["B"])
    assert tracks.column_names[:3] == ["log_id", "track_id", "category"]
    assert tracks.num_rows == 12
    assert store.read_table("meta").column("n_tracks").to_pylist() == [3, 2]
    with pytest.raises(UnknownLogError):
        store.read_table("tracks", log_ids=["nope"])


def test_a_log_id_column_must_match_the_log(store: ScenarioStore) -> None:
    store.replace_source("src", "h", [make_log("A")])
    store.write_table("A", "tags", tags_table(["a"]).append_column("log_id", pa.array(["A"])))
    assert store.read_table("tags").column_names == ["log_id", "tag", "t_start_ns"]
    with pytest.raises(ValueError, match="log_id column with other values"):
        store.write_table("A", "tags", tags_table(["a"]).append_column("log_id", pa.array(["B"])))


@pytest.mark.parametrize("name", ["Tags", "1tags", "my-tags", "tracks", "meta", "select", ""])
def test_table_names_must_be_plain_identifiers(store: ScenarioStore, name: str) -> None:
    store.replace_source("src", "h", [make_log("A")])
    with pytest.raises(InvalidNameError):
        store.write_table("A", name, tags_table(["a"]))


def test_writing_a_table_for_an_unknown_log_is_an_error(store: ScenarioStore) -> None:
    with pytest.raises(UnknownLogError, match="'nope' is not in the store"):
        store.write_table("nope", "tags", tags_table(["a"]))


def test_delete_table_removes_it_everywhere(store: ScenarioStore) -> None:
    store.replace_source("src", "h", [make_log("A"), make_log("B")])
    for log_id in ("A", "B"):
        store.write_table(log_id, "tags", tags_table([log_id]))
    assert store.delete_table("tags") == 2
    with pytest.raises(UnknownTableError, match="available: tracks, meta"):
        store.read_table("tags")
    assert list((store.root / "logs").glob("*/*/tags.*.parquet")) == []
    with pytest.raises(InvalidNameError):
        store.delete_table("tracks")


# ---------------------------------------------------------------------- queries


def test_sql_over_tracks_and_meta_with_parameters(store: ScenarioStore) -> None:
    store.replace_source("src", "h", [make_log("A", n_peds=2), make_log("B", n_peds=0)])
    peds = store.sql(
        "SELECT log_id, count(DISTINCT track_id) AS n FROM tracks WHERE category = $cat "
        "GROUP BY 1 ORDER BY 1",
        {"cat": "PEDESTRIAN"},
    ).to_pydict()
    assert peds == {"log_id": ["A"], "n": [2]}
    meta = store.sql("SELECT log_id, n_tracks, n_frames, dataset FROM meta ORDER BY log_id").to_pydict()
    assert meta == {
        "log_id": ["A", "B"],
        "n_tracks": [4, 2],
        "n_frames": [20, 12],
        "dataset": ["synthetic"] * 2,
    }


def test_an_empty_store_answers_queries_with_no_rows(store: ScenarioStore) -> None:
    assert store.sql("SELECT count(*) AS n FROM tracks").column("n").to_pylist() == [0]
    assert store.sql("SELECT * FROM meta").num_rows == 0


def test_a_bad_query_names_the_available_views(store: ScenarioStore) -> None:
    store.replace_source("src", "h", [make_log("A")])
    with pytest.raises(QueryError, match="views: tracks, meta"):
        store.sql("SELECT * FROM tags")


# ---------------------------------------------------------------------- removal, info, maintenance


def test_remove_log_deletes_its_files_and_forgets_its_source(store: ScenarioStore) -> None:
    store.replace_source("src", "h", [make_log("A"), make_log("B")])
    store.write_table("A", "tags", tags_table(["a"]))
    store.remove_log("A")
    assert store.log_ids() == ["B"]
    assert not (store.root / "logs" / "A").exists()
    assert store.sql("SELECT DISTINCT log_id FROM tracks").column("log_id").to_pylist() == ["B"]
    assert store.needs_ingest("src", "h")  # the next ingestion restores A
    with pytest.raises(UnknownLogError):
        store.remove_log("A")
    with pytest.raises(UnknownLogError):
        store.load_log("A")


def test_remove_source_deletes_all_its_logs(store: ScenarioStore) -> None:
    store.replace_source("s1", "h", [make_log("A"), make_log("B")])
    store.replace_source("s2", "h", [make_log("C")])
    assert store.remove_source("s1") == ["A", "B"]
    assert store.log_ids() == ["C"]
    assert [s.source_key for s in store.sources()] == ["s2"]


def test_info_counts_what_the_store_holds(store: ScenarioStore) -> None:
    store.replace_source("s1", "h", [make_log("A", n_t=6, n_peds=2), make_log("B", n_t=11, n_peds=0)])
    store.write_table("A", "tags", tags_table(["a"]))
    info = store.info()
    assert (info.n_sources, info.n_logs, info.n_tracks, info.n_timestamps) == (1, 2, 6, 17)
    assert info.n_frames == (12 + 2 * 4) + 22
    assert info.total_duration_s == pytest.approx(0.5 + 1.0)
    assert info.categories == {"EGO_VEHICLE": 2, "PEDESTRIAN": 2, "REGULAR_VEHICLE": 2}
    assert info.datasets == {"synthetic": 2}
    assert info.tables == ("tags",)
    assert info.table_logs == {"tags": 1}
    assert info.size_bytes > 0
    assert info.root == store.root


def _dead_pid() -> int:
    """The id of a process that has exited."""
    import subprocess
    import sys

    child = subprocess.Popen([sys.executable, "-c", "pass"])
    child.wait()
    return child.pid


def test_vacuum_removes_orphans_but_not_fresh_staging(store: ScenarioStore) -> None:
    store.replace_source("src", "h", [make_log("A")])
    orphan = store.root / "logs" / "A" / "deadbeef"
    orphan.mkdir()
    (orphan / "tracks.parquet").write_bytes(b"partial")
    old_staging = store.root / ".staging" / "123-old"
    old_staging.mkdir(parents=True)
    os.utime(old_staging, (time.time() - 7200, time.time() - 7200))
    fresh_staging = store.root / ".staging" / f"{os.getpid()}-fresh"  # a live writer's
    fresh_staging.mkdir()
    dead_staging = store.root / ".staging" / f"{_dead_pid()}-dead"  # fresh, but its writer is gone
    dead_staging.mkdir()
    check = store.check()
    assert check.ok and "logs/A/deadbeef" in check.orphaned_files
    assert set(check.stale_staging) == {".staging/123-old", f".staging/{dead_staging.name}"}
    assert store.vacuum() == 3
    assert not orphan.exists() and not old_staging.exists() and not dead_staging.exists()
    assert fresh_staging.exists()
    assert store.check().orphaned_files == () and store.check().stale_staging == ()
    assert store.load_log("A").log_id == "A"


# ---------------------------------------------------------------------- opening


def test_a_non_empty_directory_without_store_json_is_refused_and_left_alone(tmp_path: Path) -> None:
    (tmp_path / "notes.txt").write_text("mine")
    with pytest.raises(NotAStoreError, match="not empty and has no store.json"):
        ScenarioStore.open(tmp_path)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["notes.txt"]


def test_a_file_or_a_missing_directory_without_create_is_refused(tmp_path: Path) -> None:
    (tmp_path / "f").write_text("x")
    with pytest.raises(NotAStoreError, match="is a file"):
        ScenarioStore.open(tmp_path / "f")
    with pytest.raises(NotAStoreError, match="no store here"):
        ScenarioStore.open(tmp_path / "missing", create=False)
    assert not (tmp_path / "missing").exists()


def test_a_store_from_a_newer_version_is_refused(tmp_path: Path) -> None:
    ScenarioStore.open(tmp_path / "s")
    (tmp_path / "s" / "store.json").write_text(
        json.dumps({"format": "scenariominer-store", "schema_version": 99})
    )
    with pytest.raises(StoreVersionError, match="version 99"):
        ScenarioStore.open(tmp_path / "s")


def test_reopening_a_store_sees_its_content(tmp_path: Path) -> None:
    ScenarioStore.open(tmp_path / "s").replace_source("src", "h", [make_log("A")])
    assert ScenarioStore.open(tmp_path / "s", create=False).log_ids() == ["A"]


def test_store_path_precedence_is_argument_then_env_then_config_then_default(tmp_path: Path) -> None:
    env = {"SCENARIOMINER_STORE": str(tmp_path / "env")}
    assert resolve_store_path(tmp_path / "arg", "cfg", environ=env) == tmp_path / "arg"
    assert resolve_store_path(None, str(tmp_path / "cfg"), environ=env) == tmp_path / "env"
    assert resolve_store_path(None, str(tmp_path / "cfg"), environ={}) == tmp_path / "cfg"
    assert resolve_store_path(None, "", environ={}) == default_store_path()
    assert default_store_path().name == "store"
    assert resolve_store_path("~/s", environ={}) == Path.home() / "s"
