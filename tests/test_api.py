"""Ingestion through the public API: incremental, atomic per source, and tolerant of bad logs."""

from __future__ import annotations

import shutil
from pathlib import Path

import pyarrow.feather as feather
import pytest

from scenariominer import api


@pytest.fixture(scope="module")
def synth_dir(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("synth")
    api.synth(out, 4, seed=3)
    return out


def test_ingest_real_and_synthetic_logs_then_reingest_skips_everything(
    tmp_path: Path, av2_log_dir: Path, synth_dir: Path
) -> None:
    store = api.open_store(tmp_path / "store")
    first = api.ingest([av2_log_dir, synth_dir], store)
    assert first.n_ingested == 5 and not first.failed
    assert first.store.n_logs == 5
    assert first.store.n_tracks == 119 + sum(
        store.log_meta(i).n_tracks for i in store.log_ids() if i != av2_log_dir.name
    )
    assert first.store.categories["EGO_VEHICLE"] == 5
    second = api.ingest([av2_log_dir, synth_dir], store)
    assert second.n_skipped == 5 and second.n_ingested == 0
    assert second.store.n_frames == first.store.n_frames


def test_changed_preprocessing_settings_force_reingestion(tmp_path: Path, synth_dir: Path) -> None:
    from scenariominer.config import Config, PreprocessConfig

    store = api.open_store(tmp_path / "store")
    api.ingest([synth_dir], store)
    again = api.ingest([synth_dir], store, Config(preprocess=PreprocessConfig(smooth_window_s=0.7)))
    assert again.n_ingested == 4


def test_a_modified_log_is_reingested_alone(tmp_path: Path, synth_dir: Path) -> None:
    data = tmp_path / "data"
    shutil.copytree(synth_dir, data)
    store = api.open_store(tmp_path / "store")
    api.ingest([data], store)
    victim = sorted(p for p in data.iterdir() if p.is_dir())[0]
    table = feather.read_table(victim / "annotations_with_ego.feather")
    feather.write_feather(table.slice(0, table.num_rows - 1), victim / "annotations_with_ego.feather")
    report = api.ingest([data], store)
    assert report.n_ingested == 1 and report.n_skipped == 3


def test_a_broken_log_fails_alone_and_writes_nothing(tmp_path: Path, synth_dir: Path) -> None:
    data = tmp_path / "data"
    shutil.copytree(synth_dir, data)
    victim = sorted(p for p in data.iterdir() if p.is_dir())[1]
    table = feather.read_table(victim / "annotations_with_ego.feather")
    feather.write_feather(table.drop_columns(["tx_m"]), victim / "annotations_with_ego.feather")
    store = api.open_store(tmp_path / "store")
    report = api.ingest([data], store)
    assert report.n_ingested == 3
    assert len(report.failed) == 1
    assert "tx_m" in report.failed[0].error and victim.name in report.failed[0].key
    assert victim.name not in store.log_ids()
    # The rows of the good logs are all there, and none of the broken one.
    rows = store.sql("SELECT count(DISTINCT log_id) AS n FROM tracks").column("n")[0].as_py()
    assert rows == 3


def test_a_log_that_breaks_later_keeps_its_previous_version(tmp_path: Path, synth_dir: Path) -> None:
    data = tmp_path / "data"
    shutil.copytree(synth_dir, data)
    store = api.open_store(tmp_path / "store")
    api.ingest([data], store)
    victim = sorted(p for p in data.iterdir() if p.is_dir())[2]
    before = store.load_log(victim.name)
    (victim / "city_SE3_egovehicle.feather").write_bytes(b"not a feather file")
    report = api.ingest([data], store)
    assert len(report.failed) == 1 and "city_SE3_egovehicle.feather" in report.failed[0].error
    after = store.load_log(victim.name)
    assert after.n_frames == before.n_frames


def test_unknown_paths_are_reported_per_path_with_a_clear_error(tmp_path: Path) -> None:
    store = api.open_store(tmp_path / "store")
    (tmp_path / "empty").mkdir()
    report = api.ingest([tmp_path / "missing", tmp_path / "empty"], store)
    errors = {Path(r.key).name: r.error for r in report.failed}
    assert "no such file" in errors["missing"] and "not a recognised log" in errors["empty"]
    assert report.n_ingested == 0 and store.log_ids() == []
