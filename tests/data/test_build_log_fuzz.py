"""Random malformed long tables: build_log and preprocess end in a log or a LogFormatError, nothing else.

Each table mixes the defects the bad-input corpus covers one at a time (NaN/inf/huge coordinates,
zero or negative or NaN sizes, duplicate and near-coincident timestamps, one-row tracks, a NUL in an
id, a missing or wrong ego id, a track changing category), so that their combinations are tried
too. Seeded: a failure names its trial and replays.
"""

from __future__ import annotations

import numpy as np
import pytest

from scenariominer.data.log import LogFormatError, build_log
from scenariominer.data.preprocess import preprocess

_OTHERS = ["BUS", "PEDESTRIAN", "REGULAR_VEHICLE"]


def _random_table(rng: np.random.Generator) -> dict[str, object]:
    m = int(rng.integers(1, 30))
    track = rng.choice(["e", "a", "b", "c", "a\x00", ""], m)
    category = np.where(track == "e", "EGO_VEHICLE", rng.choice(_OTHERS, m))
    if rng.random() < 0.1:
        category[rng.integers(m)] = rng.choice(["EGO_VEHICLE", *_OTHERS])
    t_ns = rng.integers(0, 6, m) * rng.choice([1, 1000, 100_000_000])
    if rng.random() < 0.1:
        t_ns = t_ns + rng.integers(0, 3, m)
    fields = {k: rng.normal(size=m) * 10 for k in ("x_m", "y_m", "yaw_rad")}
    fields["length_m"] = rng.choice([4.0, 0.0, -1.0, np.nan], m, p=[0.85, 0.05, 0.05, 0.05])
    fields["width_m"] = np.full(m, 2.0)
    for k in ("x_m", "y_m"):
        if rng.random() < 0.2:
            fields[k][rng.integers(m)] = rng.choice([np.nan, np.inf, 1e300])
    ego = None if rng.random() < 0.5 else str(rng.choice(["e", "a", "zz"]))
    return {
        "track_id": track, "category": category, "timestamp_ns": t_ns, "fields": fields, "ego_track_id": ego,
    }  # fmt: skip


@pytest.mark.parametrize("seed", range(4))
def test_random_malformed_tables_give_a_log_or_a_clear_error(seed: int) -> None:
    rng = np.random.default_rng(seed)
    outcomes = {"log": 0, "error": 0}
    for trial in range(500):
        table = _random_table(rng)
        try:
            log = build_log(log_id="L", source="fuzz.csv", **table)  # type: ignore[arg-type]
            preprocess(log)
        except LogFormatError as exc:
            assert str(exc).startswith("fuzz.csv: "), exc
            outcomes["error"] += 1
        except Exception as exc:  # noqa: BLE001  # the point: anything else is a bug
            pytest.fail(f"seed {seed}, trial {trial}: {type(exc).__name__}: {exc}\n{table}")
        else:
            outcomes["log"] += 1
    assert outcomes["log"] >= 3 and outcomes["error"] >= 100, outcomes  # both paths were exercised
