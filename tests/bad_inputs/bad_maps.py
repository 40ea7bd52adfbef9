"""Bad Argoverse 2 vector maps (cases for the corpus in ``bad_registry``).

A broken map must not fail its log: the log loads without the map, with a note naming the cause.
"""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Any

from bad_av2 import LOG_ID, av2_folder, map_file, small_map
from bad_registry import case

from scenariominer.data.adapters.av2.map import write_av2_map


def _store_has_no_map(store: Any, report: Any, root: Path) -> None:
    assert store.log_meta(LOG_ID).map_dir is None


# ---------------------------------------------------------------------- vector maps


def _bad_map(root: Path, content: str | bytes) -> list[Path]:
    folder = av2_folder(root)
    path = map_file(folder)
    if isinstance(content, bytes):
        path.write_bytes(content)
    else:
        path.write_text(content)
    return [folder]


def _edited_map(root: Path, edit: Any) -> list[Path]:
    doc = small_map().to_json()
    edit(doc)
    return _bad_map(root, json.dumps(doc))


_NO_MAP = r"loaded without its vector map: log_map_archive_bad-log____TEST_city_0\.json: .*"


@case(
    "map_invalid_json",
    "map",
    "map file that is not JSON",
    "repaired",
    _NO_MAP + r"vector map is not valid JSON",
    check=_store_has_no_map,
)
def _(root: Path) -> list[Path]:
    return _bad_map(root, '{"lane_segments": {"1": ')


@case(
    "map_empty_file",
    "map",
    "map file of 0 bytes",
    "repaired",
    _NO_MAP + r"vector map is not valid JSON",
    check=_store_has_no_map,
)
def _(root: Path) -> list[Path]:
    return _bad_map(root, "")


@case(
    "map_not_an_object",
    "map",
    "map JSON that is a list",
    "repaired",
    _NO_MAP + r"vector map is not a JSON object",
    check=_store_has_no_map,
)
def _(root: Path) -> list[Path]:
    return _bad_map(root, "[1, 2, 3]")


@case(
    "map_missing_lane_segments",
    "map",
    "map without `lane_segments`",
    "repaired",
    _NO_MAP + r"lacks the 'lane_segments' layer",
    check=_store_has_no_map,
)
def _(root: Path) -> list[Path]:
    return _edited_map(root, lambda d: d.pop("lane_segments"))


@case(
    "map_lane_missing_boundary",
    "map",
    "lane without `left_lane_boundary`",
    "repaired",
    _NO_MAP + r"lane segment 1 lacks the key 'left_lane_boundary'",
    check=_store_has_no_map,
)
def _(root: Path) -> list[Path]:
    return _edited_map(root, lambda d: d["lane_segments"]["1"].pop("left_lane_boundary"))


@case(
    "map_lane_id_over_64_bits",
    "map",
    "lane id 2**70 (ids are stored as 64-bit integers)",
    "repaired",
    _NO_MAP + r"lane segment \d+ has a malformed field \(id \d+ does not fit 64 bits\)",
    check=_store_has_no_map,
)
def _(root: Path) -> list[Path]:
    return _edited_map(root, lambda d: d["lane_segments"]["1"].update(id=2**70))


@case(
    "map_coordinate_1e300",
    "map",
    "a crossing corner at x = 1e300 m",
    "repaired",
    _NO_MAP + r"pedestrian crossing \d+ edge1 has a coordinate beyond 1e\+07 m",
    check=_store_has_no_map,
)
def _(root: Path) -> list[Path]:
    def edit(doc: dict[str, Any]) -> None:
        next(iter(doc["pedestrian_crossings"].values()))["edge1"][0]["x"] = 1e300

    return _edited_map(root, edit)


@case(
    "map_lane_unknown_type",
    "map",
    "lane of type `HOVERCRAFT`",
    "repaired",
    _NO_MAP + r"lane segment 1 has unknown lane_type 'HOVERCRAFT'",
    check=_store_has_no_map,
)
def _(root: Path) -> list[Path]:
    return _edited_map(root, lambda d: d["lane_segments"]["1"].update(lane_type="HOVERCRAFT"))


@case(
    "map_malformed_point",
    "map",
    "boundary point without `x`",
    "repaired",
    _NO_MAP + r"right_lane_boundary has a malformed point",
    check=_store_has_no_map,
)
def _(root: Path) -> list[Path]:
    return _edited_map(root, lambda d: d["lane_segments"]["1"]["right_lane_boundary"][0].pop("x"))


@case(
    "map_number_overflow",
    "map",
    "lane id `1e400` (infinite)",
    "repaired",
    _NO_MAP + r"lane segment .* has a malformed field",
    check=_store_has_no_map,
)
def _(root: Path) -> list[Path]:
    text = json.dumps(small_map().to_json()).replace('"id": 1,', '"id": 1e400,', 1)
    return _bad_map(root, text)


@case(
    "map_nested_too_deeply",
    "map",
    "map JSON nested 100,000 levels",
    "repaired",
    _NO_MAP + r"nested too deeply",
    check=_store_has_no_map,
)
def _(root: Path) -> list[Path]:
    return _bad_map(root, "[" * 100_000 + "]" * 100_000)


@case(
    "map_not_utf8",
    "map",
    "map file with byte 0xff",
    "repaired",
    _NO_MAP + r"vector map is not UTF-8 text",
    check=_store_has_no_map,
)
def _(root: Path) -> list[Path]:
    return _bad_map(root, b'{"lane_segments": "\xff"}')


@case(
    "map_two_files",
    "map",
    "two `log_map_archive_*.json` files",
    "repaired",
    r"loaded without its vector map: map: several vector maps",
    check=_store_has_no_map,
)
def _(root: Path) -> list[Path]:
    folder = av2_folder(root)
    write_av2_map(small_map(), folder / "map" / "log_map_archive_other____TEST_city_1.json")
    return [folder]


@case(
    "map_folder_without_map_file",
    "map",
    "`map/` holding no map JSON",
    "repaired",
    r"loaded without its vector map: map: no Argoverse 2 vector map",
    check=_store_has_no_map,
)
def _(root: Path) -> list[Path]:
    folder = av2_folder(root)
    map_file(folder).unlink()
    (folder / "map" / "ground_height.npy").write_bytes(b"\x93NUMPY")
    return [folder]


@case(
    "map_file_is_fifo",
    "map",
    "map file is a FIFO",
    "rejected",
    r"log_map_archive_bad-log____TEST_city_0\.json: not a regular file",
)
def _(root: Path) -> list[Path]:
    folder = av2_folder(root)
    map_file(folder).unlink()
    os.mkfifo(map_file(folder))
    return [folder]
