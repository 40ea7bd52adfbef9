"""Dual-path retrieval on a small store: by category, by text, criticality filters and sorting."""

from __future__ import annotations

import math
from pathlib import Path

import pytest
from braking_builders import record, store_with_events

from scenariominer.explain.search import (
    InvalidSearchError,
    NoEventsError,
    SearchQuery,
    SortKey,
    search_events,
)
from scenariominer.llm import HashingEmbedder
from scenariominer.store import EmbeddingMismatchError, ScenarioStore

EMB = HashingEmbedder(64)


@pytest.fixture(scope="module")
def store(tmp_path_factory: pytest.TempPathFactory) -> ScenarioStore:
    records = [
        record(
            "log-a",
            "car1",
            category="cut_in",
            peak_decel_mps2=4.0,
            min_ttc_s=1.2,
            pet_s=0.8,
            llm_description="a white car cuts in from the right lane",
            explanation="moved in front",
        ),
        record(
            "log-a",
            "ped1",
            category="obj_crossing",
            peak_decel_mps2=2.0,
            min_ttc_s=math.inf,
            guest_category="PEDESTRIAN",
            llm_description="a pedestrian crosses the road in front of the ego",
        ),
        record(
            "log-b",
            "car2",
            category="cut_in",
            peak_decel_mps2=1.0,
            min_ttc_s=2.5,
            pet_s=math.nan,
            llm_description="a truck merges into the ego lane",
            headway_s=0.9,
        ),
        record(
            "log-b",
            "bus",
            category="not_relevant",
            peak_decel_mps2=6.0,
            min_ttc_s=0.4,
            llm_description="a bus drives far away on the other side",
        ),
    ]
    return store_with_events(tmp_path_factory.mktemp("search"), records, EMB)


def test_category_path_returns_every_event_of_the_category_in_log_order(store: ScenarioStore) -> None:
    hits = search_events(store, SearchQuery(category="cut_in"))
    assert [(h.event.log_id, h.event.guest_id) for h in hits] == [("log-a", "car1"), ("log-b", "car2")]
    assert all(math.isnan(h.score) for h in hits)
    first = hits[0].to_json_dict()
    assert first["category"] == "cut_in" and first["explanation"] == "moved in front"
    assert first["start_ns"] == 1_000_000_000 and first["min_ttc_s"] == 1.2
    assert search_events(store, SearchQuery(category="left_oppo")) == []


def test_text_path_ranks_by_cosine_similarity(store: ScenarioStore) -> None:
    hits = search_events(store, SearchQuery(text="a pedestrian crosses in front of the ego", k=2), EMB)
    assert len(hits) == 2
    assert hits[0].event.guest_id == "ped1"
    assert hits[0].score > hits[1].score
    assert -1.0 <= hits[1].score <= 1.0


def test_text_inside_a_category(store: ScenarioStore) -> None:
    hits = search_events(store, SearchQuery(text="a truck merges", category="cut_in", k=5), EMB)
    assert [h.event.guest_id for h in hits] == ["car2", "car1"]


def test_criticality_filters_and_sorting(store: ScenarioStore) -> None:
    hard = search_events(store, SearchQuery(min_decel_mps2=3.0, sort=SortKey.DECEL))
    assert [h.event.guest_id for h in hard] == ["bus", "car1"]
    by_ttc = search_events(store, SearchQuery(category="cut_in", sort=SortKey.TTC))
    assert [h.event.guest_id for h in by_ttc] == ["car1", "car2"]
    risky = search_events(store, SearchQuery(category="cut_in", max_ttc_s=2.0))
    assert [h.event.guest_id for h in risky] == ["car1"]
    decel = search_events(store, SearchQuery(text="car", sort=SortKey.DECEL, k=4), EMB)
    assert [h.event.peak_decel_mps2 for h in decel] == [6.0, 4.0, 2.0, 1.0]
    pet = search_events(store, SearchQuery(category="cut_in", sort=SortKey.PET))
    assert [h.event.guest_id for h in pet] == ["car1", "car2"]  # NaN sorts last
    top1 = search_events(store, SearchQuery(category="cut_in", sort=SortKey.DECEL, k=1))
    assert [h.event.guest_id for h in top1] == ["car1"]


def test_bad_queries_are_clear_errors(store: ScenarioStore, tmp_path: Path) -> None:
    with pytest.raises(EmbeddingMismatchError, match="hashing-64"):
        search_events(store, SearchQuery(text="a car"), HashingEmbedder(32))
    with pytest.raises(ValueError, match="embedder"):
        search_events(store, SearchQuery(text="a car"))
    with pytest.raises(InvalidSearchError, match="k must"):
        SearchQuery(category="cut_in", k=0)
    with pytest.raises(InvalidSearchError, match="score needs a text"):
        SearchQuery(category="cut_in", sort=SortKey.SCORE)
    # an empty text was a plain ValueError: the command line called it an internal error
    with pytest.raises(InvalidSearchError, match="the text query is empty"):
        SearchQuery(text="  ")
    with pytest.raises(NoEventsError, match="analyze"):
        search_events(ScenarioStore.open(tmp_path / "empty"), SearchQuery(category="cut_in"))


def test_an_unknown_category_is_an_error_naming_the_stored_ones(store: ScenarioStore) -> None:
    # a typo ("cut-in") matched nothing and said "0 event(s)"
    with pytest.raises(
        InvalidSearchError, match=r"unknown category 'cut-in'.*cut_in, not_relevant, obj_crossing"
    ):
        search_events(store, SearchQuery(category="cut-in"), known_categories=("cut_in", "left_oppo"))
    # a configured category no event has is a plain empty answer
    assert search_events(store, SearchQuery(category="left_oppo"), known_categories=("left_oppo",)) == []
