"""Run RefAV's published example programs unchanged through ``scenariominer mine --program``.

Reads the programs from a RefAV checkout (not shipped here: its code is RefAV's, not ours):
every fenced block of ``run/llm_prompting/RefAV/examples.txt`` and
``run/llm_prompting/NuPrompt/examples.txt``, and every ``if N in scenarios:`` block of
``run/example_scenarios.py`` (dedented). Each runs through :func:`scenariominer.api.mine` with
``program=`` (what ``mine --program FILE`` calls) on the given log(s), in the sandbox; printed:
whether it ran, the referred (track, timestamp) cells, and the first line of the error.

    .venv/bin/python benchmarks/refav_examples.py --refav PATH/TO/RefAV --logs ../shared/data/av2/LOG
"""

from __future__ import annotations

import argparse
import re
import textwrap
from pathlib import Path

_FENCE = re.compile(r"```python\n(.*?)```", re.DOTALL)
_BLOCK = re.compile(r"^if (\d+) in scenarios:\n((?:[ \t]+.*\n|\n)+)", re.MULTILINE)


def programs(refav: Path) -> list[tuple[str, str]]:
    """``(name, program)`` of every example program in the checkout."""
    out: list[tuple[str, str]] = []
    for rel in ("run/llm_prompting/RefAV/examples.txt", "run/llm_prompting/NuPrompt/examples.txt"):
        text = (refav / rel).read_text(encoding="utf-8")
        for i, block in enumerate(_FENCE.findall(text), start=1):
            out.append((f"{rel.split('/')[-2]}#{i:02d}", block))
    scenarios = (refav / "run/example_scenarios.py").read_text(encoding="utf-8")
    for number, body in _BLOCK.findall(scenarios):
        out.append((f"example_scenarios#{number}", textwrap.dedent(body)))
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--refav", type=Path, required=True, help="a RefAV checkout")
    parser.add_argument("--logs", type=Path, nargs="+", required=True, help="AV2 log folders")
    args = parser.parse_args()
    from scenariominer import api
    from scenariominer.config import load_config

    cfg = load_config(None)
    rows = []
    for name, program in programs(args.refav):
        request = api.MineRequest("refav example", logs=args.logs, program=program, use_bank=False)
        try:
            report = api.mine(request, cfg).report
        except Exception as exc:  # noqa: BLE001 - a report line per program, whatever happens
            rows.append((name, False, 0, f"{type(exc).__name__}: {exc}"))
            continue
        cells = sum(int(m.referred.sum()) for m in report.matches)
        error = str(report.failures[0].error) if report.failures else ""
        rows.append((name, not report.failures, cells, error.splitlines()[0] if error else ""))
    width = max(len(r[0]) for r in rows)
    for name, ran, cells, error in rows:
        print(f"{name:{width}s}  {'ran' if ran else 'FAILED':6s}  cells {cells:6d}  {error[:100]}")
    print(f"\n{sum(r[1] for r in rows)} of {len(rows)} example programs ran unchanged")


if __name__ == "__main__":
    main()
