"""``scenariominer llm``: inspect and exercise the configured model backends (thin Typer layer)."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer
from rich.console import Console
from rich.table import Table

from scenariominer.config import ConfigError, load_config
from scenariominer.llm.check import ChatCheck, EmbeddingCheck, check_chat, check_embeddings
from scenariominer.llm.errors import LLMError
from scenariominer.llm.usage import UsageCounter, print_usage

__all__ = ["app"]

app = typer.Typer(name="llm", help="Language-model and text-embedding backends.", no_args_is_help=True)
console = Console()
err_console = Console(stderr=True)


@app.callback()
def _group() -> None:
    """Language-model and text-embedding backends."""


def _key_value_table(title: str) -> Table:
    table = Table(title=title, show_header=False, title_justify="left")
    table.add_column("key", no_wrap=True)
    table.add_column("value", overflow="fold")
    return table


def render_chat_check(check: ChatCheck) -> None:
    """Print the active chat backend and the outcome of its test call."""
    table = _key_value_table("LLM backend")
    table.add_row("backend", check.backend)
    table.add_row("model", check.model)
    if check.base_url:
        table.add_row("server", check.base_url)
    if check.model_file is not None:
        f = check.model_file
        table.add_row("model file", str(f.path))
        table.add_row("size", f"{f.size_bytes:,} bytes ({f.size_bytes / 2**20:,.1f} MiB)")
        table.add_row("sha256", f"{f.sha256} ({'verified against pin' if f.bundled else 'computed'})")
    if check.load_time_s is not None:
        table.add_row("load time", f"{check.load_time_s:.2f} s")
    table.add_row("answer", str(check.value))
    table.add_row("attempts", str(check.attempts))
    table.add_row("latency", f"{check.latency_s:.2f} s")
    table.add_row("tokens", f"{check.prompt_tokens} prompt + {check.completion_tokens} generated")
    console.print(table)


def render_embedding_check(check: EmbeddingCheck) -> None:
    """Print the active embedder and the outcome of its test batch."""
    table = _key_value_table("Embedding backend")
    table.add_row("backend", check.backend)
    table.add_row("model", check.model)
    table.add_row("dimension", str(check.dim))
    if check.load_time_s is not None:
        table.add_row("load time", f"{check.load_time_s:.2f} s")
    table.add_row(
        "throughput", f"{check.n_texts} texts in {check.seconds:.3f} s ({check.texts_per_s:,.1f}/s)"
    )
    table.add_row("cosine", f"related {check.related_cosine:.3f}, unrelated {check.unrelated_cosine:.3f}")
    console.print(table)


@app.command()
def check(
    config: Annotated[Path | None, typer.Option("--config", "-c", help="TOML configuration file.")] = None,
    embeddings: Annotated[
        bool, typer.Option("--embeddings/--no-embeddings", help="Also check the text embedder.")
    ] = False,
    chat: Annotated[bool, typer.Option("--chat/--no-chat", help="Check the chat backend.")] = True,
) -> None:
    """Show the active backend and model, verify the model file, and run one tiny structured call."""
    try:
        cfg = load_config(config)
    except ConfigError as exc:
        err_console.print(f"[red]config error:[/red] {exc}")
        raise typer.Exit(2) from None
    usage = UsageCounter()
    try:
        if chat:
            render_chat_check(check_chat(cfg, usage))
        if embeddings:
            render_embedding_check(check_embeddings(cfg, usage))
    except LLMError as exc:
        err_console.print(f"[red]error:[/red] {exc}")
        raise typer.Exit(1) from None
    finally:
        print_usage(usage.report(), console)
