"""The ``scenariominer`` command: parse options, call one :mod:`scenariominer.api` function, render.

No pipeline logic lives here. Start-up stays fast because command modules import only Typer and
the light vocabulary of :mod:`scenariominer.schema`; every heavy import happens inside a command.

Global options (before the command): ``--debug`` shows tracebacks, ``--quiet`` silences normal
output (errors still print), ``--verbose`` is accepted for scripts and reserved for more detail.
"""

from __future__ import annotations

from typing import Annotated

import typer

from scenariominer.cli import (
    braking,
    cbr,
    corpus,
    evaluation,
    graph,
    mining,
    models,
    represent,
    server,
    simulate,
    storecmd,
)
from scenariominer.cli._common import SafeGroup, settings

__all__ = ["app", "main"]

app = typer.Typer(
    name="scenariominer",
    help="Turn recorded driving logs into a searchable, explainable scenario database.",
    no_args_is_help=True,
    pretty_exceptions_enable=False,
    cls=SafeGroup,
)


@app.callback()
def _root(
    debug: Annotated[bool, typer.Option("--debug", help="Show tracebacks of errors.")] = False,
    quiet: Annotated[bool, typer.Option("--quiet", "-q", help="Print errors only.")] = False,
    verbose: Annotated[bool, typer.Option("--verbose", "-v", help="Print more detail.")] = False,
) -> None:
    """Turn recorded driving logs into a searchable, explainable scenario database."""
    settings.debug = settings.debug or debug
    settings.quiet = quiet
    settings.verbose = verbose


corpus.register(app)
braking.register(app)
mining.register(app)
represent.register(app)
cbr.register(app)
graph.register(app)
simulate.register(app)
server.register(app)
app.add_typer(evaluation.app, name="eval", help="Evaluate braking explanations and mining against labels.")
app.add_typer(models.app, name="llm", help="Language-model and embedding backends.")
app.add_typer(storecmd.app, name="store", help="Check and clean the scenario store.")


def main() -> None:
    """Console-script entry point."""
    app()
