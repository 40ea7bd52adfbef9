"""tag_log produces the Table II matrices; LogTags survives a round trip through Arrow/Parquet."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq
import pytest
from tag_scenarios import Track, braking_lead_scene, integrate, make_log, times

import scenariominer.tags as tags_pkg
from scenariominer.config import load_config
from scenariominer.config.tags import TagConfig
from scenariominer.tags import ABSENT, TAG_FAMILIES, LogTags, TagTableError, tag_log


@pytest.fixture(scope="module")
def braking_tags() -> LogTags:
    return tag_log(braking_lead_scene())


def _assert_same(a: LogTags, b: LogTags) -> None:
    assert a.log_id == b.log_id
    np.testing.assert_array_equal(a.track_ids, b.track_ids)
    np.testing.assert_array_equal(a.categories, b.categories)
    np.testing.assert_array_equal(a.timestamps_ns, b.timestamps_ns)
    for family in TAG_FAMILIES:
        np.testing.assert_array_equal(a.codes(family), b.codes(family), err_msg=family)
    np.testing.assert_array_equal(a.ttc_s, b.ttc_s)  # inf and NaN compare equal position-wise
    np.testing.assert_array_equal(a.distance_m, b.distance_m)


def test_tag_matrices_have_the_shape_and_dtype_of_table_ii(braking_tags: LogTags) -> None:
    n, t = braking_tags.n_tracks, braking_tags.n_timestamps
    assert (n, t) == (4, 101)
    for family in TAG_FAMILIES:
        codes = braking_tags.codes(family)
        assert codes.shape == (n, t) and codes.dtype == np.int8
        assert codes.min() >= ABSENT and codes.max() < len(TAG_FAMILIES[family])
    assert braking_tags.ttc_s.shape == braking_tags.distance_m.shape == (n, t)
    # Actor tags cover the ego; interaction tags leave its row undefined.
    assert np.all(braking_tags.longitude[0] != ABSENT)
    for family in ("collision", "heading", "position", "distance", "traj_overlap"):
        assert np.all(braking_tags.codes(family)[0] == ABSENT)
    assert braking_tags.track_ids[0] == "ego"


def test_names_decode_codes(braking_tags: LogTags) -> None:
    names = braking_tags.names("position")
    assert names[0, 0] is None
    assert names[braking_tags.track_index("lead"), 0] == "FRONT"
    with pytest.raises(KeyError, match="unknown tag family"):
        braking_tags.codes("speed")


def test_arrow_round_trip_keeps_every_cell(braking_tags: LogTags) -> None:
    table = braking_tags.to_arrow()
    assert table.num_rows == int(braking_tags.valid.sum())
    assert pa.types.is_dictionary(table.schema.field("longitude").type)
    _assert_same(LogTags.from_arrow(table), braking_tags)


def test_parquet_round_trip_with_plain_string_columns(braking_tags: LogTags, tmp_path: Path) -> None:
    table = braking_tags.to_arrow()
    plain = table.cast(
        pa.schema(
            [pa.field(f.name, pa.string()) if pa.types.is_dictionary(f.type) else f for f in table.schema],
            metadata=table.schema.metadata,
        )
    )
    pq.write_table(plain, tmp_path / "tags.parquet")
    _assert_same(LogTags.from_arrow(pq.read_table(tmp_path / "tags.parquet")), braking_tags)


def test_round_trip_keeps_a_track_absent_for_part_of_the_log() -> None:
    t = times(4.0)
    present = t > 2.0
    log = make_log(
        [
            Track("ego", "EGO_VEHICLE", *integrate(t, 5.0)),
            Track("late", "PEDESTRIAN", *integrate(t, 1.0, x0_m=10.0), 0.6, 0.6, present),
        ],
        t,
    )
    tags = tag_log(log)
    assert np.all(tags.longitude[1, ~present] == ABSENT)
    _assert_same(LogTags.from_arrow(tags.to_arrow()), tags)


def test_from_arrow_names_an_unknown_tag_and_a_missing_column(braking_tags: LogTags) -> None:
    table = braking_tags.to_arrow()
    broken = table.set_column(
        table.schema.get_field_index("heading"), "heading", pa.array(["SIDEWAYS"] * table.num_rows)
    )
    with pytest.raises(TagTableError, match="SIDEWAYS"):
        LogTags.from_arrow(broken)
    with pytest.raises(TagTableError, match="ttc_s"):
        LogTags.from_arrow(table.drop_columns(["ttc_s"]))
    with pytest.raises(TagTableError, match="log id"):
        LogTags.from_arrow(table.replace_schema_metadata(None))


def test_thresholds_come_from_the_config(braking_tags: LogTags) -> None:
    # Widening the CLOSE band to 100 m turns every MEDIUM/FAR cell CLOSE.
    wide = tag_log(braking_lead_scene(), TagConfig(distance_close_m=100.0, distance_far_m=100.0))
    assert set(np.unique(wide.distance[1:])) <= {0, 1}
    assert not np.array_equal(wide.distance, braking_tags.distance)


def test_tag_config_rejects_inconsistent_thresholds_and_loads_from_the_environment() -> None:
    with pytest.raises(ValueError, match="veer_angle_rad"):
        TagConfig(veer_angle_rad=0.3, turn_angle_rad=0.17)
    cfg = load_config(environ={"SCENARIOMINER__TAGS__TTC_HIGH_S": "1.0"})
    assert cfg.tags.ttc_high_s == 1.0
    assert cfg.tags.turn_angle_rad == 0.17


def test_an_ego_only_log_is_tagged() -> None:
    t = times(2.0)
    tags = tag_log(make_log([Track("ego", "EGO_VEHICLE", *integrate(t, 0.0))], t))
    assert tags.n_tracks == 1
    assert set(tags.names("longitude")[0]) == {"STANDING_STILL"}


def test_public_api_is_exported() -> None:
    for name in tags_pkg.__all__:
        assert hasattr(tags_pkg, name)


def test_real_argoverse_log_ego_brakes_stops_and_turns_left(av2_log_dir: Path) -> None:
    from scenariominer.data.adapters.av2 import read_av2_log
    from scenariominer.data.preprocess import preprocess

    log = preprocess(read_av2_log(av2_log_dir))
    tags = tag_log(log)
    assert (tags.n_tracks, tags.n_timestamps) == (log.n_tracks, log.n_timestamps)
    t = log.t_s
    longitude = tags.names("longitude")[0]
    latitude = tags.names("latitude")[0]
    # Recorded ego motion: 4.5 m/s down to a stop at about 3.5 s, still until about 4.9 s, then a
    # 90° left turn (heading +1.6 rad between 5 s and 15 s, most of it between 9 s and 14 s).
    assert set(longitude[(t > 0.5) & (t < 3.0)]) == {"DECELERATING"}
    assert set(longitude[(t > 3.7) & (t < 4.7)]) == {"STANDING_STILL"}
    assert set(latitude[(t > 9.5) & (t < 13.5)]) == {"TURNING_LEFT"}
