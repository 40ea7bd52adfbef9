"""Execution speed of hand-written mining programs over many logs, with two baselines.

Runs every program of the shipped example bank (31 descriptions) over N logs: synthetic logs
from ``scenariominer.synth.generate_log`` (each with its vector map, generated in memory)
plus the shared Argoverse 2 log when it is beside the checkout. Prints

* the columnar path: programs × logs per second and the mean milliseconds of each program,
  running all programs of a log on one ``LogContext`` (the shared per-log arrays are computed
  once, as in a real mining run); the first program on a log pays for those arrays;
* baseline 1, the sandbox: the same programs through ``run_program`` (a resource-limited child
  process per run) for a subset of logs, to show what isolation costs per run;
* baseline 2, a naive per-timestamp Python loop (shapely distances, one vehicle-bicycle pair
  at a time) for "vehicle with a bicycle to its right", against the vectorised predicate on the
  same logs, with the number of matching cells of both (they must agree).

    .venv/bin/python benchmarks/mining.py --logs 20 --sandbox-logs 3 --repeats 3
"""

from __future__ import annotations

import os

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import argparse  # noqa: E402
import math  # noqa: E402
import statistics  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402
import shapely  # noqa: E402

from scenariominer.data.adapters.av2 import read_av2_log  # noqa: E402
from scenariominer.data.preprocess import preprocess  # noqa: E402
from scenariominer.mine.context import LogContext  # noqa: E402
from scenariominer.mine.dsl import get_objects_of_category, has_objects_in_relative_direction  # noqa: E402
from scenariominer.mine.programs import ExampleProgram, load_examples  # noqa: E402
from scenariominer.mine.sandbox import run_program, run_trusted_program  # noqa: E402
from scenariominer.synth import ScenarioCategory, generate_log  # noqa: E402

SHARED_AV2 = (
    Path(__file__).resolve().parents[2] / "shared" / "data" / "av2" / "3b3570b4-7b0b-3268-a571-b0889dbf40b6"
)


def make_contexts(n_synthetic: int, seed: int) -> list[LogContext]:
    """``n_synthetic`` synthetic logs (categories cycled) plus the shared AV2 log if present."""
    rng = np.random.default_rng(seed)
    cats = list(ScenarioCategory)
    out = []
    for i in range(n_synthetic):
        s = generate_log(cats[i % len(cats)], rng)
        out.append(LogContext(s.log, hd_map=s.av2_map))
    if SHARED_AV2.is_dir():
        out.append(LogContext(preprocess(read_av2_log(SHARED_AV2))))
    return out


def fresh(ctx: LogContext) -> LogContext:
    """A context over the same log without any cached arrays (the map object is shared)."""
    return LogContext(ctx.log, ctx.config, ctx.require_map("benchmark") if ctx.has_map else None)


def columnar(
    programs: list[ExampleProgram], contexts: list[LogContext]
) -> tuple[float, dict[str, list[float]]]:
    """Seconds for all programs on all logs (one fresh context per log) and per-program times."""
    per_program: dict[str, list[float]] = {p.description: [] for p in programs}
    t_all = time.perf_counter()
    for base in contexts:
        ctx = fresh(base)
        for p in programs:
            t0 = time.perf_counter()
            res = run_trusted_program(p.program, ctx, description=p.description)
            per_program[p.description].append(time.perf_counter() - t0)
            if not res.ok:
                raise RuntimeError(f"{p.description} failed on {ctx.log_id}: {res.error}")
    return time.perf_counter() - t_all, per_program


def sandboxed(programs: list[ExampleProgram], contexts: list[LogContext]) -> tuple[float, int]:
    """Seconds for all programs on the logs through the sandbox child process, and the run count."""
    runs = 0
    t0 = time.perf_counter()
    for ctx in contexts:
        for p in programs:
            res = run_program(p.program, ctx, description=p.description)
            if not res.ok:
                raise RuntimeError(f"{p.description} failed in the sandbox on {ctx.log_id}: {res.error}")
            runs += 1
    return time.perf_counter() - t0, runs


def naive_bicycle_right(ctx: LogContext, within_m: float = 4.0, lateral_m: float = 1.0) -> int:
    """Cells (vehicle, timestamp) with a bicycle to the vehicle's right, one pair and frame at a time."""
    vehicles = np.flatnonzero(ctx.category_mask("VEHICLE"))
    bikes = np.flatnonzero(ctx.category_mask("BICYCLE"))
    x, y = ctx.center_xy_m
    yaw, length, width = ctx.yaw_rad, ctx.length_m, ctx.width_m
    hits = 0
    for t in range(ctx.n_timestamps):
        for v in vehicles:
            if not ctx.valid[v, t]:
                continue
            c, s = math.cos(yaw[v, t]), math.sin(yaw[v, t])
            box_v = None
            found = False
            for b in bikes:
                if b == v or not ctx.valid[b, t]:
                    continue
                dx, dy = x[b, t] - x[v, t], y[b, t] - y[v, t]
                fwd, left = c * dx + s * dy, -s * dx + c * dy
                if not (-left > width[v, t] / 2 and abs(fwd) < length[v, t] / 2 + lateral_m):
                    continue
                if box_v is None:
                    box_v = _box(x[v, t], y[v, t], yaw[v, t], length[v, t], width[v, t])
                box_b = _box(x[b, t], y[b, t], yaw[b, t], length[b, t], width[b, t])
                if shapely.distance(box_v, box_b) <= within_m:
                    found = True
                    break
            hits += found
    return hits


