"""Simulated highway recordings: plan a varied set, run SUMO per recording, write highD files.

:func:`simulate_highway_set` is the whole use case below the API: it plans one scenario per
recording (:mod:`~.highway_scenario`), builds each network (:mod:`~.highway_net`), runs SUMO
headless (:mod:`~.highway_run`) and converts its outputs into ``NN_tracks.csv``,
``NN_tracksMeta.csv``, ``NN_recordingMeta.csv`` with the ground truth beside them
(:mod:`~.highway_convert`, :mod:`~.highway_truth`). A recording that fails is reported and the
others go on; existing recordings are never overwritten unless asked.

Output folder::

    DIR/NN_tracks.csv, NN_tracksMeta.csv, NN_recordingMeta.csv   highD recording NN
    DIR/NN_laneChanges.csv, NN_truthFrames.csv                    SUMO's ground truth
    DIR/highway_sim.json                                          settings and scenario per recording
    DIR/sumo/NN/                                                  SUMO network, routes, config, log
"""

from __future__ import annotations

import json
import shutil
import time
from collections import Counter
from dataclasses import dataclass, field
from pathlib import Path

from scenariominer.progress import NullProgress, Progress
from scenariominer.sim.highway_convert import convert_run
from scenariominer.sim.highway_net import build_network
from scenariominer.sim.highway_run import FCD_FILE, LANE_CHANGE_FILE, SumoBinaries, find_sumo, run_sumo
from scenariominer.sim.highway_scenario import (
    HighwayScenario,
    HighwaySettings,
    HighwaySimError,
    plan_scenarios,
)

__all__ = ["MANIFEST_FILE", "HighwaySetResult", "RecordingResult", "simulate_highway_set"]

#: Settings and scenarios of a simulated set, in the output folder.
MANIFEST_FILE = "highway_sim.json"


@dataclass(frozen=True)
class RecordingResult:
    """Outcome of one recording.

    Attributes:
        recording_id: ``NN``.
        scenario: what was simulated.
        ok: written.
        error: why not (empty when ``ok``).
        n_vehicles, n_trucks: vehicles written.
        n_rows: (vehicle, frame) rows.
        lanes: lanes of the recording (with an acceleration lane when there is an on-ramp).
        lane_changes_left, lane_changes_right: lane boundaries crossed.
        manoeuvres_by_lanes: lanes crossed per manoeuvre -> number of manoeuvres.
        sim_s: wall time of SUMO, seconds.
        convert_s: wall time of the conversion, seconds.
    """

    recording_id: int
    scenario: HighwayScenario
    ok: bool
    error: str = ""
    n_vehicles: int = 0
    n_trucks: int = 0
    n_rows: int = 0
    lanes: int = 0
    lane_changes_left: int = 0
    lane_changes_right: int = 0
    manoeuvres_by_lanes: dict[int, int] = field(default_factory=dict)
    sim_s: float = 0.0
    convert_s: float = 0.0


@dataclass(frozen=True)
class HighwaySetResult:
    """Outcome of a whole set.

    Attributes:
        out_dir: the output folder.
        settings: what was asked.
        recordings: one result per recording, in id order.
        sumo_version: ``sumo --version``'s first line.
        seconds: wall time of the whole set.
    """

    out_dir: Path
    settings: HighwaySettings
    recordings: tuple[RecordingResult, ...]
    sumo_version: str
    seconds: float

    @property
    def n_failed(self) -> int:
        """Recordings that failed."""
        return sum(not r.ok for r in self.recordings)

    @property
    def simulated_s(self) -> float:
        """Recorded (simulated) seconds over the written recordings."""
        return sum(r.scenario.record_s for r in self.recordings if r.ok)


def _existing(out_dir: Path, ids: range) -> list[str]:
    names = []
    for rec in ids:
        for suffix in ("tracks", "tracksMeta", "recordingMeta", "laneChanges", "truthFrames"):
            path = out_dir / f"{rec:02d}_{suffix}.csv"
            if path.exists():
                names.append(path.name)
    return names


def _sumo_version(sumo: str) -> str:
    import subprocess

    try:
        done = subprocess.run([sumo, "--version"], capture_output=True, text=True, check=False)
    except OSError:
        return "unknown"
    lines = done.stdout.strip().splitlines()
    return lines[0].strip() if lines else "unknown"


