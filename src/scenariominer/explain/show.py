"""Bird's-eye-view picture of a braking event, so a user can check an explanation by looking.

Drawn as in the braking paper's figures: the ego in red, the guest in orange, other objects in
grey; boxes at the key time (the closest approach inside the event), the past trajectory as a
solid line, the future as a dashed line; lanes and crosswalks drawn lightly underneath when the
log has an Argoverse 2 vector map. The title names the category and wraps the explanation.

matplotlib is imported (with the non-interactive Agg backend) only inside :func:`render_event`,
never at import time.
"""

from __future__ import annotations

import textwrap
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from scenariominer import errors as _errors
from scenariominer.config.explain import ExplainConfig
from scenariominer.data.log import Log, LogFormatError
from scenariominer.explain.records import EventRecord, records_from_table
from scenariominer.explain.search import load_events
from scenariominer.geometry import OrientedBoxes
from scenariominer.store import ScenarioStore

if TYPE_CHECKING:
    from scenariominer.data.adapters.av2.map import Av2Map

__all__ = ["EGO_COLOR", "GUEST_COLOR", "OTHER_COLOR", "UnknownEventError", "render_event", "show_event"]

#: Colours of the actors (the paper's convention).
EGO_COLOR = "#d62728"
GUEST_COLOR = "#ff7f0e"
OTHER_COLOR = "#8c8c8c"

_VIEW_MARGIN_M = 15.0
_MIN_VIEW_M = 40.0


class UnknownEventError(_errors.ExplainError, LookupError):
    """The requested event is not in the store; the message lists the log's events."""


def _box_corners(log: Log, row: int, col: int) -> np.ndarray:
    box = OrientedBoxes(
        log.x_m[row, col],
        log.y_m[row, col],
        log.yaw_rad[row, col],
        log.length_m[row, col],
        log.width_m[row, col],
    )
    return np.asarray(box.corners())


def _draw_map(ax: Any, av2_map: Av2Map, bounds: tuple[float, float, float, float]) -> None:
    import shapely

    x0, x1, y0, y1 = bounds
    view = shapely.box(x0, y0, x1, y1)
    for poly in av2_map.lane_polygons:
        if poly.is_empty or not poly.intersects(view):
            continue
        for part in getattr(poly, "geoms", [poly]):
            if part.geom_type != "Polygon":
                continue
            xs, ys = part.exterior.xy
            ax.fill(xs, ys, facecolor="#f2f2f2", edgecolor="#c8c8c8", linewidth=0.6, zorder=0)
    for poly in av2_map.crosswalk_polygons:
        if poly.is_empty or not poly.intersects(view):
            continue
        for part in getattr(poly, "geoms", [poly]):
            if part.geom_type != "Polygon":
                continue
            xs, ys = part.exterior.xy
            ax.fill(xs, ys, facecolor="none", edgecolor="#b0b0d0", hatch="////", linewidth=0.5, zorder=0.5)


