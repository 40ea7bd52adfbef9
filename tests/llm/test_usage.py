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


def test_empty_report_prints_nothing():
    console = Console(record=True)
    print_usage(UsageCounter().report(), console)
    assert console.export_text() == ""
