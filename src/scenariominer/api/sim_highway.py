"""Use case ``simulate highway``: highway traffic from SUMO, written as highD-format recordings.

The recordings read like real highD files (``scenariominer ingest DIR``); the simulator's ground
truth (lane changes, per-frame lanes, leaders and followers) lies beside them and is read with
:func:`scenariominer.sim.highway_truth.read_highway_truth`. Nothing here prints.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from scenariominer.progress import Progress
from scenariominer.sim.highway import HighwaySetResult, simulate_highway_set
from scenariominer.sim.highway_scenario import HighwaySettings

__all__ = ["HighwaySimReport", "HighwaySimRequest", "simulate_highway"]

#: The result of :func:`simulate_highway` (one entry per recording, failures included).
HighwaySimReport = HighwaySetResult


@dataclass(frozen=True)
class HighwaySimRequest:
    """Where to write and what to simulate.

    Attributes:
        out_dir: output folder (recordings ``01..K`` and their ground truth).
        settings: recordings, minutes, seed, variety preset and pinned parameters.
        overwrite: replace recordings that already exist in ``out_dir``.
        keep_sumo_outputs: keep SUMO's raw floating-car data and lane-change log in ``sumo/NN/``.
    """

    out_dir: Path
    settings: HighwaySettings = field(default_factory=HighwaySettings)
    overwrite: bool = False
    keep_sumo_outputs: bool = False


def simulate_highway(request: HighwaySimRequest, progress: Progress | None = None) -> HighwaySimReport:
    """Simulate the recordings of ``request`` with SUMO and write them (one progress bar each).

    A recording whose simulation or conversion fails is reported in the result and the others
    are written.

    Raises:
        HighwaySimError: existing recordings without ``overwrite``, SUMO not found, bad settings.
        MissingExtraError: the ``sim`` extra (sumolib, eclipse-sumo) is not installed.
    """
    return simulate_highway_set(
        request.out_dir,
        request.settings,
        overwrite=request.overwrite,
        keep_sumo_outputs=request.keep_sumo_outputs,
        progress=progress,
    )
