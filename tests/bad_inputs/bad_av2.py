"""Bad Argoverse 2 log folders and vector maps (cases for the corpus in ``bad_registry``).

Each starts from a small valid log written by the package's own writers (``LogBuilder`` →
``write_av2_log``, ``write_av2_map``) and breaks one thing.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

import numpy as np
import pyarrow as pa
import pyarrow.compute as pc
import pyarrow.feather as feather
from bad_registry import case, rewrite_feather, set_column

from scenariominer.data.adapters.av2 import (
    ANNOTATIONS_FILE,
    ANNOTATIONS_WITH_EGO_FILE,
    POSES_FILE,
    write_av2_log,
)
from scenariominer.data.adapters.av2.map import (
    Av2Map,
    DrivableArea,
    LaneSegment,
    LaneType,
    PedestrianCrossing,
    write_av2_map,
)
from scenariominer.data.log import Log
from scenariominer.testing import LogBuilder, times

ANN = ANNOTATIONS_WITH_EGO_FILE
LOG_ID = "bad-log"


def small_log(log_id: str = LOG_ID) -> Log:
    """Ego at 10 m/s for 2 s (10 Hz), a car ahead, a pedestrian crossing, an oncoming bus."""
    return (
        LogBuilder(times(2.0), log_id=log_id, dataset="av2")
        .ego(speed_mps=10.0)
        .add("car-1", "REGULAR_VEHICLE", speed_mps=8.0, x0_m=15.0)
        .add(
            "ped-1",
            "PEDESTRIAN",
            speed_mps=1.2,
            x0_m=20.0,
            y0_m=-4.0,
            yaw0_rad=np.pi / 2,
            length_m=0.6,
            width_m=0.6,
        )
        .add("bus-1", "BUS", speed_mps=6.0, x0_m=45.0, y0_m=3.5, yaw0_rad=np.pi, length_m=12.0, width_m=2.6)
        .build()
    )


def _pts(*xy: tuple[float, float]) -> np.ndarray:
    return np.array([[x, y, 0.0] for x, y in xy])


def small_map() -> Av2Map:
    """One eastbound lane under the ego's path, a crosswalk at x 19-22, the road as drivable area."""
    lane = LaneSegment(1, LaneType.VEHICLE, False, _pts((-10, 2), (70, 2)), _pts((-10, -2), (70, -2)))
    crossing = PedestrianCrossing(2, _pts((19, -6), (19, 6)), _pts((22, -6), (22, 6)))
    area = DrivableArea(3, _pts((-10, -6), (70, -6), (70, 6), (-10, 6)))
    return Av2Map((lane,), (crossing,), (area,))


def av2_folder(root: Path, log_id: str = LOG_ID, *, with_map: bool = True) -> Path:
    """Write the small log (and its map) as ``root/<log_id>/``."""
    folder = write_av2_log(small_log(log_id), root)
    if with_map:
        write_av2_map(small_map(), map_file(folder))
    return folder


def map_file(folder: Path) -> Path:
    return folder / "map" / f"log_map_archive_{folder.name}____TEST_city_0.json"


def _broken(root: Path, file: str, change: Any) -> list[Path]:
    folder = av2_folder(root)
    rewrite_feather(folder / file, change)
    return [folder]


def _rows_of(table: pa.Table, track: str) -> np.ndarray:
    return np.asarray(pc.equal(table.column("track_uuid"), track).to_numpy(zero_copy_only=False))


def _where(table: pa.Table, name: str, mask: np.ndarray, value: float) -> pa.Table:
    values = table.column(name).to_numpy().astype(float)
    values[mask] = value
    return set_column(table, name, values, pa.float64())


def _first_rows(table: pa.Table, track: str, k: int) -> np.ndarray:
    mask = _rows_of(table, track)
    mask[np.flatnonzero(mask)[k:]] = False
    return mask


# ---------------------------------------------------------------------- columns and types


@case(
    "av2_annotations_missing_column",
    "av2",
    "annotations without `tx_m`",
    "rejected",
    r"missing column\(s\) \['tx_m'\]",
)
def _(root: Path) -> list[Path]:
    return _broken(root, ANN, lambda t: t.drop_columns(["tx_m"]))


