"""The columnar Scenario value: construction rules, Boolean composition and post-processing."""

from __future__ import annotations

import numpy as np
import pytest
from mining_scenes import Obj, const, make_log

from scenariominer.config.mining import MiningConfig
from scenariominer.mine.context import LogContext
from scenariominer.mine.scenario import (
    Scenario,
    postprocess_scenario,
    reverse_relationship,
    scenario_and,
    scenario_not,
    scenario_or,
)

T = np.round(np.arange(10) * 0.1, 6)


def _ctx(config: MiningConfig | None = None) -> LogContext:
    """Ego plus tracks a, b (all frames) and c (frames 2..5 only), standing 10 m apart on a line."""
    zero = const(0.0, T)
    present_c = np.zeros(T.size, dtype=bool)
    present_c[2:6] = True
    objs = [
        Obj("ego", "EGO_VEHICLE", zero, zero, zero),
        Obj("a", "REGULAR_VEHICLE", const(10.0, T), zero, zero),
        Obj("b", "PEDESTRIAN", const(20.0, T), zero, zero, 0.5, 0.5),
        Obj("c", "BICYCLE", const(100.0, T), zero, zero, 1.8, 0.6, present=present_c),
    ]
    return LogContext(make_log(objs, T, log_id="tiny"), config)


def _mask(ctx: LogContext, cells: dict[str, list[int]]) -> np.ndarray:
    m = np.zeros((ctx.n_tracks, ctx.n_timestamps), dtype=bool)
    for tid, ts in cells.items():
        m[ctx.log.track_index(tid), ts] = True
    return m


def _rel(ctx: LogContext, rows: list[tuple[str, int, str]]) -> np.ndarray:
    return np.array([[ctx.log.track_index(a), t, ctx.log.track_index(b)] for a, t, b in rows], dtype=np.int64)


# ---------------------------------------------------------------------- construction


def test_from_mask_drops_cells_outside_the_observations_and_orphan_relations() -> None:
    ctx = _ctx()
    mask = _mask(ctx, {"a": [0, 1], "c": [0, 1, 2]})  # c is only observed from frame 2
    rel = _rel(ctx, [("a", 0, "b"), ("a", 5, "b"), ("a", 1, "c"), ("a", 1, "a")])
    s = Scenario.from_mask(ctx, mask, rel)
    assert s.referred[ctx.log.track_index("c")].tolist() == [False, False, True] + [False] * 7
    # (a, 5) is not referred, c is absent at frame 1, and a track is never related to itself
    assert s.relations.tolist() == _rel(ctx, [("a", 0, "b")]).tolist()


def test_constructor_rejects_cells_outside_the_log_and_relations_off_referred_cells() -> None:
    ctx = _ctx()
    bad = _mask(ctx, {"c": [0]})
    with pytest.raises(ValueError, match="valid mask"):
        Scenario(ctx, bad, np.zeros((0, 3), dtype=np.int64))
    with pytest.raises(ValueError, match="referred cell"):
        Scenario(ctx, _mask(ctx, {"a": [0]}), _rel(ctx, [("a", 1, "b")]))
    with pytest.raises(ValueError, match="shape"):
        Scenario(ctx, np.zeros((2, 2), dtype=bool), np.zeros((0, 3), dtype=np.int64))


def test_from_arrays_validates_untrusted_input() -> None:
    ctx = _ctx()
    ok = Scenario.from_arrays(ctx, _mask(ctx, {"a": [3]}), _rel(ctx, [("a", 3, "b"), ("a", 3, "b")]))
    assert ok.relations.shape == (1, 3)
    with pytest.raises(ValueError, match="boolean"):
        Scenario.from_arrays(ctx, np.zeros((ctx.n_tracks, ctx.n_timestamps)), [])
    with pytest.raises(ValueError, match="outside the log"):
        Scenario.from_arrays(ctx, _mask(ctx, {"a": [3]}), [[1, 3, 99]])


def test_scenario_arrays_are_read_only() -> None:
    s = Scenario.from_mask(_ctx(), _mask(_ctx(), {"a": [0]}))
    with pytest.raises(ValueError):
        s.referred[0, 0] = True


