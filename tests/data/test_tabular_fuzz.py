"""Random edits of a small fleet CSV: each file is ingested or fails with a clear error, never with
an unexpected exception (which the ingest loop reports as "unexpected ...; please report it").

Edits: odd cell values (empty, NaN, inf, 1e400, text, markup, escape and bidi characters, NUL,
numbers too large for 64 bits), dropped or renamed columns, duplicated and removed rows.
Seeded: a failure names its seed and trial and replays.
"""

from __future__ import annotations

import csv
import io
import random
from pathlib import Path

import pytest

from scenariominer.config import Config
from scenariominer.data.ingest import MemorySink, ingest_sources

_COLUMNS = [
    "log_id", "track_id", "timestamp_ns", "category", "x_m", "y_m", "yaw_rad", "length_m", "width_m",
    "vx_mps", "vy_mps", "is_ego", "timestamp_s", "z_m", "height_m",
]  # fmt: skip
_ODD = [
    "", "nan", "inf", "-inf", "1e400", "abc", "[/x]", "\x1b[31m", "true", "TRUE", "2", "-1", "0x10", "1,5",
    " 3 ", "\u202e", "18446744073709551615", "9" * 40, "None", "null", '"', "é", "\x00",
]  # fmt: skip
_T0 = 1_700_000_000_000_000_000


def _rows() -> list[list[str]]:
    rows = []
    for t in range(5):
        stamp = str(_T0 + t * 100_000_000)
        rows.append(["L1", "ego", stamp, "EGO_VEHICLE", str(float(t)), "0", "0", "4.9", "2.0", "10", "0",
                     "true", "", "0", "1.5"])  # fmt: skip
        rows.append(["L1", "p7", stamp, "PEDESTRIAN", "20", "-3", "1.57", "0.6", "0.6", "0", "1.5", "false",
                     "", "0", "1.5"])  # fmt: skip
        rows.append(["L2", "e2", str(t), "car", "1", "1", "0", "4", "2", "", "", "1", "", "", ""])
    return rows


def _edited_csv(rnd: random.Random) -> str:
    columns, rows = list(_COLUMNS), _rows()
    for _ in range(rnd.randint(1, 4)):
        r = rnd.random()
        if r < 0.6:
            rows[rnd.randrange(len(rows))][rnd.randrange(len(columns))] = rnd.choice(_ODD)
        elif r < 0.7:
            i = rnd.randrange(len(columns))
            columns.pop(i)
            for row in rows:
                row.pop(i)
        elif r < 0.8:
            rows.append(list(rows[rnd.randrange(len(rows))]))
        elif r < 0.9 and len(rows) > 1:
            rows.pop(rnd.randrange(len(rows)))
        else:
            columns[rnd.randrange(len(columns))] = rnd.choice(["x_m", "log_id", "", "X_M", "track_id "])
    buffer = io.StringIO()
    writer = csv.writer(buffer)
    writer.writerow(columns)
    writer.writerows(rows)
    return buffer.getvalue()


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_random_csv_edits_are_ingested_or_refused_clearly(seed: int, tmp_path: Path) -> None:
    rnd = random.Random(seed)
    statuses = {"ingested": 0, "failed": 0}
    for trial in range(500):
        path = tmp_path / f"fleet{trial}.csv"
        path.write_text(_edited_csv(rnd), encoding="utf-8")
        for result in ingest_sources([path], MemorySink(), Config()):
            statuses[result.status] += 1
            assert "unexpected" not in result.error, f"seed {seed}, trial {trial}: {result.error}"
            assert result.status == "ingested" or result.error.startswith(str(path)), result.error
    assert statuses["ingested"] >= 50 and statuses["failed"] >= 200, statuses
