"""Accounting of model calls: calls, cache hits, tokens and latency per backend and model.

One :class:`UsageCounter` is shared by the chat client and the embedder of a command; at the end
the command prints :meth:`UsageCounter.report` with :func:`print_usage`.
"""

from __future__ import annotations

import threading
from dataclasses import dataclass
from enum import StrEnum
from typing import TYPE_CHECKING

from scenariominer.llm.base import Completion

if TYPE_CHECKING:
    from rich.console import Console
    from rich.table import Table

__all__ = ["CallKind", "UsageCounter", "UsageReport", "UsageRow", "print_usage"]


class CallKind(StrEnum):
    """What was asked of a model."""

    CHAT = "chat"
    EMBEDDING = "embedding"


@dataclass(frozen=True)
class UsageRow:
    """Totals for one (kind, backend, model).

    Attributes:
        kind: chat or embedding.
        backend: backend name.
        model: model identity.
        requests: chat requests or texts to embed, including those served from the cache.
        calls: backend calls actually made (cache misses; an embedding batch counts once).
        cache_hits: requests (chat) or texts (embedding) answered from the cache.
        failures: backend calls that raised.
        prompt_tokens: prompt tokens of the calls made (as reported by the backend).
        completion_tokens: generated tokens of the calls made.
        latency_s: summed wall-clock seconds of the calls made.
    """

    kind: CallKind
    backend: str
    model: str
    requests: int = 0
    calls: int = 0
    cache_hits: int = 0
    failures: int = 0
    prompt_tokens: int = 0
    completion_tokens: int = 0
    latency_s: float = 0.0


@dataclass(frozen=True)
class UsageReport:
    """A snapshot of a :class:`UsageCounter`.

    Attributes:
        rows: one row per (kind, backend, model), in first-use order.
    """

    rows: tuple[UsageRow, ...] = ()

    @property
    def calls(self) -> int:
        """Backend calls made, all rows."""
        return sum(r.calls for r in self.rows)

    @property
    def cache_hits(self) -> int:
        """Cache hits, all rows."""
        return sum(r.cache_hits for r in self.rows)

    @property
    def prompt_tokens(self) -> int:
        """Prompt tokens, all rows."""
        return sum(r.prompt_tokens for r in self.rows)

    @property
    def completion_tokens(self) -> int:
        """Generated tokens, all rows."""
        return sum(r.completion_tokens for r in self.rows)

    @property
    def latency_s(self) -> float:
        """Seconds spent in backend calls, all rows."""
        return sum(r.latency_s for r in self.rows)

    def to_table(self) -> Table:
        """Render as a Rich table with one line per row and a total line."""
        from rich.table import Table

        table = Table(title="Model usage", title_justify="left", caption_justify="left")
        table.add_column("model", no_wrap=True)
        for name in ("req", "calls", "hits", "fails", "prompt tok", "gen tok", "s"):
            table.add_column(name, justify="right", no_wrap=True)
        # short row labels, the models named below the table: a long model name folded into a
        # narrow first column made each row four lines tall on an 80-column terminal
        labels = _row_labels([r.kind.value for r in self.rows])
        legend = [
            f"{label}: {r.model.split('@')[0]} ({r.backend})"  # the file hash is in the cache key
            for label, r in zip(labels, self.rows, strict=True)
        ]
        for label, r in zip(labels, self.rows, strict=True):
            table.add_row(
                label,
                str(r.requests),
                str(r.calls),
                str(r.cache_hits),
                str(r.failures),
                str(r.prompt_tokens),
                str(r.completion_tokens),
                f"{r.latency_s:.1f}",
            )
        if len(self.rows) > 1:
            table.add_row(
                "total",
                str(sum(r.requests for r in self.rows)),
                str(self.calls),
                str(self.cache_hits),
                str(sum(r.failures for r in self.rows)),
                str(self.prompt_tokens),
                str(self.completion_tokens),
                f"{self.latency_s:.1f}",
                style="bold",
            )
        table.caption = "; ".join(
            [*legend, "req: requests; calls: backend calls made; hits: answered from the cache"]
        )
        return table


def _row_labels(kinds: list[str]) -> list[str]:
    """``chat``, ``embedding``; ``chat 1``, ``chat 2`` where one kind has several rows."""
    return [k if kinds.count(k) == 1 else f"{k} {kinds[: i + 1].count(k)}" for i, k in enumerate(kinds)]


class UsageCounter:
    """Thread-safe accumulator of :class:`UsageRow` totals."""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._rows: dict[tuple[CallKind, str, str], dict[str, float]] = {}

    def _add(self, kind: CallKind, backend: str, model: str, **amounts: float) -> None:
        with self._lock:
            row = self._rows.setdefault((kind, backend, model), {})
            for name, value in amounts.items():
                row[name] = row.get(name, 0) + value

    def record_chat(self, backend: str, model: str, completion: Completion) -> None:
        """Count one chat request answered by ``completion`` (a cache hit when ``completion.cached``)."""
        if completion.cached:
            self._add(CallKind.CHAT, backend, model, requests=1, cache_hits=1)
        else:
            self._add(
                CallKind.CHAT,
                backend,
                model,
                requests=1,
                calls=1,
                prompt_tokens=completion.prompt_tokens,
                completion_tokens=completion.completion_tokens,
                latency_s=completion.latency_s,
            )

    def record_failure(self, kind: CallKind, backend: str, model: str) -> None:
        """Count one backend call that raised."""
        self._add(kind, backend, model, requests=1 if kind is CallKind.CHAT else 0, failures=1)

    def record_embedding(
        self,
        backend: str,
        model: str,
        *,
        texts: int,
        cache_hits: int,
        calls: int,
        prompt_tokens: int = 0,
        latency_s: float = 0.0,
    ) -> None:
        """Count one embedding request of ``texts`` texts of which ``cache_hits`` came from the cache."""
        self._add(
            CallKind.EMBEDDING,
            backend,
            model,
            requests=texts,
            cache_hits=cache_hits,
            calls=calls,
            prompt_tokens=prompt_tokens,
            latency_s=latency_s,
        )

    def report(self) -> UsageReport:
        """Return a snapshot of the totals so far."""
        with self._lock:
            items = [(k, dict(v)) for k, v in self._rows.items()]
        rows = [
            UsageRow(
                kind=kind,
                backend=backend,
                model=model,
                requests=int(v.get("requests", 0)),
                calls=int(v.get("calls", 0)),
                cache_hits=int(v.get("cache_hits", 0)),
                failures=int(v.get("failures", 0)),
                prompt_tokens=int(v.get("prompt_tokens", 0)),
                completion_tokens=int(v.get("completion_tokens", 0)),
                latency_s=float(v.get("latency_s", 0.0)),
            )
            for (kind, backend, model), v in items
        ]
        return UsageReport(tuple(rows))

    def reset(self) -> None:
        """Forget all totals."""
        with self._lock:
            self._rows.clear()


def print_usage(report: UsageReport, console: Console | None = None) -> None:
    """Print ``report`` as a table (nothing when no model was used)."""
    if not report.rows:
        return
    from rich.console import Console

    (console or Console(stderr=True, emoji=False)).print(report.to_table())