def test_views_list_referred_and_related_timestamps() -> None:
    ctx = _ctx()
    s = Scenario.from_mask(ctx, _mask(ctx, {"a": [1, 2]}), _rel(ctx, [("a", 2, "b")]))
    ts = ctx.log.timestamps_ns
    assert {k: v.tolist() for k, v in s.referred_timestamps().items()} == {"a": ts[[1, 2]].tolist()}
    assert {k: {kk: vv.tolist() for kk, vv in v.items()} for k, v in s.related_timestamps().items()} == {
        "a": {"b": [int(ts[2])]}
    }
    assert len(s) == 1 and list(s) == ["a"] and "a" in s and "b" not in s
    assert s.related_mask[ctx.log.track_index("b")].tolist() == [False, False, True] + [False] * 7
    assert s.timestamp_mask.sum() == 2 and not s.is_empty and Scenario.empty(ctx).is_empty


# ---------------------------------------------------------------------- composition


def test_and_keeps_common_cells_with_the_relations_of_every_input() -> None:
    ctx = _ctx()
    s1 = Scenario.from_mask(ctx, _mask(ctx, {"a": [0, 1, 2], "b": [0]}), _rel(ctx, [("a", 1, "b")]))
    s2 = Scenario.from_mask(ctx, _mask(ctx, {"a": [1, 2, 3]}), _rel(ctx, [("a", 2, "ego"), ("a", 3, "ego")]))
    both = scenario_and([s1, s2])
    assert both.referred.sum() == 2 and both.referred[ctx.log.track_index("a"), [1, 2]].all()
    assert both.relations.tolist() == _rel(ctx, [("a", 1, "b"), ("a", 2, "ego")]).tolist()
    assert scenario_and(s1, s2).referred.tolist() == both.referred.tolist()


def test_or_unites_cells_and_relations() -> None:
    ctx = _ctx()
    s1 = Scenario.from_mask(ctx, _mask(ctx, {"a": [0]}), _rel(ctx, [("a", 0, "b")]))
    s2 = Scenario.from_mask(ctx, _mask(ctx, {"b": [5]}))
    either = scenario_or([s1, s2])
    assert either.n_referred_cells == 2 and either.relations.shape == (1, 3)


def test_composition_rejects_non_scenarios_and_mixed_logs() -> None:
    ctx, other = _ctx(), _ctx()
    s = Scenario.empty(ctx)
    with pytest.raises(TypeError, match="not a scenario"):
        scenario_and([s, "vehicles"])  # type: ignore[list-item]
    with pytest.raises(ValueError, match="different logs"):
        scenario_or([s, Scenario.empty(other)])
    with pytest.raises(ValueError, match="at least one"):
        scenario_and([])


def test_not_returns_candidate_cells_where_the_predicate_fails_keeping_old_relations() -> None:
    ctx = _ctx()
    cand = Scenario.from_mask(ctx, _mask(ctx, {"a": [0, 1, 2]}), _rel(ctx, [("a", 0, "b"), ("a", 1, "b")]))

    def holds_at_frame_1(track_candidates: Scenario, log_dir: LogContext) -> Scenario:
        return track_candidates.restrict(_mask(log_dir, {"a": [1]}))

    result = scenario_not(holds_at_frame_1)(cand, ctx)
    assert np.flatnonzero(result.referred[ctx.log.track_index("a")]).tolist() == [0, 2]
    assert result.relations.tolist() == _rel(ctx, [("a", 0, "b")]).tolist()


def test_not_explains_misuse() -> None:
    ctx = _ctx()
    with pytest.raises(TypeError, match="FUNCTION, not a scenario"):
        scenario_not(Scenario.empty(ctx))  # type: ignore[arg-type]
    with pytest.raises(TypeError, match="returned int"):
        scenario_not(lambda tc, log: 3)(Scenario.empty(ctx), ctx)


