"""Configuration: defaults are the papers' values; TOML and environment override them."""

from __future__ import annotations

from pathlib import Path

import pytest

from scenariominer.config import Config, ConfigError, load_config


def test_defaults_without_file() -> None:
    cfg = load_config(environ={})
    assert cfg == Config()
    assert cfg.preprocess.smooth_window_s == 1.0
    assert cfg.ingest.highd_window_s == 15.0


def test_toml_values_override_defaults(tmp_path: Path) -> None:
    p = tmp_path / "c.toml"
    p.write_text("[preprocess]\nsmooth_window_s = 0.7\n[ingest]\nhighd_ego_ids = [3, 4]\n")
    cfg = load_config(p, environ={})
    assert cfg.preprocess.smooth_window_s == 0.7
    assert cfg.ingest.highd_ego_ids == (3, 4)


def test_environment_overrides_file(tmp_path: Path) -> None:
    p = tmp_path / "c.toml"
    p.write_text("[preprocess]\nsmooth_window_s = 0.7\n")
    cfg = load_config(
        p,
        environ={
            "SCENARIOMINER__PREPROCESS__SMOOTH_WINDOW_S": "1.5",
            "SCENARIOMINER__PREPROCESS__SMOOTH_YAW": "false",
        },
    )
    assert cfg.preprocess.smooth_window_s == 1.5
    assert cfg.preprocess.smooth_yaw is False


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("[preprocess]\nsmooth_window = 1\n", r"unknown key\(s\) \['smooth_window'\] in \[preprocess\]"),
        ("[nonsense]\na = 1\n", r"unknown key\(s\) \['nonsense'\]"),
        ("[preprocess]\nsmooth_polyorder = 'three'\n", "preprocess.smooth_polyorder must be an integer"),
        ("[preprocess\n", "not valid TOML"),
    ],
)
def test_bad_files_name_the_key(tmp_path: Path, text: str, message: str) -> None:
    p = tmp_path / "c.toml"
    p.write_text(text)
    with pytest.raises(ConfigError, match=message):
        load_config(p, environ={})


def test_missing_file_is_a_clear_error(tmp_path: Path) -> None:
    with pytest.raises(ConfigError, match="does not exist"):
        load_config(tmp_path / "nope.toml", environ={})


@pytest.mark.parametrize(
    ("toml", "message"),
    [
        ("[preprocess]\nsmooth_window_s = -1.0\n", "smooth_window_s must be in (0, 60]"),
        ("[preprocess]\nsmooth_polyorder = 0\n", "smooth_polyorder must be an integer from 1 to 7"),
        ("[preprocess]\nmax_gap_s = nan\n", "preprocess.max_gap_s must be a finite number"),
        ("[ingest]\nmin_track_frames = 0\n", "min_track_frames must be at least 1"),
        ("[ingest]\nhighd_radius_m = inf\n", "ingest.highd_radius_m must be a finite number"),
        ("[ingest]\nhighd_ego_ids = [3, -1]\n", "highd_ego_ids must hold non-negative"),
        ("[ingest]\nhighd_window_s = true\n", "ingest.highd_window_s must be a number"),
        ("[preprocess]\nwindow = 3\n", "unknown key(s) ['window'] in [preprocess]"),
        # integers: inf crashed the loader with OverflowError; 2.5 was silently truncated to 2
        ("[llm]\ntop_k = inf\n", "llm.top_k must be an integer, got inf"),
        ("[mining.generation]\nmax_attempts = 2.5\n", "max_attempts must be an integer, got 2.5"),
        ("[llm]\nseed = 99999999999999999999999\n", "llm.seed must fit 64 bits"),
    ],
)
def test_bad_values_name_the_file_and_the_key(tmp_path: Path, toml: str, message: str) -> None:
    path = tmp_path / "bad.toml"
    path.write_text(toml, encoding="utf-8")
    with pytest.raises(ConfigError) as info:
        load_config(path, environ={})
    assert message in str(info.value) and str(path) in str(info.value)


def test_environment_values_are_validated_too() -> None:
    with pytest.raises(ConfigError, match="smooth_window_s"):
        load_config(environ={"SCENARIOMINER__PREPROCESS__SMOOTH_WINDOW_S": "0"})
