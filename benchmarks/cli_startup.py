"""Start-up time of the command line: ``scenariominer --help`` against ``python -c pass``.

Both are run as fresh processes in the same run (best and median of ``--repeats``), and the ratio
is printed: the command line must stay light (heavy modules are imported inside commands only).

    .venv/bin/python benchmarks/cli_startup.py --repeats 15
"""

from __future__ import annotations

import argparse
import shutil
import statistics
import subprocess
import sys
import time
from pathlib import Path


def _times(cmd: list[str], repeats: int) -> list[float]:
    out = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        out.append(time.perf_counter() - t0)
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=15)
    args = parser.parse_args()
    exe = shutil.which("scenariominer") or str(Path(sys.executable).parent / "scenariominer")
    runs = {
        "python -c pass": [sys.executable, "-c", "pass"],
        "scenariominer --help": [exe, "--help"],
        "scenariominer mine --help": [exe, "mine", "--help"],
    }
    results = {name: _times(cmd, args.repeats) for name, cmd in runs.items()}
    base = statistics.median(results["python -c pass"])
    print(f"{'command':28s} {'best s':>8s} {'median s':>9s} {'x python -c pass':>17s}")
    for name, times in results.items():
        med = statistics.median(times)
        print(f"{name:28s} {min(times):8.3f} {med:9.3f} {med / base:17.1f}")
    help_s = statistics.median(results["scenariominer --help"])
    verdict = "under" if help_s < 0.3 else "OVER"
    print(f"\nscenariominer --help: {help_s:.3f} s median ({verdict} the 0.3 s goal)")


if __name__ == "__main__":
    main()
