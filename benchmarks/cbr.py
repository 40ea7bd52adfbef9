"""Rollout check speed: all manoeuvres in one vectorised call against one call per manoeuvre.

Both variants roll out the same synthetic scenes (drawn by ``scenariominer.cbr.scenes``), and the
outcomes are checked to agree; the ratio of their times is printed, plus scenes labelled per
second (what ``cbr build`` spends outside the embedder).

    .venv/bin/python benchmarks/cbr.py --scenes 300
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from scenariominer.cbr.rollout import rollout
from scenariominer.cbr.scenes import draw_scene
from scenariominer.cbr.vocab import load_manoeuvres, load_risk_types


def main() -> None:
    """Run the benchmark and print the times and their ratio."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scenes", type=int, default=300)
    args = parser.parse_args()
    manoeuvres = load_manoeuvres().manoeuvres
    rng = np.random.default_rng(0)
    names = load_risk_types().names
    scenes = [draw_scene(rng, names[i % len(names)], str(i)).rollout_scene() for i in range(args.scenes)]

    t0 = time.perf_counter()
    together = [rollout(s, manoeuvres) for s in scenes]
    t_vec = time.perf_counter() - t0

    t0 = time.perf_counter()
    apart = [{m.name: rollout(s, [m])[m.name] for m in manoeuvres} for s in scenes]
    t_loop = time.perf_counter() - t0

    agree = all(
        a[m.name].collision == b[m.name].collision
        for a, b in zip(together, apart, strict=True)
        for m in manoeuvres
    )
    print(f"scenes: {len(scenes)}, manoeuvres: {len(manoeuvres)}, time steps: {scenes[0].t_s.size}")
    print(f"all manoeuvres per call : {t_vec:.3f} s ({len(scenes) / t_vec:.0f} scenes/s)")
    print(f"one manoeuvre per call  : {t_loop:.3f} s ({len(scenes) / t_loop:.0f} scenes/s)")
    print(f"speed-up: {t_loop / t_vec:.1f}x; outcomes agree: {agree}")


if __name__ == "__main__":
    main()
