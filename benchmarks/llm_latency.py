"""Prompt-evaluation time of the embedded model in fresh processes, with and without prefix states.

Every measurement runs in a new Python process (as a user's command would), with greedy decoding
and the answer cache off, so each call really runs the model:

1. **Prefix cache.** For the mining system prompt (~4,500 tokens) and the braking judgement prompt,
   a process makes two calls with different user messages. Three cases: persisted prefix states
   off; on with an empty state directory (the first process ever); on with the states the previous
   process wrote (every later process). Printed: prompt-evaluation seconds of the first and second
   call, and where the prefix came from.
2. **Seconds per braking event**, before (prompt v2: the tag-by-tag description, every category,
   the whole answer from the LLM) and after (the hybrid judgement from the event's facts), on the
   same events of a synthetic set, each in a fresh process with warm prefix states.
3. **Seconds per mining description** (one program-writing call) in a fresh process, without and
   with the persisted prefix.

    .venv/bin/python benchmarks/llm_latency.py [--events 6]

Timings depend on the CPU and on whatever else runs; compare rows of one run only.
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

BENCH = Path(__file__).resolve()


def _child(args: argparse.Namespace) -> None:
    """One fresh process: the calls of one case, one JSON line per call on stdout."""
    from scenariominer.config.llm import LLMConfig
    from scenariominer.explain.categories import CategorySet
    from scenariominer.explain.classify import classify_description
    from scenariominer.explain.judge import Judge, judge_event
    from scenariominer.llm.base import ChatRequest, GenerationParams, system, user
    from scenariominer.llm.factory import make_chat_client
    from scenariominer.mine.prompts import system_prompt as mining_prompt

    llm = LLMConfig(
        model_path=args.model, cache=False, cache_dir=args.cache_dir, prefix_cache=args.prefix == "on"
    )
    client = make_chat_client(llm)
    backend: Any = client.backend
    if args.child in ("mining", "judge-prompt"):
        from scenariominer.explain.prompts import judge_system_prompt

        sys_text = mining_prompt() if args.child == "mining" else judge_system_prompt(CategorySet.default())
        for q in ("vehicle turning left at an intersection", "pedestrian crossing in front of a bus"):
            t0 = time.perf_counter()
            c = backend.complete(
                ChatRequest(
                    (system(sys_text), user(f"Write the program for: {q}")), GenerationParams(max_tokens=8)
                )
            )
            row = {"wall_s": time.perf_counter() - t0, "prompt_eval_s": c.prompt_eval_s}
            row.update(prompt_tokens=c.prompt_tokens, reused=c.reused_prompt_tokens)
            row.update(prefix=backend.last_prefix.source.value)
            print(json.dumps(row), flush=True)
        return
    events = json.loads(Path(args.events_file).read_text())
    cats = CategorySet.default()
    for e in events:
        t0 = time.perf_counter()
        if args.child == "braking-v2":
            out = classify_description(client, e["tag_description"], cats, max_tokens=200)
        else:
            cands = [c for c in e["rule_candidates"].split(",") if c]
            out = judge_event(client, e["facts"], cands, cats, Judge.HYBRID, max_tokens=200)
        row = {"wall_s": time.perf_counter() - t0, "status": out.status.value, "category": out.category}
        print(json.dumps(row), flush=True)


def _run(case: str, prefix: str, cache_dir: Path, model: str, events_file: str = "") -> list[dict[str, Any]]:
    cmd = [sys.executable, str(BENCH), "--child", case, "--prefix", prefix, "--cache-dir", str(cache_dir)]
    cmd += ["--model", model, "--events-file", events_file]
    t0 = time.perf_counter()
    out = subprocess.run(cmd, capture_output=True, text=True, check=True).stdout
    rows = [json.loads(line) for line in out.splitlines() if line.startswith("{")]
    for r in rows:
        r["process_s"] = time.perf_counter() - t0
    return rows


def _events(n: int, tmp: Path) -> str:
    """Facts and tag descriptions of ``n`` braking events of a synthetic set (rules only, no model)."""
    from scenariominer import api
    from scenariominer.config import Config
    from scenariominer.config.llm import EmbeddingConfig
    from scenariominer.store import ScenarioStore

    cfg = Config(embedding=EmbeddingConfig(backend="hashing"))  # type: ignore[arg-type]
    api.synth(tmp / "synth", max(4, n), seed=21)
    store = ScenarioStore.open(tmp / "store")
    api.ingest([tmp / "synth"], store, cfg)
    api.analyze(store, api.AnalyzeRequest(judge="rules"), cfg)
    rows = store.read_table("events").select(["tag_description", "facts", "rule_candidates"]).to_pylist()
    path = tmp / "events.json"
    path.write_text(json.dumps(rows[:n]))
    return str(path)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--events", type=int, default=6, help="braking events to time per prompt")
    parser.add_argument("--child", default="", help=argparse.SUPPRESS)
    parser.add_argument("--prefix", default="on", help=argparse.SUPPRESS)
    parser.add_argument("--cache-dir", default="", help=argparse.SUPPRESS)
    parser.add_argument("--model", default="", help=argparse.SUPPRESS)
    parser.add_argument("--events-file", default="", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.child:
        _child(args)
        return
    from scenariominer.llm.cache import resolve_cache_dir
    from scenariominer.llm.model_files import ensure_model_file

    model = str(ensure_model_file(resolve_cache_dir()).path)
    with tempfile.TemporaryDirectory() as tmp_name:
        tmp = Path(tmp_name)
        print("1. prefix cache, two calls per fresh process (prompt-evaluation seconds)")
        print(f"{'prompt':14s} {'case':28s} {'1st call':>9s} {'2nd call':>9s}  prefix of 1st call")
        for case in ("mining", "judge-prompt"):
            states = tmp / f"states-{case}"
            for label, prefix in (("off", "off"), ("on, first process", "on"), ("on, later process", "on")):
                a, b = _run(case, prefix, states, model)
                line = f"{case:14s} {label:28s} {a['prompt_eval_s']:9.2f} {b['prompt_eval_s']:9.2f}"
                print(f"{line}  {a['prefix']} ({a['reused']}/{a['prompt_tokens']} tokens reused)")
        events_file = _events(args.events, tmp)
        warm = tmp / "states-braking"
        _run("judge-prompt", "on", warm, model)  # persist the judgement prefix
        print(
            f"\n2. seconds per braking event ({args.events} synthetic events, fresh process, warm prefixes)"
        )
        for case, label in (
            ("braking-v2", "before: prompt v2, tag description"),
            ("braking-hybrid", "after: hybrid"),
        ):
            rows = _run(case, "on", warm, model, events_file)
            walls = [r["wall_s"] for r in rows]
            mean, median = statistics.mean(walls), statistics.median(walls)
            print(f"  {label:38s} mean {mean:6.2f} s  median {median:6.2f} s")
        print("\n3. seconds per mining description (first call of a fresh process, 8 generated tokens)")
        mining_states = tmp / "states-mining-2"
        for label, prefix in (("before: no persisted prefix", "off"), ("after: persisted prefix", "on")):
            if prefix == "on":
                _run("mining", "on", mining_states, model)  # an earlier process wrote the state
            first = _run("mining", prefix, mining_states, model)[0]
            print(
                f"  {label:38s} {first['wall_s']:6.2f} s (prompt evaluation {first['prompt_eval_s']:.2f} s)"
            )


if __name__ == "__main__":
    main()
