"""A private local Ray cluster (2 CPUs on loopback) shared by the executor tests; skipped without ray."""

from __future__ import annotations

from collections.abc import Iterator

import pytest

from scenariominer.exec.base import Executor


@pytest.fixture(scope="session")
def ray_executor() -> Iterator[Executor]:
    ray = pytest.importorskip("ray")
    from scenariominer.exec.ray_executor import RayExecutor

    ex = RayExecutor("", 2, init_kwargs={"object_store_memory": 200 * 2**20})
    yield ex
    ray.shutdown()
