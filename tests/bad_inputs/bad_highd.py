"""Bad highD recordings (cases for the corpus in ``bad_registry``).

Each starts from the small 2 + 2 lane recording of ``tests/data/highd_files.py`` and breaks one thing.
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path
from typing import Any

from bad_registry import case
from highd_files import (
    LOWER_MARKINGS_M,
    UPPER_MARKINGS_M,
    edit_csv,
    small_highway_vehicles,
    write_small_highway,
)

from scenariominer.data.adapters.highd import write_highd_recording

# ---------------------------------------------------------------------- highD


def _highd(root: Path, edit: Any = None, file: str = "tracks") -> list[Path]:
    files = write_small_highway(root)
    if edit is not None:
        edit_csv(getattr(files, file), edit)
    return [root]


def _set(rows: list[list[str]], column: str, value: Any, where: Any = lambda r: True) -> list[list[str]]:
    """Rows with ``column`` set to ``value(row)`` (or ``value``) on the data rows where ``where(row)``."""
    k = rows[0].index(column)
    out = [rows[0]]
    for r in rows[1:]:
        if where(r):
            r = [*r[:k], str(value(r) if callable(value) else value), *r[k + 1 :]]
        out.append(r)
    return out


@case(
    "highd_tracks_missing_column",
    "highd",
    "tracks without `xVelocity`",
    "rejected",
    r"01_tracks\.csv: missing column\(s\) \['xVelocity'\]",
)
def _(root: Path) -> list[Path]:
    return _highd(root, lambda rows: [r[:6] + r[7:] for r in rows])


@case(
    "highd_recording_id_infinite",
    "highd",
    "recordingMeta `id` of `inf`",
    "rejected",
    r"01_recordingMeta\.csv: column 'id' is not an integer: 'inf'",
)
def _(root: Path) -> list[Path]:
    return _highd(root, lambda rows: _set(rows, "id", "inf"), "recording_meta")


@case(
    "highd_lane_marking_nan",
    "highd",
    "`upperLaneMarkings` with a `nan`",
    "rejected",
    r"01_recordingMeta\.csv: column 'upperLaneMarkings' has a non-finite or out-of-range marking",
)
def _(root: Path) -> list[Path]:
    def edit(rows: list[list[str]]) -> list[list[str]]:
        k = rows[0].index("upperLaneMarkings")
        return _set(rows, "upperLaneMarkings", lambda r: r[k] + ";nan")

    return _highd(root, edit, "recording_meta")


@case(
    "highd_frame_rate_contradicts_tracks",
    "highd",
    "`frameRate` 50 for 25 Hz tracks",
    "rejected",
    r"01_recordingMeta\.csv: frameRate 50 Hz disagrees with the tracks: .* imply 25 frames per second",
)
def _(root: Path) -> list[Path]:
    return _highd(root, lambda rows: _set(rows, "frameRate", 50), "recording_meta")


@case(
    "highd_frame_rate_zero",
    "highd",
    "`frameRate` 0",
    "rejected",
    r"01_recordingMeta\.csv: frameRate must be a positive number",
)
def _(root: Path) -> list[Path]:
    return _highd(root, lambda rows: _set(rows, "frameRate", 0), "recording_meta")


@case(
    "highd_frame_rate_not_a_number",
    "highd",
    "`frameRate` `fast`",
    "rejected",
    r"column 'frameRate' is not a number: 'fast'",
)
def _(root: Path) -> list[Path]:
    return _highd(root, lambda rows: _set(rows, "frameRate", "fast"), "recording_meta")


@case(
    "highd_duration_shorter_than_tracks",
    "highd",
    "`duration` 5 s for 20 s of tracks",
    "rejected",
    r"the tracks span 20\.00 s at frameRate 25 Hz, longer than the recording's duration of 5 s",
)
def _(root: Path) -> list[Path]:
    return _highd(root, lambda rows: _set(rows, "duration", "5.00"), "recording_meta")


@case(
    "highd_meta_span_disagrees_for_one_vehicle",
    "highd",
    "`numFrames` of one vehicle off by one",
    "repaired",
    r"dropped 1 vehicle\(s\) whose rows in 01_tracks\.csv disagree with 01_tracksMeta\.csv "
    r"\(e\.g\. vehicle 3: initialFrame=51, finalFrame=350, numFrames=299 in tracksMeta "
    r"but frames 51\.\.350 in 300 row\(s\)\)",
)
def _(root: Path) -> list[Path]:
    return _highd(root, lambda rows: _set(rows, "numFrames", 299, lambda r: r[0] == "3"), "tracks_meta")


@case(
    "highd_meta_describes_other_tracks",
    "highd",
    "every `initialFrame` shifted by one",
    "rejected",
    r"01_tracksMeta\.csv: does not describe 01_tracks\.csv: the frame span of every vehicle disagrees",
)
def _(root: Path) -> list[Path]:
    return _highd(root, lambda rows: _set(rows, "initialFrame", lambda r: int(r[3]) + 1), "tracks_meta")


@case(
    "highd_meta_vehicle_without_rows",
    "highd",
    "tracksMeta lists a vehicle with no rows",
    "repaired",
    r"01_tracksMeta\.csv: ignored 1 vehicle\(s\) with no rows in 01_tracks\.csv \(e\.g\. \[9\]\)",
)
def _(root: Path) -> list[Path]:
    return _highd(root, lambda rows: [*rows, ["9", *rows[-1][1:]]], "tracks_meta")


@case(
    "highd_rows_of_vehicle_missing_from_meta",
    "highd",
    "tracks of a vehicle absent from tracksMeta",
    "rejected",
    r"1 vehicle id\(s\) of the tracks are not listed in 01_tracksMeta\.csv, e\.g\. \[3\]",
)
def _(root: Path) -> list[Path]:
    return _highd(root, lambda rows: [r for r in rows if r[0] != "3"], "tracks_meta")


@case("highd_non_numeric_cell", "highd", "`x` of `abc`", "rejected", r"01_tracks\.csv: cannot parse CSV")
def _(root: Path) -> list[Path]:
    return _highd(root, lambda rows: _set(rows, "x", "abc", lambda r: r[:2] == ["7", "2"]))


@case(
    "highd_tracks_header_only",
    "highd",
    "tracks file with a header and no rows",
    "rejected",
    r"01_tracks\.csv: the file has a header but no rows",
)
def _(root: Path) -> list[Path]:
    return _highd(root, lambda rows: rows[:1])


@case("highd_tracks_empty_file", "highd", "tracks file of 0 bytes", "rejected", r"01_tracks\.csv: empty file")
def _(root: Path) -> list[Path]:
    files = write_small_highway(root)
    files.tracks.write_bytes(b"")
    return [root]


@case(
    "highd_tracks_not_utf8",
    "highd",
    "tracks header with byte 0xff",
    "rejected",
    r"01_tracks\.csv: not a text CSV file",
)
def _(root: Path) -> list[Path]:
    files = write_small_highway(root)
    files.tracks.write_bytes(b"\xff" + files.tracks.read_bytes())
    return [root]


@case("highd_byte_order_mark", "highd", "UTF-8 byte-order mark before each header", "accepted")
def _(root: Path) -> list[Path]:
    files = write_small_highway(root)
    for path in files.all:
        path.write_bytes(b"\xef\xbb\xbf" + path.read_bytes())
    return [root]


@case(
    "highd_semicolon_delimiter",
    "highd",
    "tracks separated by `;`",
    "rejected",
    r"01_tracks\.csv: the header has no ',' but ';': .*comma-separated",
)
def _(root: Path) -> list[Path]:
    files = write_small_highway(root)
    files.tracks.write_text(files.tracks.read_text().replace(",", ";"))
    return [root]


@case(
    "highd_nan_position",
    "highd",
    "empty `x` cell",
    "rejected",
    r"01_tracks\.csv: column 'x' has 1 missing/non-finite value\(s\) \(first at id 2, frame 7\)",
)
def _(root: Path) -> list[Path]:
    return _highd(root, lambda rows: _set(rows, "x", "", lambda r: r[:2] == ["7", "2"]))


@case(
    "highd_duplicate_rows_conflicting",
    "highd",
    "two rows for one (id, frame), different `x`",
    "rejected",
    r"1 duplicate \(id, frame\) row\(s\) with different values, e\.g\. id 1 at frame 10",
)
def _(root: Path) -> list[Path]:
    return _highd(root, lambda rows: [*rows, [rows[10][0], rows[10][1], "999.00", *rows[10][3:]]])


@case(
    "highd_duplicate_rows_identical",
    "highd",
    "a row repeated exactly",
    "repaired",
    r"01_tracks\.csv: collapsed 1 exact duplicate \(id, frame\) row",
)
def _(root: Path) -> list[Path]:
    return _highd(root, lambda rows: [*rows, rows[10]])


@case(
    "highd_unsorted_rows",
    "highd",
    "rows in reverse order",
    "repaired",
    r"01_tracks\.csv: rows were not sorted by \(id, frame\); sorted them",
)
def _(root: Path) -> list[Path]:
    return _highd(root, lambda rows: rows[:1] + rows[1:][::-1])


@case(
    "highd_unknown_class",
    "highd",
    "class `Tractor`",
    "rejected",
    r"01_tracksMeta\.csv: column 'class': unknown object category 'Tractor'",
)
def _(root: Path) -> list[Path]:
    return _highd(root, lambda rows: _set(rows, "class", "Tractor", lambda r: r[0] == "2"), "tracks_meta")


@case(
    "highd_bad_driving_direction",
    "highd",
    "`drivingDirection` 3",
    "rejected",
    r"drivingDirection must be 1 \(left\) or 2 \(right\), got 3 for vehicle 2",
)
def _(root: Path) -> list[Path]:
    return _highd(root, lambda rows: _set(rows, "drivingDirection", 3, lambda r: r[0] == "2"), "tracks_meta")


@case(
    "highd_missing_meta_file",
    "highd",
    "no `recordingMeta` file",
    "rejected",
    r"highD recording 01 is incomplete: 01_recordingMeta\.csv is missing",
)
def _(root: Path) -> list[Path]:
    write_small_highway(root).recording_meta.unlink()
    return [root]


@case(
    "highd_recording_meta_without_rows",
    "highd",
    "recordingMeta with a header only",
    "rejected",
    r"01_recordingMeta\.csv: no data row",
)
def _(root: Path) -> list[Path]:
    return _highd(root, lambda rows: rows[:1], "recording_meta")


@case(
    "highd_no_full_window",
    "highd",
    "no vehicle visible for a whole window",
    "rejected",
    r"no vehicle of highD recording 01 is visible for a full 4 s window",
)
def _(root: Path) -> list[Path]:
    short = [
        replace(v, x_m=v.x_m[:50], y_m=v.y_m[:50], vx_mps=None, vy_mps=None) for v in small_highway_vehicles()
    ]
    write_highd_recording(
        root, 1, short, upper_lane_markings_m=UPPER_MARKINGS_M, lower_lane_markings_m=LOWER_MARKINGS_M
    )
    return [root]
