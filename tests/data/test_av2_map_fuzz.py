"""Random edits of a real vector map: validation either refuses the map naming the cause, or the map
reads and builds its geometry. Never another exception (a map that validates and then fails would
break every mining program on its log).

Seeded: a failure names its trial and replays.
"""

from __future__ import annotations

import contextlib
import copy
import json
import random
import warnings
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from scenariominer.data.adapters.av2.map import read_av2_map, validate_av2_map
from scenariominer.data.log import LogFormatError

_LOG = Path(__file__).parents[1] / "real_data/av2/adcf7d18-0510-35b0-a2fa-b4cea13a6d76"
_MAP = next((_LOG / "map").glob("log_map_archive_*.json"))
_VALUES: list[Any] = [
    None, "x", -1, 0, 1.5, 1e308, float("nan"), float("inf"), [], {}, [1], {"x": 1}, True, 2**70,
]  # fmt: skip


def _paths(node: Any, prefix: tuple[Any, ...] = ()) -> Iterator[tuple[Any, ...]]:
    """Every key path under ``node`` (lists: their first three items)."""
    items = node.items() if isinstance(node, dict) else enumerate(node[:3]) if isinstance(node, list) else ()
    for key, child in items:
        yield (*prefix, key)
        yield from _paths(child, (*prefix, key))


def _edit(doc: dict[str, Any], path: tuple[Any, ...], rnd: random.Random) -> None:
    parent = doc
    for key in path[:-1]:
        parent = parent[key]
    if rnd.random() < 0.3 and isinstance(parent, dict):
        del parent[path[-1]]
    else:
        parent[path[-1]] = rnd.choice(_VALUES)


@pytest.mark.parametrize("seed", range(2))
def test_random_map_edits_are_refused_or_read(seed: int, tmp_path: Path) -> None:
    doc = json.loads(_MAP.read_text(encoding="utf-8"))
    # edit sites: the layers themselves and the first three records of each
    sample = {layer: dict(list(doc[layer].items())[:3]) for layer in ("lane_segments", "pedestrian_crossings",
                                                                       "drivable_areas")}  # fmt: skip
    sites = list(_paths(sample))
    rnd = random.Random(seed)
    file = tmp_path / "log_map_archive_fuzz____PIT_city_1.json"
    outcomes = {"read": 0, "refused": 0}
    for trial in range(150):
        edited = copy.deepcopy(doc)
        for _ in range(rnd.randint(1, 3)):
            with contextlib.suppress(KeyError, IndexError, TypeError):  # an earlier edit took the parent
                _edit(edited, rnd.choice(sites), rnd)
        file.write_text(json.dumps(edited), encoding="utf-8")
        try:
            validate_av2_map(file)
        except LogFormatError as exc:
            assert exc.source == str(file), exc
            outcomes["refused"] += 1
            continue
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("error", RuntimeWarning)  # overflow in geometry means bad input passed
                av2_map = read_av2_map(file)  # builds the polygons, centre lines and index
                av2_map.in_drivable_area([[0.0, 0.0]])
                av2_map.lane_index_at([[0.0, 0.0]])
        except Exception as exc:  # noqa: BLE001  # the point: a validated map must read
            pytest.fail(f"seed {seed}, trial {trial}: validated, then {type(exc).__name__}: {exc}")
        outcomes["read"] += 1
    assert outcomes["read"] >= 10 and outcomes["refused"] >= 50, outcomes
