"""Synthetic, labelled braking scenarios written as Argoverse 2 sensor logs with a vector map.

Each generated log lasts 15 s at 10 Hz and contains the ego, one labelled *guest* whose behaviour
makes the ego brake (or, for ``not_relevant``, traffic that does not), and several background
objects (moving traffic, parked cars, pedestrians on the sidewalks). Every log comes with a small
vector map (a straight four-lane road, or a four-way intersection with crosswalks) in the
Argoverse 2 JSON format, so map-aware features work on synthetic data as on real data.

How a scenario is made (all in closed form with numpy, never a per-frame simulation loop):

1. Actors follow *paths* (dense polylines along the map's lane centre lines, crosswalks or
   sidewalks) with piecewise-linear *speed profiles*; position along the path is the exact
   integral of the profile.
2. The guest's timing is drawn first. The ego's braking is then *derived* from it, so it is
   physically consistent: for a leader (cut-in, braking lead, stopped object) the gentlest
   deceleration at or above a drawn preference that keeps a gap is found by checking candidate
   profiles on a fine time grid; for a crossing actor (pedestrian, crossing vehicle, oncoming
   vehicle in a left turn) the ego brakes to stop a drawn margin before the swept corridor of
   the guest, timed so that it would otherwise arrive while the guest is in that corridor, and
   drives on once the guest has cleared it.
3. Background actors are drawn at random and kept only if their boxes never come near the ego's
   within a 3 s look-ahead (so they cannot explain the braking) nor overlap the guest.
4. Annotation noise is added: position jitter (0.05-0.1 m), heading jitter, random missing
   frames, occlusion gaps, and a visibility range.
5. The scene is placed in the city frame by a random rotation and translation.

Labels follow the braking paper's annotation scheme (``log_id``, ``guest_id``,
``scenario_category``) plus the time window of the interaction: from the guest's triggering
action (or the ego's braking onset, whichever is earlier) until the ego drives on again after
yielding or following to a stop, or, where it does not (a cut-in, a stopped object ahead), until
it has reached its lowest speed. For ``not_relevant`` it is the time the guest spends within
40 m of the ego.

The in-memory logs (:func:`generate_log`) carry the ego's box centre (``dataset="synthetic"``).
Written logs follow the Argoverse 2 convention (the writer moves the ego pose to the rear axle,
:data:`~scenariominer.data.adapters.av2.AV2_EGO_CENTER_OFFSET_M` behind the box centre, and the reader back).
"""

from __future__ import annotations

from scenariominer.synth.generate import (
    generate,
    generate_log,
)
from scenariominer.synth.vocab import (
    LABEL_COLUMNS,
    MapLayout,
    ScenarioCategory,
    ScenarioLabel,
    SynthLog,
    SynthResult,
    read_labels,
    write_labels,
)

__all__ = [
    "LABEL_COLUMNS",
    "MapLayout",
    "ScenarioCategory",
    "ScenarioLabel",
    "SynthLog",
    "SynthResult",
    "generate",
    "generate_log",
    "read_labels",
    "write_labels",
]
