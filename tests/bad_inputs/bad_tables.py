"""Bad tabular files and paths (cases for the corpus in ``bad_registry``).

Tabular cases start from a small valid CSV or Parquet table; path cases from nothing.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq
from bad_av2 import small_log
from bad_registry import case
from highd_files import write_small_highway

from scenariominer.data.adapters.highd import HighDFiles
from scenariominer.data.adapters.tabular import write_tabular

# ---------------------------------------------------------------------- tabular

HEADER = ["log_id", "track_id", "timestamp_ns", "category", "x_m", "y_m", "yaw_rad", "length_m", "width_m"]
T0_NS = 1_700_000_000_000_000_000


def tab_rows(log_id: str = "fleet-1", n: int = 10) -> list[list[str]]:
    """Header and rows of a valid log: the ego at 10 m/s and a car at 20 m/s, ``n`` frames at 10 Hz."""
    rows = [HEADER]
    for k in range(n):
        t = str(T0_NS + k * 100_000_000)
        rows.append([log_id, "ego", t, "EGO_VEHICLE", f"{k:.1f}", "0", "0", "4.9", "2.0"])
        rows.append([log_id, "car", t, "REGULAR_VEHICLE", f"{10 + 2 * k:.1f}", "3.5", "0", "4.5", "1.9"])
    return rows


def _csv(root: Path, rows: list[list[str]], name: str = "fleet.csv") -> list[Path]:
    root.mkdir(parents=True, exist_ok=True)
    path = root / name
    path.write_text("\n".join(",".join(r) for r in rows) + "\n", encoding="utf-8")
    return [path]


def _tab(root: Path, edit: Any) -> list[Path]:
    return _csv(root, edit(tab_rows()))


def _cell(rows: list[list[str]], column: str, value: str, row: int = 3) -> list[list[str]]:
    k = rows[0].index(column)
    rows[row] = [*rows[row][:k], value, *rows[row][k + 1 :]]
    return rows


@case(
    "tabular_missing_columns",
    "tabular",
    "CSV without `yaw_rad`, `length_m`, `width_m`",
    "rejected",
    r"fleet\.csv: missing column\(s\) \['yaw_rad', 'length_m', 'width_m'\]",
)
def _(root: Path) -> list[Path]:
    return _tab(root, lambda rows: [r[:6] for r in rows])


@case(
    "tabular_header_name_with_spaces",
    "tabular",
    "CSV header `track_id ` (a space after the name)",
    "rejected",
    r"fleet\.csv: column name 'track_id ' has spaces around it; name it 'track_id'",
)
def _(root: Path) -> list[Path]:
    return _tab(root, lambda rows: [[c if c != "track_id" else "track_id " for c in rows[0]], *rows[1:]])


@case("tabular_empty_file", "tabular", "CSV of 0 bytes", "rejected", r"fleet\.csv: empty file")
def _(root: Path) -> list[Path]:
    root.mkdir(parents=True)
    (root / "fleet.csv").write_bytes(b"")
    return [root / "fleet.csv"]


@case(
    "tabular_header_only",
    "tabular",
    "CSV with a header and no rows",
    "rejected",
    r"fleet\.csv: the table has no rows",
)
def _(root: Path) -> list[Path]:
    return _tab(root, lambda rows: rows[:1])


@case(
    "tabular_non_numeric_cell", "tabular", "`x_m` of `zero`", "rejected", r"fleet\.csv: cannot read the table"
)
def _(root: Path) -> list[Path]:
    return _tab(root, lambda rows: _cell(rows, "x_m", "zero"))


@case(
    "tabular_empty_track_id",
    "tabular",
    "an empty `track_id`",
    "rejected",
    r"fleet\.csv: column 'track_id' has 1 empty value",
)
def _(root: Path) -> list[Path]:
    return _tab(root, lambda rows: _cell(rows, "track_id", ""))


@case(
    "tabular_nan_position",
    "tabular",
    "`x_m` of NaN",
    "repaired",
    r"dropped 1 row\(s\) with NaN/inf position, yaw or size",
)
def _(root: Path) -> list[Path]:
    return _tab(root, lambda rows: _cell(rows, "x_m", "NaN"))


@case(
    "tabular_inf_yaw",
    "tabular",
    "`yaw_rad` of inf",
    "repaired",
    r"dropped 1 row\(s\) with NaN/inf position, yaw or size",
)
def _(root: Path) -> list[Path]:
    return _tab(root, lambda rows: _cell(rows, "yaw_rad", "inf", row=6))


@case(
    "tabular_huge_coordinates",
    "tabular",
    "`y_m` of -3e9",
    "repaired",
    r"dropped 1 row\(s\) with a coordinate beyond 1e\+07 m",
)
def _(root: Path) -> list[Path]:
    return _tab(root, lambda rows: _cell(rows, "y_m", "-3e9", row=8))


@case(
    "tabular_negative_sizes",
    "tabular",
    "negative `length_m`",
    "repaired",
    r"set length_m of 1 row\(s\) from zero or negative to 0\.1 m",
)
def _(root: Path) -> list[Path]:
    return _tab(root, lambda rows: _cell(rows, "length_m", "-4.5", row=4))


@case(
    "tabular_conflicting_duplicates",
    "tabular",
    "two rows for one (track, timestamp), different `x_m`",
    "rejected",
    r"fleet\.csv: log 'fleet-1': 1 duplicate \(track, timestamp\) row\(s\) with different values",
)
def _(root: Path) -> list[Path]:
    return _tab(root, lambda rows: [*rows, _cell([rows[0], list(rows[4])], "x_m", "99.0", row=1)[1]])


@case(
    "tabular_exact_duplicates",
    "tabular",
    "a row repeated exactly",
    "repaired",
    r"collapsed 1 exact duplicate row",
)
def _(root: Path) -> list[Path]:
    return _tab(root, lambda rows: [*rows, rows[4]])


@case(
    "tabular_one_frame_track",
    "tabular",
    "a track with one row",
    "repaired",
    r"dropped 1 track\(s\) with fewer than 2 frames \(e\.g\. \['blip'\]\)",
)
def _(root: Path) -> list[Path]:
    return _tab(
        root, lambda rows: [*rows, ["fleet-1", "blip", str(T0_NS), "BOLLARD", "5", "5", "0", "0.3", "0.3"]]
    )


@case(
    "tabular_unknown_category",
    "tabular",
    "category `Hovercraft`",
    "rejected",
    r"fleet\.csv: log 'fleet-1': unknown object category 'Hovercraft'",
)
def _(root: Path) -> list[Path]:
    return _tab(root, lambda rows: [r if r[1] != "car" else [*r[:3], "Hovercraft", *r[4:]] for r in rows])


@case(
    "tabular_category_changes",
    "tabular",
    "a track switching category",
    "rejected",
    r"log 'fleet-1': track 'car' changes category",
)
def _(root: Path) -> list[Path]:
    return _tab(root, lambda rows: _cell(rows, "category", "TRUCK", row=len(rows) - 1))


@case(
    "tabular_no_ego",
    "tabular",
    "no `EGO_VEHICLE` track and no `is_ego`",
    "rejected",
    r"fleet\.csv: log 'fleet-1': no ego track",
)
def _(root: Path) -> list[Path]:
    return _tab(
        root, lambda rows: [r if r[1] != "ego" else [*r[:3], "REGULAR_VEHICLE", *r[4:]] for r in rows]
    )


@case(
    "tabular_several_is_ego_tracks",
    "tabular",
    "`is_ego` true on two tracks",
    "rejected",
    r"log 'fleet-1': is_ego marks several tracks \['car', 'ego'\]",
)
def _(root: Path) -> list[Path]:
    return _tab(root, lambda rows: [[*rows[0], "is_ego"], *([*r, "true"] for r in rows[1:])])


@case(
    "tabular_is_ego_conflicts_with_category",
    "tabular",
    "`is_ego` on one track, `EGO_VEHICLE` on another",
    "rejected",
    r"is_ego marks track 'car' but track\(s\) \['ego'\] have category EGO_VEHICLE",
)
def _(root: Path) -> list[Path]:
    return _tab(
        root, lambda rows: [[*rows[0], "is_ego"], *([*r, str(r[1] == "car").lower()] for r in rows[1:])]
    )


@case(
    "tabular_nan_timestamp_s",
    "tabular",
    "`timestamp_s` of `nan` (read as empty)",
    "rejected",
    r"fleet\.csv: column 'timestamp_s' has 1 empty value",
)
def _(root: Path) -> list[Path]:
    def edit(rows: list[list[str]]) -> list[list[str]]:
        rows = [
            [*r[:2], "timestamp_s" if i == 0 else f"{(int(r[2]) - T0_NS) / 1e9:.1f}", *r[3:]]
            for i, r in enumerate(rows)
        ]
        return _cell(rows, "timestamp_s", "nan")

    return _tab(root, edit)


@case(
    "tabular_timestamp_overflow",
    "tabular",
    "`timestamp_ns` of 2**64 - 1",
    "rejected",
    r"fleet\.csv: cannot read the table",
)
def _(root: Path) -> list[Path]:
    return _tab(root, lambda rows: _cell(rows, "timestamp_ns", str(2**64 - 1)))


@case(
    "tabular_semicolon_delimiter",
    "tabular",
    "CSV separated by `;`",
    "rejected",
    r"fleet\.csv: the header has no ',' but ';': .*comma-separated",
)
def _(root: Path) -> list[Path]:
    root.mkdir(parents=True)
    (root / "fleet.csv").write_text("\n".join(";".join(r) for r in tab_rows()) + "\n")
    return [root / "fleet.csv"]


@case("tabular_byte_order_mark", "tabular", "UTF-8 byte-order mark before the header", "accepted")
def _(root: Path) -> list[Path]:
    (path,) = _csv(root, tab_rows())
    path.write_bytes(b"\xef\xbb\xbf" + path.read_bytes())
    return [path]


@case(
    "tabular_invalid_utf8",
    "tabular",
    "track id with byte 0xff",
    "rejected",
    r"fleet\.csv: not a text CSV file \(cannot decode as UTF-8\)",
)
def _(root: Path) -> list[Path]:
    (path,) = _csv(root, tab_rows())
    path.write_bytes(path.read_bytes().replace(b",car,", b",c\xffr,", 1))
    return [path]


@case(
    "tabular_log_id_control_characters",
    "tabular",
    "`log_id` holding an escape character",
    "rejected",
    r"log id 'fleet\\x1b\[2J' contains control characters",
)
def _(root: Path) -> list[Path]:
    return _csv(root, tab_rows("fleet\x1b[2J"))


def _stays_in_store(store: Any, report: Any, root: Path) -> None:
    assert "../../escaped" in store.log_ids()
    assert not (root.parent / "escaped").exists() and not (store.root.parent / "escaped").exists()


@case(
    "tabular_log_id_path_traversal", "tabular", "`log_id` `../../escaped`", "accepted", check=_stays_in_store
)
def _(root: Path) -> list[Path]:
    return _csv(root, tab_rows("../../escaped"))


@case(
    "tabular_parquet_not_parquet",
    "tabular",
    "`.parquet` file holding text",
    "rejected",
    r"fleet\.parquet: not a readable Parquet file",
)
def _(root: Path) -> list[Path]:
    root.mkdir(parents=True)
    (root / "fleet.parquet").write_text("log_id,track_id\n")
    return [root / "fleet.parquet"]


@case(
    "tabular_parquet_truncated",
    "tabular",
    "Parquet file cut in half",
    "rejected",
    r"fleet\.parquet: not a readable Parquet file",
)
def _(root: Path) -> list[Path]:
    path = write_tabular([small_log("fleet-1")], root / "fleet.parquet")
    data = path.read_bytes()
    path.write_bytes(data[: len(data) // 2])
    return [path]


@case(
    "tabular_parquet_string_coordinates",
    "tabular",
    "Parquet `x_m` of strings",
    "rejected",
    r"fleet\.parquet: cannot read the table",
)
def _(root: Path) -> list[Path]:
    path = write_tabular([small_log("fleet-1")], root / "fleet.parquet")
    table = pq.read_table(path)
    i = table.column_names.index("x_m")
    pq.write_table(table.set_column(i, "x_m", pa.array(["a"] * table.num_rows)), path)
    return [path]


def _clock_rows(offset_ns: Any, n_tracks: int = 200, n_frames: int = 100) -> pa.Table:
    """``n_tracks`` tracks of ``n_frames`` at 10 Hz, track ``i`` stamped ``offset_ns(i)`` late."""
    k = np.arange(n_frames)
    ids = np.repeat([f"t{i}" for i in range(n_tracks)], n_frames)
    ids[:n_frames] = "ego"
    cats = np.where(ids == "ego", "EGO_VEHICLE", "REGULAR_VEHICLE")
    ts = np.concatenate([T0_NS + k * 100_000_000 + offset_ns(i) for i in range(n_tracks)])
    x = np.concatenate([k * 1.0 + 7.0 * i for i in range(n_tracks)])
    return pa.table(
        {
            "log_id": ["clocks"] * ids.size,
            "track_id": ids,
            "category": cats,
            "timestamp_ns": pa.array(ts, pa.int64()),
            "x_m": x,
            "y_m": np.repeat(np.arange(n_tracks) % 5 * 3.5, n_frames),
            "yaw_rad": np.zeros(ids.size),
            "length_m": np.full(ids.size, 4.5),
            "width_m": np.full(ids.size, 1.9),
        }
    )


def _one_clock(store: Any, report: Any, root: Path) -> None:
    meta = store.log_meta("clocks")
    assert meta.n_timestamps == 100 and meta.n_tracks == 200


@case(
    "tabular_track_clocks_1us_apart",
    "tabular",
    "200 tracks x 100 frames, each track's clock 1 µs later",
    "repaired",
    r"snapped 19900 timestamp\(s\) of 199 track\(s\) on their own clocks \(shifts up to 199 µs\) "
    r"to one clock of 100 timestamps",
    check=_one_clock,
)
def _(root: Path) -> list[Path]:
    root.mkdir(parents=True)
    pq.write_table(_clock_rows(lambda i: i * 1000), root / "clocks.parquet")
    return [root / "clocks.parquet"]


@case(
    "tabular_track_clocks_far_apart",
    "tabular",
    "200 tracks x 100 frames on clocks up to a frame apart",
    "rejected",
    r"clocks\.parquet: log 'clocks': the tracks are on different clocks: \d+ distinct timestamps",
)
def _(root: Path) -> list[Path]:
    root.mkdir(parents=True)
    offsets = np.random.default_rng(0).integers(0, 100_000_000, 200)
    pq.write_table(_clock_rows(lambda i: int(offsets[i]) if i else 0), root / "clocks.parquet")
    return [root / "clocks.parquet"]


def _bracket_file_printed(store: Any, output: Any, root: Path) -> None:
    assert "fleet-1" in store.log_ids() and "Traceback" not in output


@case(
    "tabular_file_name_with_markup",
    "tabular",
    "file named `[red]fleet[blink].csv`",
    "accepted",
    via="cli",
    check=_bracket_file_printed,
)
def _(root: Path) -> list[Path]:
    return _csv(root, tab_rows(), name="[red]fleet[blink].csv")


# ---------------------------------------------------------------------- paths


@case("path_missing", "path", "a path that does not exist", "rejected", r"missing: no such file or directory")
def _(root: Path) -> list[Path]:
    return [root / "missing"]


@case("path_symlink_loop", "path", "a symlink pointing to itself", "rejected", r"loop")
def _(root: Path) -> list[Path]:
    root.mkdir(parents=True)
    os.symlink(root / "loop", root / "loop")
    return [root / "loop"]


@case(
    "path_dangling_symlink",
    "path",
    "a symlink to nothing",
    "rejected",
    r"dangling: no such file or directory",
)
def _(root: Path) -> list[Path]:
    root.mkdir(parents=True)
    os.symlink(root / "nowhere", root / "dangling")
    return [root / "dangling"]


@case("path_fifo", "path", "a FIFO given as the path", "rejected", r"pipe\.csv: not a recognised log")
def _(root: Path) -> list[Path]:
    root.mkdir(parents=True)
    os.mkfifo(root / "pipe.csv")
    return [root / "pipe.csv"]


@case("path_empty_folder", "path", "an empty folder", "rejected", r"empty: not a recognised log")
def _(root: Path) -> list[Path]:
    (root / "empty").mkdir(parents=True)
    return [root / "empty"]


@case("path_unrecognised_file", "path", "a `.txt` file", "rejected", r"notes\.txt: not a recognised log")
def _(root: Path) -> list[Path]:
    root.mkdir(parents=True)
    (root / "notes.txt").write_text("nothing to see\n")
    return [root / "notes.txt"]


@case(
    "path_file_name_not_utf8",
    "path",
    "tabular file name with byte 0xff",
    "rejected",
    r"fleet-\\xff\.csv.*the path is not valid UTF-8",
)
def _(root: Path) -> list[Path]:
    return _csv(root, tab_rows(), name=os.fsdecode(b"fleet-\xff.csv"))


@case(
    "path_highd_tracks_file_is_folder",
    "path",
    "`01_tracks.csv` is a folder",
    "rejected",
    r"highD recording 01 is incomplete: 01_tracks\.csv is not a regular file",
)
def _(root: Path) -> list[Path]:
    files: HighDFiles = write_small_highway(root)
    files.tracks.unlink()
    files.tracks.mkdir()
    return [files.tracks_meta]
