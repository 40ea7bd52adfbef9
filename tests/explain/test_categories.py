"""Scenario categories: the paper's defaults, user files, and clear errors for bad files."""

from __future__ import annotations

from pathlib import Path

import pytest

from scenariominer.explain.categories import CategoryFileError, CategorySet, load_categories


def test_default_categories_are_the_papers_plus_fallbacks() -> None:
    cats = load_categories(None)
    assert cats.names == (
        "cut_in",
        "left_oppo",
        "right_ped",
        "obj_crossing",
        "unknown_but_relevant",
        "not_relevant",
    )
    assert cats.scenario_names == ("cut_in", "left_oppo", "right_ped", "obj_crossing")
    assert cats.source == "builtin"
    assert "oncoming" in cats.definition("left_oppo")
    with pytest.raises(KeyError, match="known"):
        cats.definition("lead_brake")


def test_user_file_adds_missing_fallbacks_last(tmp_path: Path) -> None:
    path = tmp_path / "cats.toml"
    path.write_text(
        'not_relevant = "The guest does not matter."\n'
        'lead_brake = "The vehicle ahead brakes suddenly."\n'
        'approach_stop = """The ego approaches\n   a stopped vehicle."""\n'
    )
    cats = load_categories(path)
    assert cats.names == ("lead_brake", "approach_stop", "unknown_but_relevant", "not_relevant")
    assert cats.definition("not_relevant") == "The guest does not matter."
    assert cats.definition("approach_stop") == "The ego approaches a stopped vehicle."
    assert cats.source == str(path)
    assert cats.fingerprint != CategorySet.default().fingerprint


def test_categories_table_form(tmp_path: Path) -> None:
    path = tmp_path / "cats.toml"
    path.write_text('[categories]\nlead_brake = "The vehicle ahead brakes."\n')
    assert load_categories(path).scenario_names == ("lead_brake",)


@pytest.mark.parametrize(
    ("content", "problem"),
    [
        ('invalid = "x"\n', "reserved"),
        ('Cut-In = "x"\n', "lower-case"),
        ('cut_in = ""\n', "non-empty"),
        ("cut_in = 3\n", "non-empty"),
        ('not_relevant = "x"\n', "no scenario category"),
        ("cut_in = \n", "not valid TOML"),
    ],
)
def test_bad_category_files_name_the_problem(tmp_path: Path, content: str, problem: str) -> None:
    path = tmp_path / "cats.toml"
    path.write_text(content)
    with pytest.raises(CategoryFileError, match=problem) as info:
        load_categories(path)
    assert str(path) in str(info.value)


def test_missing_file(tmp_path: Path) -> None:
    with pytest.raises(CategoryFileError, match="does not exist"):
        load_categories(tmp_path / "nope.toml")