@case(
    "av2_poses_missing_column",
    "av2",
    "ego poses without `qw`",
    "rejected",
    r"city_SE3_egovehicle\.feather: missing column\(s\) \['qw'\]",
)
def _(root: Path) -> list[Path]:
    return _broken(root, POSES_FILE, lambda t: t.drop_columns(["qw"]))


@case(
    "av2_coordinate_as_string",
    "av2",
    "`tx_m` stored as strings",
    "rejected",
    r"column 'tx_m' has type string",
)
def _(root: Path) -> list[Path]:
    return _broken(root, ANN, lambda t: set_column(t, "tx_m", [str(v) for v in t.column("tx_m").to_pylist()]))


@case(
    "av2_float_timestamps",
    "av2",
    "`timestamp_ns` stored as floats",
    "rejected",
    r"'timestamp_ns' has type double, expected integer nanoseconds",
)
def _(root: Path) -> list[Path]:
    return _broken(
        root, ANN, lambda t: set_column(t, "timestamp_ns", t.column("timestamp_ns").to_numpy() * 1.0)
    )


def _wrap(t: pa.Table) -> pa.Table:
    wrapped = t.column("timestamp_ns").to_numpy().astype(np.uint64) + np.uint64(2**63)
    return set_column(t, "timestamp_ns", wrapped, pa.uint64())


@case(
    "av2_wrapped_uint64_timestamps",
    "av2",
    "unsigned timestamps beyond the int64 range",
    "rejected",
    r"outside the int64 range",
)
def _(root: Path) -> list[Path]:
    folder = av2_folder(root)
    rewrite_feather(folder / ANN, _wrap)
    rewrite_feather(folder / POSES_FILE, _wrap)
    return [folder]


@case("av2_null_track_id", "av2", "a missing `track_uuid`", "rejected", r"'track_uuid' has 1 missing value")
def _(root: Path) -> list[Path]:
    return _broken(
        root,
        ANN,
        lambda t: set_column(t, "track_uuid", [None, *t.column("track_uuid").to_pylist()[1:]], pa.string()),
    )


# ---------------------------------------------------------------------- values


@case(
    "av2_nan_translation",
    "av2",
    "NaN `tx_m` in two rows",
    "repaired",
    r"dropped 2 row\(s\) with NaN/inf position, yaw or size",
)
def _(root: Path) -> list[Path]:
    return _broken(root, ANN, lambda t: _where(t, "tx_m", _first_rows(t, "car-1", 2), np.nan))


@case(
    "av2_inf_translation",
    "av2",
    "infinite `ty_m` in one row",
    "repaired",
    r"dropped 1 row\(s\) with NaN/inf position, yaw or size",
)
def _(root: Path) -> list[Path]:
    return _broken(root, ANN, lambda t: _where(t, "ty_m", _first_rows(t, "bus-1", 1), np.inf))


@case(
    "av2_nan_rotation",
    "av2",
    "NaN quaternion (no yaw)",
    "rejected",
    r"non-finite, zero or overflowing rotation quaternion",
)
def _(root: Path) -> list[Path]:
    return _broken(root, ANN, lambda t: _where(t, "qz", _first_rows(t, "car-1", 1), np.nan))


@case(
    "av2_overflowing_rotation_quaternion",
    "av2",
    "a pose quaternion component of 1e300 (its norm overflows)",
    "rejected",
    r"city_SE3_egovehicle\.feather: 1 pose row\(s\) have a non-finite, zero or overflowing rotation quat",
)
def _(root: Path) -> list[Path]:
    return _broken(root, POSES_FILE, lambda t: _where(t, "qz", np.arange(t.num_rows) == 2, 1e300))


@case(
    "av2_box_length_1e300",
    "av2",
    "`length_m` of 1e300",
    "repaired",
    r"dropped 1 row\(s\) with a length or width beyond 100 m",
)
def _(root: Path) -> list[Path]:
    return _broken(root, ANN, lambda t: _where(t, "length_m", _first_rows(t, "bus-1", 1), 1e300))


