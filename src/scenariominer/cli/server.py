"""Command ``serve``: the scenario browser (HTTP API and web UI) over the store."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from scenariominer.cli._common import ConfigOpt, StoreOpt, console, load_cfg
from scenariominer.cli.text import safe


def serve(
    store: StoreOpt = None,
    config: ConfigOpt = None,
    host: Annotated[
        str, typer.Option("--host", help="Address to bind; anything but loopback needs --token.")
    ] = "127.0.0.1",
    port: Annotated[int, typer.Option("--port", "-p", min=0, max=65535, help="TCP port.")] = 8787,
    token: Annotated[
        str | None,
        typer.Option(
            "--token",
            envvar="SCENARIOMINER_SERVER_TOKEN",
            help="Bearer token every API call must carry (required off loopback).",
        ),
    ] = None,
    data_root: Annotated[
        list[Path] | None,
        typer.Option(
            "--data-root",
            help="Folder that paths in requests (ingest, synth) must lie in (repeatable; default: cwd).",
        ),
    ] = None,
    workers: Annotated[int, typer.Option("--workers", min=1, help="Jobs running at once.")] = 1,
    max_queued: Annotated[int, typer.Option("--max-queued", min=1, help="Jobs waiting at most.")] = 8,
) -> None:
    """Serve the scenario browser: an HTTP API (OpenAPI at /openapi.json) and a web UI at /."""
    from scenariominer import api
    from scenariominer.server import ServerSettings
    from scenariominer.server import serve as run_server

    cfg = load_cfg(config)
    st = api.open_existing_store(store, cfg)
    settings = ServerSettings.create(
        st.root,
        data_root or (),
        config_path=config,
        host=host,
        port=port,
        token=token,
        workers=workers,
        max_queued=max_queued,
    )
    console().print(
        f"scenario browser on http://{safe(host)}:{port}/ (store {safe(st.root)})", soft_wrap=True
    )
    run_server(settings, cfg)


def register(app: typer.Typer) -> None:
    """Add the ``serve`` command to ``app``."""
    app.command("serve")(serve)
