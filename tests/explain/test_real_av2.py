"""The pipeline's pure stage and the picture on the real Argoverse 2 sample log (slow: real data)."""

from __future__ import annotations

from pathlib import Path

import pytest

from scenariominer.config import Config
from scenariominer.data.adapters.av2 import read_av2_log
from scenariominer.data.adapters.av2.map import read_av2_map
from scenariominer.data.log import Log
from scenariominer.data.preprocess import preprocess
from scenariominer.explain.categories import CategorySet
from scenariominer.explain.pipeline import LogOutcome, LogStatus, analyze_log
from scenariominer.explain.show import render_event

pytestmark = pytest.mark.slow


@pytest.fixture(scope="module")
def outcome(av2_log_dir: Path) -> tuple[Log, LogOutcome]:
    log = preprocess(read_av2_log(av2_log_dir))
    return log, analyze_log(log, Config(), CategorySet.default(), None)


def test_real_log_yields_described_pending_events(outcome: tuple[Log, LogOutcome]) -> None:
    log, result = outcome
    assert result.status is LogStatus.ANALYZED
    assert result.records, "the sample log has braking with risky objects"
    for r in result.records:
        assert r.llm_status == "pending" and r.category == r.baseline_category  # the rules' result, for now
        assert f"smallest gap: {r.min_distance_m:.1f} m" in r.facts
        assert r.tag_description.startswith("Overview: a ")
        assert r.guest_id in set(log.track_ids.tolist())
        assert r.peak_decel_mps2 >= 0.0 and r.min_ttc_s > 0.0
        assert r.baseline_category in {"cut_in", "left_oppo", "right_ped", "obj_crossing", "not_relevant"}


def test_real_log_picture_with_map(
    outcome: tuple[Log, LogOutcome], av2_log_dir: Path, tmp_path: Path
) -> None:
    log, result = outcome
    out = render_event(
        log, result.records[0], tmp_path / "av2.png", av2_map=read_av2_map(av2_log_dir), dpi=60
    )
    assert out.read_bytes().startswith(b"\x89PNG")
