"""Command ``simulate highway``: SUMO highway traffic written as highD-format recordings."""

from __future__ import annotations

import json
from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer

from scenariominer.cli._common import JsonOpt, console, err_console
from scenariominer.cli.progress import progress_bar
from scenariominer.cli.text import safe

if TYPE_CHECKING:
    from scenariominer.sim.highway import HighwaySetResult


def _report_json(report: HighwaySetResult) -> str:
    return json.dumps(
        {
            "out_dir": str(report.out_dir),
            "sumo_version": report.sumo_version,
            "seconds": report.seconds,
            "recordings": [
                {
                    **r.scenario.to_json(),
                    "ok": r.ok,
                    "error": r.error,
                    "vehicles": r.n_vehicles,
                    "trucks": r.n_trucks,
                    "recording_lanes": r.lanes,
                    "lane_changes_left": r.lane_changes_left,
                    "lane_changes_right": r.lane_changes_right,
                    "manoeuvres_by_lanes_crossed": {str(k): v for k, v in r.manoeuvres_by_lanes.items()},
                    "sim_s": r.sim_s,
                    "convert_s": r.convert_s,
                }
                for r in report.recordings
            ],
        }
    )


def render_report(report: HighwaySetResult) -> None:
    """Print one row per recording (failures on stderr) and the totals.

    Columns: road (main-road lanes, on-ramp, lane drop), speed limit, mean demand, truck share,
    vehicles written, lane boundaries crossed left/right, multi-lane manoeuvres, SUMO seconds.
    """
    from rich.table import Table

    for r in report.recordings:
        if not r.ok:
            err_console().print(
                f"[red]failed[/red] recording {r.recording_id:02d}: {safe(r.error)}", soft_wrap=True
            )
    table = Table(title=f"simulated highway recordings in {safe(report.out_dir)}", title_justify="left")
    for name in ("rec", "road", "km/h", "veh/h", "trucks", "vehicles", "left", "right", "multi", "sim s"):
        table.add_column(name, justify="left" if name == "road" else "right", no_wrap=name == "road")
    for r in report.recordings:
        if not r.ok:
            continue
        s = r.scenario
        road = f"{s.lanes}" + (" ramp" if s.on_ramp else "") + (" drop" if s.lane_drop else "")
        multi = sum(n for k, n in r.manoeuvres_by_lanes.items() if k >= 2)
        table.add_row(
            f"{r.recording_id:02d}",
            road,
            "none" if s.speed_limit_kmh is None else f"{s.speed_limit_kmh:.0f}",
            f"{sum(s.demand_vph) / len(s.demand_vph):.0f}",
            f"{100 * s.truck_share:.0f}%",
            str(r.n_vehicles),
            str(r.lane_changes_left),
            str(r.lane_changes_right),
            str(multi),
            f"{r.sim_s:.0f}",
        )
    out = console()
    out.print(table)
    written = len(report.recordings) - report.n_failed
    out.print(
        f"{written} recording(s) written, {report.n_failed} failed; {report.simulated_s / 60:.1f} simulated "
        f"minutes in {report.seconds:.1f} s ({safe(report.sumo_version)}). "
        f"Ingest with: scenariominer ingest {safe(report.out_dir)}",
        highlight=False,
        soft_wrap=True,
    )


def highway(
    out: Annotated[Path, typer.Option("--out", "-o", help="Output folder for the recordings.")],
    minutes: Annotated[float, typer.Option(help="Recorded minutes per recording.")] = 10.0,
    recordings: Annotated[int, typer.Option(help="Number of recordings (01..K).")] = 6,
    seed: Annotated[int, typer.Option(help="Seed of the whole set (same seed, same files).")] = 1,
    variety: Annotated[
        str,
        typer.Option(
            help="mixed: vary lanes, demand, limit, trucks, on-ramp and lane drop per recording; "
            "fixed: the same road and demand for all. Options given below pin that parameter."
        ),
    ] = "mixed",
    lanes: Annotated[int | None, typer.Option(help="Main-road lanes, 2-4.")] = None,
    demand: Annotated[
        float | None, typer.Option("--demand", help="Mean main-road demand, vehicles per hour (all lanes).")
    ] = None,
    speed_limit: Annotated[
        float | None, typer.Option("--speed-limit", help="Speed limit in km/h (0: unlimited).")
    ] = None,
    truck_share: Annotated[
        float | None, typer.Option("--truck-share", help="Fraction of trucks, 0-1.")
    ] = None,
    on_ramp: Annotated[
        bool | None, typer.Option("--on-ramp/--no-on-ramp", help="An on-ramp joins in the section.")
    ] = None,
    lane_drop: Annotated[
        bool | None,
        typer.Option("--lane-drop/--no-lane-drop", help="The rightmost lane ends in the section."),
    ] = None,
    section: Annotated[float, typer.Option("--section-m", help="Recorded road length, metres.")] = 1000.0,
    frame_rate: Annotated[
        float, typer.Option("--frame-rate", help="Frames per second: 10, 20 or 25.")
    ] = 10.0,
    overwrite: Annotated[
        bool, typer.Option("--overwrite", help="Replace existing recordings 01..K.")
    ] = False,
    keep_sumo: Annotated[
        bool, typer.Option("--keep-sumo-output", help="Keep SUMO's raw outputs in OUT/sumo/NN/.")
    ] = False,
    json_out: JsonOpt = False,
) -> None:
    """Simulate highway traffic with SUMO and write highD-format recordings with ground truth.

    Writes OUT/NN_tracks.csv, NN_tracksMeta.csv, NN_recordingMeta.csv (read by `scenariominer
    ingest`) and the simulator's ground truth NN_laneChanges.csv, NN_truthFrames.csv (see
    docs/simulate.md). A recording that fails is reported and the others are written; the exit
    status is 1 when any failed.
    """
    from scenariominer import api
    from scenariominer.sim.highway_scenario import HighwaySettings

    settings = HighwaySettings(
        recordings=recordings,
        minutes=minutes,
        seed=seed,
        variety=variety,
        lanes=lanes,
        demand_vph=demand,
        speed_limit_kmh=speed_limit,
        truck_share=truck_share,
        on_ramp=on_ramp,
        lane_drop=lane_drop,
        section_m=section,
        frame_rate_hz=frame_rate,
    )
    request = api.HighwaySimRequest(
        out_dir=out, settings=settings, overwrite=overwrite, keep_sumo_outputs=keep_sumo
    )
    with progress_bar(not json_out) as bar:
        report = api.simulate_highway(request, progress=bar)
    if json_out:
        console().print_json(_report_json(report))
    else:
        render_report(report)
    if report.n_failed:
        raise typer.Exit(1)


def register(app: typer.Typer) -> None:
    """Add the ``highway`` command to the ``simulate`` group."""
    app.command("highway")(highway)
