"""Simulated urban braking scenarios: SUMO runs exported as labelled Argoverse 2 logs.

:func:`simulate_urban_set` is the whole use case below the API. For log ``i`` of a set it draws a
scenario of family ``FAMILIES[i % 7]`` (:mod:`~.urban_scenario`), builds its junction network
(:mod:`~.urban_net`), runs SUMO under TraCI with and without the guest (:mod:`~.urban_run`),
labels the braking from the simulator's state (:mod:`~.urban_label`) and writes the log with its
vector map (:mod:`~.urban_export`). A scenario that gives no clean label is drawn again (up to
:data:`MAX_ATTEMPTS` times); the reasons are counted in the result. A log whose simulation fails
is reported and the others go on.

Output folder::

    DIR/<log_id>/annotations_with_ego.feather, city_SE3_egovehicle.feather, map/log_map_archive_*.json
    DIR/labels.csv       log_id, guest_id, scenario_category, start_ns, end_ns (the synthetic
                         generator's columns, read by ``scenariominer eval braking``) + noise_level,
                         onset_ns, style, attempt, id_switches
    DIR/sumo/NNN/        SUMO network and routes of log NNN (with ``keep_sumo``)
"""

from __future__ import annotations

import csv
import shutil
import time
from collections import Counter
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

from scenariominer.progress import NullProgress, Progress
from scenariominer.sim.urban_export import export_log
from scenariominer.sim.urban_label import label_run
from scenariominer.sim.urban_net import UrbanSimError, build_network
from scenariominer.sim.urban_run import run_scenario
from scenariominer.sim.urban_scenario import FAMILIES, NOISE_LEVELS, UrbanScenario, draw_scenario, noise_for
from scenariominer.synth.vocab import LABEL_COLUMNS, ScenarioCategory

__all__ = [
    "EXTRA_LABEL_COLUMNS",
    "LABELS_FILE",
    "MAX_ATTEMPTS",
    "UrbanLogResult",
    "UrbanSetResult",
    "UrbanSettings",
    "find_sumo_programs",
    "simulate_urban_set",
    "write_urban_labels",
]

#: Draws per log before it is given up.
MAX_ATTEMPTS = 8
#: The labels file in the output folder.
LABELS_FILE = "labels.csv"
#: Columns of ``labels.csv`` after :data:`~scenariominer.synth.vocab.LABEL_COLUMNS`.
EXTRA_LABEL_COLUMNS: tuple[str, ...] = ("noise_level", "onset_ns", "style", "attempt", "id_switches")


@dataclass(frozen=True)
class UrbanSettings:
    """What to simulate.

    Attributes:
        n: number of logs.
        seed: seed of the whole set (same seed, same files).
        noise: a noise level (``none``, ``low``, ``medium``, ``high``) or ``mixed``.
        categories: scenario categories to cycle through (all of :data:`FAMILIES` when empty).
    """

    n: int = 40
    seed: int = 0
    noise: str = "mixed"
    categories: tuple[str, ...] = ()

    def families(self) -> tuple[ScenarioCategory, ...]:
        """The families to cycle through; raises :class:`UrbanSimError` on a bad setting."""
        if not 1 <= self.n <= 10_000:
            raise UrbanSimError(f"n must be between 1 and 10000, got {self.n}")
        if self.noise not in NOISE_LEVELS:
            raise UrbanSimError(f"unknown noise level {self.noise!r}; choose one of {list(NOISE_LEVELS)}")
        if not self.categories:
            return FAMILIES
        known = {f.value: f for f in FAMILIES}
        bad = [c for c in self.categories if c not in known]
        if bad:
            raise UrbanSimError(f"unknown urban scenario category {bad}; choose from {sorted(known)}")
        return tuple(known[c] for c in self.categories)


@dataclass(frozen=True)
class UrbanLogResult:
    """Outcome of one log.

    Attributes:
        index: position in the set.
        category: the scenario category asked for.
        ok: written and labelled.
        error: why not (empty when ``ok``).
        log_id, guest_id: the written log and its labelled guest.
        noise: noise level.
        style: the ego's driving style.
        attempts: draws it took.
        rejected: reasons of the rejected draws.
        n_tracks: tracks written (the ego included).
        sim_s: wall time, seconds.
    """

    index: int
    category: ScenarioCategory
    ok: bool
    error: str = ""
    log_id: str = ""
    guest_id: str = ""
    noise: str = ""
    style: str = ""
    attempts: int = 0
    rejected: tuple[str, ...] = ()
    n_tracks: int = 0
    sim_s: float = 0.0


@dataclass(frozen=True)
class UrbanSetResult:
    """Outcome of a whole set.

    Attributes:
        out_dir: the output folder.
        settings: what was asked.
        logs: one result per log, in index order.
        labels_csv: the labels file.
        seconds: wall time.
        rejections: reason -> number of draws dropped for it (over all logs).
    """

    out_dir: Path
    settings: UrbanSettings
    logs: tuple[UrbanLogResult, ...]
    labels_csv: Path
    seconds: float
    rejections: dict[str, int] = field(default_factory=dict)

    @property
    def n_failed(self) -> int:
        """Logs that could not be made."""
        return sum(not r.ok for r in self.logs)


def find_sumo_programs() -> tuple[str, str]:
    """Paths of ``sumo`` and ``netconvert`` (:func:`scenariominer.sim.highway_run.find_sumo`).

    Raises:
        MissingExtraError: sumolib is not installed.
        UrbanSimError: a program cannot be found.
    """
    from scenariominer.sim.highway_run import find_sumo

    found = find_sumo(UrbanSimError)
    return found.sumo, found.netconvert


