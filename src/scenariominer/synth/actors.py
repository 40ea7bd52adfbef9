"""Paths, speed profiles and tracks of the generator's road users, and their sizes."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import shapely
from numpy.typing import NDArray

from scenariominer.data.log import FloatArray
from scenariominer.geometry import OrientedBoxes, boxes_overlap, rotate_xy, wrap_angle

BoolArray = NDArray[np.bool_]


# ---------------------------------------------------------------------- geometry helpers


def _arc(center: tuple[float, float], radius: float, a0: float, a1: float, n: int = 24) -> FloatArray:
    ang = np.linspace(a0, a1, n)
    return np.stack([center[0] + radius * np.cos(ang), center[1] + radius * np.sin(ang)], axis=1)


@dataclass(frozen=True, eq=False)
class _Path:
    """A dense polyline with arc length and heading; poses beyond its ends are extrapolated straight."""

    xy: FloatArray  # (M, 2)
    s: FloatArray  # (M,)
    heading: FloatArray  # (M,) unwrapped

    @classmethod
    def through(cls, points: FloatArray, spacing_m: float = 0.5) -> _Path:
        pts = np.asarray(points, dtype=np.float64)
        seg = np.linalg.norm(np.diff(pts, axis=0), axis=1)
        pts = pts[np.concatenate([[True], seg > 1e-9])]
        cum = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(pts, axis=0), axis=1))])
        s = np.append(np.arange(0.0, cum[-1], spacing_m), cum[-1])
        xy = np.stack([np.interp(s, cum, pts[:, 0]), np.interp(s, cum, pts[:, 1])], axis=1)
        d = np.diff(xy, axis=0)
        seg_heading = np.arctan2(d[:, 1], d[:, 0])
        heading = np.unwrap(np.append(seg_heading, seg_heading[-1]))
        return cls(xy=xy, s=s, heading=heading)

    @property
    def length_m(self) -> float:
        return float(self.s[-1])

    def pose(self, s_m: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
        """``x, y, yaw`` at arc lengths ``s_m`` (any shape)."""
        s = np.asarray(s_m, dtype=np.float64)
        sc = np.clip(s, 0.0, self.length_m)
        yaw = np.interp(sc, self.s, self.heading)
        over = s - sc
        x = np.interp(sc, self.s, self.xy[:, 0]) + over * np.cos(yaw)
        y = np.interp(sc, self.s, self.xy[:, 1]) + over * np.sin(yaw)
        return x, y, wrap_angle(yaw)

    def rotated(self, theta: float) -> _Path:
        return _Path(xy=rotate_xy(self.xy, theta), s=self.s, heading=self.heading + theta)


@dataclass(frozen=True, eq=False)
class _Profile:
    """Piecewise-linear speed over time (knots), constant beyond the first and last knot."""

    t_s: FloatArray  # (K,) strictly increasing
    v_mps: FloatArray  # (K,) >= 0
    s0_m: float  # distance travelled at t_s[0]

    @classmethod
    def of(cls, knots: Sequence[tuple[float, float]], s0_m: float = 0.0) -> _Profile:
        t = [float(knots[0][0])]
        v = [max(float(knots[0][1]), 0.0)]
        for tk, vk in knots[1:]:
            if tk > t[-1] + 1e-9:
                t.append(float(tk))
                v.append(max(float(vk), 0.0))
            else:
                v[-1] = max(float(vk), 0.0)
        return cls(t_s=np.asarray(t), v_mps=np.asarray(v), s0_m=s0_m)

    def speed(self, t: FloatArray) -> FloatArray:
        return np.interp(t, self.t_s, self.v_mps)

    def distance(self, t: FloatArray) -> FloatArray:
        """Distance travelled at times ``t`` (exact integral of the piecewise-linear speed)."""
        t = np.asarray(t, dtype=np.float64)
        dt = np.diff(self.t_s)
        s_knot = self.s0_m + np.concatenate([[0.0], np.cumsum(0.5 * (self.v_mps[:-1] + self.v_mps[1:]) * dt)])
        acc = np.append(np.diff(self.v_mps) / dt, 0.0)  # constant speed after the last knot
        k = np.clip(np.searchsorted(self.t_s, t, side="right") - 1, 0, self.t_s.size - 1)
        tau = t - self.t_s[k]
        a = np.where(tau < 0.0, 0.0, acc[k])  # constant speed before the first knot
        return np.asarray(s_knot[k] + self.v_mps[k] * tau + 0.5 * a * tau**2, dtype=np.float64)

    def time_at(self, s_m: float, t_max_s: float = 60.0) -> float:
        """First time the distance reaches ``s_m`` (``inf`` if not before ``t_max_s``)."""
        grid = np.arange(min(self.t_s[0], 0.0) - 30.0, t_max_s, 0.005)
        dist = self.distance(grid)
        i = int(np.searchsorted(np.maximum.accumulate(dist), s_m))
        return float(grid[i]) if i < grid.size else float("inf")


def _boxes(x: FloatArray, y: FloatArray, yaw: FloatArray, length: float, width: float) -> NDArray[np.object_]:
    """Shapely rectangles of boxes centred at ``x, y`` with heading ``yaw`` (all ``(K,)``)."""
    local = np.array([[0.5, 0.5], [-0.5, 0.5], [-0.5, -0.5], [0.5, -0.5]]) * [length, width]
    c, s = np.cos(yaw)[:, None], np.sin(yaw)[:, None]
    cx = x[:, None] + c * local[:, 0] - s * local[:, 1]
    cy = y[:, None] + s * local[:, 0] + c * local[:, 1]
    return np.asarray(shapely.polygons(np.stack([cx, cy], axis=2)), dtype=object)


def _first_run_on(
    path: _Path, length: float, width: float, region: shapely.Geometry, step_m: float = 0.25
) -> tuple[float, float] | None:
    """Arc lengths where a box moving along ``path`` first enters and then leaves ``region``."""
    s = np.arange(0.0, path.length_m, step_m)
    x, y, yaw = path.pose(s)
    hit = np.asarray(shapely.intersects(_boxes(x, y, yaw, length, width), region), dtype=bool)
    if not hit.any():
        return None
    i0 = int(np.argmax(hit))
    rest = hit[i0:]
    i1 = i0 + (int(np.argmin(rest)) - 1 if not rest.all() else rest.size - 1)
    return float(s[i0]), float(s[i1])


# ---------------------------------------------------------------------- actors


@dataclass(eq=False)
class _Track:
    """One actor's noise-free states on the log's frame grid (canonical frame)."""

    category: str
    length: float
    width: float
    height: float
    x: FloatArray
    y: FloatArray
    yaw: FloatArray
    valid: BoolArray
    track_id: str = ""

    @classmethod
    def along(
        cls, path: _Path, profile: _Profile, t: FloatArray, category: str, size: tuple[float, float, float]
    ) -> _Track:
        x, y, yaw = path.pose(profile.distance(t))
        return cls(category, *size, x=x, y=y, yaw=yaw, valid=np.ones(t.size, dtype=bool))

    @property
    def box(self) -> tuple[FloatArray, FloatArray, FloatArray, float, float]:
        return self.x, self.y, self.yaw, self.length, self.width


def _conflicts(a: _Track, b: _Track, horizon_frames: int, margin_m: float) -> bool:
    """Whether ``a`` at frame i and ``b`` at frame j overlap for some ``|i - j| <= horizon_frames``."""
    n = a.x.size
    i, j = np.nonzero(np.abs(np.arange(n)[:, None] - np.arange(n)[None, :]) <= horizon_frames)
    ok = a.valid[i] & b.valid[j]
    i, j = i[ok], j[ok]
    return bool(
        boxes_overlap(
            OrientedBoxes(
                a.x[i],
                a.y[i],
                a.yaw[i],
                np.asarray(a.length, dtype=np.float64),
                np.asarray(a.width, dtype=np.float64),
            ),
            OrientedBoxes(
                b.x[j],
                b.y[j],
                b.yaw[j],
                np.asarray(b.length, dtype=np.float64),
                np.asarray(b.width, dtype=np.float64),
            ),
            margin_m,
        ).any()
    )


_SIZES_M: dict[str, tuple[tuple[float, float], tuple[float, float], tuple[float, float]]] = {
    "REGULAR_VEHICLE": ((4.2, 5.1), (1.75, 2.05), (1.4, 1.9)),
    "LARGE_VEHICLE": ((5.5, 6.5), (2.0, 2.3), (2.0, 2.8)),
    "BOX_TRUCK": ((6.5, 8.5), (2.3, 2.6), (3.0, 3.6)),
    "TRUCK": ((7.0, 9.5), (2.4, 2.6), (3.0, 3.8)),
    "BUS": ((11.5, 13.0), (2.5, 2.6), (3.0, 3.4)),
    "PEDESTRIAN": ((0.45, 0.8), (0.45, 0.8), (1.5, 1.9)),
    "BICYCLIST": ((1.6, 1.9), (0.6, 0.8), (1.6, 1.9)),
    "MOTORCYCLIST": ((2.0, 2.3), (0.8, 1.0), (1.5, 1.7)),
}

_VEHICLE_MIX = (
    ("REGULAR_VEHICLE", 0.76),
    ("LARGE_VEHICLE", 0.08),
    ("BOX_TRUCK", 0.07),
    ("TRUCK", 0.04),
    ("BUS", 0.05),
)


def _size(rng: np.random.Generator, category: str) -> tuple[float, float, float]:
    (l0, l1), (w0, w1), (h0, h1) = _SIZES_M[category]
    return float(rng.uniform(l0, l1)), float(rng.uniform(w0, w1)), float(rng.uniform(h0, h1))


def _pick(rng: np.random.Generator, mix: Sequence[tuple[str, float]]) -> str:
    names = [m[0] for m in mix]
    weights = np.asarray([m[1] for m in mix])
    return str(names[int(rng.choice(len(names), p=weights / weights.sum()))])
