"""``ingest``, ``analyze``, ``mine`` and ``embed windows`` give identical stored results on every
executor, and a killed worker loses nothing committed (a re-run completes only what is missing)."""

from __future__ import annotations

import multiprocessing
import os
import signal
from collections.abc import Callable
from dataclasses import replace
from pathlib import Path

import numpy as np
import pyarrow as pa
import pyarrow.compute as pc
import pytest

from scenariominer import api
from scenariominer.config import Config, load_config
from scenariominer.exec import InlineExecutor, ProcessExecutor
from scenariominer.exec.base import Executor
from scenariominer.mine.programs import load_examples
from scenariominer.represent.window_table import load_windows
from scenariominer.store import ScenarioStore

N_LOGS = 10
BANK_QUERY = "vehicle braking hard"  # trusted bank program, run in-process by the worker
SANDBOXED = "vehicle following another vehicle"  # its bank text given as a user program: sandboxed
#: Columns that record when or how long something ran: they differ between any two runs.
VOLATILE = {"seconds", "analyzed_at", "execution_s", "mined_at", "created_at", "latency_s"}


@pytest.fixture(scope="module")
def logs_dir(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("synth") / "logs"
    api.synth(out, N_LOGS, seed=5)
    return out


@pytest.fixture(scope="module")
def config(tmp_path_factory: pytest.TempPathFactory) -> Config:
    path = tmp_path_factory.mktemp("cfg") / "cfg.toml"
    path.write_text('[embedding]\nbackend = "hashing"\nhashing_dim = 32\n[explain]\njudge = "rules"\n')
    return load_config(path)


def _table(store: ScenarioStore, name: str) -> pa.Table:
    table = store.read_table(name)
    keep = [c for c in table.column_names if c not in VOLATILE]
    table = table.select(keep)
    for i, field in enumerate(table.schema):  # NaN != NaN in Table.equals: compare NaN as null
        if pa.types.is_floating(field.type):
            column = table.column(i)
            table = table.set_column(i, field, pc.if_else(pc.is_nan(column), None, column))
    return table.sort_by([(c, "ascending") for c in keep if pa.types.is_string(table.schema.field(c).type)])


def _run_all(root: Path, logs_dir: Path, config: Config, executor: Executor) -> dict[str, object]:
    """Ingest, analyze and mine (a bank and a sandboxed program) on ``executor``; what was stored."""
    store = api.open_store(root, config)
    ingest = api.ingest([logs_dir], store, config, executor=executor)
    assert ingest.n_ingested == N_LOGS and not ingest.failed
    report = api.analyze(store, api.AnalyzeRequest(judge="rules"), config, executor=executor)
    assert report.n_failed == 0 and report.n_analyzed == N_LOGS
    program = next(e.program for e in load_examples(()) if e.description == SANDBOXED)
    for description, text in [(BANK_QUERY, None), (SANDBOXED, program)]:
        result = api.mine(api.MineRequest(description, store=store, program=text), config, executor=executor)
        assert not result.report.failures and result.report.n_logs == N_LOGS
    windows = api.build_windows(store, api.WindowsRequest(), config, executor=executor)
    assert windows.n_built == N_LOGS and not windows.failed
    cut = load_windows(store)
    return {
        "windows": {f: getattr(cut, f) for f in ("window_ids", "agent_ids", "track_ids", "xy_m", "valid")},
        "logs": {i: store.load_log(i).to_arrow() for i in store.log_ids()},
        **{name: _table(store, name) for name in ("events", "tags", "mining_results", "mining_runs")},
    }


@pytest.fixture(scope="module")
def reference(tmp_path_factory: pytest.TempPathFactory, logs_dir: Path, config: Config) -> dict[str, object]:
    return _run_all(tmp_path_factory.mktemp("local"), logs_dir, config, InlineExecutor())


def _assert_same(got: dict[str, object], want: dict[str, object]) -> None:
    assert got.keys() == want.keys()
    for field, array in want["windows"].items():  # type: ignore[attr-defined]
        assert array.size > 0 and np.array_equal(got["windows"][field], array), field  # type: ignore[index]
    assert got["logs"].keys() == want["logs"].keys()  # type: ignore[attr-defined]
    for log_id, table in want["logs"].items():  # type: ignore[attr-defined]
        assert got["logs"][log_id].equals(table), log_id  # type: ignore[index]
    for name in ("events", "tags", "mining_results", "mining_runs"):
        assert got[name].num_rows > 0, name  # type: ignore[attr-defined]
        assert got[name].equals(want[name]), name  # type: ignore[attr-defined]


def test_process_pool_stores_what_the_local_executor_stores(
    tmp_path: Path, logs_dir: Path, config: Config, reference: dict[str, object]
) -> None:
    ex = ProcessExecutor(2, min_items=1)
    try:
        _assert_same(_run_all(tmp_path / "store", logs_dir, config, ex), reference)
    finally:
        ex.close()


def test_ray_stores_what_the_local_executor_stores(
    tmp_path: Path, logs_dir: Path, config: Config, reference: dict[str, object], ray_executor: Executor
) -> None:
    _assert_same(_run_all(tmp_path / "store", logs_dir, config, ray_executor), reference)


class _Killer:
    """A progress sink that SIGKILLs the processes ``victims()`` names once an item has come back.

    With the pool, the other worker is then almost always in the middle of an item (the driver hands
    out the next item only after this callback), which dies with it; the assertions hold either
    way. If ``victims()`` names none at one item, the next item tries again.
    """

    def __init__(self, victims: Callable[[], list[int]]) -> None:
        self.victims = victims
        self.killed: list[int] = []

    def start(self, description: str, total: int | None) -> None:
        """Nothing to do."""

    def advance(self, n: int = 1, message: str | None = None) -> None:
        """Kill the victims once."""
        if not self.killed:
            for pid in self.victims():
                os.kill(pid, signal.SIGKILL)
                self.killed.append(pid)

    def finish(self) -> None:
        """Nothing to do."""


def test_a_killed_worker_loses_nothing_and_a_rerun_completes_only_the_missing_sources(
    tmp_path: Path, logs_dir: Path, config: Config, reference: dict[str, object]
) -> None:
    store = api.open_store(tmp_path / "store", config)
    ex = ProcessExecutor(2, retries=0, min_items=1)  # no retries: the killed pool's items fail
    killer = _Killer(ex.worker_pids)
    try:
        first = api.ingest([logs_dir], store, config, executor=ex, progress=killer)
    finally:
        ex.close()
    assert killer.killed
    lost = {r.key for r in first.failed}  # the items in flight when the pool died (almost always 1)
    assert all("WorkerDied" in r.error for r in first.failed)
    assert store.check().ok  # nothing half-written is visible
    committed = set(store.log_ids())  # a source's folder is named after its log
    assert committed | {Path(k).name for k in lost} == set(reference["logs"])  # type: ignore[call-overload]
    ex = ProcessExecutor(2, min_items=1)
    try:
        second = api.ingest([logs_dir], store, config, executor=ex)
    finally:
        ex.close()
    # Only the missing sources are read again; one killed after its commit is already there.
    missing = {k for k in lost if Path(k).name not in committed}
    assert {r.key for r in second.sources if r.status == "ingested"} == missing
    assert second.n_skipped == len(committed) and not second.failed
    for log_id, table in reference["logs"].items():  # type: ignore[attr-defined]
        assert store.load_log(log_id).to_arrow().equals(table)


def test_with_retries_a_killed_worker_is_invisible_to_the_user(
    tmp_path: Path, logs_dir: Path, config: Config, reference: dict[str, object]
) -> None:
    store = api.open_store(tmp_path / "store", config)
    ex = ProcessExecutor(2, retries=2, min_items=1)
    killer = _Killer(ex.worker_pids)
    try:
        report = api.ingest([logs_dir], store, config, executor=ex, progress=killer)
    finally:
        ex.close()
    assert killer.killed and not report.failed
    assert report.n_ingested + report.n_skipped == N_LOGS  # skipped: killed after its commit
    assert sorted(store.log_ids()) == sorted(reference["logs"])  # type: ignore[call-overload]


def _ray_task_pids() -> list[int]:
    """Ray worker processes running a task right now (Ray names them ``ray::<function>``)."""
    pids = []
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit():
            try:
                cmdline = (entry / "cmdline").read_bytes()
            except OSError:
                continue
            if cmdline.startswith(b"ray::_call"):
                pids.append(int(entry.name))
    return pids


@pytest.mark.skipif(not Path("/proc").is_dir(), reason="finds Ray's workers through /proc")
def test_ray_retries_the_tasks_of_a_killed_worker(
    tmp_path: Path, logs_dir: Path, config: Config, reference: dict[str, object], ray_executor: Executor
) -> None:
    store = api.open_store(tmp_path / "store", config)
    killer = _Killer(_ray_task_pids)
    report = api.ingest([logs_dir], store, config, executor=ray_executor, progress=killer)
    assert killer.killed  # a worker was busy and was killed
    # A task killed after its commit finds its source stored when Ray runs it again ("skipped").
    assert not report.failed and report.n_ingested + report.n_skipped == N_LOGS
    assert sorted(store.log_ids()) == sorted(reference["logs"])  # type: ignore[call-overload]
    assert store.check().ok
    for log_id, table in reference["logs"].items():  # type: ignore[attr-defined]
        assert store.load_log(log_id).to_arrow().equals(table)


def test_a_killed_analyze_worker_loses_nothing_and_a_rerun_analyses_only_the_missing_logs(
    tmp_path: Path, logs_dir: Path, config: Config, reference: dict[str, object]
) -> None:
    store = api.open_store(tmp_path / "store", config)
    api.ingest([logs_dir], store, config, executor=InlineExecutor())
    ex = ProcessExecutor(2, retries=0, min_items=1)
    killer = _Killer(ex.worker_pids)
    try:
        first = api.analyze(store, api.AnalyzeRequest(judge="rules"), config, progress=killer, executor=ex)
    finally:
        ex.close()
    lost = {r.log_id for r in first.logs if r.status.value == "failed"}
    assert killer.killed
    assert all("WorkerDied" in r.error for r in first.logs if r.log_id in lost)
    assert store.check().ok
    ex = ProcessExecutor(2, min_items=1)
    try:
        second = api.analyze(store, api.AnalyzeRequest(judge="rules"), config, executor=ex)
    finally:
        ex.close()
    again = {r.log_id for r in second.logs if r.status.value == "analyzed"}
    assert again <= lost  # only logs whose worker died (one killed after its commit is complete)
    assert second.n_unchanged == N_LOGS - len(again) and second.n_failed == 0
    for name in ("events", "tags"):
        assert _table(store, name).equals(reference[name]), name


class _ChildCounter:
    """A progress sink that records how many child processes run as each item comes back."""

    def __init__(self) -> None:
        self.children: list[int] = []

    def start(self, description: str, total: int | None) -> None:
        """Nothing to do."""

    def advance(self, n: int = 1, message: str | None = None) -> None:
        """Count the live children."""
        self.children.append(len(multiprocessing.active_children()))

    def finish(self) -> None:
        """Nothing to do."""


@pytest.mark.parametrize(("workers", "pooled"), [(2, False), (3, True)])
def test_the_default_ingest_runs_here_unless_the_pool_has_more_than_two_workers(
    tmp_path: Path, logs_dir: Path, config: Config, workers: int, pooled: bool
) -> None:
    cfg = replace(config, exec=replace(config.exec, workers=workers, min_ingest_bytes=0))
    counter = _ChildCounter()
    report = api.ingest([logs_dir], api.open_store(tmp_path / "store", cfg), cfg, progress=counter)
    assert report.n_logs_ingested == N_LOGS and not report.failed
    assert len(counter.children) == N_LOGS
    assert (max(counter.children) >= workers) if pooled else (max(counter.children) == 0)
