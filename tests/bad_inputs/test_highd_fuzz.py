"""Random edits of a small highD recording's three CSV files: each recording is ingested or fails
with a clear error, never with an unexpected exception, with numeric warnings as errors.

Edits: odd cell values (empty, NaN, inf, 1e300, text, markup, NUL, a ';' list), dropped or renamed
columns, removed and duplicated rows. Seeded: a failure names its seed and trial and replays.
"""

from __future__ import annotations

import random
import shutil
import warnings
from pathlib import Path

from highd_files import edit_csv, highd_config, write_small_highway

from scenariominer.data.ingest import MemorySink, ingest_sources

_ODD = [
    "", "nan", "inf", "-inf", "1e300", "-1e300", "abc", "0", "-1", "9" * 30, "1;2", "[/x]", "\x00",
    "2.5", "-0",
]  # fmt: skip


def _edit(rows: list[list[str]], rnd: random.Random) -> list[list[str]]:
    kind = rnd.random()
    if kind < 0.6 and len(rows) > 1:
        i = rnd.randrange(1, len(rows))
        rows[i][rnd.randrange(len(rows[i]))] = rnd.choice(_ODD)
    elif kind < 0.7:
        j = rnd.randrange(len(rows[0]))
        rows = [row[:j] + row[j + 1 :] for row in rows]
    elif kind < 0.8 and len(rows) > 2:
        rows.pop(rnd.randrange(1, len(rows)))
    elif kind < 0.9 and len(rows) > 1:
        rows.append(list(rows[rnd.randrange(1, len(rows))]))
    else:
        rows[0][rnd.randrange(len(rows[0]))] = rnd.choice(["id", "frame", "x", "", "ID "])
    return rows


def test_random_highd_edits_are_ingested_or_refused_clearly(tmp_path: Path) -> None:
    rnd = random.Random(2)
    good = tmp_path / "good"
    write_small_highway(good)
    names = sorted(f.name for f in good.iterdir())
    statuses = {"ingested": 0, "failed": 0}
    for trial in range(180):
        folder = tmp_path / f"t{trial}"
        shutil.copytree(good, folder)
        for _ in range(rnd.randint(1, 3)):
            edit_csv(folder / rnd.choice(names), lambda rows: _edit(rows, rnd))
        with warnings.catch_warnings():
            warnings.simplefilter("error", RuntimeWarning)
            results = ingest_sources([folder], MemorySink(), highd_config())
        for result in results:
            statuses[result.status] += 1
            assert "unexpected" not in result.error, f"trial {trial}: {result.error}"
        shutil.rmtree(folder)
    assert statuses["ingested"] >= 30 and statuses["failed"] >= 30, statuses
