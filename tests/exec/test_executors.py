"""The executor contract (order, failure isolation, retries, worker death, cancellation) for each backend."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import pytest

from scenariominer.errors import ExecutorError
from scenariominer.exec import CANCELLED, InlineExecutor, ItemOutcome, ProcessExecutor, make_executor
from scenariominer.exec.base import Executor
from scenariominer.testing.faults import DieOnce, FailOnce, Square

ITEMS = list(range(8))


@pytest.fixture(params=["local", "process", "ray"])
def executor(request: pytest.FixtureRequest) -> Iterator[Executor]:
    ex: Executor
    if request.param == "ray":
        ex = request.getfixturevalue("ray_executor")
    elif request.param == "process":
        ex = ProcessExecutor(2, retries=2, min_items=1)
    else:
        ex = InlineExecutor(retries=2)
    yield ex
    ex.close()


def test_results_come_back_in_item_order_with_keys(executor: Executor) -> None:
    outcomes = executor.map(Square(), ITEMS, keys=[f"k{i}" for i in ITEMS])
    assert [o.value for o in outcomes] == [i * i for i in ITEMS]
    assert [o.key for o in outcomes] == [f"k{i}" for i in ITEMS]
    assert all(o.ok and o.attempts == 1 for o in outcomes)


def test_a_failing_item_is_reported_and_the_rest_go_on(executor: Executor) -> None:
    seen: list[ItemOutcome[int]] = []
    outcomes = executor.map(Square(bad=(3, 5)), ITEMS, on_outcome=seen.append)
    failed = {o.key: o.error for o in outcomes if not o.ok}
    assert failed == {"3": "ValueError: item 3 is bad", "5": "ValueError: item 5 is bad"}
    assert [o.value for o in outcomes if o.ok] == [i * i for i in ITEMS if i not in (3, 5)]
    assert sorted(o.key for o in seen) == sorted(str(i) for i in ITEMS)  # progress saw every item


def test_transient_errors_are_retried(executor: Executor, tmp_path: Path) -> None:
    outcomes = executor.map(FailOnce(str(tmp_path)), ITEMS)
    assert [o.value for o in outcomes] == [i * i for i in ITEMS]
    assert all(o.attempts == 2 for o in outcomes)


def test_transient_errors_fail_once_retries_are_spent(tmp_path: Path) -> None:
    outcomes = InlineExecutor(retries=0).map(FailOnce(str(tmp_path)), [1, 2])
    assert [o.error for o in outcomes] == [
        "TransientError: item 1: busy, try again",
        "TransientError: item 2: busy, try again",
    ]


def test_a_dead_worker_is_replaced_and_its_item_retried(tmp_path: Path) -> None:
    ex = ProcessExecutor(2, retries=2, min_items=1)
    try:
        outcomes = ex.map(DieOnce(str(tmp_path), victim=4), ITEMS)
    finally:
        ex.close()
    assert [o.value for o in outcomes] == [i * i for i in ITEMS]
    assert outcomes[4].attempts >= 2  # the victim ran again in a fresh pool


def test_a_worker_that_keeps_dying_is_reported_without_losing_the_others(tmp_path: Path) -> None:
    ex = ProcessExecutor(2, retries=0, min_items=1)
    try:
        outcomes = ex.map(DieOnce(str(tmp_path), victim=4), ITEMS)
    finally:
        ex.close()
    assert outcomes[4].error.startswith("WorkerDied")
    # Items running beside the victim when the pool broke fail too (no retries left); every other
    # item finished with its value.
    assert all(o.value == int(o.key) ** 2 for o in outcomes if o.ok)
    assert sum(o.ok for o in outcomes) >= len(ITEMS) - 2


def test_cancel_stops_the_run_and_reports_unfinished_items(executor: Executor) -> None:
    def stop_after_first(_outcome: ItemOutcome[int]) -> None:
        executor.cancel()

    outcomes = executor.map(Square(), ITEMS, on_outcome=stop_after_first)
    done = [o for o in outcomes if o.ok]
    assert 1 <= len(done) < len(ITEMS)
    assert all(o.error == CANCELLED for o in outcomes if not o.ok)


def test_few_items_run_in_process_without_a_pool() -> None:
    ex = ProcessExecutor(2, min_items=4)
    assert [o.value for o in ex.map(Square(), [1, 2, 3])] == [1, 4, 9]
    assert ex.worker_pids() == []  # no pool was started


def test_make_executor_names() -> None:
    assert make_executor(name="local").name == "local"
    assert make_executor(name="process").name == "process"
    with pytest.raises(ExecutorError, match="unknown executor 'dask'"):
        make_executor(name="dask")


def test_keys_must_match_items() -> None:
    with pytest.raises(ValueError, match="2 keys for 3 items"):
        InlineExecutor().map(Square(), [1, 2, 3], keys=["a", "b"])
