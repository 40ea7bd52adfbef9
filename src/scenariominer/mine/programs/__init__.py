"""Hand-written mining programs: the few-shot example bank and the benchmark set.

The bank is data, not code: ``examples.toml`` (shipped in this package) lists descriptions in
the style of the Argoverse 2 scenario-mining prompts, each with a program in the mining DSL and
tags. :func:`load_examples` reads it (plus any user TOML files of the same shape) into
:class:`ExampleProgram` records; the language-model stage picks few-shot examples from them and
the benchmarks run them with :func:`scenariominer.mine.sandbox.run_trusted_program`.

File format (one table per example)::

    [[example]]
    description = "vehicle with a bicycle to its right"
    tags = ["relation", "direction"]
    needs_map = false
    program = '''
    vehicles = get_objects_of_category(log_dir, category='VEHICLE')
    ...
    output_scenario(result, description, log_dir, output_dir)
    '''
"""

from __future__ import annotations

import tomllib
from collections.abc import Iterable
from dataclasses import dataclass
from importlib import resources
from pathlib import Path
from typing import Any

from scenariominer import errors as _errors

__all__ = ["BUILTIN_EXAMPLES_FILE", "ExampleBankError", "ExampleProgram", "load_examples", "parse_examples"]

#: Name of the TOML file shipped with the package.
BUILTIN_EXAMPLES_FILE = "examples.toml"


class ExampleBankError(_errors.MiningError, ValueError):
    """An example-bank file is unreadable or malformed; the message names the file and entry."""


@dataclass(frozen=True)
class ExampleProgram:
    """One description with its hand-written mining program.

    Attributes:
        description: the natural-language scenario description.
        program: the program text in the mining DSL (ends with ``output_scenario(...)``).
        tags: what the program exercises (``relation``, ``map``, ``motion``, ...).
        needs_map: whether the program calls HD-map predicates.
        source: the file the example was read from.
    """

    description: str
    program: str
    tags: tuple[str, ...] = ()
    needs_map: bool = False
    source: str = BUILTIN_EXAMPLES_FILE


def _entry(raw: Any, index: int, source: str) -> ExampleProgram:
    where = f"{source}: example {index + 1}"
    if not isinstance(raw, dict):
        raise ExampleBankError(f"{where} is not a table")
    unknown = sorted(set(raw) - {"description", "program", "tags", "needs_map"})
    if unknown:
        raise ExampleBankError(f"{where} has unknown key(s) {unknown}")
    description, program = raw.get("description"), raw.get("program")
    if not isinstance(description, str) or not description.strip():
        raise ExampleBankError(f"{where} needs a non-empty string 'description'")
    if not isinstance(program, str) or "output_scenario" not in program:
        raise ExampleBankError(
            f"{where} ({description!r}) needs a 'program' string that calls output_scenario"
        )
    tags = raw.get("tags", [])
    if not isinstance(tags, list) or not all(isinstance(t, str) for t in tags):
        raise ExampleBankError(f"{where} ({description!r}): 'tags' must be a list of strings")
    needs_map = raw.get("needs_map", False)
    if not isinstance(needs_map, bool):
        raise ExampleBankError(f"{where} ({description!r}): 'needs_map' must be true or false")
    return ExampleProgram(description.strip(), program.strip() + "\n", tuple(tags), needs_map, source)


def parse_examples(text: str, source: str = "<text>") -> tuple[ExampleProgram, ...]:
    """Parse example-bank TOML text.

    Raises:
        ExampleBankError: invalid TOML, a missing ``[[example]]`` array or a malformed entry.
    """
    try:
        doc = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ExampleBankError(f"{source}: not valid TOML ({exc})") from None
    entries = doc.get("example")
    if not isinstance(entries, list):
        raise ExampleBankError(f"{source}: expected an array of [[example]] tables")
    return tuple(_entry(raw, i, source) for i, raw in enumerate(entries))


def load_examples(extra: Iterable[str | Path] = (), *, builtin: bool = True) -> tuple[ExampleProgram, ...]:
    """Load the shipped example bank and any extra bank files.

    A description that occurs again in a later file replaces the earlier program, so users can
    override shipped examples.

    Args:
        extra: paths of additional TOML files in the same format.
        builtin: include the bank shipped with the package.

    Raises:
        ExampleBankError: a file is missing, unreadable or malformed.
    """
    texts: list[tuple[str, str]] = []
    if builtin:
        ref = resources.files(__package__).joinpath(BUILTIN_EXAMPLES_FILE)
        texts.append((ref.read_text(encoding="utf-8"), BUILTIN_EXAMPLES_FILE))
    for path in extra:
        p = Path(path)
        try:
            texts.append((p.read_text(encoding="utf-8"), str(p)))
        except OSError as exc:
            raise ExampleBankError(f"{p}: cannot read the example bank ({exc.strerror or exc})") from None
    merged: dict[str, ExampleProgram] = {}
    for text, source in texts:
        for ex in parse_examples(text, source):
            merged[ex.description.lower()] = ex
    return tuple(merged.values())
