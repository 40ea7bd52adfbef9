"""Case base: near-duplicates, bad rows, import files, vocabularies."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from scenariominer.cbr.cases import Case, read_case_file
from scenariominer.cbr.vocab import CbrError, load_manoeuvres, load_risk_types

from .helpers import EMBEDDER, case_base


def test_default_vocabularies_are_the_papers_table_1() -> None:
    assert len(load_risk_types().names) == 7
    m = load_manoeuvres()
    assert len(m.names) == 8
    assert m.by_effort()[0].name == "emergency_braking"
    assert m.get("braking_and_steering_left").label == "Emergency Braking and Evasive Steering Left"


def test_near_duplicate_within_risk_type_is_reported_not_stored(tmp_path: Path) -> None:
    base = case_base(tmp_path)
    n = len(base)
    dup = Case(
        "d1",
        "vehicle_ahead",
        "A stopped truck blocks the lane far ahead on a wet road.",
        manoeuvre="emergency_braking",
    )
    report = base.add([dup], EMBEDDER, 0.97)
    assert report.added == () and report.duplicates[0].existing_id == "a1"
    assert report.duplicates[0].similarity >= 0.97
    assert len(base) == n


def test_same_caption_in_another_risk_type_is_not_a_duplicate(tmp_path: Path) -> None:
    base = case_base(tmp_path)
    other = Case(
        "o1",
        "head_on",
        "a stopped truck blocks the lane far ahead on a wet road",
        manoeuvre="evasive_steering_right",
    )
    assert base.add([other], EMBEDDER, 0.97).added == ("o1",)


def test_bad_cases_are_rejected_with_reason_and_the_rest_stored(tmp_path: Path) -> None:
    base = case_base(tmp_path, [])
    cases = [
        Case("x1", "meteor_strike", "a rock falls", manoeuvre="emergency_braking"),
        Case("x2", "pedestrian", "a man crosses", manoeuvre="fly"),
        Case("x3", "pedestrian", "a woman crosses", manoeuvre="emergency_braking"),
    ]
    report = base.add(cases, EMBEDDER, 0.97)
    assert report.added == ("x3",)
    reasons = dict(report.rejected)
    assert "unknown risk type 'meteor_strike'" in reasons["x1"]
    assert "unknown manoeuvre 'fly'" in reasons["x2"]


def test_remove_and_get(tmp_path: Path) -> None:
    base = case_base(tmp_path)
    assert base.get("a2").caption.startswith("the car in front")
    assert base.remove(["a2", "zz"]) == 1
    with pytest.raises(CbrError, match="no case 'a2'"):
        base.get("a2")


def test_import_csv_and_jsonl(tmp_path: Path) -> None:
    csv_file = tmp_path / "cases.csv"
    csv_file.write_text(
        "risk_type,caption,manoeuvre,justification\n"
        "pedestrian,a jogger crosses at night,Emergency Braking,stops in time\n"
        "pedestrian,,emergency_braking,\n",
        encoding="utf-8",
    )
    cases, rejected = read_case_file(csv_file, load_manoeuvres())
    assert [c.manoeuvre for c in cases] == ["emergency_braking"]  # the label became the name
    assert cases[0].source == "import:cases.csv"
    assert rejected[0][0] == "cases.csv:3" and "caption" in rejected[0][1]
    jl = tmp_path / "cases.jsonl"
    rows = [
        {"risk_type": "head_on", "caption": "wrong-way van", "manoeuvre": "evasive_steering_right"},
        {"colour": "red"},
    ]
    jl.write_text("\n".join(json.dumps(r) for r in rows) + "\n{broken\n", encoding="utf-8")
    cases, rejected = read_case_file(jl, load_manoeuvres())
    assert len(cases) == 1 and len(rejected) == 2
    assert "unknown field" in rejected[0][1] and "not JSON" in rejected[1][1]
    (tmp_path / "cases.xlsx").write_bytes(b"PK")
    with pytest.raises(CbrError, match="unknown case file type"):
        read_case_file(tmp_path / "cases.xlsx", load_manoeuvres())


def test_bad_vocabulary_file_names_the_problem(tmp_path: Path) -> None:
    p = tmp_path / "m.toml"
    p.write_text('[brake]\nlabel = "Brake"\neffort = "low"\n', encoding="utf-8")
    with pytest.raises(CbrError, match=r"brake.effort must be a number"):
        load_manoeuvres(p)
