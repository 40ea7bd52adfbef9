"""Text that programs, logs and users control is printed as data (issue 12 B), and errors are one line."""

from __future__ import annotations

from pathlib import Path

import pytest
from typer.testing import CliRunner

from scenariominer.cli import app
from scenariominer.cli._common import settings
from scenariominer.cli.text import plain, safe

runner = CliRunner()

HOSTILE = [
    "[/x]",
    "[bold red]boom[/]",
    "[link=http://evil.example]click[/link]",
    "\x1b[31mred\x1b[0m",
    "\x1b]8;;http://evil.example\x1b\\link\x1b]8;;\x1b\\",
    "\x1b]0;title\x07",
    "\x9b2J",
    "bell\x07 backspace\x08 nul\x00",
    "lone \ud800 surrogate",
    "\u202eevil",
    "ends with a backslash \\",
    "ends with two \\\\",
]


@pytest.mark.parametrize("text", HOSTILE)
def test_plain_leaves_no_escape_or_control_character(text: str) -> None:
    out = plain(text)
    out.encode("utf-8")  # always encodable
    assert not any(ord(c) < 0x20 and c not in "\n\t" for c in out)
    assert "\x1b" not in out and "\x9b" not in out and "\u202e" not in out


@pytest.mark.parametrize("text", HOSTILE)
def test_safe_text_prints_literally_through_rich(text: str) -> None:
    from rich.console import Console

    console = Console(record=True, width=300, color_system=None)
    console.print(f"[red]{safe(text)}[/red]")
    shown = console.export_text()
    assert shown == plain(text) + "\n"  # the very characters, markup included, are shown


def test_plain_keeps_ordinary_text() -> None:
    assert plain("Straße, 速度 5 m/s\n\tok") == "Straße, 速度 5 m/s\n\tok"


def test_a_markup_like_store_path_does_not_crash_info(tmp_path: Path) -> None:
    store = tmp_path / "[/x]"
    result = runner.invoke(app, ["info", "--store", str(store)])
    assert result.exit_code == 2, result.output
    assert "[/x]" in result.output and "Traceback" not in result.output


def test_emoji_codes_in_ids_are_printed_as_typed(tmp_path: Path) -> None:
    # Rich turned ":id:" of an event id into an emoji ("bad:id:x" was shown as "bad🆔x")
    store = tmp_path / "a:id:b:smile:"
    result = runner.invoke(app, ["info", "--store", str(store)])
    assert result.exit_code == 2, result.output
    assert "a:id:b:smile:" in " ".join(result.output.split())
    assert "\U0001f194" not in result.output and "\U0001f604" not in result.output


def test_empty_queries_are_usage_errors_not_internal_ones(tmp_path: Path, av2_log_dir: Path) -> None:
    # `mine ""` listed every track of every log; `search ""` was "internal error: ValueError"
    result = runner.invoke(app, ["mine", " ", "--logs", str(av2_log_dir)])
    assert result.exit_code == 2, result.output
    assert "the description is empty" in " ".join(result.output.split())
    result = runner.invoke(app, ["search", "", "--store", str(tmp_path / "s")])
    assert result.exit_code == 2, result.output
    assert "the text query is empty" in result.output and "internal error" not in result.output


def test_a_program_file_that_is_not_utf8_is_a_clear_error(tmp_path: Path, av2_log_dir: Path) -> None:
    prog = tmp_path / "p.py"
    prog.write_bytes(b"output_scenario(\xff\xfe)\n")
    result = runner.invoke(app, ["mine", "x", "--logs", str(av2_log_dir), "--program", str(prog)])
    assert result.exit_code == 2
    assert "not UTF-8" in result.output and "Traceback" not in result.output


def test_program_error_text_with_markup_is_printed_and_failing_everywhere_exits_1(
    tmp_path: Path, av2_log_dir: Path
) -> None:
    prog = tmp_path / "p.py"
    prog.write_text(
        "cat = '[/x]\\x1b]8;;http://e\\x1b\\\\'\n"
        "output_scenario(get_objects_of_category(log_dir, category=cat), description)\n",
        encoding="utf-8",
    )
    result = runner.invoke(app, ["mine", "x", "--logs", str(av2_log_dir), "--program", str(prog)])
    assert result.exit_code == 1, result.output
    assert "[/x]" in result.output and "\x1b" not in result.output
    assert "failed on every log (1)" in result.output


def test_debug_shows_the_traceback_and_internal_errors_say_so(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    from scenariominer import api

    def broken(*args: object, **kwargs: object) -> None:
        raise ZeroDivisionError("division by zero")

    monkeypatch.setattr(api, "info", broken, raising=False)
    from scenariominer.store import ScenarioStore

    ScenarioStore.open(tmp_path / "s", create=True)
    result = runner.invoke(app, ["info", "--store", str(tmp_path / "s")])
    assert result.exit_code == 1
    assert "internal error" in result.output and "--debug" in result.output
    result = runner.invoke(app, ["--debug", "info", "--store", str(tmp_path / "s")])
    settings.debug = False
    assert isinstance(result.exception, ZeroDivisionError)


def test_quiet_prints_nothing_but_errors(tmp_path: Path) -> None:
    from scenariominer.store import ScenarioStore

    ScenarioStore.open(tmp_path / "s", create=True)
    loud = runner.invoke(app, ["info", "--store", str(tmp_path / "s")])
    quiet = runner.invoke(app, ["--quiet", "info", "--store", str(tmp_path / "s")])
    again = runner.invoke(app, ["info", "--store", str(tmp_path / "s")])
    assert "logs" in loud.output and quiet.output == "" and "logs" in again.output
    failing = runner.invoke(app, ["--quiet", "info", "--store", str(tmp_path / "none")])
    assert failing.exit_code == 2 and "error" in failing.output


def test_an_unknown_option_is_a_usage_error_not_an_internal_one() -> None:
    result = runner.invoke(app, ["analyze", "--no-such-option"])
    assert result.exit_code == 2
    assert "No such option" in result.output and "internal error" not in result.output


def test_a_closed_output_pipe_is_no_internal_error() -> None:
    # ``scenariominer ... | head -1``: the reader is gone; click ends the command quietly (status 1).
    import typer

    from scenariominer.cli._common import SafeGroup

    demo = typer.Typer(cls=SafeGroup)

    @demo.command()
    def write() -> None:
        raise BrokenPipeError(32, "Broken pipe")

    @demo.command()
    def other() -> None:  # a second command keeps ``write`` a subcommand
        pass

    result = runner.invoke(demo, ["write"])
    assert result.exit_code == 1
    assert "internal error" not in result.output + result.stderr


def test_a_program_that_cannot_run_is_refused_once_before_any_log(tmp_path: Path, av2_log_dir: Path) -> None:
    # it was run on each log, failed on each with the same syntax error, and printed "status ok"
    prog = tmp_path / "p.py"
    prog.write_text("v = get_objects_of_category(log_dir, category='VEHICLE'\n", encoding="utf-8")
    result = runner.invoke(app, ["mine", "x", "--logs", str(av2_log_dir), "--program", str(prog)])
    assert result.exit_code == 2, result.output
    shown = " ".join(result.output.split())
    assert shown.count("'(' was never closed") == 1 and "the program was not run" in shown
    assert "program ok" not in shown
