"""Throughput of the served embedded model at 1, 2 and 4 concurrent requests.

Starts ``scenariominer llm serve``'s server (llama-cpp-python's OpenAI-compatible server over the
bundled GGUF) on a free loopback port, warms it with one request, then sends the same batch of
braking-judgement requests (the hybrid prompt over the facts of synthetic events; answer cache
off) through the ``openai`` chat backend with 1, 2 and 4 requests in flight. Prints requests/s,
generated tokens/s and the ratio to one request at a time, measured in the same run.

    .venv/bin/python benchmarks/llm_served.py [--requests 8]
"""

from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--requests", type=int, default=8, help="requests per concurrency level")
    args = parser.parse_args()

    from scenariominer import api
    from scenariominer.config import Config
    from scenariominer.config.llm import EmbeddingConfig, LLMConfig
    from scenariominer.explain.categories import CategorySet
    from scenariominer.explain.judge import Judge, allowed_categories
    from scenariominer.explain.prompts import judge_messages
    from scenariominer.llm.cache import resolve_cache_dir
    from scenariominer.llm.factory import make_chat_client
    from scenariominer.llm.model_files import ensure_model_file
    from scenariominer.llm.server import ServedModel, ServeSettings, free_port
    from scenariominer.llm.usage import UsageCounter
    from scenariominer.store import ScenarioStore

    cats = CategorySet.default()
    with tempfile.TemporaryDirectory() as tmp_name:
        tmp = Path(tmp_name)
        cfg = Config(embedding=EmbeddingConfig(backend="hashing"))  # type: ignore[arg-type]
        api.synth(tmp / "synth", 8, seed=4)
        store = ScenarioStore.open(tmp / "store")
        api.ingest([tmp / "synth"], store, cfg)
        api.analyze(store, api.AnalyzeRequest(judge="rules"), cfg)
        rows = store.read_table("events").select(["facts", "rule_candidates"]).to_pylist()
        conversations = []
        for i in range(args.requests):
            row = rows[i % len(rows)]
            cands = [c for c in str(row["rule_candidates"]).split(",") if c]
            allowed = allowed_categories(Judge.LLM, cands, cats)
            # a distinct suffix per request: nothing is answered from a cache
            conversations.append(judge_messages(f"{row['facts']}\nrequest: {i}", allowed, cats))
        model = ensure_model_file(resolve_cache_dir())
        settings = ServeSettings(model.path, port=free_port())
        with ServedModel(settings, log_path=tmp / "server.log") as server:
            print(f"server {server.base_url} ({model.path.name}); {args.requests} requests per level")
            base = 0.0
            for level in (1, 2, 4):
                llm = LLMConfig(
                    backend="openai",  # type: ignore[arg-type]
                    base_url=server.base_url,
                    model=settings.alias,
                    structured_mode="json_object_schema",  # type: ignore[arg-type]
                    cache=False,
                    max_concurrency=level,
                    timeout_s=900.0,
                    max_tokens=120,
                )
                warm = make_chat_client(llm)
                warm.complete_many(conversations[:1])  # the system prompt is evaluated once
                warm.close()
                usage = UsageCounter()
                client = make_chat_client(llm, usage=usage)
                t0 = time.perf_counter()
                done = client.complete_many(conversations, return_exceptions=True)
                seconds = time.perf_counter() - t0
                tokens = usage.report().completion_tokens
                failed = sum(isinstance(c, BaseException) for c in done)
                rps = args.requests / seconds
                base = base or rps
                print(
                    f"  concurrency {level}: {seconds:6.1f} s, {rps:5.3f} requests/s, "
                    f"{tokens / seconds:5.1f} generated tokens/s, {rps / base:4.2f}x of 1 in flight"
                    + (f", {failed} failed" if failed else "")
                )
                client.close()


if __name__ == "__main__":
    main()