def _box(cx: float, cy: float, yaw: float, length: float, width: float) -> shapely.Polygon:
    c, s = math.cos(yaw), math.sin(yaw)
    pts = [(sl * length / 2, sw * width / 2) for sl, sw in ((1, 1), (1, -1), (-1, -1), (-1, 1))]
    return shapely.Polygon([(cx + c * a - s * b, cy + s * a + c * b) for a, b in pts])


def vectorised_bicycle_right(ctx: LogContext) -> int:
    """The same cells with the vectorised predicate (no post-processing)."""
    vehicles = get_objects_of_category(ctx, "VEHICLE")
    bikes = get_objects_of_category(ctx, "BICYCLE")
    return has_objects_in_relative_direction(
        vehicles, bikes, ctx, direction="right", within_distance=4, lateral_thresh=1
    ).n_referred_cells


def main() -> None:
    parser = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument("--logs", type=int, default=20, help="synthetic logs (the shared AV2 log is added)")
    parser.add_argument("--sandbox-logs", type=int, default=3, help="logs for the sandbox baseline")
    parser.add_argument(
        "--repeats", type=int, default=3, help="repeats of the columnar run (median reported)"
    )
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()

    programs = list(load_examples())
    t0 = time.perf_counter()
    contexts = make_contexts(args.logs, args.seed)
    cells = sum(c.n_tracks * c.n_timestamps for c in contexts)
    print(
        f"{len(contexts)} logs ({args.logs} synthetic{' + shared AV2' if SHARED_AV2.is_dir() else ''}), "
        f"{sum(c.n_tracks for c in contexts)} tracks, {cells:,} track-timestamp cells; "
        f"built in {time.perf_counter() - t0:.1f} s"
    )
    for ctx in contexts:  # read the maps once so that no run below pays for parsing them
        _ = ctx.has_map

    totals = []
    per_program: dict[str, list[float]] = {}
    for _ in range(args.repeats):
        total, per = columnar(programs, contexts)
        totals.append(total)
        for k, v in per.items():
            per_program.setdefault(k, []).extend(v)
    total = statistics.median(totals)
    n_runs = len(programs) * len(contexts)
    print(
        f"\ncolumnar (in-process, one context per log): {n_runs} program runs in {total:.2f} s "
        f"= {n_runs / total:.1f} programs x logs / s, {1000 * total / n_runs:.1f} ms per run "
        f"(median of {args.repeats})"
    )
    print(f"{'program':<70} {'mean ms':>8} {'max ms':>8}")
    for desc, times in sorted(per_program.items(), key=lambda kv: -statistics.mean(kv[1])):
        print(f"{desc[:70]:<70} {1000 * statistics.mean(times):8.1f} {1000 * max(times):8.1f}")

    sub = contexts[: args.sandbox_logs]
    if sub:
        run_program(programs[0].program, sub[0], description="warm-up")  # start the process server
        sb_total, sb_runs = sandboxed(programs, sub)
        col_sub, _ = columnar(programs, sub)
        print(
            f"\nbaseline 1, sandbox child per run: {sb_runs} runs on {len(sub)} logs in {sb_total:.2f} s = "
            f"{1000 * sb_total / sb_runs:.0f} ms per run ({sb_runs / sb_total:.1f} runs/s) vs "
            f"{1000 * col_sub / sb_runs:.1f} ms in-process on the same logs ({sb_total / col_sub:.0f}x)"
        )

    t_naive = t_vec = 0.0
    n_naive = n_vec = 0
    for ctx in contexts:
        t1 = time.perf_counter()
        n_naive += naive_bicycle_right(fresh(ctx))
        t2 = time.perf_counter()
        n_vec += vectorised_bicycle_right(fresh(ctx))
        t3 = time.perf_counter()
        t_naive += t2 - t1
        t_vec += t3 - t2
    print(
        f"\nbaseline 2, 'vehicle with a bicycle to its right' per timestamp and pair in Python: "
        f"{t_naive:.2f} s vs {t_vec:.3f} s vectorised ({t_naive / t_vec:.0f}x) over {len(contexts)} logs; "
        f"matching cells naive {n_naive}, vectorised {n_vec}"
    )


if __name__ == "__main__":
    main()
