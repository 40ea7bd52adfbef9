"""'stopped car' on a third real log, mined by the product and scored by the official evaluator.

tests/real_data/av2/3bffdcff-... is the second log of av2-api's scenario-mining test data, with
its official ground truth for "stopped car" (tests/real_data/av2/scenario_mining_gt_3bffdcff.pkl;
see tests/real_data/README.md). The ground truth refers to the parked cars too, so the phrase
rules read "stopped" as at rest at the timestamp, parked included; reading it as momentarily
stopped only (``has_velocity`` alone, the rules' old sense) scores far lower.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from typer.testing import CliRunner

from scenariominer.cli import app
from scenariominer.eval.mining import evaluate_mining_files

REAL = Path(__file__).resolve().parents[1] / "real_data" / "av2"
LOG = REAL / "3bffdcff-c3a7-38b6-a0f2-64196d130958"
GT = REAL / "scenario_mining_gt_3bffdcff.pkl"

MOMENTARY_ONLY = """
cars = get_objects_of_category(log_dir, category='REGULAR_VEHICLE')
stopped = has_velocity(cars, log_dir, min_velocity=0, max_velocity=0.5)
output_scenario(stopped, description, log_dir, output_dir)
"""


def _mine(tmp_path: Path, name: str, *extra: str) -> tuple[str, Path]:
    out = tmp_path / f"{name}.pkl"
    args = ["mine", "stopped car", "--logs", str(LOG), "--no-bank", "--export", "av2", "--out", str(out)]
    res = CliRunner().invoke(app, [*args, "--store", str(tmp_path / name), *extra])
    assert res.exit_code == 0, res.output
    return res.output, out


@pytest.mark.slow  # imports av2's evaluator (torch) and runs TrackEval twice
def test_stopped_car_is_read_by_the_rules_and_scores_well_against_the_official_ground_truth(
    tmp_path: Path,
) -> None:
    output, pred = _mine(tmp_path, "rules")
    assert "read by the phrase rules" in output and "stationary(subject, log_dir)" in output
    ev = evaluate_mining_files(pred, GT, REAL)
    assert ev.timestamp_f1 == 1.0
    assert ev.hota_temporal > 0.8 and ev.hota_track > 0.9  # measured 0.856 and 0.941

    program = tmp_path / "momentary.py"
    program.write_text(MOMENTARY_ONLY, encoding="utf-8")
    _, momentary = _mine(tmp_path, "momentary", "--program", str(program))
    assert evaluate_mining_files(momentary, GT, REAL).hota_temporal < 0.3  # measured 0.264