def test_reverse_relationship_makes_related_objects_referred() -> None:
    ctx = _ctx()
    s = Scenario.from_mask(ctx, _mask(ctx, {"a": [0, 1]}), _rel(ctx, [("a", 0, "b"), ("a", 1, "ego")]))
    r = reverse_relationship(s)
    assert isinstance(r, Scenario)
    assert np.flatnonzero(r.referred[ctx.log.track_index("b")]).tolist() == [0]
    assert np.flatnonzero(r.referred[ctx.log.track_index("ego")]).tolist() == [1]
    assert r.relations.tolist() == _rel(ctx, [("ego", 1, "a"), ("b", 0, "a")]).tolist()
    wrapped = reverse_relationship(lambda *args: s)
    assert callable(wrapped) and wrapped().relations.tolist() == r.relations.tolist()  # type: ignore[operator,union-attr]


# ---------------------------------------------------------------------- post-processing


def test_postprocess_drops_single_timestamp_tracks_and_widens_short_runs() -> None:
    ctx = _ctx()
    s = Scenario.from_mask(ctx, _mask(ctx, {"a": [5], "b": [2, 7]}))
    out = postprocess_scenario(s)
    assert not out.referred[ctx.log.track_index("a")].any()  # one timestamp: noise
    # each single-frame run of b grows by (3 - 1) // 2 = 1 frame on both sides
    assert np.flatnonzero(out.referred[ctx.log.track_index("b")]).tolist() == [1, 2, 3, 6, 7, 8]


def test_postprocess_thresholds_come_from_the_config() -> None:
    ctx = _ctx(MiningConfig(postprocess_min_timestamps=1, postprocess_min_run_timestamps=5))
    s = Scenario.from_mask(ctx, _mask(ctx, {"a": [5], "c": [2]}))
    out = postprocess_scenario(s)
    assert np.flatnonzero(out.referred[ctx.log.track_index("a")]).tolist() == [3, 4, 5, 6, 7]
    # c is only observed in frames 2..5: widening stays inside its observations
    assert np.flatnonzero(out.referred[ctx.log.track_index("c")]).tolist() == [2, 3, 4]


def test_postprocess_drops_relations_between_far_apart_objects() -> None:
    # ego at x = 0, a at 10 m, c at 100 m
    ctx = _ctx()
    s = Scenario.from_mask(ctx, _mask(ctx, {"ego": [2, 3, 4]}), _rel(ctx, [("ego", 3, "a"), ("ego", 3, "c")]))
    assert postprocess_scenario(s).relations.tolist() == _rel(ctx, [("ego", 3, "a")]).tolist()
    far = _ctx(MiningConfig(postprocess_max_relation_distance_m=5.0))
    s2 = Scenario.from_mask(far, _mask(far, {"ego": [2, 3, 4]}), _rel(far, [("ego", 3, "a")]))
    assert postprocess_scenario(s2).relations.shape == (0, 3)


def test_postprocess_unrefers_cells_whose_related_objects_were_all_dropped() -> None:
    # RefAV refers a track at the timestamps of its remaining related objects: a cell whose every
    # relation was beyond 50 m is no longer referred, and a track with no relation left is dropped
    ctx = _ctx(MiningConfig(postprocess_min_run_timestamps=1))
    ego, a = ctx.log.track_index("ego"), ctx.log.track_index("a")
    rel = _rel(
        ctx,
        [("ego", 2, "a"), ("ego", 3, "a"), ("ego", 3, "c"), ("ego", 4, "c"), ("ego", 5, "c")]
        + [("a", 2, "c"), ("a", 3, "c"), ("a", 4, "c")],
    )
    s = Scenario.from_mask(ctx, _mask(ctx, {"ego": [2, 3, 4, 5, 6], "a": [2, 3, 4]}), rel)
    out = postprocess_scenario(s)
    # frames 4 and 5 only had c (100 m away); frame 6 never had a related object and stays
    assert np.flatnonzero(out.referred[ego]).tolist() == [2, 3, 6]
    assert out.relations.tolist() == _rel(ctx, [("ego", 2, "a"), ("ego", 3, "a")]).tolist()
    # a was only related to c, 90 m away: nothing of it is left
    assert not out.referred[a].any()


def test_public_api_of_the_mining_package() -> None:
    import scenariominer.mine as mine

    for name in mine.__all__:
        assert getattr(mine, name) is not None
    assert {"Scenario", "LogContext", "run_program", "run_trusted_program", "load_examples"} <= set(
        mine.__all__
    )