def render_event(
    log: Log,
    event: EventRecord,
    out_path: str | Path,
    *,
    av2_map: Av2Map | None = None,
    cfg: ExplainConfig | None = None,
    dpi: int = 110,
) -> Path:
    """Draw one event as a bird's-eye-view PNG.

    Args:
        log: the event's log.
        event: the stored event.
        out_path: where to write the PNG (parent folders are created).
        av2_map: the log's vector map, drawn underneath when given.
        cfg: how much past and future to draw; defaults to :class:`ExplainConfig`.
        dpi: resolution.

    Returns:
        The written path.

    Raises:
        KeyError: the event's guest is not in the log.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.patches import Polygon

    cfg = cfg or ExplainConfig()
    e, g = log.ego_index, log.track_index(event.guest_id)
    ts = log.timestamps_ns
    key = int(np.clip(np.searchsorted(ts, event.closest_ns), 0, ts.size - 1))
    lo = int(np.searchsorted(ts, ts[key] - round(cfg.show_past_s * 1e9), side="left"))
    hi = int(np.searchsorted(ts, ts[key] + round(cfg.show_future_s * 1e9), side="right"))

    fig, ax = plt.subplots(figsize=(7.5, 7.5))
    try:
        focus_x = np.concatenate([log.x_m[e, lo:hi], log.x_m[g, lo:hi]])
        focus_y = np.concatenate([log.y_m[e, lo:hi], log.y_m[g, lo:hi]])
        cx = 0.5 * (np.nanmin(focus_x) + np.nanmax(focus_x))
        cy = 0.5 * (np.nanmin(focus_y) + np.nanmax(focus_y))
        half = 0.5 * max(np.nanmax(focus_x) - np.nanmin(focus_x), np.nanmax(focus_y) - np.nanmin(focus_y))
        half = max(half + _VIEW_MARGIN_M, _MIN_VIEW_M / 2)
        bounds = (cx - half, cx + half, cy - half, cy + half)
        if av2_map is not None:
            _draw_map(ax, av2_map, bounds)

        others = [r for r in range(log.n_tracks) if r not in (e, g) and log.valid[r, key]]
        for row, color, z, label in [(r, OTHER_COLOR, 2, None) for r in others] + [
            (g, GUEST_COLOR, 4, f"guest {event.guest_category}"),
            (e, EGO_COLOR, 5, "ego"),
        ]:
            past = slice(lo, key + 1)
            future = slice(key, hi)
            lw = 1.0 if color == OTHER_COLOR else 2.0
            ax.plot(log.x_m[row, past], log.y_m[row, past], "-", color=color, lw=lw, zorder=z, alpha=0.9)
            ax.plot(log.x_m[row, future], log.y_m[row, future], "--", color=color, lw=lw, zorder=z, alpha=0.9)
            if log.valid[row, key]:
                corners = _box_corners(log, row, key)
                ax.add_patch(
                    Polygon(
                        corners,
                        closed=True,
                        facecolor=color,
                        edgecolor="black",
                        lw=0.6,
                        alpha=0.85,
                        zorder=z + 0.5,
                        label=label,
                    )
                )
                if row == g and max(log.length_m[row, key], log.width_m[row, key]) < 2.0:
                    # Small guests (pedestrians, cyclists) get a ring so they stand out.
                    ax.plot(
                        log.x_m[row, key],
                        log.y_m[row, key],
                        "o",
                        ms=14,
                        mfc="none",
                        mec=color,
                        mew=1.5,
                        zorder=z + 0.4,
                    )
                # A tick from the centre to the front edge shows which way the box faces.
                front = corners[[0, 3]].mean(axis=0)
                ax.plot(
                    [log.x_m[row, key], front[0]],
                    [log.y_m[row, key], front[1]],
                    "-",
                    color="black",
                    lw=0.8,
                    zorder=z + 0.6,
                )
        ax.set_xlim(bounds[0], bounds[1])
        ax.set_ylim(bounds[2], bounds[3])
        ax.set_aspect("equal")
        ax.set_xlabel("x (m, city frame)")
        ax.set_ylabel("y (m, city frame)")
        ax.grid(True, lw=0.3, alpha=0.5)
        ax.legend(loc="upper right", fontsize=8, framealpha=0.8)
        t_key = (ts[key] - ts[0]) * 1e-9
        head = f"category: {event.category}" + (
            f" (baseline: {event.baseline_category})" if event.baseline_category != event.category else ""
        )
        explanation = textwrap.fill(event.explanation or "(no explanation)", width=95)
        ax.set_title(f"{head}\n{explanation}", fontsize=9, loc="left")
        ttc = "none" if not np.isfinite(event.min_ttc_s) else f"{event.min_ttc_s:.1f} s"
        fig.text(
            0.01,
            0.008,
            f"log {event.log_id}   guest {event.guest_id}\n"
            f"key time {t_key:.1f} s   min TTC {ttc}   peak decel {event.peak_decel_mps2:.1f} m/s²   "
            f"solid: past {cfg.show_past_s:g} s, dashed: next {cfg.show_future_s:g} s",
            fontsize=7,
            color="#444444",
        )
        out = Path(out_path)
        out.parent.mkdir(parents=True, exist_ok=True)
        fig.tight_layout(rect=(0, 0.035, 1, 1))
        fig.savefig(out, dpi=dpi)
    finally:
        plt.close(fig)
    return out


def _find_event(records: list[EventRecord], log_id: str, event_id: str | None) -> EventRecord:
    if not records:
        raise UnknownEventError(f"log {log_id} has no braking events")
    if event_id is None:
        return max(records, key=lambda r: (r.peak_decel_mps2, -r.start_ns))
    for r in records:
        if event_id in (r.event_id, f"{r.guest_id}:{r.start_ns}", r.guest_id):
            return r
    listed = ", ".join(r.event_id for r in records[:10])
    raise UnknownEventError(f"event {event_id!r} is not in log {log_id}; its events: {listed}")


def show_event(
    store: ScenarioStore,
    log_id: str,
    out_path: str | Path,
    event_id: str | None = None,
    cfg: ExplainConfig | None = None,
) -> Path:
    """Render an event of a stored log as a PNG (see :func:`render_event`).

    Args:
        store: the store.
        log_id: the log.
        out_path: PNG to write.
        event_id: the event's id (``<log>:<guest>:<start_ns>``, ``<guest>:<start_ns>`` or the guest
            id); ``None`` picks the event with the hardest braking.
        cfg: drawing settings.

    Raises:
        UnknownLogError: the log is not in the store.
        NoEventsError: no log has been analysed.
        UnknownEventError: the event is not in the log.
    """
    records = records_from_table(load_events(store, [log_id]))
    event = _find_event(records, log_id, event_id)
    log = store.load_log(log_id)
    av2_map = None
    if log.map_dir is not None:
        from scenariominer.data.adapters.av2.map import read_av2_map

        try:
            av2_map = read_av2_map(log.map_dir)
        except LogFormatError:
            av2_map = None  # the picture is still useful without the map
    return render_event(log, event, out_path, av2_map=av2_map, cfg=cfg)
