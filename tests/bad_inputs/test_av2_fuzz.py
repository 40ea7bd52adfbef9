"""Random edits of a small Argoverse 2 log folder's Feather files: each folder is ingested or fails
with a clear error naming it, never with an unexpected exception, with numeric warnings as errors
(an overflow or an invalid value means a garbage number got through).

Edits: odd values in one cell (NaN, inf, 1e300, 2**62, empty or markup text, NUL), nulls, dropped
or retyped columns, removed and duplicated rows, in the annotations and the ego poses.
Seeded: a failure names its seed and trial and replays.
"""

from __future__ import annotations

import random
import shutil
import warnings
from pathlib import Path

import numpy as np
import pyarrow as pa
import pyarrow.feather as feather
import pytest
from bad_av2 import ANN, av2_folder

from scenariominer.config import Config
from scenariominer.data.adapters.av2 import POSES_FILE
from scenariominer.data.ingest import MemorySink, ingest_sources

_FLOATS = [np.nan, np.inf, -np.inf, 1e300, -1e300, 0.0, -1.0, 2.0**62, -(2.0**62)]
_TEXTS = ["", "\x00", "[/x]", "EGO_VEHICLE", "BUS", "x" * 1000]


def _edit(table: pa.Table, rnd: random.Random) -> pa.Table:
    name = rnd.choice(table.column_names)
    i = table.column_names.index(name)
    kind = rnd.random()
    if kind < 0.5:  # one odd value
        values = table.column(name).to_numpy(zero_copy_only=False).copy()
        row = rnd.randrange(len(values))
        if values.dtype.kind == "f":
            values[row] = rnd.choice(_FLOATS)
        elif values.dtype.kind in "iu":
            values[row] = rnd.choice([0, -1, 2**62, -(2**62), values[0]])
        else:
            values[row] = rnd.choice(_TEXTS)
        return table.set_column(i, name, pa.array(values, type=table.schema.field(name).type))
    if kind < 0.6:
        return table.drop_columns([name])
    if kind < 0.7:
        return table.set_column(i, name, table.column(name).cast(pa.string()))
    if kind < 0.8:
        keep = sorted(rnd.sample(range(table.num_rows), k=max(1, table.num_rows // 3)))
        return table.take(keep)
    if kind < 0.9:
        return pa.concat_tables([table, table.slice(rnd.randrange(table.num_rows), 1)])
    column = table.column(name)
    nulled = [None if rnd.random() < 0.2 else v for v in column.to_pylist()]
    return table.set_column(i, name, pa.array(nulled, type=column.type))


@pytest.mark.parametrize("seed", [3, 4])
def test_random_feather_edits_are_ingested_or_refused_clearly(seed: int, tmp_path: Path) -> None:
    rnd = random.Random(seed)
    good = av2_folder(tmp_path / "good")
    statuses = {"ingested": 0, "failed": 0}
    for trial in range(120):
        folder = tmp_path / f"t{trial}" / good.name
        shutil.copytree(good, folder)
        for _ in range(rnd.randint(1, 3)):
            file = folder / rnd.choice([ANN, POSES_FILE])
            feather.write_feather(_edit(feather.read_table(file), rnd), file)
        with warnings.catch_warnings():
            warnings.simplefilter("error", RuntimeWarning)
            results = ingest_sources([folder], MemorySink(), Config())
        for result in results:
            statuses[result.status] += 1
            assert "unexpected" not in result.error, f"seed {seed}, trial {trial}: {result.error}"
        shutil.rmtree(folder.parent)
    assert statuses["ingested"] >= 10 and statuses["failed"] >= 30, statuses
