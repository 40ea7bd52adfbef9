"""The lane under each object at each frame, vectorised over tracks × timestamps.

A box centre is *on* the lane segments whose polygons (the area between the left and right
boundaries) contain it, edges included; in none, it is on no lane (``-1``): this is what
``on_road`` tests, and it is decided by the polygons alone. Among several containing lanes
(overlapping lanes inside intersections, merges, a bike lane overlapping a vehicle lane) the lane
is chosen by, in order:

1. **lane type for the object's category**: a motor vehicle (the ``VEHICLE`` group less
   motorcycles, :data:`BIKE_LANE_AVOIDERS`) is put in a bike lane only when no vehicle or bus
   lane contains it; a bicycle or cyclist (:data:`BIKE_LANE_USERS`) is put in a bike lane
   whenever one contains it; other categories (pedestrians, motorcycles, objects) have no
   preference. Buses and cars may use bus lanes alike.
2. **heading agreement**: lanes whose direction at the centre-line point nearest the centre is
   more than :data:`LANE_HEADING_TOLERANCE_DEG` further from the object's heading than the
   best-agreeing lane's are dropped (a NaN heading drops none);
3. **continuity**: among the equally aligned lanes left, the track's lane at its previous
   on-lane frame, or one of that lane's successors, wins, so a car that entered an intersection
   from lane ``A`` stays on ``A``'s successor where a parallel lane overlaps it, and a car
   waiting where two successors overlap does not flip between them; a car turning onto another
   lane leaves the old one by rule 2 as soon as their directions differ by the tolerance;
4. **cost**: distance from the centre to the lane's centre line plus
   ``LANE_HEADING_WEIGHT_M * (1 - cos(dyaw))`` (:meth:`Av2Map.lane_candidates`), lowest wins; this
   alone was the rule before.

Continuity makes a frame depend on the one before; instead of a loop over frames, every frame
with several candidates is first solved assuming its track stays on the lane of the last solved
frame, and the frames up to the first one that leaves it are accepted at once; each round thus
settles one lane change per run of ambiguous frames (a few rounds per log).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from scenariominer.data.adapters.av2.map import Av2Map
from scenariominer.data.categories import CATEGORY_GROUPS
from scenariominer.geometry import wrap_angle

__all__ = [
    "BIKE_LANE_AVOIDERS",
    "BIKE_LANE_USERS",
    "LANE_HEADING_TOLERANCE_DEG",
    "assign_lanes",
    "successor_codes",
]

IntArray = NDArray[np.int64]
FloatArray = NDArray[np.float64]

#: Categories put in a bike lane whenever one contains their centre.
BIKE_LANE_USERS: frozenset[str] = frozenset({"BICYCLE", "BICYCLIST"})

#: Categories put in a bike lane only when no other lane contains their centre: motor vehicles.
BIKE_LANE_AVOIDERS: frozenset[str] = CATEGORY_GROUPS["VEHICLE"] - {"MOTORCYCLE"}

#: A containing lane stays a candidate when its direction is at most this much (degrees) further
#: from the object's heading than the best-agreeing containing lane's: about the noise of a box
#: heading and of a lane's local direction, so lanes within it count as equally aligned.
LANE_HEADING_TOLERANCE_DEG = 3.0

_TYPE_CODE = {"VEHICLE": 0, "BIKE": 1, "BUS": 2}  # any other type: 3
#: rank of a lane type (columns VEHICLE, BIKE, BUS, other) for a category class (rows: no
#: preference, bike-lane avoider, bike-lane user); the lowest rank among containing lanes wins.
_TYPE_RANK = np.array([[0, 0, 0, 0], [0, 1, 0, 0], [1, 0, 1, 1]], dtype=np.int64)


def successor_codes(successors: Sequence[Sequence[int]]) -> IntArray:
    """Sorted codes ``i * L + j`` of the lane-graph links ``i -> j`` (``L`` lanes, one list per lane)."""
    n = len(successors)
    codes = [i * n + j for i, succ in enumerate(successors) for j in succ]
    return np.unique(np.asarray(codes, dtype=np.int64))


def _category_classes(categories: ArrayLike) -> IntArray:
    """Class (row of ``_TYPE_RANK``) of each category name, same shape."""
    names, inverse = np.unique(np.asarray(categories).astype(str), return_inverse=True)
    cls = np.zeros(names.shape, dtype=np.int64)
    cls[np.isin(names, sorted(BIKE_LANE_AVOIDERS))] = 1
    cls[np.isin(names, sorted(BIKE_LANE_USERS))] = 2
    return cls[inverse].reshape(np.shape(categories))


def _group_starts(keys: IntArray) -> IntArray:
    """Start positions of the runs of equal values in the sorted ``keys``."""
    if keys.size == 0:
        return np.zeros(0, dtype=np.int64)
    return np.flatnonzero(np.concatenate([[True], keys[1:] != keys[:-1]])).astype(np.int64)


def _lowest_per_point(point: IntArray, value: FloatArray, tolerance: float) -> NDArray[np.bool_]:
    """Pairs whose ``value`` is within ``tolerance`` of their point's lowest (``point`` sorted)."""
    starts = _group_starts(point)
    lowest = np.minimum.reduceat(value, starts)
    out: NDArray[np.bool_] = value <= np.repeat(lowest, np.diff(np.append(starts, point.size))) + tolerance
    return out


