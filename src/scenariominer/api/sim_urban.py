"""Use case ``simulate urban``: braking scenarios from SUMO, written as labelled Argoverse 2 logs.

The logs read like real Argoverse 2 sensor logs (``scenariominer ingest DIR``), each with a
vector map built from the SUMO network; ``DIR/labels.csv`` names, for every log, the road user
that forced the ego to brake (from the simulator's state) in the columns that
``scenariominer eval braking`` reads. Nothing here prints.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from scenariominer.progress import Progress
from scenariominer.sim.urban import UrbanSetResult, UrbanSettings, simulate_urban_set

__all__ = ["UrbanSimReport", "UrbanSimRequest", "simulate_urban"]

#: The result of :func:`simulate_urban` (one entry per log, failures included).
UrbanSimReport = UrbanSetResult


@dataclass(frozen=True)
class UrbanSimRequest:
    """Where to write and what to simulate.

    Attributes:
        out_dir: output folder (one folder per log and ``labels.csv``).
        settings: number of logs, seed, noise level and categories.
        overwrite: replace an earlier set in ``out_dir`` (the logs its ``labels.csv`` lists).
        keep_sumo_outputs: keep each log's SUMO network and routes in ``sumo/NNN/``.
    """

    out_dir: Path
    settings: UrbanSettings = field(default_factory=UrbanSettings)
    overwrite: bool = False
    keep_sumo_outputs: bool = False


def simulate_urban(request: UrbanSimRequest, progress: Progress | None = None) -> UrbanSimReport:
    """Simulate the logs of ``request`` with SUMO and write them with ``labels.csv``.

    A log whose simulation fails (or that gives no clean label in its draws) is reported in the
    result and the others are written.

    Raises:
        UrbanSimError: a bad setting (number of logs, noise level, category), an earlier set in
            ``out_dir`` without ``overwrite``, SUMO not found.
        MissingExtraError: the ``sim`` extra (sumolib, traci, eclipse-sumo) is not installed.
    """
    return simulate_urban_set(
        request.out_dir,
        request.settings,
        overwrite=request.overwrite,
        keep_sumo=request.keep_sumo_outputs,
        progress=progress,
    )
