"""Texts of synthetic cases, written from the scene's data with templates of varied wording.

These are generated, not human-written: the caption, the analysis fields and the justification of
a synthetic case are filled from the drawn parameters (kinds, speeds, gaps, sides, blockers) and
the rollout outcomes (which manoeuvres collide with what, the clearance kept). Each slot has
several phrasings drawn at random so captions of similar scenes are not word-for-word equal.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from scenariominer.cbr.cases import Case
from scenariominer.cbr.rollout import RECORDED
from scenariominer.cbr.scenes import LabelledScene
from scenariominer.cbr.vocab import ManoeuvreSet

__all__ = ["case_from_scene"]

_ROLE_NAMES = {
    "main": "the {kind} involved",
    "left": "the car in the left lane",
    "right": "the parked {right} on the right",
    "behind": "the car following closely behind",
}


def _kmh(mps: float) -> int:
    return int(5 * round(mps * 3.6 / 5))


def _pick(rng: np.random.Generator, options: list[str]) -> str:
    return options[int(rng.integers(len(options)))]


def _main_text(risk: str, f: dict[str, Any], rng: np.random.Generator) -> tuple[str, str, str]:
    """(position, action, caption sentence) of the main road user."""
    kind, gap = f["kind"], max(1.0, float(f.get("gap_m", 0.0)))
    other_kmh = _kmh(float(f.get("other_speed_mps", 0.0)))
    if risk == "vehicle_ahead":
        pos = f"in the ego lane, about {gap:.0f} m ahead"
        act = {
            "stopped": "stationary in the lane",
            "slow": f"crawling at about {other_kmh} km/h",
            "braking": "braking sharply from cruising speed",
        }[f["action"]]
        sent = _pick(
            rng,
            [
                f"A {kind} about {gap:.0f} m ahead in the same lane is {act}.",
                f"{gap:.0f} m ahead in the ego's lane a {kind} is {act}.",
            ],
        )
    elif risk == "pedestrian":
        side = f["side"]
        pos = f"at the {side} edge of the ego lane, about {gap:.0f} m ahead"
        act = f"crossing from the {side} at about {f['other_speed_mps']:.1f} m/s"
        sent = _pick(
            rng,
            [
                f"A {kind} steps out from the {side} about {gap:.0f} m ahead and crosses the road.",
                f"About {gap:.0f} m ahead a {kind} starts crossing from the {side} side.",
            ],
        )
    elif risk == "adjacent_vehicle":
        side = f["side"]
        where = (
            "alongside"
            if abs(f["offset_m"]) < 2.5
            else ("slightly ahead" if f["offset_m"] > 0 else "slightly behind")
        )
        pos = (
            f"in the {side} lane, {where} the ego"
            if where == "alongside"
            else f"in the {side} lane, {where} of the ego"
        )
        act = f"drifting into the ego lane at about {f['lateral_mps']:.1f} m/s sideways"
        sent = _pick(
            rng,
            [
                f"A {kind} in the {side} lane, {where}, swerves towards the ego's lane.",
                f"The {kind} travelling {where} in the {side} lane drifts over the lane line "
                "towards the ego.",
            ],
        )
    elif risk == "merging_vehicle":
        side = f["side"]
        src = "an on-ramp" if side == "right" else "the left lane"
        pos = f"entering from {src}, about {gap:.0f} m ahead"
        act = f"merging in front of the ego at about {other_kmh} km/h"
        sent = _pick(
            rng,
            [
                f"A {kind} from {src} merges into the ego's lane about {gap:.0f} m ahead, "
                "slower than the ego.",
                f"About {gap:.0f} m ahead a slower {kind} cuts in from {src}.",
            ],
        )
    elif risk == "oncoming_vehicle":
        pos = f"in the opposite lane, about {gap:.0f} m ahead"
        back = " and then steers back" if f["returns"] else ""
        act = f"crossing the centre line by about {f['intrusion_m']:.1f} m{back}"
        sent = _pick(
            rng,
            [
                f"An oncoming {kind} at about {other_kmh} km/h cuts across the centre line "
                f"into the ego's lane{back}.",
                f"The oncoming {kind} drifts about {f['intrusion_m']:.1f} m over the centre line{back}.",
            ],
        )
    elif risk == "head_on":
        pos = f"in the ego lane, about {gap:.0f} m ahead, facing the ego"
        act = f"driving straight at the ego at about {other_kmh} km/h"
        sent = _pick(
            rng,
            [
                f"A {kind} comes towards the ego in the ego's own lane at about {other_kmh} km/h.",
                f"In the ego's lane a wrong-way {kind} approaches head-on.",
            ],
        )
    else:
        pos = f"coming from the opposite direction, turning about {gap:.0f} m ahead"
        act = f"turning left across the ego's path at about {other_kmh} km/h"
        sent = _pick(
            rng,
            [
                f"At the junction ahead an oncoming {kind} turns left across the ego's path.",
                f"An oncoming {kind} starts a left turn in front of the ego about {gap:.0f} m ahead.",
            ],
        )
    return pos, act, sent


def _surroundings(f: dict[str, Any]) -> list[str]:
    out = []
    if f.get("left_blocked"):
        out.append(
            "an oncoming car in the left lane" if f["left_lane"] == "oncoming" else "a car in the left lane"
        )
    if f.get("right_blocked"):
        out.append(f"a {f['right_blocked']} parked on the right")
    if "follower_gap_m" in f:
        out.append(f"a car following {f['follower_gap_m']:.0f} m behind")
    return out


def _role(name: str, f: dict[str, Any]) -> str:
    return _ROLE_NAMES.get(name, name).format(
        kind=f.get("kind", "vehicle"), right=f.get("right_blocked", "vehicle")
    )


def case_from_scene(
    labelled: LabelledScene, manoeuvres: ManoeuvreSet, rng: np.random.Generator, source: str = "synthetic"
) -> Case:
    """The case of a labelled scene: caption, analysis fields and justification from its data."""
    s, f = labelled.scene, labelled.scene.facts
    pos, act, sentence = _main_text(s.risk_type, f, rng)
    speed = _kmh(s.ego_speed_mps)
    around = _surroundings(f)
    lanes = (
        "an oncoming lane on the left"
        if f["left_lane"] == "oncoming"
        else "a same-direction lane on the left"
    )
    road = f"{f['road']} with {lanes}"
    opener = _pick(
        rng,
        [
            f"The ego car drives at about {speed} km/h on an {f['road']}."
            if f["road"][0] in "aeiou"
            else f"The ego car drives at about {speed} km/h on a {f['road']}.",
            f"Travelling at roughly {speed} km/h along the {f['road']}, the ego car approaches.",
            f"Ego vehicle at about {speed} km/h on the {f['road']}.",
        ],
    )
    tail = ""
    if around:
        tail = (
            " "
            + _pick(rng, ["Nearby there is ", "Around the ego: ", "Also present: "])
            + ", ".join(around)
            + "."
        )
    caption = f"{opener} {sentence}{tail}"
    rec = labelled.outcomes[RECORDED]
    event_context = _pick(
        rng,
        [
            f"Without a reaction the ego would hit {_role(rec.closest_id, f)} in about {f['tc_s']:.1f} s.",
            f"The {f['kind']} is {act}; keeping course, the ego collides after about {f['tc_s']:.1f} s.",
        ],
    )
    chosen = manoeuvres.get(labelled.manoeuvre)
    good = labelled.outcomes[chosen.name]
    clear = "" if not math.isfinite(good.min_distance_m) else f", keeping {good.min_distance_m:.1f} m clear"
    failed = []
    for m in manoeuvres.by_effort():
        if m.name == chosen.name:
            break
        o = labelled.outcomes[m.name]
        failed.append(f"{m.label.lower()} would still hit {_role(o.closest_id, f)}")
    justification = f"{chosen.label} avoids the collision{clear}."
    if failed:
        justification += (
            " "
            + _pick(rng, ["Gentler options fail: ", "Less effort is not enough: "])
            + "; ".join(failed[:2])
            + "."
        )
    road_context = road + (f"; {', '.join(around)}" if around else "")
    return Case(
        case_id=f"syn-{s.scene_id}",
        risk_type=s.risk_type,
        caption=caption,
        road_context=road_context,
        other_vehicle_position=pos,
        other_vehicle_action=act,
        event_context=event_context,
        manoeuvre=chosen.name,
        justification=justification,
        source=source,
        time_s=round(float(f["tc_s"]), 2),
    )
