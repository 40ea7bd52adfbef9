"""Tabular adapter: long Parquet/CSV fleet tables round-trip and bad files fail with the cause."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq
import pytest

from scenariominer.config import Config, IngestConfig
from scenariominer.data.adapters.tabular import TabularReader, read_tabular, write_tabular
from scenariominer.data.log import STATE_FIELDS, Log, LogFormatError, build_log
from scenariominer.data.sources import LogReader

HEADER = "log_id,track_id,timestamp_ns,category,x_m,y_m,yaw_rad,length_m,width_m"


def _log(log_id: str, x0: float) -> Log:
    """Ego driving +x at 10 m/s and a pedestrian crossing, 5 frames at 10 Hz, plus a bus for 3 frames."""
    t = np.arange(5)
    rows = {
        "ego": ("EGO_VEHICLE", t, x0 + 1.0 * t, np.zeros(5), 0.0, 4.9, 2.0),
        "ped-7": ("PEDESTRIAN", t, np.full(5, x0 + 20.0), -3.0 + 0.15 * t, np.pi / 2, 0.6, 0.6),
        "bus": ("BUS", t[1:4], x0 + 40.0 - 0.8 * t[1:4], np.full(3, 3.5), np.pi, 12.0, 2.6),
    }
    cols: dict[str, list[object]] = {k: [] for k in ("tid", "cat", "ts", "x", "y", "yaw", "l", "w")}
    for tid, (cat, frames, x, y, yaw, length, width) in rows.items():
        n = len(frames)
        cols["tid"] += [tid] * n
        cols["cat"] += [cat] * n
        cols["ts"] += list(1_700_000_000_000_000_000 + frames * 100_000_000)
        cols["x"] += list(x)
        cols["y"] += list(y)
        cols["yaw"] += [yaw] * n
        cols["l"] += [length] * n
        cols["w"] += [width] * n
    f = {
        "x_m": np.asarray(cols["x"], dtype=float),
        "y_m": np.asarray(cols["y"], dtype=float),
        "yaw_rad": np.asarray(cols["yaw"], dtype=float),
        "length_m": np.asarray(cols["l"], dtype=float),
        "width_m": np.asarray(cols["w"], dtype=float),
    }
    return build_log(
        log_id=log_id,
        track_id=cols["tid"],
        category=cols["cat"],
        timestamp_ns=np.asarray(cols["ts"], dtype=np.int64),
        fields=f,
        ego_track_id=None,
        source="<test>",
        dataset="tabular",
    )


def _assert_same(a: Log, b: Log) -> None:
    assert a.log_id == b.log_id
    np.testing.assert_array_equal(a.timestamps_ns, b.timestamps_ns)
    np.testing.assert_array_equal(a.track_ids, b.track_ids)
    np.testing.assert_array_equal(a.categories, b.categories)
    np.testing.assert_array_equal(a.valid, b.valid)
    for name in STATE_FIELDS:
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name), err_msg=name)


def _write(path: Path, *lines: str) -> Path:
    path.write_text("\n".join(lines) + "\n")
    return path


def test_reader_satisfies_the_protocol() -> None:
    assert isinstance(TabularReader(), LogReader)
    assert TabularReader.format == "tabular"


@pytest.mark.parametrize("name", ["fleet.parquet", "fleet.csv"])
def test_round_trip_of_several_logs_in_one_file(tmp_path: Path, name: str) -> None:
    logs = [_log("drive-b", 100.0), _log("drive-a", 0.0)]
    path = write_tabular(logs, tmp_path / "out" / name)
    back = list(read_tabular(path))
    assert [b.log_id for b in back] == ["drive-a", "drive-b"]  # ascending log id
    for original, read in zip(sorted(logs, key=lambda g: g.log_id), back, strict=True):
        _assert_same(original, read)
        assert read.dataset == "tabular" and read.source_path == path
    assert back[0].track_ids.tolist() == ["ego", "bus", "ped-7"]
    assert back[0].categories.tolist() == ["EGO_VEHICLE", "BUS", "PEDESTRIAN"]


def test_reader_reads_a_file_through_discovery_with_the_configured_minimum_track_length(
    tmp_path: Path,
) -> None:
    path = write_tabular([_log("a", 0.0)], tmp_path / "a.parquet")
    reader = TabularReader()
    (source,) = reader.discover(path)
    assert source.files == (path.resolve(),) and source.format == "tabular"
    (log,) = reader.read(source, Config(ingest=IngestConfig(min_track_frames=4)))
    assert log.track_ids.tolist() == ["ego", "ped-7"]  # the 3-frame bus is dropped
    assert "dropped 1 track(s) with fewer than 4 frames" in log.notes[0]
    assert log.source_hash == source.content_hash()


def test_seconds_timestamps_and_is_ego_column(tmp_path: Path) -> None:
    path = _write(
        tmp_path / "small.csv",
        "log_id,track_id,timestamp_s,category,x_m,y_m,yaw_rad,length_m,width_m,is_ego,vx_mps,vy_mps,height_m",
        "L,1,0.0,car,0,0,0,4.5,1.9,true,5,0,1.4",
        "L,1,0.5,car,2.5,0,0,4.5,1.9,true,5,0,1.4",
        "L,2,0.0,Pedestrian,10,5,-1.5708,0.5,0.5,false,0,-1,1.7",
        "L,2,0.5,Pedestrian,10,4.5,-1.5708,0.5,0.5,false,0,-1,1.7",
    )
    (log,) = read_tabular(path)
    assert log.timestamps_ns.tolist() == [0, 500_000_000]
    assert log.track_ids.tolist() == ["1", "2"]
    assert log.categories.tolist() == ["EGO_VEHICLE", "PEDESTRIAN"]  # aliases map onto Argoverse 2 names
    np.testing.assert_allclose(log.vx_mps[0], 5.0)
    np.testing.assert_allclose(log.vy_mps[1], -1.0)
    np.testing.assert_allclose(log.height_m[:, 0], [1.4, 1.7])


def test_integer_ids_in_parquet_become_strings(tmp_path: Path) -> None:
    table = pa.table(
        {
            "log_id": [7, 7],
            "track_id": [3, 3],
            "timestamp_ns": pa.array([0, 100], type=pa.int32()),
            "category": ["EGO_VEHICLE"] * 2,
            **{c: [0.0, 1.0] for c in ("x_m", "y_m", "yaw_rad", "length_m", "width_m")},
        }
    )
    pq.write_table(table, tmp_path / "ints.parquet")
    (log,) = read_tabular(tmp_path / "ints.parquet")
    assert log.log_id == "7" and log.track_ids.tolist() == ["3"]


# --------------------------------------------------------------------------------------- bad input


def test_missing_columns_are_listed_with_the_expected_schema(tmp_path: Path) -> None:
    path = _write(tmp_path / "bad.csv", "log_id,track_id,category,x_m,y_m", "L,1,car,0,0")
    with pytest.raises(LogFormatError) as err:
        list(read_tabular(path))
    msg = str(err.value)
    assert msg.startswith(str(path))
    assert "missing column(s) ['yaw_rad', 'length_m', 'width_m', 'timestamp_ns (or timestamp_s)']" in msg
    assert "docs/tabular-schema.md" in msg and "optional" in msg


def test_nan_position_row_is_dropped_with_a_note(tmp_path: Path) -> None:
    path = _write(
        tmp_path / "nan.csv",
        HEADER,
        "L,ego,0,EGO_VEHICLE,0,0,0,4,2",
        "L,ego,100,EGO_VEHICLE,1,0,0,4,2",
        "L,ego,200,EGO_VEHICLE,NaN,0,0,4,2",
        "L,ego,300,EGO_VEHICLE,3,0,0,4,2",
        *(f"L,car,{t},car,{t / 10},5,0,4,2" for t in (0, 100, 200, 300)),
    )
    (log,) = read_tabular(path)
    assert log.valid[1].all()
    assert log.valid[0].tolist() == [True, True, False, True]
    assert np.isnan(log.x_m[0, 2])
    assert log.notes == ("dropped 1 row(s) with NaN/inf position, yaw or size (gaps are interpolated)",)


def test_conflicting_duplicate_timestamps_name_file_log_and_track(tmp_path: Path) -> None:
    path = _write(
        tmp_path / "dup.csv",
        HEADER,
        "L,ego,0,EGO_VEHICLE,0,0,0,4,2",
        "L,ego,100,EGO_VEHICLE,1,0,0,4,2",
        "L,car,100,REGULAR_VEHICLE,9,0,0,4,2",
        "L,car,100,REGULAR_VEHICLE,9.5,0,0,4,2",
    )
    with pytest.raises(
        LogFormatError, match=r"dup\.csv: log 'L': 1 duplicate .*track \S*'car'\S* at timestamp_ns=100"
    ):
        list(read_tabular(path))


def test_one_frame_track_is_dropped_with_a_note(tmp_path: Path) -> None:
    path = _write(
        tmp_path / "short.csv",
        HEADER,
        "L,ego,0,EGO_VEHICLE,0,0,0,4,2",
        "L,ego,100,EGO_VEHICLE,1,0,0,4,2",
        "L,blip,100,BOLLARD,5,5,0,0.3,0.3",
    )
    (log,) = read_tabular(path)
    assert log.track_ids.tolist() == ["ego"]
    assert log.notes == ("dropped 1 track(s) with fewer than 2 frames (e.g. ['blip'])",)


def test_unsorted_time_is_sorted(tmp_path: Path) -> None:
    # 10 Hz: the ego moves 1 m per frame (10 m/s), the car 2 m per frame (20 m/s).
    rows = [f"L,ego,{k * 100_000_000},EGO_VEHICLE,{k},0,0,4,2" for k in range(4)]
    rows += [f"L,car,{k * 100_000_000},REGULAR_VEHICLE,{10 + 2 * k},1,0,4,2" for k in (1, 2, 3)]
    ordered = list(read_tabular(_write(tmp_path / "sorted.csv", HEADER, *rows)))[0]
    shuffled = [rows[i] for i in (5, 2, 0, 6, 3, 1, 4)]
    log = list(read_tabular(_write(tmp_path / "shuffled.csv", HEADER, *shuffled)))[0]
    _assert_same(ordered, log)
    np.testing.assert_allclose(log.x_m[0], [0, 1, 2, 3])
    np.testing.assert_allclose(log.vx_mps[1, 1:], 20.0)


def test_unknown_category_names_the_value_and_the_file(tmp_path: Path) -> None:
    path = _write(
        tmp_path / "cat.csv",
        HEADER,
        "L,ego,0,EGO_VEHICLE,0,0,0,4,2",
        "L,ego,100,EGO_VEHICLE,1,0,0,4,2",
        "L,x,0,Hovercraft,5,5,0,3,2",
        "L,x,100,Hovercraft,6,5,0,3,2",
    )
    with pytest.raises(LogFormatError, match=r"cat\.csv: log 'L': unknown object category 'Hovercraft'"):
        list(read_tabular(path))


def test_ego_must_be_unique(tmp_path: Path) -> None:
    header = HEADER + ",is_ego"
    two_marked = _write(
        tmp_path / "two.csv",
        header,
        "L,a,0,car,0,0,0,4,2,true",
        "L,a,100,car,1,0,0,4,2,true",
        "L,b,0,car,5,0,0,4,2,true",
    )
    with pytest.raises(LogFormatError, match=r"two\.csv: log 'L': is_ego marks several tracks \['a', 'b'\]"):
        list(read_tabular(two_marked))
    conflict = _write(
        tmp_path / "conflict.csv",
        header,
        "L,a,0,car,0,0,0,4,2,true",
        "L,a,100,car,1,0,0,4,2,true",
        "L,b,0,EGO_VEHICLE,5,0,0,4,2,false",
        "L,b,100,EGO_VEHICLE,6,0,0,4,2,false",
    )
    with pytest.raises(LogFormatError, match=r"is_ego marks track 'a' but track\(s\) \['b'\] have category"):
        list(read_tabular(conflict))
    no_ego = _write(tmp_path / "none.csv", HEADER, "L,a,0,car,0,0,0,4,2", "L,a,100,car,1,0,0,4,2")
    with pytest.raises(LogFormatError, match=r"none\.csv: log 'L': no ego track"):
        list(read_tabular(no_ego))


def test_empty_ids_and_unparsable_values_are_errors(tmp_path: Path) -> None:
    empty = _write(tmp_path / "empty.csv", HEADER, ",ego,0,EGO_VEHICLE,0,0,0,4,2")
    with pytest.raises(LogFormatError, match=r"empty\.csv: column 'log_id' has 1 empty value"):
        list(read_tabular(empty))
    text = _write(tmp_path / "text.csv", HEADER, "L,ego,0,EGO_VEHICLE,zero,0,0,4,2")
    with pytest.raises(LogFormatError, match=r"text\.csv: cannot read the table"):
        list(read_tabular(text))


# ------------------------------------------------------------------------------- discovery and writing


def test_discover_finds_tables_recursively_and_skips_highd_and_hidden_files(tmp_path: Path) -> None:
    write_tabular([_log("a", 0.0)], tmp_path / "fleet" / "2024" / "a.parquet")
    write_tabular([_log("b", 0.0)], tmp_path / "fleet" / "b.csv")
    for skipped in ("01_tracks.csv", "01_tracksMeta.csv", "01_recordingMeta.csv", ".hidden.csv", "x.feather"):
        (tmp_path / "fleet" / skipped).write_text("x\n")
    (tmp_path / "fleet" / ".cache").mkdir()
    (tmp_path / "fleet" / ".cache" / "c.csv").write_text("x\n")
    sources = TabularReader().discover(tmp_path / "fleet")
    assert [s.path.relative_to((tmp_path / "fleet").resolve()).as_posix() for s in sources] == [
        "2024/a.parquet",
        "b.csv",
    ]
    assert TabularReader().discover(tmp_path / "fleet" / "x.feather") == []
    assert TabularReader().discover(tmp_path / "nowhere") == []


def test_write_tabular_rejects_unknown_suffixes_and_duplicate_logs(tmp_path: Path) -> None:
    with pytest.raises(ValueError, match="suffix '.feather'"):
        write_tabular([_log("a", 0.0)], tmp_path / "a.feather")
    with pytest.raises(ValueError, match="occurs twice"):
        write_tabular([_log("a", 0.0), _log("a", 1.0)], tmp_path / "a.csv")
    with pytest.raises(ValueError, match="at least one log"):
        write_tabular([], tmp_path / "a.csv")