def _choose(
    groups: IntArray,
    prev_lane: IntArray,
    starts: IntArray,
    counts: IntArray,
    lane: IntArray,
    cost: FloatArray,
    succ: IntArray,
    n_lanes: int,
) -> IntArray:
    """Chosen pair (position in ``lane``/``cost``) of each candidate group given the previous lane.

    The lane continuing ``prev_lane`` (itself or a successor) wins, then the lowest cost.

    ``groups`` index ``starts``/``counts`` (a group is one point's candidate pairs); ``prev_lane``
    is the lane of the track's previous on-lane frame for each group (``-1``: none).
    """
    cnt = counts[groups]
    sub_starts = np.concatenate([[0], np.cumsum(cnt)[:-1]]).astype(np.int64)
    sub_group = np.repeat(np.arange(groups.size), cnt)
    pos = np.repeat(starts[groups] - sub_starts, cnt) + np.arange(int(cnt.sum()))
    prev = prev_lane[sub_group]
    cand = lane[pos]
    c = cost[pos]
    follows = (prev >= 0) & ((cand == prev) | np.isin(prev * n_lanes + cand, succ))
    order = np.lexsort((c, ~follows, sub_group))
    chosen: IntArray = pos[order[sub_starts]]
    return chosen


def assign_lanes(
    hd_map: Av2Map,
    succ: IntArray,
    x_m: FloatArray,
    y_m: FloatArray,
    yaw_rad: FloatArray,
    categories: ArrayLike | None = None,
) -> tuple[IntArray, FloatArray]:
    """Lane segment under each point and the lane's local direction there (see module docstring).

    Args:
        hd_map: the vector map.
        succ: lane-graph links of ``hd_map`` as :func:`successor_codes`.
        x_m: point x. A 2-D array is read as tracks × timestamps (continuity runs along each
            row); any other shape as independent points (no continuity). NaN points get no lane.
        y_m: point y, same shape.
        yaw_rad: heading at each point, same shape; NaN counts as no preference.
        categories: category name of each row of a 2-D input (``(N,)``), or of each point (the
            input's shape); ``None``: no lane-type preference.

    Returns:
        Lane indices (into ``hd_map.lane_segments``) of the input shape, ``-1`` where no lane
        polygon contains the point, and the local direction (radians) of the chosen lane's centre
        line at the point (NaN where no lane).
    """
    shape = np.shape(x_m)
    xy = np.stack([np.ravel(x_m), np.ravel(y_m)], axis=1).astype(np.float64)
    k = xy.shape[0]
    out_lane = np.full(k, -1, dtype=np.int64)
    out_dir = np.full(k, np.nan)
    yaw = np.broadcast_to(np.asarray(yaw_rad, dtype=np.float64), shape).reshape(-1)
    point, lane, cost, lane_yaw = hd_map.lane_candidates(xy.reshape(-1, 2), yaw)
    if point.size == 0:
        return out_lane.reshape(shape), out_dir.reshape(shape)

    keep = np.ones(point.size, dtype=bool)
    # 1. lane type: keep each point's candidates of the lowest rank for its category
    if categories is not None:
        cats = np.asarray(categories)
        if len(shape) == 2 and cats.shape == (shape[0],):
            cls = np.repeat(_category_classes(cats), shape[1])
        else:
            cls = np.broadcast_to(_category_classes(cats), shape).reshape(-1)
        codes = np.asarray([_TYPE_CODE.get(str(t), 3) for t in hd_map.lane_types], dtype=np.int64)
        keep &= _lowest_per_point(point, _TYPE_RANK[cls[point], codes[lane]].astype(np.float64), 0.0)
    # 2. heading agreement within the tolerance of the best-agreeing lane (NaN heading: keep all)
    mismatch = np.abs(wrap_angle(yaw[point] - lane_yaw))
    mismatch = np.where(keep, np.nan_to_num(mismatch, nan=0.0), np.inf)
    keep &= _lowest_per_point(point, mismatch, np.radians(LANE_HEADING_TOLERANCE_DEG))
    point, lane, cost, lane_yaw = point[keep], lane[keep], cost[keep], lane_yaw[keep]

    starts = _group_starts(point)
    counts = np.diff(np.append(starts, point.size))
    frames = point[starts]  # one group per on-lane point, in row-major order
    n_groups = frames.size
    # previous on-lane frame of the same track (group g - 1 when in the same row)
    anchor = np.full(n_groups, -1, dtype=np.int64)
    if len(shape) == 2 and n_groups > 1:
        row = frames // max(shape[1], 1)
        same = row[1:] == row[:-1]
        anchor[1:][same] = np.arange(n_groups - 1)[same]

    chosen = starts.copy()  # a group with one candidate: that one
    pending = np.flatnonzero(counts > 1)
    while pending.size:
        anc = anchor[pending]
        is_pending = np.zeros(n_groups + 1, dtype=bool)  # slot -1: "no anchor", never pending
        is_pending[pending] = True
        head = ~is_pending[anc]
        run = np.cumsum(head) - 1
        head_anchor = anc[head]
        run_prev = np.where(head_anchor >= 0, lane[chosen[head_anchor]], -1)
        hyp = run_prev[run]  # the lane each run is assumed to stay on
        pick = _choose(pending, hyp, starts, counts, lane, cost, succ, hd_map.n_lanes)
        leaves = lane[pick] != hyp
        left_before = np.cumsum(leaves) - leaves
        # exact where no earlier frame of the run left the assumed lane (the first leaver too)
        exact = left_before == left_before[head][run]
        chosen[pending[exact]] = pick[exact]
        pending = pending[~exact]

    out_lane[frames] = lane[chosen]
    out_dir[frames] = lane_yaw[chosen]
    return out_lane.reshape(shape), out_dir.reshape(shape)
