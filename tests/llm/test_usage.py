"""Usage accounting and its report table."""

from __future__ import annotations

from rich.console import Console

from scenariominer.llm import CallKind, Completion, UsageCounter, print_usage


def test_counter_aggregates_per_backend_and_model_and_renders():
    usage = UsageCounter()
    usage.record_chat("llamacpp", "qwen", Completion("a", 100, 20, 2.5))
    usage.record_chat("llamacpp", "qwen", Completion("a", 100, 20, 2.5, cached=True))
    usage.record_chat("llamacpp", "qwen", Completion("b", 50, 10, 1.5))
    usage.record_failure(CallKind.CHAT, "llamacpp", "qwen")
    usage.record_embedding("hashing", "hashing-8", texts=10, cache_hits=4, calls=1, latency_s=0.5)
    report = usage.report()
    chat, emb = report.rows
    assert (chat.requests, chat.calls, chat.cache_hits, chat.failures) == (4, 2, 1, 1)
    assert (chat.prompt_tokens, chat.completion_tokens, chat.latency_s) == (150, 30, 4.0)
    assert (emb.kind, emb.requests, emb.cache_hits, emb.calls) == (CallKind.EMBEDDING, 10, 4, 1)
    assert (report.calls, report.cache_hits, report.latency_s) == (3, 5, 4.5)

    console = Console(record=True, width=160)
    print_usage(report, console)
    text = console.export_text()
    assert "Model usage" in text
    assert "qwen" in text and "hashing-8" in text
    assert "total" in text and "4.5" in text


def test_rows_stay_one_line_each_on_an_80_column_terminal():
    # a long model name in the first column folded each row into four lines
    usage = UsageCounter()
    name = "qwen2.5-coder-1.5b-instruct-q4_k_m"
    usage.record_chat("llamacpp", name, Completion("a", 219, 14, 11.8))
    usage.record_chat("openai", "other-model", Completion("a", 10, 1, 0.5))
    usage.record_embedding("sentence-transformers", "all-MiniLM-L6-v2", texts=16, cache_hits=3, calls=4,
                           latency_s=11.8)  # fmt: skip
    console = Console(record=True, width=80)
    print_usage(usage.report(), console)
    lines = console.export_text().splitlines()
    rows = [line for line in lines if line.startswith("│")]
    assert [r.split("│")[1].strip() for r in rows] == ["chat 1", "chat 2", "embedding", "total"]
    legend = " ".join(" ".join(lines).split())
    assert (
        f"chat 1: {name} (llamacpp)" in legend
        and "embedding: all-MiniLM-L6-v2 (sentence-transformers)" in legend
    )


def test_empty_report_prints_nothing():
    console = Console(record=True)
    print_usage(UsageCounter().report(), console)
    assert console.export_text() == ""
