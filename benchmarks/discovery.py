"""Finding the logs of a large dataset root: ``Av2Reader.discover`` against listing the folders.

Makes N log folders (each with an empty annotation file: discovery looks at names only) under a
split folder and prints the seconds of discovery as a ratio to the floor measured in the same
run, one ``os.scandir`` pass over the same folders checking for the annotation file.

    python benchmarks/discovery.py --n 3000
"""

from __future__ import annotations

import argparse
import os
import tempfile
import time
from pathlib import Path

from scenariominer.data.adapters.av2.logs import ANNOTATIONS_FILE, Av2Reader


def main() -> None:
    parser = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument("--n", type=int, default=3000, help="number of log folders")
    args = parser.parse_args()
    root = Path(tempfile.mkdtemp(prefix="sm-bench-discovery-"))
    for i in range(args.n):
        log_dir = root / "train" / f"log-{i:06d}"
        log_dir.mkdir(parents=True)
        (log_dir / ANNOTATIONS_FILE).touch()

    t = time.perf_counter()
    with os.scandir(root / "train") as entries:
        floor = [e.path for e in entries if os.path.isfile(os.path.join(e.path, ANNOTATIONS_FILE))]
    floor_s = time.perf_counter() - t

    t = time.perf_counter()
    found = Av2Reader().discover(root)
    discover_s = time.perf_counter() - t
    assert len(found) == len(floor) == args.n

    print(f"{'stage':<34}{'seconds':>9}{'folders/s':>12}{'vs floor':>10}")
    for name, sec in (("os.scandir + isfile (floor)", floor_s), ("Av2Reader.discover", discover_s)):
        print(f"{name:<34}{sec:9.3f}{args.n / sec:12,.0f}{sec / floor_s:9.1f}x")
    print(f"log folders: {args.n:,} under {root}")


if __name__ == "__main__":
    main()
