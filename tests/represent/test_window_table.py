"""Windows in the store: round trip, incremental building, failures that spare the rest."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from scenariominer.config.represent import WindowConfig
from scenariominer.data.log import Log
from scenariominer.represent.errors import NoWindowsError
from scenariominer.represent.pipeline import build_store_windows
from scenariominer.represent.window_table import WINDOWS_TABLE, load_windows, log_window_records
from scenariominer.represent.windows import extract_windows
from scenariominer.store import ScenarioStore
from scenariominer.testing import LogBuilder, times

CONFIG = WindowConfig(lengths_s=(4.0,), overlap=0.5, n_steps=8, k_neighbours=2)


def built_log(log_id: str, speed_mps: float = 10.0) -> Log:
    """An ego with one car ahead and one behind, 10 s at 10 Hz."""
    t = times(10.0)
    return (
        LogBuilder(t, log_id=log_id)
        .ego(speed_mps=speed_mps)
        .add("ahead", "REGULAR_VEHICLE", speed_mps=speed_mps, x0_m=15.0)
        .add("behind", "TRUCK", speed_mps=speed_mps, x0_m=-25.0, y0_m=3.5)
        .build()
    )


def add_logs(store: ScenarioStore, *logs: Log, source_hash: str = "h1") -> None:
    """Put hand-built logs in the store, one source each."""
    for log in logs:
        store.replace_source(f"src-{log.log_id}", source_hash, [log.replace(source_hash=source_hash)])


def test_round_trip_gives_the_same_arrays(tmp_path: Path) -> None:
    store = ScenarioStore.open(tmp_path / "store")
    add_logs(store, built_log("a"))
    report = build_store_windows(store, CONFIG)
    assert [(r.log_id, r.status, r.n_windows) for r in report.logs] == [("a", "built", 4)]
    loaded = load_windows(store)
    direct = extract_windows(store.load_log("a"), CONFIG)
    order = np.argsort(direct.window_ids)
    np.testing.assert_array_equal(loaded.window_ids, direct.window_ids[order])
    np.testing.assert_array_equal(loaded.xy_m, direct.xy_m[order])
    np.testing.assert_array_equal(loaded.valid, direct.valid[order])
    np.testing.assert_array_equal(loaded.track_ids, direct.track_ids[order])
    np.testing.assert_array_equal(loaded.start_ns, direct.start_ns[order])


def test_adding_a_log_cuts_its_windows_only(tmp_path: Path) -> None:
    store = ScenarioStore.open(tmp_path / "store")
    add_logs(store, built_log("a"))
    build_store_windows(store, CONFIG)
    version_before = store.corpus(WINDOWS_TABLE).info().version
    rows_a = {r.key: r.version for r in store.corpus(WINDOWS_TABLE).rows()}
    add_logs(store, built_log("b", speed_mps=20.0))
    report = build_store_windows(store, CONFIG)
    assert {r.log_id: r.status for r in report.logs} == {"a": "current", "b": "built"}
    rows_after = {r.key: r.version for r in store.corpus(WINDOWS_TABLE).rows()}
    # a's rows were not rewritten; b's were written in one later version
    assert {k: v for k, v in rows_after.items() if k.startswith("a|")} == rows_a
    assert {v for k, v in rows_after.items() if k.startswith("b|")} == {version_before + 1}
    assert len(load_windows(store, log_ids=["b"])) == 4


def test_a_changed_log_or_setting_recuts_and_drops_stale_windows(tmp_path: Path) -> None:
    store = ScenarioStore.open(tmp_path / "store")
    add_logs(store, built_log("a"))
    build_store_windows(store, CONFIG)
    add_logs(store, built_log("a", speed_mps=5.0), source_hash="h2")
    assert build_store_windows(store, CONFIG).logs[0].status == "built"
    longer = WindowConfig(lengths_s=(8.0,), n_steps=8, k_neighbours=2)
    report = build_store_windows(store, longer)
    assert report.logs[0].n_windows == 1
    assert store.corpus(WINDOWS_TABLE).keys() == ["a|ego|0|8000"]
    assert log_window_records(store)["a"].window_ids == ("a|ego|0|8000",)


def test_an_unknown_log_fails_alone(tmp_path: Path) -> None:
    store = ScenarioStore.open(tmp_path / "store")
    add_logs(store, built_log("a"))
    report = build_store_windows(store, CONFIG, log_ids=["missing", "a"])
    assert [r.status for r in report.logs] == ["failed", "built"]
    assert "missing" in report.failed[0].error
    assert report.n_windows == 4


def test_loading_from_an_empty_store_names_the_fix(tmp_path: Path) -> None:
    store = ScenarioStore.open(tmp_path / "store")
    with pytest.raises(NoWindowsError, match="embed windows"):
        load_windows(store)
