"""What every command shares: the options declared once, consoles, configuration and error handling.

Errors: a :class:`~scenariominer.errors.ScenarioMinerError` (or an ``OSError`` about a file) is the
user's to fix: one line on stderr, exit status 2. Anything else is a bug: one line naming it and
asking for ``--debug``, exit status 1. ``--debug`` (or ``SCENARIOMINER_DEBUG=1``) shows the traceback.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any

import typer
from typer.core import TyperGroup

from scenariominer.cli.text import safe

if TYPE_CHECKING:
    from rich.console import Console

    from scenariominer.config import Config

__all__ = [
    "ConfigOpt",
    "ExecutorOpt",
    "JsonOpt",
    "RayAddressOpt",
    "WorkersOpt",
    "StoreOpt",
    "SafeGroup",
    "console",
    "err_console",
    "load_cfg",
    "settings",
    "with_exec",
]

StoreOpt = Annotated[
    Path | None,
    typer.Option(
        "--store", "-s", help="Store directory (default: $SCENARIOMINER_STORE or the per-user data dir)."
    ),
]
ConfigOpt = Annotated[Path | None, typer.Option("--config", "-c", help="TOML configuration file.")]
JsonOpt = Annotated[bool, typer.Option("--json", help="Print the result as JSON (for scripts).")]
ExecutorOpt = Annotated[
    str | None,
    typer.Option(
        "--executor",
        help="Where the per-log work runs: local (this process), process (a pool of local workers) "
        "or ray (a Ray cluster). Default: exec.executor (process).",
    ),
]
WorkersOpt = Annotated[
    int | None, typer.Option("--workers", min=0, help="Workers or concurrent tasks (0: every core).")
]
RayAddressOpt = Annotated[
    str | None,
    typer.Option(
        "--ray-address", help="Ray cluster to join: auto, HOST:PORT or ray://HOST:PORT (--executor ray)."
    ),
]


@dataclass
class Settings:
    """Global options of the root command (``scenariominer --debug --quiet ...``)."""

    debug: bool = False
    quiet: bool = False
    verbose: bool = False


settings = Settings(debug=os.environ.get("SCENARIOMINER_DEBUG", "") not in ("", "0"))

_consoles: dict[str, Console] = {}


def console() -> Console:
    """The stdout console (created on first use: importing Rich costs start-up time)."""
    if "out" not in _consoles:
        from rich.console import Console

        _consoles["out"] = Console(emoji=False)  # ":id:" in an id stays text, not 🆔
    _consoles["out"].quiet = settings.quiet  # follows the current command's --quiet
    return _consoles["out"]


def err_console() -> Console:
    """The stderr console (errors are printed even with ``--quiet``)."""
    if "err" not in _consoles:
        from rich.console import Console

        _consoles["err"] = Console(stderr=True, emoji=False)
    return _consoles["err"]


def load_cfg(path: Path | None) -> Config:
    """The configuration tree from ``path`` (or the defaults and environment)."""
    from scenariominer.config import load_config

    return load_config(path)


def with_exec(cfg: Config, executor: str | None, workers: int | None, ray_address: str | None) -> Config:
    """``cfg`` with the command line's executor options applied (checked like the config file's)."""
    import dataclasses

    changes: dict[str, Any] = {}
    if executor is not None:
        changes["executor"] = executor
    if workers is not None:
        changes["workers"] = workers
    if ray_address is not None:
        changes["ray_address"] = ray_address
    if not changes:
        return cfg
    return dataclasses.replace(cfg, exec=dataclasses.replace(cfg.exec, **changes))


def _report(exc: BaseException) -> int:
    """Print ``exc`` as one line and return the exit status it deserves."""
    from scenariominer.errors import ScenarioMinerError

    if isinstance(exc, ScenarioMinerError):
        label = "config error" if type(exc).__name__ == "ConfigError" else "error"
        err_console().print(f"[red]{label}:[/red] {safe(exc)}", soft_wrap=True, highlight=False)
        return 2
    if isinstance(exc, OSError) and exc.filename is not None:
        what = exc.strerror or type(exc).__name__
        err_console().print(f"[red]error:[/red] {safe(exc.filename)}: {safe(what)}", soft_wrap=True)
        return 2
    err_console().print(
        f"[red]internal error:[/red] {safe(type(exc).__name__)}: {safe(exc)} "
        "(a bug: run again with --debug for the traceback and report it)",
        soft_wrap=True,
        highlight=False,
    )
    return 1


def _is_usage_exception(exc: Exception) -> bool:
    """Whether ``exc`` is click's own (a usage error, an exit): click prints those itself.

    Typer 0.29 carries its own copy of click (``typer._click``); both are recognised.
    """
    import click

    modules: list[Any] = [click.exceptions]
    try:
        from typer._click import exceptions as typer_click  # type: ignore[import-not-found,unused-ignore]

        modules.append(typer_click)
    except ImportError:  # an older typer uses click itself
        pass
    kinds = tuple(
        getattr(m, name) for m in modules for name in ("ClickException", "Exit") if hasattr(m, name)
    )
    return isinstance(exc, kinds)


class SafeGroup(TyperGroup):
    """The root command group: turns exceptions escaping a command into one line and an exit status."""

    def invoke(self, ctx: Any) -> Any:
        """Run the command; report errors as the module docstring says."""
        try:
            return super().invoke(ctx)
        except (typer.Exit, typer.Abort, SystemExit, KeyboardInterrupt):
            raise
        except BrokenPipeError:
            raise  # the reader of our output is gone (``| head``): click exits quietly with status 1
        except Exception as exc:
            if _is_usage_exception(exc):
                raise
            if settings.debug:
                raise
            raise typer.Exit(_report(exc)) from None