@case(
    "av2_zero_rotation_quaternion",
    "av2",
    "all-zero quaternion",
    "rejected",
    r"non-finite, zero or overflowing rotation quaternion",
)
def _(root: Path) -> list[Path]:
    def change(t: pa.Table) -> pa.Table:
        mask = _first_rows(t, "ped-1", 1)
        for name in ("qw", "qx", "qy", "qz"):
            t = _where(t, name, mask, 0.0)
        return t

    return _broken(root, ANN, change)


@case(
    "av2_nan_size",
    "av2",
    "NaN `length_m`",
    "repaired",
    r"dropped 1 row\(s\) with NaN/inf position, yaw or size",
)
def _(root: Path) -> list[Path]:
    return _broken(root, ANN, lambda t: _where(t, "length_m", _first_rows(t, "car-1", 1), np.nan))


@case(
    "av2_inf_size",
    "av2",
    "infinite `width_m`",
    "repaired",
    r"dropped 1 row\(s\) with NaN/inf position, yaw or size",
)
def _(root: Path) -> list[Path]:
    return _broken(root, ANN, lambda t: _where(t, "width_m", _first_rows(t, "bus-1", 1), np.inf))


@case(
    "av2_ego_rows_all_unusable",
    "av2",
    "NaN `length_m` in every row of the ego",
    "rejected",
    r"annotations_with_ego\.feather: the ego track '[^']+' has no row with a usable position, yaw and size",
)
def _(root: Path) -> list[Path]:
    def change(t: pa.Table) -> pa.Table:
        ego = np.asarray(pc.equal(t.column("category"), "EGO_VEHICLE").to_numpy(zero_copy_only=False))
        return _where(t, "length_m", ego, np.nan)

    return _broken(root, ANN, change)


@case(
    "av2_zero_size",
    "av2",
    "`length_m` of 0",
    "repaired",
    r"set length_m of 3 row\(s\) from zero or negative to 0\.1 m",
)
def _(root: Path) -> list[Path]:
    return _broken(root, ANN, lambda t: _where(t, "length_m", _first_rows(t, "ped-1", 3), 0.0))


@case(
    "av2_negative_size",
    "av2",
    "negative `width_m`",
    "repaired",
    r"set width_m of 1 row\(s\) from zero or negative to 0\.1 m",
)
def _(root: Path) -> list[Path]:
    return _broken(root, ANN, lambda t: _where(t, "width_m", _first_rows(t, "car-1", 1), -2.0))


@case(
    "av2_huge_coordinates",
    "av2",
    "`tx_m` of 1e12 m",
    "repaired",
    r"dropped 2 row\(s\) with a coordinate beyond 1e\+07 m",
)
def _(root: Path) -> list[Path]:
    return _broken(root, ANN, lambda t: _where(t, "tx_m", _first_rows(t, "bus-1", 2), 1e12))


@case("av2_negative_timestamps", "av2", "timestamps before 1970 (negative)", "accepted")
def _(root: Path) -> list[Path]:
    folder = av2_folder(root)
    for file in (ANN, POSES_FILE):
        rewrite_feather(
            folder / file,
            lambda t: set_column(t, "timestamp_ns", t.column("timestamp_ns").to_numpy() - 10**15),
        )
    return [folder]


@case("av2_unsorted_rows", "av2", "annotation rows in random order", "accepted")
def _(root: Path) -> list[Path]:
    return _broken(root, ANN, lambda t: t.take(np.random.default_rng(0).permutation(t.num_rows)))


# ---------------------------------------------------------------------- files


@case(
    "av2_empty_annotation_file",
    "av2",
    "annotation file of 0 bytes",
    "rejected",
    r"annotations_with_ego\.feather: not a readable Feather file",
)
def _(root: Path) -> list[Path]:
    folder = av2_folder(root)
    (folder / ANN).write_bytes(b"")
    return [folder]