def _one(
    scenario: HighwayScenario, out_dir: Path, binaries: SumoBinaries, keep_outputs: bool, progress: Progress
) -> RecordingResult:
    """Simulate and write one recording; a :class:`HighwaySimError` becomes a failed result.

    The files are written into ``sumo/NN/staged`` first and moved into ``out_dir`` only when all
    of them are complete, so a failure leaves no partial recording (and an older one in place).
    """
    rec = scenario.recording_id
    work = out_dir / "sumo" / f"{rec:02d}"
    if work.exists():
        shutil.rmtree(work)
    total = int(round(scenario.end_s)) + 1
    progress.start(f"recording {rec:02d}", total)
    done = 0

    def on_step(sim_time_s: float) -> None:
        nonlocal done
        now = min(int(sim_time_s), total - 1)
        if now > done:
            progress.advance(now - done, f"{sim_time_s:.0f} s simulated")
            done = now

    try:
        t0 = time.perf_counter()
        net = build_network(scenario, work, binaries.netconvert)
        run_sumo(scenario, net, binaries, work, on_step=on_step)
        t1 = time.perf_counter()
        progress.advance(max(total - 1 - done, 0), "writing the recording")
        staged = work / "staged"
        converted = convert_run(scenario, net, work / FCD_FILE, work / LANE_CHANGE_FILE, staged)
        for path in sorted(staged.iterdir()):  # all five files, each replaced atomically
            path.replace(out_dir / path.name)
        staged.rmdir()
        t2 = time.perf_counter()
        progress.advance(1, f"{converted.n_vehicles} vehicles")
    except (HighwaySimError, ValueError, OSError) as exc:
        return RecordingResult(rec, scenario, ok=False, error=str(exc))
    finally:
        progress.finish()
        if not keep_outputs:
            for name in (FCD_FILE, LANE_CHANGE_FILE):
                (work / name).unlink(missing_ok=True)
    by_lanes = Counter({c.manoeuvre: c.lanes_crossed for c in converted.lane_changes}.values())
    return RecordingResult(
        recording_id=rec,
        scenario=scenario,
        ok=True,
        n_vehicles=converted.n_vehicles,
        n_trucks=converted.n_trucks,
        n_rows=converted.n_rows,
        lanes=converted.lanes,
        lane_changes_left=sum(c.direction == "left" for c in converted.lane_changes),
        lane_changes_right=sum(c.direction == "right" for c in converted.lane_changes),
        manoeuvres_by_lanes=dict(sorted(by_lanes.items())),
        sim_s=round(t1 - t0, 2),
        convert_s=round(t2 - t1, 2),
    )


def _write_manifest(
    root: Path, settings: HighwaySettings, version: str, results: tuple[RecordingResult, ...]
) -> None:
    """Write ``highway_sim.json``; entries of recordings this run did not touch are kept."""
    path = root / MANIFEST_FILE
    entries: dict[int, object] = {}
    if path.is_file():
        try:
            old = json.loads(path.read_text(encoding="utf-8"))
            entries = {int(e["recording_id"]): e for e in old.get("recordings", [])}
        except (ValueError, KeyError, TypeError, AttributeError):
            entries = {}  # an unreadable manifest is replaced
    for r in results:
        before = entries.get(r.recording_id)
        if not r.ok and isinstance(before, dict) and before.get("written"):
            before["last_attempt_error"] = r.error  # the older recording is still in place
            continue
        entries[r.recording_id] = {
            **r.scenario.to_json(),
            "seed": settings.seed,
            "variety": settings.variety,
            "written": r.ok,
            "error": r.error,
            "vehicles": r.n_vehicles,
        }
    manifest = {
        "generator": "scenariominer simulate highway",
        "sumo_version": version,
        "settings": {k: getattr(settings, k) for k in settings.__dataclass_fields__},
        "recordings": [entries[k] for k in sorted(entries)],
    }
    path.write_text(json.dumps(manifest, indent=2) + "\n", encoding="utf-8")


def simulate_highway_set(
    out_dir: str | Path,
    settings: HighwaySettings,
    *,
    overwrite: bool = False,
    keep_sumo_outputs: bool = False,
    progress: Progress | None = None,
) -> HighwaySetResult:
    """Simulate recordings ``01..K`` into ``out_dir`` (see the module docstring for the layout).

    Args:
        out_dir: output folder (created).
        settings: what to simulate.
        overwrite: replace recordings ``01..K`` that already exist in ``out_dir``.
        keep_sumo_outputs: keep SUMO's raw floating-car data and lane-change log in ``sumo/NN/``.
        progress: one bar per recording (simulated seconds).

    Returns:
        The per-recording outcome; a failed recording carries its error and the others are written.

    Raises:
        HighwaySimError: recordings exist and ``overwrite`` is off, or SUMO cannot be found.
        MissingExtraError: sumolib is not installed.
    """
    progress = progress or NullProgress()
    root = Path(out_dir)
    if root.exists() and not root.is_dir():
        raise HighwaySimError(f"output path {root} exists and is not a folder")
    clash = _existing(root, range(1, settings.recordings + 1)) if root.is_dir() else []
    if clash and not overwrite:
        raise HighwaySimError(
            f"{root} already holds recording files ({', '.join(clash[:3])}"
            f"{', ...' if len(clash) > 3 else ''}); choose another folder or pass --overwrite"
        )
    binaries = find_sumo()
    root.mkdir(parents=True, exist_ok=True)
    scenarios = plan_scenarios(settings)
    version = _sumo_version(binaries.sumo)
    t0 = time.perf_counter()
    results = tuple(_one(s, root, binaries, keep_sumo_outputs, progress) for s in scenarios)
    _write_manifest(root, settings, version, results)
    return HighwaySetResult(
        out_dir=root,
        settings=settings,
        recordings=results,
        sumo_version=version,
        seconds=round(time.perf_counter() - t0, 2),
    )
