"""Who forced the ego to brake: the label of an urban run, from the simulator's own state.

Each scenario runs twice, with the guest and without it (:mod:`.urban_run`). The guest *caused*
a braking when

1. the ego's speed with the guest falls more than :data:`DIVERGENCE_MPS` below its speed without
   it (the *divergence*);
2. the ego really brakes there: from the *onset* (the start of the deceleration that leads to the
   divergence) its speed drops by at least :data:`MIN_DROP_MPS` with a deceleration of at least
   :data:`MIN_DECEL_MPS2`;
3. without the guest the ego loses less than :data:`AMBIGUOUS_SHARE` of that speed drop (it may
   slow down for a turn; if it brakes as much, something else would also explain the braking:
   the run is *ambiguous*);
4. SUMO's state around the divergence names the guest as the reason, in the way of the family:
   the ego's leader (``vehicle.getLeader``) for a braking lead, a cut-in (the guest was not the
   leader 3 s before and changed lanes) or a stopped vehicle; one of the ego's junction foes
   (``vehicle.getJunctionFoes``) for an oncoming or crossing vehicle; a pedestrian on the
   crossing or its walking areas (its SUMO edge) for a pedestrian; and no other vehicle is the
   ego's leader within :data:`OTHER_LEADER_M` for the junction families.

A run that fails one of these is not labelled (:attr:`UrbanLabel.reason` says why) and the
scenario is drawn again. The interaction window runs from the guest's action (at most
:data:`MAX_LEAD_S` before the onset) to the ego driving on again (its speed back above its
minimum plus 1 m/s), or to its lowest speed when it does not.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from scenariominer.sim.urban_run import GUEST_ID, STEP_S, RunRecord
from scenariominer.synth.vocab import ScenarioCategory

__all__ = [
    "AMBIGUOUS_SHARE",
    "DIVERGENCE_MPS",
    "MAX_LEAD_S",
    "MIN_DECEL_MPS2",
    "MIN_DROP_MPS",
    "OTHER_LEADER_M",
    "UrbanLabel",
    "label_run",
]

#: Speed difference (m/s) with and without the guest that marks the guest's effect.
DIVERGENCE_MPS = 1.0
#: Smallest speed drop (m/s) and peak deceleration (m/s²) that count as braking.
MIN_DROP_MPS = 2.0
MIN_DECEL_MPS2 = 1.0
#: Without the guest the ego may slow down (for a turn) by at most this share of its braking.
AMBIGUOUS_SHARE = 0.5
#: A vehicle other than the guest this close ahead (m) makes a junction scenario ambiguous.
OTHER_LEADER_M = 30.0
#: The window starts at most this long (s) before the onset.
MAX_LEAD_S = 5.0
#: Extra deceleration (m/s², negative) with the guest, against the run without it, that starts a braking.
_ONSET_ACCEL_MPS2 = -0.3


@dataclass(frozen=True)
class UrbanLabel:
    """The label of one run (or why it has none).

    Attributes:
        category: the scenario category; ``None`` when the run is not labelled.
        onset_index: step of the ego's braking onset (-1 without a label).
        start_index, end_index: first and last step of the interaction window.
        reason: why the run is not labelled (empty when it is).
    """

    category: ScenarioCategory | None
    onset_index: int = -1
    start_index: int = -1
    end_index: int = -1
    reason: str = ""

    @property
    def ok(self) -> bool:
        """Whether the run is labelled."""
        return self.category is not None


def _onset(accel: np.ndarray, accel_without: np.ndarray, div: int, first: int) -> int:
    """Walk back from the divergence while the ego brakes harder than it would without the guest."""
    k = div
    while k > first and accel[k - 1] - accel_without[k - 1] < _ONSET_ACCEL_MPS2:
        k -= 1
    return k


def _leader_cause(family: ScenarioCategory, full: RunRecord, onset: int, div: int) -> str:
    """Empty when SUMO's leader state supports ``family``; else the reason it does not."""
    n = len(full.ego_leader)
    window = range(max(onset - 5, 0), min(div + 10, n))
    if not any(full.ego_leader[k] == GUEST_ID for k in window):
        return "the guest is not the ego's leader when it brakes"
    before = max(onset - int(3.0 / STEP_S), 0)
    if family is ScenarioCategory.CUT_IN:
        if full.ego_leader[before] == GUEST_ID:
            return "the guest was already the ego's leader 3 s before the braking (not a cut-in)"
        lanes = {full.guest_lane[k] for k in range(before, min(div + 10, n)) if full.guest_lane[k] >= 0}
        if len(lanes) < 2:
            return "the guest did not change lanes"
    elif family is ScenarioCategory.LEAD_BRAKE:
        if full.ego_leader[before] != GUEST_ID:
            return "the guest was not the ego's leader before it braked"
        acc = full.guest_accel_mps2[max(onset - 20, 0) : min(div + 5, n)]
        if not np.nanmin(acc, initial=np.inf) < -1.0:
            return "the leader did not brake"
    elif family is ScenarioCategory.APPROACH_STOP and not full.guest_speed_mps[onset] < 0.5:
        return "the vehicle ahead is not stopped"
    return ""