@case(
    "av2_truncated_annotation_file",
    "av2",
    "annotation file cut in half",
    "rejected",
    r"annotations_with_ego\.feather: not a readable Feather file",
)
def _(root: Path) -> list[Path]:
    folder = av2_folder(root)
    data = (folder / ANN).read_bytes()
    (folder / ANN).write_bytes(data[: len(data) // 2])
    return [folder]


@case(
    "av2_annotation_file_not_feather",
    "av2",
    "annotation file holding text",
    "rejected",
    r"annotations_with_ego\.feather: not a readable Feather file",
)
def _(root: Path) -> list[Path]:
    folder = av2_folder(root)
    (folder / ANN).write_text("timestamp_ns,track_uuid\n1,a\n")
    return [folder]


@case(
    "av2_annotations_without_rows",
    "av2",
    "annotation table with no rows",
    "rejected",
    r"annotations_with_ego\.feather: the table has no rows",
)
def _(root: Path) -> list[Path]:
    return _broken(root, ANN, lambda t: t.slice(0, 0))


@case(
    "av2_poses_missing_file",
    "av2",
    "no `city_SE3_egovehicle.feather`",
    "rejected",
    r"city_SE3_egovehicle\.feather: (missing file|cannot read file)",
)
def _(root: Path) -> list[Path]:
    folder = av2_folder(root)
    (folder / POSES_FILE).unlink()
    return [folder]


@case(
    "av2_poses_without_rows",
    "av2",
    "ego-pose table with no rows",
    "rejected",
    r"city_SE3_egovehicle\.feather: the table has no rows",
)
def _(root: Path) -> list[Path]:
    return _broken(root, POSES_FILE, lambda t: t.slice(0, 0))


@case("av2_annotation_file_is_fifo", "av2", "annotation file is a FIFO", "rejected", r"not a recognised log")
def _(root: Path) -> list[Path]:
    folder = av2_folder(root)
    (folder / ANN).unlink()
    os.mkfifo(folder / ANN)
    return [folder]


@case(
    "av2_poses_file_is_fifo",
    "av2",
    "ego-pose file is a FIFO",
    "rejected",
    r"city_SE3_egovehicle\.feather: not a regular file",
)
def _(root: Path) -> list[Path]:
    folder = av2_folder(root)
    (folder / POSES_FILE).unlink()
    os.mkfifo(folder / POSES_FILE)
    return [folder]


@case(
    "av2_annotation_path_is_folder",
    "av2",
    "`annotations_with_ego.feather` is a folder",
    "rejected",
    r"not a recognised log",
)
def _(root: Path) -> list[Path]:
    folder = av2_folder(root)
    (folder / ANN).unlink()
    (folder / ANN).mkdir()
    return [folder]


@case(
    "av2_poses_path_is_folder",
    "av2",
    "`city_SE3_egovehicle.feather` is a folder",
    "rejected",
    r"city_SE3_egovehicle\.feather: not a regular file \(a folder",
)
def _(root: Path) -> list[Path]:
    folder = av2_folder(root)
    (folder / POSES_FILE).unlink()
    (folder / POSES_FILE).mkdir()
    return [folder]


# ---------------------------------------------------------------------- rows, tracks and the ego


def _duplicate_first(t: pa.Table, change_x: bool) -> pa.Table:
    extra = t.slice(5, 1)
    if change_x:
        extra = set_column(extra, "tx_m", [extra.column("tx_m")[0].as_py() + 1.0], pa.float64())
    return pa.concat_tables([t, extra])


@case(
    "av2_duplicate_rows_identical",
    "av2",
    "a row repeated exactly",
    "repaired",
    r"collapsed 1 exact duplicate row",
)
def _(root: Path) -> list[Path]:
    return _broken(root, ANN, lambda t: _duplicate_first(t, change_x=False))


@case(
    "av2_duplicate_rows_conflicting",
    "av2",
    "two rows for one (track, timestamp), different boxes",
    "rejected",
    r"1 duplicate \(track, timestamp\) row\(s\) with different values",
)
def _(root: Path) -> list[Path]:
    return _broken(root, ANN, lambda t: _duplicate_first(t, change_x=True))


@case(
    "av2_one_frame_track",
    "av2",
    "a track seen at one timestamp",
    "repaired",
    r"dropped 1 track\(s\) with fewer than 2 frames \(e\.g\. \['blip'\]\)",
)
def _(root: Path) -> list[Path]:
    def change(t: pa.Table) -> pa.Table:
        blip = set_column(t.slice(3, 1), "track_uuid", ["blip"])
        return pa.concat_tables([t, set_column(blip, "category", ["BOLLARD"])])

    return _broken(root, ANN, change)


@case(
    "av2_all_tracks_one_frame",
    "av2",
    "every track (the ego too) at one timestamp",
    "rejected",
    r"the ego track has only 1 frame",
)
def _(root: Path) -> list[Path]:
    return _broken(
        root, ANN, lambda t: t.filter(pc.equal(t.column("timestamp_ns"), t.column("timestamp_ns")[0]))
    )


@case(
    "av2_no_ego_rows",
    "av2",
    "plain `annotations.feather` without the ego",
    "repaired",
    r"ego track synthesised from city_SE3_egovehicle\.feather",
)
def _(root: Path) -> list[Path]:
    folder = av2_folder(root)
    table = feather.read_table(folder / ANN)
    feather.write_feather(
        table.filter(pc.not_equal(table.column("category"), "EGO_VEHICLE")), folder / ANNOTATIONS_FILE
    )
    (folder / ANN).unlink()
    return [folder]


@case(
    "av2_several_ego_tracks",
    "av2",
    "two tracks with category EGO_VEHICLE",
    "rejected",
    r"several tracks have category EGO_VEHICLE",
)
def _(root: Path) -> list[Path]:
    def change(t: pa.Table) -> pa.Table:
        cats = t.column("category").to_pylist()
        ids = t.column("track_uuid").to_pylist()
        return set_column(
            t, "category", ["EGO_VEHICLE" if i == "car-1" else c for i, c in zip(ids, cats, strict=True)]
        )

    return _broken(root, ANN, change)


@case(
    "av2_poses_duplicate_timestamps",
    "av2",
    "two ego poses at one timestamp",
    "rejected",
    r"1 duplicate pose timestamp",
)
def _(root: Path) -> list[Path]:
    return _broken(root, POSES_FILE, lambda t: pa.concat_tables([t, t.slice(2, 1)]))


@case(
    "av2_poses_do_not_cover_annotations",
    "av2",
    "ego poses end before the annotations",
    "rejected",
    r"outside the pose range .* cannot be extrapolated",
)
def _(root: Path) -> list[Path]:
    return _broken(root, POSES_FILE, lambda t: t.slice(0, t.num_rows - 3))


@case(
    "av2_pose_missing_at_annotation_time",
    "av2",
    "no ego pose at one annotation timestamp",
    "repaired",
    r"interpolated the ego pose at 1 annotation timestamp",
)
def _(root: Path) -> list[Path]:
    return _broken(root, POSES_FILE, lambda t: pa.concat_tables([t.slice(0, 5), t.slice(6)]))


# ---------------------------------------------------------------------- categories and ids


def _recategorise(track: str, category: str) -> Any:
    def change(t: pa.Table) -> pa.Table:
        ids = t.column("track_uuid").to_pylist()
        cats = t.column("category").to_pylist()
        return set_column(
            t, "category", [category if i == track else c for i, c in zip(ids, cats, strict=True)]
        )

    return change


def _rename_track(track: str, new: str) -> Any:
    def change(t: pa.Table) -> pa.Table:
        return set_column(
            t, "track_uuid", [new if i == track else i for i in t.column("track_uuid").to_pylist()]
        )

    return change


@case(
    "av2_unknown_category", "av2", "category `SPACESHIP`", "rejected", r"unknown object category 'SPACESHIP'"
)
def _(root: Path) -> list[Path]:
    return _broken(root, ANN, _recategorise("car-1", "SPACESHIP"))


@case(
    "av2_category_changes_within_track",
    "av2",
    "a track switching category halfway",
    "rejected",
    r"track 'car-1' changes category",
)
def _(root: Path) -> list[Path]:
    def change(t: pa.Table) -> pa.Table:
        mask = _first_rows(t, "car-1", 5)
        cats = np.asarray(t.column("category").to_pylist(), dtype=object)
        cats[mask] = "TRUCK"
        return set_column(t, "category", cats.tolist())

    return _broken(root, ANN, change)


def _markup_shown_literally(store: Any, output: Any, root: Path) -> None:
    assert "[bold red]SPACESHIP[/bold red]" in output


@case(
    "av2_category_with_rich_markup",
    "av2",
    "category holding Rich markup `[bold red]…`",
    "rejected",
    r"unknown object category '\[bold red\]SPACESHIP\[/bold red\]'",
    via="cli",
    check=_markup_shown_literally,
)
def _(root: Path) -> list[Path]:
    return _broken(root, ANN, _recategorise("car-1", "[bold red]SPACESHIP[/bold red]"))


def _no_escape_printed(store: Any, output: Any, root: Path) -> None:
    assert "\x1b" not in output and "\\x1b[31m" in output


@case(
    "av2_category_with_ansi_escape",
    "av2",
    "category holding an ANSI colour escape",
    "rejected",
    r"unknown object category",
    via="cli",
    check=_no_escape_printed,
)
def _(root: Path) -> list[Path]:
    return _broken(root, ANN, _recategorise("car-1", "\x1b[31mCAR\x1b[0m"))


def _control_id_stored(store: Any, report: Any, root: Path) -> None:
    assert "car\x07\x1b[31m\n\t1" in store.load_log(LOG_ID).track_ids.tolist()


@case(
    "av2_track_id_with_control_characters",
    "av2",
    "track id with BEL, ESC, newline, tab",
    "accepted",
    check=_control_id_stored,
)
def _(root: Path) -> list[Path]:
    return _broken(root, ANN, _rename_track("car-1", "car\x07\x1b[31m\n\t1"))


def _nul_ids_kept_apart(store: Any, report: Any, root: Path) -> None:
    ids = store.load_log(LOG_ID).track_ids.tolist()
    assert "car\ufffda" in ids and "car\ufffdb" in ids


@case(
    "av2_track_id_with_nul",
    "av2",
    "track ids `car\\0a`, `car\\0b` (Arrow cuts at NUL)",
    "repaired",
    r"replaced NUL characters with U\+FFFD in 2 track id\(s\)",
    check=_nul_ids_kept_apart,
)
def _(root: Path) -> list[Path]:
    folder = av2_folder(root)
    rewrite_feather(folder / ANN, _rename_track("car-1", "car\x00a"))
    rewrite_feather(folder / ANN, _rename_track("ped-1", "car\x00b"))
    return [folder]


def _markup_id_printed(store: Any, output: Any, root: Path) -> None:
    assert "[link=http://example.com]car[/link]" in store.load_log(LOG_ID).track_ids.tolist()


@case(
    "av2_track_id_with_rich_markup",
    "av2",
    "track id holding Rich markup",
    "accepted",
    via="cli",
    check=_markup_id_printed,
)
def _(root: Path) -> list[Path]:
    return _broken(root, ANN, _rename_track("car-1", "[link=http://example.com]car[/link]"))


def _bracket_name_printed(store: Any, output: Any, root: Path) -> None:
    assert "[bold]log[blink]" in store.log_ids()


@case(
    "av2_folder_name_with_brackets",
    "av2",
    "log folder named `[bold]log[blink]`",
    "accepted",
    via="cli",
    check=_bracket_name_printed,
)
def _(root: Path) -> list[Path]:
    return [av2_folder(root, "[bold]log[blink]")]


@case(
    "av2_folder_name_not_utf8",
    "av2",
    "log folder name with byte 0xff (not UTF-8)",
    "rejected",
    r"log-\\xff.*the path is not valid UTF-8",
)
def _(root: Path) -> list[Path]:
    folder = av2_folder(root / "tmp", "renamed", with_map=False)
    target = root / os.fsdecode(b"log-\xff")
    folder.rename(target)
    return [target]
