"""The scenario browser: an HTTP API and a web UI over :mod:`scenariominer.api` (``scenariominer serve``).

* :mod:`.settings`: what is served and how (store, data roots, address, token, job limits);
* :mod:`.app`: the FastAPI application (:func:`create_app`), one route per use case;
* :mod:`.jobs`: long work in worker processes with a bounded queue, progress events, a job table;
* :mod:`.worker`: what a worker process runs;
* ``static/``: the web UI (plain HTML, JavaScript and CSS; nothing fetched from elsewhere).

FastAPI and uvicorn are imported only when a server is built (``scenariominer[server]``).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from scenariominer.server.settings import ServerSettings

if TYPE_CHECKING:
    from fastapi import FastAPI

    from scenariominer.config import Config

__all__ = ["ServerSettings", "create_app", "serve"]


def create_app(settings: ServerSettings, config: Config | None = None) -> FastAPI:
    """The FastAPI application for ``settings`` (see :func:`scenariominer.server.app.create_app`)."""
    from scenariominer.server.app import create_app as _create

    return _create(settings, config)


def serve(settings: ServerSettings, config: Config | None = None) -> None:
    """Build the application and run it with uvicorn until interrupted."""
    from scenariominer._optional import require

    uvicorn = require("uvicorn", extra="server", purpose="the scenario browser (scenariominer serve)")
    uvicorn.run(create_app(settings, config), host=settings.host, port=settings.port, log_level="info")
