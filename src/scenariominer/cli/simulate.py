"""The ``simulate`` command group: traffic made by a real simulator (SUMO), written as log files.

Each scenario family lives in its own module that adds one command to :data:`app`
(:mod:`scenariominer.cli.simulate_highway`, :mod:`scenariominer.cli.simulate_urban`).
"""

from __future__ import annotations

import importlib

import typer

app = typer.Typer(
    name="simulate", help="Make traffic with SUMO and write it as recordings or logs.", no_args_is_help=True
)

_FAMILIES = ("scenariominer.cli.simulate_highway", "scenariominer.cli.simulate_urban")


@app.callback()
def _group() -> None:
    """Make traffic with SUMO and write it as recordings or logs."""


def register(root: typer.Typer) -> None:
    """Add the ``simulate`` group (with every family module that is present) to ``root``."""
    for name in _FAMILIES:
        try:
            module = importlib.import_module(name)
        except ModuleNotFoundError as err:
            if err.name != name:
                raise
            continue
        module.register(app)
    root.add_typer(app, name="simulate")
