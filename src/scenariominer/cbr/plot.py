"""Picture of a rollout check: the recorded ego path and the recommended manoeuvre's path."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from scenariominer.cbr.rollout import RECORDED, RolloutOutcome, RolloutScene

__all__ = ["plot_rollout"]


def plot_rollout(
    scene: RolloutScene, outcomes: dict[str, RolloutOutcome], manoeuvre: str, out: Path, title: str = ""
) -> Path:
    """Write a bird's-eye PNG of a rollout check and return its path.

    Other road users' paths are grey (start box outlined), the recorded ego path blue and the path
    under ``manoeuvre`` green if it avoids the conflict, red if not.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.patches import Polygon

    from scenariominer.geometry import OrientedBoxes

    fig, ax = plt.subplots(figsize=(8, 6))
    try:
        o = scene.others
        xs, ys = np.asarray(o.x_m), np.asarray(o.y_m)
        rec, rec_o = (scene.ego_x_m, scene.ego_y_m), outcomes[RECORDED]
        chosen = outcomes[manoeuvre]
        ex = np.concatenate([rec[0], chosen.x_m])
        ey = np.concatenate([rec[1], chosen.y_m])
        cx, cy = float(np.nanmean(ex)), float(np.nanmean(ey))
        half = max(25.0, 0.6 * float(max(np.nanmax(ex) - np.nanmin(ex), np.nanmax(ey) - np.nanmin(ey))))
        near = np.nanmin(np.hypot(xs - cx, ys - cy), axis=1, initial=np.inf) < 1.5 * half
        for i in np.flatnonzero(near):
            ok = np.isfinite(xs[i])
            ax.plot(xs[i][ok], ys[i][ok], color="0.6", lw=1)
            j = int(np.argmax(ok))
            box = OrientedBoxes(
                np.asarray(o.x_m)[i, j],
                np.asarray(o.y_m)[i, j],
                np.asarray(o.yaw_rad)[i, j],
                np.asarray(o.length_m)[i, j],
                np.asarray(o.width_m)[i, j],
            )
            ax.add_patch(Polygon(box.corners(), closed=True, fill=False, ec="0.4", lw=0.8))
        ax.plot(rec[0], rec[1], color="tab:blue", lw=2.5, label=f"recorded ego ({_verdict(rec_o)})")
        colour = "tab:green" if chosen.avoided else "tab:red"
        ax.plot(
            chosen.x_m, chosen.y_m, color=colour, lw=2.5, ls="--", label=f"{manoeuvre} ({_verdict(chosen)})"
        )
        ax.plot([rec[0][0]], [rec[1][0]], "ko", ms=5, label="manoeuvre start")
        ax.set_xlim(cx - half, cx + half)
        ax.set_ylim(cy - 0.75 * half, cy + 0.75 * half)
        ax.set_aspect("equal")
        ax.set_xlabel("x [m]")
        ax.set_ylabel("y [m]")
        ax.legend(loc="upper left", fontsize=8)
        ax.set_title(title or "rollout check", fontsize=9)
        out.parent.mkdir(parents=True, exist_ok=True)
        fig.tight_layout()
        fig.savefig(out, dpi=110)
    finally:
        plt.close(fig)
    return out


def _verdict(o: RolloutOutcome) -> str:
    if o.collision:
        return f"collision at {o.first_collision_s:.1f} s"
    ttc = "inf" if not np.isfinite(o.min_ttc_s) else f"{o.min_ttc_s:.1f} s"
    return f"clear, min dist {o.min_distance_m:.1f} m, min TTC {ttc}"
