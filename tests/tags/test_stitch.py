"""Tracker-noise repair: id switches stitched, ghosts dropped, dropped frames filled."""

from __future__ import annotations

import numpy as np
import pytest
from yield_scenarios import pedestrian_yield

from scenariominer.config.tags import KeyIdentConfig, StitchConfig
from scenariominer.events.counterfactual import identify_key_objects
from scenariominer.tags import tag_log
from scenariominer.tags.stitch import ALIAS_NOTE_PREFIX, aliases_from_notes, match_switches, stitch_tracks
from scenariominer.testing import LogBuilder, times


def test_id_switch_on_the_key_object_is_stitched_and_found_once() -> None:
    log = pedestrian_yield(split_at_s=3.0).build(smooth=True)
    assert {"ped", "ped_b"} <= set(log.track_ids.tolist())
    result = stitch_tracks(log)
    assert result.aliases == {"ped": ("ped_b",)}
    assert "ped_b" not in result.log.track_ids
    ped = result.log.track_index("ped")
    assert result.log.valid[ped].all()  # the two dropped frames between the ids are filled
    assert result.n_filled == 2
    events = identify_key_objects(
        result.log, tag_log(result.log), KeyIdentConfig(method="combined"), aliases=result.aliases
    )
    assert [(ev.track_id, ev.aliases) for ev in events] == [("ped", ("ped_b",))]


def test_ghost_detection_is_dropped() -> None:
    t = times(6.0)
    ghost = (t >= 2.0 - 1e-9) & (t <= 2.2 + 1e-9)  # three frames right in the ego's path
    log = (
        LogBuilder(t)
        .ego(speed_mps=8.0)
        .add("car", "REGULAR_VEHICLE", speed_mps=8.0, x0_m=25.0)
        .add("ghost", "REGULAR_VEHICLE", x0_m=20.0, present=ghost)
        .build(smooth=True)
    )
    result = stitch_tracks(log)
    assert result.ghosts == ("ghost",)
    assert result.log.track_ids.tolist() == ["ego", "car"]
    assert any("ghost" in note for note in result.notes)


def test_implausibly_fast_track_is_a_ghost() -> None:
    t = times(4.0)
    log = LogBuilder(t).ego(speed_mps=5.0).add("streak", "REGULAR_VEHICLE", speed_mps=90.0, x0_m=10.0).build()
    assert stitch_tracks(log).ghosts == ("streak",)


def test_far_restart_is_not_the_same_object() -> None:
    # Two pedestrians: one leaves the view, another appears 6 m from where the first would be.
    t = times(6.0)
    log = (
        LogBuilder(t)
        .ego(speed_mps=0.0)
        .add("p1", "PEDESTRIAN", speed_mps=1.4, x0_m=10.0, y0_m=-5.0, yaw0_rad=np.pi / 2, present=t < 2.0)
        .add("p2", "PEDESTRIAN", speed_mps=1.4, x0_m=16.0, y0_m=-2.0, yaw0_rad=np.pi / 2, present=t >= 2.3)
        .build(smooth=True)
    )
    assert match_switches(log, StitchConfig()) == []
    assert stitch_tracks(log).aliases == {}


def test_other_category_is_not_stitched() -> None:
    t = times(6.0)
    log = (
        LogBuilder(t)
        .ego(speed_mps=0.0)
        .add("a", "REGULAR_VEHICLE", speed_mps=5.0, x0_m=10.0, present=t < 2.0)
        .add("b", "BUS", speed_mps=5.0, x0_m=10.0, present=t >= 2.2, length_m=4.5)
        .build(smooth=True)
    )
    assert match_switches(log, StitchConfig()) == []


def test_disabled_and_clean_logs_are_returned_unchanged() -> None:
    log = pedestrian_yield(split_at_s=3.0).build(smooth=True)
    assert stitch_tracks(log, StitchConfig(enabled=False)).log is log
    clean = pedestrian_yield().build(smooth=True)
    assert stitch_tracks(clean).log is clean


def test_alias_note_round_trip() -> None:
    notes = f"the guest is observed in only 2 frame(s) of the window; {ALIAS_NOTE_PREFIX}b,c"
    assert aliases_from_notes(notes) == ("b", "c")
    assert aliases_from_notes("nothing here") == ()


def test_bad_stitch_config() -> None:
    with pytest.raises(ValueError, match="max_gap_s"):
        StitchConfig(max_gap_s=-1.0)
