"""Cross-checks of a highD recording's three files: frame rate, duration and per-vehicle spans.

Each file can be well-formed on its own and still disagree with the others: a ``frameRate`` of 50
for 25 Hz tracks halves every speed and time; a ``tracksMeta`` row whose ``initialFrame`` /
``finalFrame`` / ``numFrames`` do not match the vehicle's rows in ``tracks`` marks a truncated or
edited file. These functions find such disagreements; :func:`~.format.read_highd_recording` refuses
the recording or drops the vehicle, with the reason.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from scenariominer.data.log import FloatArray, LogFormatError

IntArray = NDArray[np.int64]

__all__ = ["FRAME_RATE_TOLERANCE", "META_SPAN_COLUMNS", "check_frame_rate", "meta_span_mismatch"]

#: Relative difference between ``frameRate`` and the rate the tracks imply that is refused.
FRAME_RATE_TOLERANCE = 0.1
#: tracksMeta columns compared with each vehicle's rows in the tracks file.
META_SPAN_COLUMNS: tuple[str, ...] = ("initialFrame", "finalFrame", "numFrames")
# Rows slower than this say little about the frame rate (positions have 1 cm resolution).
_MIN_SPEED_MPS = 5.0
_MIN_PAIRS = 20


def implied_frame_rate(vid: IntArray, frame: IntArray, x_m: FloatArray, vx_mps: FloatArray) -> float | None:
    """Frames per second implied by ``xVelocity`` over the x step between consecutive frames.

    Rows must be sorted by (id, frame). Uses pairs of consecutive frames of one vehicle moving at
    least 5 m/s; ``None`` when there are fewer than 20 such pairs.
    """
    same = (vid[1:] == vid[:-1]) & (np.diff(frame) == 1)
    dx = np.diff(x_m)[same]
    v = 0.5 * (vx_mps[1:] + vx_mps[:-1])[same]
    ok = (np.abs(v) >= _MIN_SPEED_MPS) & (dx != 0)
    if int(ok.sum()) < _MIN_PAIRS:
        return None
    return float(np.median(v[ok] / dx[ok]))


def check_frame_rate(
    frame_rate_hz: float,
    duration_s: float | None,
    vid: IntArray,
    frame: IntArray,
    x_m: FloatArray,
    vx_mps: FloatArray,
    recording_meta: Path,
) -> None:
    """Refuse a ``frameRate`` the tracks contradict.

    Raises:
        LogFormatError: naming ``recordingMeta``, when the positions and velocities imply a rate more
            than :data:`FRAME_RATE_TOLERANCE` away from ``frameRate``, or when the tracks span more
            time at that rate than the recording's ``duration``.
    """
    implied = implied_frame_rate(vid, frame, x_m, vx_mps)
    if implied is not None and abs(implied / frame_rate_hz - 1.0) > FRAME_RATE_TOLERANCE:
        raise LogFormatError(
            recording_meta,
            f"frameRate {frame_rate_hz:g} Hz disagrees with the tracks: their x steps and xVelocity imply "
            f"{implied:.3g} frames per second",
        )
    span_s = float(frame.max() - frame.min() + 1) / frame_rate_hz
    if duration_s is not None and duration_s > 0 and span_s > 1.05 * duration_s + 1.0 / frame_rate_hz:
        raise LogFormatError(
            recording_meta,
            f"the tracks span {span_s:.2f} s at frameRate {frame_rate_hz:g} Hz, longer than the recording's "
            f"duration of {duration_s:g} s (frameRate or duration is wrong)",
        )


def meta_span_mismatch(
    first_frame: IntArray,
    last_frame: IntArray,
    n_rows: IntArray,
    meta: Mapping[str, NDArray[np.int64]],
) -> tuple[NDArray[np.bool_], str]:
    """Vehicles whose rows disagree with their tracksMeta span, and an example of the disagreement.

    Args:
        first_frame: ``(V,)`` each vehicle's first frame in the tracks file.
        last_frame: ``(V,)`` each vehicle's last frame in the tracks file.
        n_rows: ``(V,)`` each vehicle's number of rows in the tracks file.
        meta: the vehicle's tracksMeta values, ``(V,)`` per column of :data:`META_SPAN_COLUMNS`
            present in the file.

    Returns:
        ``(V,)`` True for a vehicle that disagrees, and a description of the first one ('' if none).
    """
    got = {"initialFrame": first_frame, "finalFrame": last_frame, "numFrames": n_rows}
    bad = np.zeros(first_frame.shape, dtype=bool)
    for name in META_SPAN_COLUMNS:
        if name in meta:
            bad |= np.asarray(meta[name], dtype=np.int64) != got[name]
    if not bad.any():
        return bad, ""
    i = int(np.flatnonzero(bad)[0])
    listed = ", ".join(f"{name}={int(meta[name][i])}" for name in META_SPAN_COLUMNS if name in meta)
    actual = f"frames {int(first_frame[i])}..{int(last_frame[i])} in {int(n_rows[i])} row(s)"
    return bad, f"{listed} in tracksMeta but {actual}"
