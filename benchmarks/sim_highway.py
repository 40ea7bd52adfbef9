"""Simulated highway sets: SUMO time against simulated time, and what the 15 s windows contain.

``--simulate``: runs ``simulate_highway_set`` into a temporary folder and prints, per recording,
the wall time of SUMO and of the conversion against the simulated seconds (the ratio is how much
faster than real time the set is made). ``--set DIR``: for an existing set, counts the behaviours
of every 15 s ego window (the windows ``scenariominer ingest`` makes with no ego cap), judged by
``scenariominer.eval.highway_truth.window_truth`` from the recordings.

    .venv/bin/python benchmarks/sim_highway.py --simulate --recordings 2 --minutes 5
    .venv/bin/python benchmarks/sim_highway.py --set /work/data/highway_sim
"""

from __future__ import annotations

import argparse
import tempfile
import time
from collections import Counter
from pathlib import Path

from scenariominer.data.adapters.highd import HighDFiles, plan_windows, read_highd_recording
from scenariominer.eval.highway_truth import load_recording_truth, window_truth
from scenariominer.sim.highway import simulate_highway_set
from scenariominer.sim.highway_scenario import HighwaySettings

#: Behaviour name -> test on a window's truth (``eval.highway_truth.TRUTH_FIELDS``).
BEHAVIOURS = {
    "lane change": lambda t: t["lane_changes"] > 0,
    "lane change left": lambda t: t["lane_changes_left"] > 0,
    "lane change right": lambda t: t["lane_changes_right"] > 0,
    "2+ lanes to the left": lambda t: t["max_shift_left"] >= 2,
    "2+ lanes to the right": lambda t: t["max_shift_right"] >= 2,
    "overtaken or overtaking": lambda t: t["overtakes"] > 0,
    "cut-in in front": lambda t: t["cut_ins"] > 0,
    "merge out of the rightmost lane": lambda t: t["merge"] > 0,
    "evasive lane change": lambda t: t["evasive"] > 0,
    "stop-and-go": lambda t: t["stop_and_go"] > 0,
    "mean speed < 10 m/s": lambda t: t["mean_speed_mps"] < 10,
    "follows a leader": lambda t: t["follows"] > 0,
}


def simulate(recordings: int, minutes: float, seed: int) -> None:
    """Simulate a set and print the time ratios."""
    with tempfile.TemporaryDirectory() as tmp:
        t0 = time.perf_counter()
        result = simulate_highway_set(
            Path(tmp), HighwaySettings(recordings=recordings, minutes=minutes, seed=seed)
        )
        wall = time.perf_counter() - t0
    for r in result.recordings:
        simulated = r.scenario.end_s
        print(
            f"recording {r.recording_id:02d}: {r.n_vehicles} vehicles, {simulated:.0f} s simulated "
            f"(incl. {r.scenario.warmup_s:.0f} s warm-up) in SUMO {r.sim_s:.1f} s "
            f"+ convert {r.convert_s:.1f} s = {simulated / max(r.sim_s + r.convert_s, 1e-9):.0f}x real time"
        )
    print(
        f"set: {result.simulated_s:.0f} recorded s in {wall:.1f} s wall "
        f"= {result.simulated_s / wall:.0f}x real time"
    )


def window_behaviours(folder: Path, window_s: float = 15.0) -> None:
    """Count behaviours over every ego window of every recording in ``folder``."""
    counts: Counter[str] = Counter()
    n = 0
    for tracks in sorted(folder.glob("[0-9][0-9]_tracks.csv")):
        files = HighDFiles.from_path(tracks)
        assert files is not None
        rec = read_highd_recording(files)
        truth = load_recording_truth(str(tracks))
        for w in plan_windows(rec, window_s):
            t = window_truth(truth, w.ego_id, w.first_frame, w.stop_frame - 1)
            if t is None:
                continue
            n += 1
            counts.update(name for name, test in BEHAVIOURS.items() if test(t))
    print(f"{n} windows of {window_s:.0f} s in {folder}")
    for name in BEHAVIOURS:
        print(f"  {name}: {counts[name]} ({100 * counts[name] / max(n, 1):.1f} %)")


def main() -> None:
    """Parse the arguments and run the chosen part."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--simulate", action="store_true")
    parser.add_argument("--recordings", type=int, default=2)
    parser.add_argument("--minutes", type=float, default=5.0)
    parser.add_argument("--seed", type=int, default=31)
    parser.add_argument("--set", type=Path, default=None)
    args = parser.parse_args()
    if args.simulate:
        simulate(args.recordings, args.minutes, args.seed)
    if args.set is not None:
        window_behaviours(args.set)


if __name__ == "__main__":
    main()