def _one(
    index: int,
    family: ScenarioCategory,
    settings: UrbanSettings,
    out_dir: Path,
    programs: tuple[str, str],
    keep_sumo: bool,
) -> tuple[UrbanLogResult, tuple[str, ...] | None]:
    sumo, netconvert = programs
    t0 = time.perf_counter()
    noise = noise_for(settings.noise, index)
    work = out_dir / "sumo" / f"{index:03d}"
    rejected: list[str] = []
    scenario: UrbanScenario | None = None
    try:
        for attempt in range(MAX_ATTEMPTS):
            scenario = draw_scenario(family, index, attempt, settings.seed, noise)
            if work.exists():
                shutil.rmtree(work)
            net = build_network(scenario.net, work, netconvert)
            full = run_scenario(scenario, net, sumo, with_guest=True)
            without = run_scenario(scenario, net, sumo, with_guest=False)
            label = label_run(family, full, without)
            if not label.ok:
                rejected.append(label.reason)
                continue
            try:
                written = export_log(scenario, full, label, net, out_dir, index)
            except UrbanSimError as exc:
                rejected.append(str(exc).split(": ", 1)[-1])
                continue
            row = (
                written.log_id,
                written.guest_id,
                family.value,
                str(written.start_ns),
                str(written.end_ns),
                noise.value,
                str(written.onset_ns),
                scenario.style.value,
                str(attempt),
                str(written.id_switches),
            )
            return (
                UrbanLogResult(
                    index,
                    family,
                    True,
                    log_id=written.log_id,
                    guest_id=written.guest_id,
                    noise=noise.value,
                    style=scenario.style.value,
                    attempts=attempt + 1,
                    rejected=tuple(rejected),
                    n_tracks=written.n_tracks,
                    sim_s=round(time.perf_counter() - t0, 2),
                ),  # fmt: skip
                row,
            )
        error = f"no clean label in {MAX_ATTEMPTS} draws (last: {rejected[-1] if rejected else '?'})"
    except (UrbanSimError, OSError, ValueError) as exc:
        error = str(exc)
    finally:
        if not keep_sumo and work.exists():
            shutil.rmtree(work)
    return (
        UrbanLogResult(
            index,
            family,
            False,
            error=error,
            noise=noise.value,
            attempts=len(rejected),
            rejected=tuple(rejected),
            sim_s=round(time.perf_counter() - t0, 2),
        ),  # fmt: skip
        None,
    )


def write_urban_labels(rows: Sequence[Sequence[str]], path: Path) -> Path:
    """Write ``labels.csv``: :data:`LABEL_COLUMNS` then :data:`EXTRA_LABEL_COLUMNS`."""
    with path.open("w", newline="", encoding="utf-8") as fh:
        writer = csv.writer(fh)
        writer.writerow((*LABEL_COLUMNS, *EXTRA_LABEL_COLUMNS))
        writer.writerows(rows)
    return path


def _remove_old_set(out_dir: Path, overwrite: bool) -> None:
    """Refuse to write over an earlier set, or (``overwrite``) remove the logs its labels list."""
    labels = out_dir / LABELS_FILE
    if not labels.is_file():
        return
    if not overwrite:
        raise UrbanSimError(
            f"{out_dir} already holds a set ({LABELS_FILE}); choose another folder or use --overwrite "
            f"(which removes the logs that {LABELS_FILE} lists)"
        )
    with labels.open(newline="", encoding="utf-8") as fh:
        old_ids = [row.get("log_id", "") for row in csv.DictReader(fh)]
    for log_id in old_ids:
        folder = out_dir / log_id
        if log_id and "/" not in log_id and log_id not in (".", "..") and folder.is_dir():
            shutil.rmtree(folder)
    labels.unlink()


def simulate_urban_set(
    out_dir: Path,
    settings: UrbanSettings,
    *,
    overwrite: bool = False,
    keep_sumo: bool = False,
    progress: Progress | None = None,
) -> UrbanSetResult:
    """Simulate ``settings.n`` labelled urban braking scenarios into ``out_dir``.

    Args:
        out_dir: output folder (created if needed).
        settings: number of logs, seed, noise, categories.
        overwrite: replace an earlier set in ``out_dir`` (its logs listed in ``labels.csv`` are
            removed first); without it a folder holding ``labels.csv`` is refused.
        keep_sumo: keep each log's SUMO network, routes and error log in ``sumo/NNN/``.
        progress: one step per log.

    Raises:
        UrbanSimError: a bad setting, an earlier set in ``out_dir`` without ``overwrite``, or SUMO
            cannot be found.
        MissingExtraError: the ``sim`` extra (sumolib, traci, eclipse-sumo) is not installed.
    """
    from scenariominer._optional import require

    families = settings.families()
    programs = find_sumo_programs()
    require("traci", extra="sim", purpose="simulating urban scenarios with SUMO")
    progress = progress or NullProgress()
    out_dir = Path(out_dir)
    _remove_old_set(out_dir, overwrite)
    out_dir.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    results: list[UrbanLogResult] = []
    rows: list[tuple[str, ...]] = []
    progress.start("urban scenarios", settings.n)
    try:
        for i in range(settings.n):
            result, row = _one(i, families[i % len(families)], settings, out_dir, programs, keep_sumo)
            results.append(result)
            if row is not None:
                rows.append(row)
            progress.advance(1, f"{result.category.value}: {'ok' if result.ok else 'failed'}")
    finally:
        progress.finish()
    labels_csv = write_urban_labels(rows, out_dir / LABELS_FILE)
    if not keep_sumo and (out_dir / "sumo").is_dir() and not any((out_dir / "sumo").iterdir()):
        (out_dir / "sumo").rmdir()
    reasons = Counter(r for res in results for r in res.rejected)
    return UrbanSetResult(
        out_dir, settings, tuple(results), labels_csv, round(time.perf_counter() - t0, 2), dict(reasons)
    )
