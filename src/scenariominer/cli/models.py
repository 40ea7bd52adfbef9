"""The ``llm`` command group: inspect and exercise the configured model backends."""

from __future__ import annotations

from typing import TYPE_CHECKING, Annotated

import typer

from scenariominer.cli._common import ConfigOpt, console, err_console, load_cfg
from scenariominer.cli.text import safe

if TYPE_CHECKING:
    from rich.table import Table

    from scenariominer.llm.check import ChatCheck, EmbeddingCheck

app = typer.Typer(name="llm", help="Language-model and text-embedding backends.", no_args_is_help=True)


@app.callback()
def _group() -> None:
    """Language-model and text-embedding backends."""


def _key_value_table(title: str) -> Table:
    from rich.table import Table

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
        table.add_row("model file", safe(f.path))
        table.add_row("size", f"{f.size_bytes:,} bytes ({f.size_bytes / 2**20:,.1f} MiB)")
        table.add_row("sha256", f"{f.sha256} ({'verified against pin' if f.bundled else 'computed'})")
    if check.load_time_s is not None:
        table.add_row("load time", f"{check.load_time_s:.2f} s")
    table.add_row("answer", safe(check.value))
    table.add_row("attempts", str(check.attempts))
    table.add_row("latency", f"{check.latency_s:.2f} s")
    table.add_row("tokens", f"{check.prompt_tokens} prompt + {check.completion_tokens} generated")
    console().print(table)


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
    console().print(table)


@app.command()
def check(
    config: ConfigOpt = None,
    embeddings: Annotated[
        bool, typer.Option("--embeddings/--no-embeddings", help="Also check the text embedder.")
    ] = False,
    chat: Annotated[bool, typer.Option("--chat/--no-chat", help="Check the chat backend.")] = True,
) -> None:
    """Show the active backend and model, verify the model file, and run one tiny structured call."""
    from scenariominer import api
    from scenariominer.llm.usage import UsageCounter, print_usage

    cfg = load_cfg(config)
    usage = UsageCounter()
    try:
        result = api.llm_check(cfg, chat=chat, embeddings=embeddings, usage=usage)
        if result.chat is not None:
            render_chat_check(result.chat)
        if result.embeddings is not None:
            render_embedding_check(result.embeddings)
    finally:
        print_usage(usage.report(), console())


@app.command()
def serve(
    config: ConfigOpt = None,
    host: Annotated[
        str, typer.Option("--host", help="Interface to listen on (no authentication!).")
    ] = "127.0.0.1",
    port: Annotated[int, typer.Option("--port", min=1, max=65535, help="TCP port.")] = 8765,
) -> None:
    """Serve the configured GGUF model (the bundled one by default) over an OpenAI-compatible API.

    Point any command at it with ``[llm] backend = "openai"``, ``base_url = "http://HOST:PORT/v1"``,
    ``model = "scenariominer"`` and ``structured_mode = "json_object_schema"``. Stop with Ctrl-C.
    """
    from scenariominer import api

    settings = api.serve_settings(load_cfg(config), host=host, port=port)
    err_console().print(
        f"serving {safe(settings.model_path.name)} as {safe(settings.alias)!r} at {safe(settings.base_url)}",
        soft_wrap=True,
    )
    raise typer.Exit(api.serve(settings))
