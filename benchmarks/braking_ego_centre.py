"""Copy of a labelled Argoverse 2 braking set with the ego at its rear axle (the ego-centre ablation).

Usage::

    python benchmarks/braking_ego_centre.py SRC_DIR OUT_DIR

Since the consolidation issue the AV2 reader puts the ego at the centre of its box,
``AV2_EGO_CENTER_OFFSET_M`` ahead of the pose Argoverse 2 records (the rear axle). This script
writes each log of ``SRC_DIR`` again with the ego moved back by that offset, so that reading the
copy puts the ego where the pose is, as the reader did before the change: ingesting both and
running ``analyze`` and ``eval braking`` on each measures what the ego centre is worth. The map
folders and ``labels.csv`` are copied unchanged; other road users are not touched.
"""

from __future__ import annotations

import argparse
import shutil
from pathlib import Path

import numpy as np

from scenariominer.data.adapters.av2 import AV2_EGO_CENTER_OFFSET_M, read_av2_log, write_av2_log
from scenariominer.data.log import Log


def ego_at_pose(log: Log) -> Log:
    """``log`` with the ego's box centre moved back along its heading to the recorded pose."""
    e = log.ego_index
    x, y = log.x_m.copy(), log.y_m.copy()
    x[e] -= AV2_EGO_CENTER_OFFSET_M * np.cos(log.yaw_rad[e])
    y[e] -= AV2_EGO_CENTER_OFFSET_M * np.sin(log.yaw_rad[e])
    return log.replace(x_m=x, y_m=y)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("src", type=Path, help="folder of AV2 logs with labels.csv")
    parser.add_argument("out", type=Path, help="output folder")
    args = parser.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    logs = sorted(p for p in args.src.iterdir() if (p / "city_SE3_egovehicle.feather").is_file())
    for src_dir in logs:
        out_dir = write_av2_log(ego_at_pose(read_av2_log(src_dir)), args.out)
        if (src_dir / "map").is_dir():
            shutil.copytree(src_dir / "map", out_dir / "map", dirs_exist_ok=True)
    shutil.copy(args.src / "labels.csv", args.out / "labels.csv")
    print(f"{len(logs)} log(s) written to {args.out} with the ego at its rear axle")


if __name__ == "__main__":
    main()
