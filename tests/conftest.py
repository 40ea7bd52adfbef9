"""Shared fixtures: the real Argoverse 2 sample log kept beside the repository in ``../shared/data``.

CI clones the repository with ``shared/`` next to it, so the data is found relative to the repo
root rather than copied into it. Tests that need it are skipped (with the reason) when it is absent.
"""

from __future__ import annotations

from pathlib import Path

import pytest

#: Timeout of tests marked ``slow`` (the first call of the embedded model in a process can take
#: minutes on 2 cores); the default for the others is ``timeout`` in pyproject.toml.
SLOW_TIMEOUT_S = 1800


def pytest_collection_modifyitems(items: list[pytest.Item]) -> None:
    """Give slow tests the longer timeout unless they set their own."""
    for item in items:
        if item.get_closest_marker("slow") and not item.get_closest_marker("timeout"):
            item.add_marker(pytest.mark.timeout(SLOW_TIMEOUT_S))


SHARED_DATA = Path(__file__).resolve().parents[1].parent / "shared" / "data"
AV2_LOG_ID = "3b3570b4-7b0b-3268-a571-b0889dbf40b6"


@pytest.fixture(scope="session")
def av2_log_dir() -> Path:
    """Folder of the real Argoverse 2 sample log (annotations, poses, vector map)."""
    path = SHARED_DATA / "av2" / AV2_LOG_ID
    if not (path / "annotations_with_ego.feather").is_file():
        pytest.skip(f"shared Argoverse 2 sample log not found at {path} (expected ../shared beside the repo)")
    return path


@pytest.fixture(scope="session")
def av2_gt_pkl() -> Path:
    """Ground-truth pickle of the Argoverse 2 scenario-mining task for the sample log."""
    path = SHARED_DATA / "av2" / "scenario_mining_gt_3b3570b4.pkl"
    if not path.is_file():
        pytest.skip(
            f"shared scenario-mining ground truth not found at {path} (expected ../shared beside the repo)"
        )
    return path
