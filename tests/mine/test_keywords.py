"""Keyword extraction for the multimodal filter: colours, object phrases, spatial words."""

from __future__ import annotations

from typing import Any

import pytest

from scenariominer.mine.keywords import KeywordSet, ObjectPhrase, extract_keywords, load_nlp


def test_phrases_are_the_objects_without_repeats_or_the_description() -> None:
    kw = KeywordSet(
        "red car left of a red car",
        ("red",),
        (ObjectPhrase("car", ("red",), "red car"), ObjectPhrase("car", ("red",), "red car")),
        ("left",),
    )
    assert kw.phrases() == ["red car"]
    assert kw.phrases(include_spatial=True) == ["red car", "left"]
    assert KeywordSet("  something  ", (), (), ()).phrases() == ["something"]


@pytest.fixture(scope="module")
def nlp() -> Any:
    pytest.importorskip("spacy")
    return load_nlp()


@pytest.mark.slow  # loads spaCy's English pipeline (a few seconds)
@pytest.mark.parametrize(
    ("description", "colours", "phrases", "spatial"),
    [
        ("red car with a bicycle to its right", ("red",), ["red car", "bicycle"], ("right",)),
        (
            "pedestrian crossing in front of a white bus",
            ("white",),
            ["pedestrian crossing", "white bus"],
            ("in front of",),
        ),
        (
            "two pedestrians next to a dark blue van",
            ("dark", "blue"),
            ["pedestrians", "dark blue van"],
            ("next to",),
        ),
        ("bus in the bike lane", (), ["bus", "bike lane"], ()),
        ("pedestrian facing the ego vehicle", (), ["pedestrian"], ()),
        ("vehicle behind a black truck", ("black",), ["vehicle", "black truck"], ("behind",)),
    ],
)
def test_keywords_of_descriptions(
    nlp: Any, description: str, colours: tuple[str, ...], phrases: list[str], spatial: tuple[str, ...]
) -> None:
    kw = extract_keywords(description, nlp)
    assert kw.colours == colours
    assert kw.phrases() == phrases
    assert kw.spatial == spatial
    assert kw.description == description


@pytest.mark.slow
def test_object_phrases_carry_their_colours_and_lemmas(nlp: Any) -> None:
    kw = extract_keywords("two red cars near a green bicycle", nlp)
    assert [(o.noun, o.colours, o.phrase) for o in kw.objects] == [
        ("car", ("red",), "red cars"),
        ("bicycle", ("green",), "green bicycle"),
    ]
    assert kw.spatial == ("near",)
