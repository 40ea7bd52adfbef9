"""The AV2 export re-reads each mined log from its source, through the reader of its format."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from scenariominer.api.mining import raw_logs_for
from scenariominer.config import Config
from scenariominer.data.adapters.av2 import read_av2_log
from scenariominer.data.preprocess import preprocess


def test_smoothed_logs_are_replaced_by_their_raw_source(av2_log_dir: Path) -> None:
    raw = read_av2_log(av2_log_dir)
    smoothed = preprocess(raw)
    assert not np.allclose(smoothed.x_m[raw.valid], raw.x_m[raw.valid])  # smoothing moved something
    got = raw_logs_for([smoothed], Config())[raw.log_id]
    np.testing.assert_array_equal(got.x_m[raw.valid], raw.x_m[raw.valid])
    assert got.ego_pose_offset_m == raw.ego_pose_offset_m


def test_logs_without_a_readable_source_are_kept(av2_log_dir: Path, tmp_path: Path) -> None:
    log = preprocess(read_av2_log(av2_log_dir))
    gone = log.replace(source_path=tmp_path / "gone")
    unknown = log.replace(log_id="other", dataset="no-such-format")
    out = raw_logs_for([gone, unknown], Config())
    assert out[log.log_id] is gone and out["other"] is unknown