def _junction_cause(family: ScenarioCategory, full: RunRecord, onset: int, div: int) -> str:
    n = len(full.ego_leader)
    window = range(max(onset - 5, 0), min(div + 10, n))
    other = [
        k
        for k in range(onset, min(div + 1, n))
        if full.ego_leader[k] not in ("", GUEST_ID) and full.ego_leader_gap_m[k] < OTHER_LEADER_M
    ]
    if other:
        return f"another vehicle ({full.ego_leader[other[0]]}) is close ahead of the ego"
    if family in (ScenarioCategory.PED_CROSSING, ScenarioCategory.RIGHT_PED):
        if not any(full.guest_edge[k].startswith(":") for k in window):
            return "the pedestrian is not on a crossing or its walking areas when the ego brakes"
        return ""
    if not any(GUEST_ID in full.ego_foes[k] for k in window):
        return "the guest is not one of the ego's junction foes when it brakes"
    return ""


def label_run(family: ScenarioCategory, full: RunRecord, without: RunRecord) -> UrbanLabel:
    """Label the run ``full`` of a scenario of ``family`` against its run ``without`` the guest."""
    n = min(full.t_s.size, without.t_s.size)
    diff = without.ego_speed_mps[:n] - full.ego_speed_mps[:n]
    # Measured from the guest's action: a guest present from the start (a leader) may already
    # have set the ego's speed a little before it acts.
    i_act = int(np.searchsorted(full.t_s, full.guest_action_s)) if np.isfinite(full.guest_action_s) else 0
    if i_act >= n:
        return UrbanLabel(None, reason="the guest never acted")
    hits = np.flatnonzero(diff[i_act:] - max(float(diff[i_act]), 0.0) > DIVERGENCE_MPS)
    if hits.size == 0:
        return UrbanLabel(None, reason="the guest did not slow the ego down")
    div = i_act + int(hits[0])
    onset = _onset(full.ego_accel_mps2, without.ego_accel_mps2, div, i_act)
    horizon = slice(onset, min(onset + int(12.0 / STEP_S), full.t_s.size))
    v = full.ego_speed_mps[horizon]
    drop = float(full.ego_speed_mps[onset] - v.min())
    if drop < MIN_DROP_MPS or float(full.ego_accel_mps2[horizon].min()) > -MIN_DECEL_MPS2:
        return UrbanLabel(None, reason=f"the ego barely braked (speed drop {drop:.1f} m/s)")
    if full.collisions:
        return UrbanLabel(None, reason=f"the ego collided with {', '.join(full.collisions)}")
    v_cf = without.ego_speed_mps[onset : min(onset + int(12.0 / STEP_S), n)]
    if v_cf.size and float(without.ego_speed_mps[onset] - v_cf.min()) > AMBIGUOUS_SHARE * drop:
        return UrbanLabel(None, reason="the ego brakes without the guest too (ambiguous cause)")
    leader_family = family in (
        ScenarioCategory.CUT_IN,
        ScenarioCategory.LEAD_BRAKE,
        ScenarioCategory.APPROACH_STOP,
    )
    why = (_leader_cause if leader_family else _junction_cause)(family, full, onset, div)
    if why:
        return UrbanLabel(None, onset_index=onset, reason=why)
    i_min = onset + int(np.argmin(v))
    after = np.flatnonzero(full.ego_speed_mps[i_min:] > full.ego_speed_mps[i_min] + 1.0)
    end = i_min + int(after[0]) if after.size else i_min
    action = full.guest_action_s
    start = onset
    if np.isfinite(action):
        i_act = int(np.searchsorted(full.t_s, action))
        start = max(min(onset, i_act), onset - int(MAX_LEAD_S / STEP_S))
    return UrbanLabel(family, onset_index=onset, start_index=start, end_index=end)
