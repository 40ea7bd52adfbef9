"""Success rate, attempts and timing of LLM program generation over the example bank.

For every description of the shipped bank, asks the configured chat model (the embedded one by
default) for a program with the fault-tolerant loop (``mine.loop.generate_program``, K tries),
leave-one-out: the description's own bank entry is never one of its few-shot examples, so this
measures generation, not recall. Each program is validated on the shared Argoverse 2 log (when it
is beside the checkout) and on a synthetic log with a vector map. One JSON line per description
goes to ``OUT/results.jsonl`` (the run resumes where it stopped), then a summary is printed:

    .venv/bin/python benchmarks/mining_generation.py OUT [--limit N]

On 2 CPU cores the embedded model needs about 4 minutes for its first call and 25 s per call
after it, so all 31 descriptions take about half an hour.
"""

from __future__ import annotations

import argparse
import json
import statistics
import time
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np

from scenariominer.config import load_config
from scenariominer.data.adapters.av2 import read_av2_log
from scenariominer.data.preprocess import preprocess
from scenariominer.mine.context import LogContext
from scenariominer.mine.loop import ProgramCache, generate_program
from scenariominer.mine.programs import load_examples
from scenariominer.mine.query import make_synthesizer
from scenariominer.synth import generate_log

SHARED_LOG = Path(__file__).resolve().parents[2] / "shared/data/av2/3b3570b4-7b0b-3268-a571-b0889dbf40b6"
KEY = "vehicle with a bicycle to its right"


def _contexts(cfg: Any) -> list[LogContext]:
    contexts = []
    if SHARED_LOG.is_dir():
        contexts.append(LogContext(preprocess(read_av2_log(SHARED_LOG)), cfg.mining))
    syn = generate_log("right_ped", np.random.default_rng(7))
    contexts.append(LogContext(syn.log, cfg.mining, syn.av2_map))
    return contexts


def _summary(rows: list[dict[str, Any]]) -> None:
    ok = [r for r in rows if r["status"] == "ok"]
    print(f"descriptions {len(rows)}, running program within K: {len(ok)} ({len(ok) / len(rows):.0%})")
    print(
        f"first try {sum(r['attempts'] == 1 and r['status'] == 'ok' for r in rows)}; mean attempts "
        f"{statistics.mean(r['attempts'] for r in rows):.2f} (successes "
        f"{statistics.mean(r['attempts'] for r in ok) if ok else float('nan'):.2f})"
    )
    calls = [g for r in rows for g in r["per_attempt_generation_s"]]
    checks = [v for r in rows for v in r["per_attempt_validation_s"]]
    print(
        f"model calls {len(calls)}: median {statistics.median(calls):.1f} s, mean "
        f"{statistics.mean(calls):.1f} s, max {max(calls):.1f} s (a process's first call "
        "evaluates the whole system message)"
    )
    print(f"check + sandboxed validation per attempt: mean {statistics.mean(checks):.2f} s")
    for r in rows:
        if r["status"] != "ok":
            print(f"manual review: {r['description']!r}: {(r['errors'][-1] or '')[:120]}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out", type=Path, help="folder for results.jsonl and the caches")
    parser.add_argument("--limit", type=int, default=1000, help="at most this many descriptions")
    args = parser.parse_args()
    out: Path = args.out
    out.mkdir(parents=True, exist_ok=True)
    cfg = load_config()
    # a fresh answer cache per run, so every call is a real model call
    cfg = replace(cfg, llm=replace(cfg.llm, cache_dir=str(out / "llmcache")))
    contexts = _contexts(cfg)
    synth = make_synthesizer(cfg, leave_one_out=True)
    cache = ProgramCache(out / "programs.sqlite3")
    bank = load_examples()
    order = [e for e in bank if e.description == KEY] + [e for e in bank if e.description != KEY]
    results = out / "results.jsonl"
    rows: list[dict[str, Any]] = []
    if results.exists():
        rows = [json.loads(line) for line in results.read_text().splitlines() if line.strip()]
    done = {r["description"] for r in rows}
    for ex in order[: args.limit]:
        if ex.description in done:
            continue
        t0 = time.perf_counter()
        rep = generate_program(ex.description, synth, contexts, config=cfg.mining, cache=cache)
        row = {
            "description": ex.description,
            "status": rep.status.value,
            "attempts": rep.attempts_used,
            "generation_s": rep.generation_s,
            "wall_s": time.perf_counter() - t0,
            "errors": [None if a.error is None else a.error.feedback() for a in rep.attempts],
            "per_attempt_generation_s": [a.generation_s for a in rep.attempts],
            "per_attempt_validation_s": [a.execution_s for a in rep.attempts],
            "programs": [a.program for a in rep.attempts],
            "program": rep.program,
            "examples": [e.description for e in synth.examples_for(ex.description)],
        }
        rows.append(row)
        with results.open("a", encoding="utf-8") as fh:
            fh.write(json.dumps(row) + "\n")
        line = f"{row['status']:>13}  {row['attempts']} attempt(s)  {row['wall_s']:6.1f} s"
        print(f"{line}  {ex.description}", flush=True)
    if rows:
        _summary(rows)


if __name__ == "__main__":
    main()
