"""The bad-input corpus: every malformed input the ingestion must survive, with its expected outcome.

A case writes its bad file(s) into a folder and returns the path(s) to ingest. ``test_bad_inputs.py``
ingests them through ``scenariominer.api.ingest`` (or the ``scenariominer ingest`` command, for the
cases where printing the error is the point) next to a good log, and checks the outcome:

* ``rejected``: the source fails alone; the error matches ``pattern``; nothing of it is stored.
* ``repaired``: the log(s) are stored; a note (``Log.notes``, in the report and the store) matches
  ``pattern``.
* ``accepted``: nothing to repair (the input is odd, not wrong: unsorted rows, a byte-order mark);
  stored as is, optionally checked by ``check``.

Cases register themselves with :func:`case` in ``bad_av2.py``, ``bad_maps.py``, ``bad_highd.py`` and
``bad_tables.py``; :func:`all_cases` collects them. ``docs/bad-input.md`` lists them; regenerate its
table with ``.venv/bin/python tests/bad_inputs/bad_registry.py --write-doc`` (a test checks it is
current).
"""

from __future__ import annotations

import sys
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Literal

import pyarrow as pa
import pyarrow.feather as feather

Outcome = Literal["rejected", "repaired", "accepted"]
#: A generator: writes the bad input under the given folder, returns the path(s) to ingest.
Make = Callable[[Path], Sequence[Path]]
#: An extra check of a case: (store, ingest report or CLI output, the case's folder) -> None.
Check = Callable[[Any, Any, Path], None]

DOC = Path(__file__).resolve().parents[2] / "docs" / "bad-input.md"
BEGIN, END = "<!-- BEGIN bad-input table -->", "<!-- END bad-input table -->"
FORMAT_TITLES = {
    "av2": "Argoverse 2 log folders",
    "map": "Argoverse 2 vector maps",
    "highd": "highD recordings",
    "tabular": "Tabular files (CSV, Parquet)",
    "path": "Paths",
}


@dataclass(frozen=True)
class Case:
    """One class of bad input.

    Attributes:
        name: unique identifier (the pytest id and the row in docs/bad-input.md).
        fmt: ``av2``, ``map``, ``highd``, ``tabular`` or ``path``.
        what: the input, in a few words.
        make: writes it (see :data:`Make`).
        outcome: ``rejected``, ``repaired`` or ``accepted``.
        pattern: regex the error (rejected) or a note (repaired) must match (``re.search``).
        via: ``api`` (``scenariominer.api.ingest``) or ``cli`` (``scenariominer ingest``).
        check: extra assertions, if any.
    """

    name: str
    fmt: str
    what: str
    make: Make
    outcome: Outcome
    pattern: str = ""
    via: Literal["api", "cli"] = "api"
    check: Check | None = None


CASES: list[Case] = []


def case(
    name: str,
    fmt: str,
    what: str,
    outcome: Outcome,
    pattern: str = "",
    *,
    via: Literal["api", "cli"] = "api",
    check: Check | None = None,
) -> Callable[[Make], Make]:
    """Register the decorated generator as a case."""

    def register(make: Make) -> Make:
        if any(c.name == name for c in CASES):
            raise ValueError(f"bad-input case {name!r} registered twice")
        if outcome != "accepted" and not pattern:
            raise ValueError(f"bad-input case {name!r} needs a pattern")
        CASES.append(Case(name, fmt, what, make, outcome, pattern, via, check))
        return make

    return register


def all_cases() -> list[Case]:
    """Every registered case (imports the modules that register them)."""
    import bad_av2  # noqa: F401
    import bad_highd  # noqa: F401
    import bad_maps  # noqa: F401
    import bad_tables  # noqa: F401

    return list(CASES)


# ---------------------------------------------------------------------- helpers for generators


def rewrite_feather(path: Path, change: Callable[[pa.Table], pa.Table]) -> None:
    """Rewrite a Feather file through ``change``."""
    feather.write_feather(change(feather.read_table(path)), path)


def set_column(table: pa.Table, name: str, values: Any, type: pa.DataType | None = None) -> pa.Table:
    """``table`` with column ``name`` replaced by ``values``."""
    return table.set_column(table.column_names.index(name), name, pa.array(values, type=type))


# ---------------------------------------------------------------------- the doc


def _cell(text: str) -> str:
    return text.replace("|", "\\|")


def render_table(cases: Sequence[Case]) -> str:
    """The Markdown tables of docs/bad-input.md, one per format, with a summary line."""
    n = {o: sum(c.outcome == o for c in cases) for o in ("rejected", "repaired", "accepted")}
    out = [
        f"{len(cases)} classes: {n['rejected']} rejected, {n['repaired']} repaired, "
        f"{n['accepted']} accepted unchanged.",
    ]
    for fmt, title in FORMAT_TITLES.items():
        rows = [c for c in cases if c.fmt == fmt]
        if not rows:
            continue
        out += [
            "",
            f"### {title}",
            "",
            "| case | input | outcome | error or note (regex) |",
            "|---|---|---|---|",
        ]
        for c in rows:
            pattern = f"`{_cell(c.pattern)}`" if c.pattern else ""
            via = " (CLI)" if c.via == "cli" else ""
            out.append(f"| `{c.name}` | {_cell(c.what)} | {c.outcome}{via} | {pattern} |")
    return "\n".join(out)


def doc_with_table(text: str, cases: Sequence[Case]) -> str:
    """``text`` (docs/bad-input.md) with the part between the markers replaced by the tables."""
    head, _, rest = text.partition(BEGIN)
    _, _, tail = rest.partition(END)
    return f"{head}{BEGIN}\n{render_table(cases)}\n{END}{tail}"


if __name__ == "__main__":
    if sys.argv[1:] != ["--write-doc"]:
        sys.exit("usage: bad_registry.py --write-doc")
    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "data"))  # highd_files, as in pytest
    import bad_registry

    DOC.write_text(
        doc_with_table(DOC.read_text(encoding="utf-8"), bad_registry.all_cases()), encoding="utf-8"
    )
    print(f"wrote {DOC}")
