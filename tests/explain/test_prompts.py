"""The prompt: role, tag guide, categories, instructions in the shared system message; the
description alone in the user message."""

from __future__ import annotations

from scenariominer.config.tags import TagConfig
from scenariominer.explain.categories import CategoryDef, CategorySet
from scenariominer.explain.prompts import JUDGE_PROMPT_VERSION, build_messages, system_prompt
from scenariominer.llm.base import Role


def test_messages_put_everything_shared_in_the_system_message() -> None:
    cats = CategorySet.default()
    a = build_messages("Overview: first.", cats)
    b = build_messages("Overview: second.", cats)
    assert [m.role for m in a] == [Role.SYSTEM, Role.USER]
    assert a[0] == b[0]  # identical prefix for every event
    assert a[1].content == "Scenario description:\nOverview: first."
    for name in cats.names:
        assert f"- {name}: {cats.definition(name)}" in a[0].content
    for key in ('"description"', '"category"', '"explanation"'):
        assert key in a[0].content


def test_a_new_prompt_version_forces_re_analysis(monkeypatch) -> None:  # type: ignore[no-untyped-def]
    import scenariominer.explain.pipeline as pipeline
    from scenariominer.config import Config
    from scenariominer.testing import HashingEmbedder

    cats, embedder = CategorySet.default(), HashingEmbedder(16)
    before = pipeline.analysis_fingerprint(Config(), cats, None, embedder)
    monkeypatch.setattr(pipeline, "JUDGE_PROMPT_VERSION", JUDGE_PROMPT_VERSION + "-next")
    assert pipeline.analysis_fingerprint(Config(), cats, None, embedder) != before


def test_tag_guide_quotes_the_configured_thresholds() -> None:
    text = system_prompt(CategorySet.default(), TagConfig(distance_close_m=12.0, ttc_high_s=1.2))
    assert "CLOSE (under 12 m)" in text
    assert "HIGH (collision predicted within 1.2 s)" in text
    assert "0.05 to 0.17 rad" in text


def test_custom_categories_are_listed_in_order() -> None:
    cats = CategorySet((CategoryDef("lead_brake", "The lead brakes."), CategoryDef("not_relevant", "No.")))
    text = system_prompt(cats)
    assert text.index("- lead_brake: The lead brakes.") < text.index("- not_relevant: No.")
    assert "cut_in" not in text


def test_builtin_categories_come_with_a_tag_pattern_checklist() -> None:
    text = system_prompt(CategorySet.default())
    assert "a. the ego is TURNING_LEFT or VEERING_LEFT" in text
    assert "OPPOSITE: left_oppo;" in text
    assert "PEDESTRIAN: right_ped;" in text
    assert "while ahead of the ego: cut_in.\n" in text


def test_checklist_lists_only_the_patterns_of_present_categories() -> None:
    cats = CategorySet((CategoryDef("right_ped", "A pedestrian."), CategoryDef("not_relevant", "No.")))
    text = system_prompt(cats)
    assert "a. the ego is TURNING_RIGHT or VEERING_RIGHT and the guest is a PEDESTRIAN: right_ped." in text
    assert "left_oppo" not in text and "b." not in text
