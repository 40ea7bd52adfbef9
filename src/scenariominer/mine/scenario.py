"""The columnar scenario value and its Boolean composition.

A scenario over one log says, for every *referred* track, at which timestamps the description
holds, and, for relational scenarios, which *related* tracks made it hold at each timestamp
("the vehicle" is referred, "the bicycle to its right" is related). RefAV stores this as nested
``{uuid: {uuid: [timestamps]}}`` dictionaries; here it is columnar:

* ``referred``: ``(N, T)`` bool over the log's tracks × timestamps,
* ``relations``: ``(K, 3)`` int64 rows ``(referred track, timestamp index, related track)``,
  unique and sorted, every row on a referred cell.

Relations are one level deep: when a relational predicate takes a relational scenario as its
subject, the subject's relations are kept on the cells that stay referred and the new relations
are added; the reference scenario's own relations are not carried (the evaluator only knows
referred, related and other objects).

Composition (:func:`scenario_and`, :func:`scenario_or`, :func:`scenario_not`,
:func:`reverse_relationship`) and :func:`postprocess_scenario` are pure functions of scenarios.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass
from functools import wraps
from typing import Any

import numpy as np
from numpy.typing import NDArray

from scenariominer.config.mining import MiningConfig
from scenariominer.data.log import BoolArray
from scenariominer.mine.context import IntArray, LogContext

__all__ = [
    "Scenario",
    "postprocess_scenario",
    "reverse_relationship",
    "scenario_and",
    "scenario_not",
    "scenario_or",
]

_EMPTY_RELATIONS = np.zeros((0, 3), dtype=np.int64)


def _unique_rows(rel: IntArray) -> IntArray:
    if rel.shape[0] == 0:
        return _EMPTY_RELATIONS.copy()
    order = np.lexsort((rel[:, 2], rel[:, 1], rel[:, 0]))
    rel = rel[order]
    keep = np.ones(rel.shape[0], dtype=bool)
    keep[1:] = np.any(rel[1:] != rel[:-1], axis=1)
    return np.ascontiguousarray(rel[keep])


@dataclass(frozen=True, eq=False)
class Scenario:
    """Where and when a description holds in one log (see module docstring).

    Build with :meth:`from_mask` (normalising) or :meth:`from_arrays` (validating untrusted
    arrays); the constructor expects already-normalised arrays and checks them.

    Attributes:
        context: the log (with its shared arrays) the scenario refers to.
        referred: ``(N, T)`` bool, True where the track is a referred object at that timestamp;
            always a subset of the log's ``valid`` mask.
        relations: ``(K, 3)`` int64 ``(referred track, timestamp index, related track)`` rows.
    """

    context: LogContext
    referred: BoolArray
    relations: IntArray

    def __post_init__(self) -> None:
        ctx = self.context
        shape = (ctx.n_tracks, ctx.n_timestamps)
        if self.referred.shape != shape or self.referred.dtype != np.bool_:
            raise ValueError(
                f"referred must be a bool array of shape {shape}, "
                f"got {self.referred.dtype} {self.referred.shape}"
            )
        if self.relations.ndim != 2 or self.relations.shape[1] != 3 or self.relations.dtype != np.int64:
            raise ValueError(f"relations must be an int64 array of shape (K, 3), got {self.relations.shape}")
        if np.any(self.referred & ~ctx.valid):
            raise ValueError("referred cells must be observations of the log (inside its valid mask)")
        rel = self.relations
        if rel.shape[0]:
            if rel.min() < 0 or rel[:, [0, 2]].max() >= shape[0] or rel[:, 1].max() >= shape[1]:
                raise ValueError("relations index a track or timestamp outside the log")
            if not self.referred[rel[:, 0], rel[:, 1]].all():
                raise ValueError("every relation must start at a referred cell")
            if not ctx.valid[rel[:, 2], rel[:, 1]].all():
                raise ValueError("every related track must be observed at the relation's timestamp")
        self.referred.flags.writeable = False
        self.relations.flags.writeable = False

    # ------------------------------------------------------------------ construction
    @classmethod
    def empty(cls, context: LogContext) -> Scenario:
        """The scenario that holds nowhere."""
        return cls(
            context, np.zeros((context.n_tracks, context.n_timestamps), dtype=bool), _EMPTY_RELATIONS.copy()
        )

    @classmethod
    def from_mask(cls, context: LogContext, mask: BoolArray, relations: IntArray | None = None) -> Scenario:
        """Normalise a candidate mask and relations into a scenario.

        Cells outside the log's observations are dropped, as are relations that do not start at
        a referred cell or whose related track is not observed; duplicate relations collapse.

        Args:
            context: the log.
            mask: ``(N, T)`` bool candidate referred cells.
            relations: ``(K, 3)`` int rows ``(track, timestamp index, related track)`` or ``None``.
        """
        referred = np.asarray(mask, dtype=bool) & context.valid
        rel = _EMPTY_RELATIONS if relations is None else np.asarray(relations, dtype=np.int64).reshape(-1, 3)
        if rel.shape[0]:
            ok = (
                referred[rel[:, 0], rel[:, 1]]
                & context.valid[rel[:, 2], rel[:, 1]]
                & (rel[:, 0] != rel[:, 2])
            )
            rel = rel[ok]
        return cls(context, np.ascontiguousarray(referred), _unique_rows(rel))

    @classmethod
    def from_arrays(cls, context: LogContext, referred: Any, relations: Any) -> Scenario:
        """Rebuild a scenario from plain arrays received from elsewhere (e.g. a sandbox child).

        Raises:
            ValueError: shapes, types or indices do not fit ``context``; the message says which.
        """
        ref = np.asarray(referred)
        rel = np.asarray(relations)
        if ref.dtype != np.bool_:
            raise ValueError(f"referred must be boolean, got {ref.dtype}")
        if rel.size == 0:
            rel = _EMPTY_RELATIONS
        if not np.issubdtype(rel.dtype, np.integer):
            raise ValueError(f"relations must be integers, got {rel.dtype}")
        return cls(context, np.ascontiguousarray(ref), _unique_rows(rel.astype(np.int64).reshape(-1, 3)))

    # ------------------------------------------------------------------ views
    @property
    def log_id(self) -> str:
        """Identifier of the log."""
        return self.context.log_id

    @property
    def n_referred_cells(self) -> int:
        """Number of (track, timestamp) cells where a referred object is present."""
        return int(self.referred.sum())

    @property
    def referred_tracks(self) -> IntArray:
        """``(R,)`` indices of tracks referred at least once, ascending."""
        return np.flatnonzero(self.referred.any(axis=1)).astype(np.int64)

    @property
    def timestamp_mask(self) -> BoolArray:
        """``(T,)`` timestamps with at least one referred object."""
        return np.asarray(self.referred.any(axis=0))

    @property
    def is_empty(self) -> bool:
        """Whether no object is referred anywhere."""
        return not bool(self.referred.any())

    @property
    def related_mask(self) -> BoolArray:
        """``(N, T)`` cells where a track is a related object of some referred object."""
        out = np.zeros_like(self.referred)
        if self.relations.shape[0]:
            out[self.relations[:, 2], self.relations[:, 1]] = True
        return out

    def referred_timestamps(self) -> dict[str, NDArray[np.int64]]:
        """``{track_id: timestamps_ns}`` of every referred track."""
        ts = self.context.log.timestamps_ns
        ids = self.context.log.track_ids
        return {str(ids[i]): ts[self.referred[i]] for i in self.referred_tracks}

    def related_timestamps(self) -> dict[str, dict[str, NDArray[np.int64]]]:
        """``{referred track_id: {related track_id: timestamps_ns}}`` of the relations."""
        ts = self.context.log.timestamps_ns
        ids = self.context.log.track_ids
        out: dict[str, dict[str, NDArray[np.int64]]] = {}
        rel = self.relations
        if rel.shape[0] == 0:
            return out
        pairs, inverse = np.unique(rel[:, [0, 2]], axis=0, return_inverse=True)
        for k, (a, b) in enumerate(pairs):
            out.setdefault(str(ids[a]), {})[str(ids[b])] = ts[np.sort(rel[inverse.reshape(-1) == k, 1])]
        return out

    def __len__(self) -> int:
        """Number of referred tracks (as ``len`` of a RefAV scenario dict)."""
        return int(self.referred_tracks.size)

    def __iter__(self) -> Iterator[str]:
        """Track ids of the referred tracks."""
        ids = self.context.log.track_ids
        return iter([str(ids[i]) for i in self.referred_tracks])

    def __contains__(self, track_id: object) -> bool:
        """Whether ``track_id`` is referred at some timestamp."""
        return str(track_id) in set(self)

    def __repr__(self) -> str:
        return (
            f"Scenario(log={self.log_id!r}, referred_tracks={len(self)}, referred_cells="
            f"{self.n_referred_cells}, relations={self.relations.shape[0]})"
        )

    # ------------------------------------------------------------------ algebra
    def restrict(self, mask: BoolArray) -> Scenario:
        """Keep only the referred cells inside ``mask`` ``(N, T)``, with their relations."""
        referred = self.referred & np.asarray(mask, dtype=bool)
        rel = self.relations
        if rel.shape[0]:
            rel = rel[referred[rel[:, 0], rel[:, 1]]]
        return Scenario(self.context, referred, np.ascontiguousarray(rel))

    def with_relations(self, relations: IntArray) -> Scenario:
        """Add relations (rows on cells that are not referred are dropped)."""
        rel = np.concatenate([self.relations, np.asarray(relations, dtype=np.int64).reshape(-1, 3)])
        return Scenario.from_mask(self.context, self.referred, rel)

    def reversed(self) -> Scenario:
        """Swap roles: every related object becomes referred with its referrer as related object."""
        rel = self.relations
        referred = np.zeros_like(self.referred)
        if rel.shape[0]:
            referred[rel[:, 2], rel[:, 1]] = True
        return Scenario(self.context, referred, _unique_rows(rel[:, [2, 1, 0]]))


def _check_scenarios(scenarios: Sequence[Any], func: str) -> list[Scenario]:
    items = list(scenarios)
    if not items:
        raise ValueError(f"{func}() needs at least one scenario, e.g. {func}([scenario_a, scenario_b])")
    for i, s in enumerate(items):
        if not isinstance(s, Scenario):
            raise TypeError(
                f"{func}() item {i} is a {type(s).__name__}, not a scenario; pass scenarios returned by "
                f"predicates, e.g. {func}([scenario_a, scenario_b])"
            )
    ctx = items[0].context
    if any(s.context is not ctx for s in items[1:]):
        raise ValueError(f"{func}() got scenarios of different logs")
    return items


def _flatten_args(scenarios: Any, more: tuple[Any, ...]) -> list[Any]:
    if isinstance(scenarios, Scenario):
        return [scenarios, *more]
    if isinstance(scenarios, list | tuple):
        return [*scenarios, *more]
    return [scenarios, *more]


def scenario_and(scenarios: Sequence[Scenario], *more: Scenario) -> Scenario:
    """Objects and timestamps present in EVERY input scenario (intersection).

    A track is referred at a timestamp only if it is referred at that timestamp in all inputs.
    The related objects of all inputs are kept at the remaining cells.

    Args:
        scenarios: a list of scenarios of the same log, e.g. ``[moving_vehicles, vehicles_on_road]``.
        *more: further scenarios; ``scenario_and(a, b)`` is accepted as well as ``scenario_and([a, b])``.

    Returns:
        A scenario: the intersection of the inputs' referred cells.

    Example:
        moving_cars_on_road = scenario_and([moving_cars, cars_on_road])
    """
    items = _check_scenarios(_flatten_args(scenarios, more), "scenario_and")
    referred = items[0].referred.copy()
    for s in items[1:]:
        referred &= s.referred
    rel = np.concatenate([s.relations for s in items])
    return Scenario.from_mask(items[0].context, referred, rel)


def scenario_or(scenarios: Sequence[Scenario], *more: Scenario) -> Scenario:
    """Objects and timestamps present in ANY input scenario (union), with all related objects.

    Args:
        scenarios: a list of scenarios of the same log, e.g. ``[dogs_on_road, strollers_on_road]``.
        *more: further scenarios; ``scenario_or(a, b)`` is accepted as well as ``scenario_or([a, b])``.

    Returns:
        A scenario: the union of the inputs' referred cells and relations.

    Example:
        be_cautious_around = scenario_or([dogs_on_road, strollers_on_road])
    """
    items = _check_scenarios(_flatten_args(scenarios, more), "scenario_or")
    referred = items[0].referred.copy()
    for s in items[1:]:
        referred |= s.referred
    rel = np.concatenate([s.relations for s in items])
    return Scenario.from_mask(items[0].context, referred, rel)


def _check_predicate(func: Any, wrapper: str) -> None:
    if isinstance(func, Scenario):
        raise TypeError(
            f"{wrapper}() takes a predicate FUNCTION, not a scenario: write "
            f"{wrapper}(stationary)(vehicles, log_dir), not {wrapper}(stationary(vehicles, log_dir))"
        )
    if not callable(func):
        raise TypeError(
            f"{wrapper}() takes a predicate function such as stationary, got {type(func).__name__}"
        )


def _check_result(result: Any, func: Any, wrapper: str) -> Scenario:
    if not isinstance(result, Scenario):
        name = getattr(func, "__name__", "the function")
        raise TypeError(
            f"{wrapper}({name}) needs a predicate that returns a scenario; "
            f"{name} returned {type(result).__name__}"
        )
    return result


def scenario_not(func: Callable[..., Scenario]) -> Callable[..., Scenario]:
    """Wrap a predicate so that it returns the track candidates where the predicate does NOT hold.

    ``scenario_not(f)(track_candidates, ...)`` calls ``f(track_candidates, ...)`` with the same
    arguments and returns the cells of ``track_candidates`` (with their existing related objects)
    that are not in ``f``'s result. No new relations are created, also when ``f`` is relational.

    Args:
        func: a predicate function whose first argument is the track candidates (not a scenario).

    Returns:
        A function with the same arguments as ``func`` that returns a scenario.

    Example:
        active_vehicles = scenario_not(stationary)(vehicles, log_dir)
        vehicles_without_peds_ahead = scenario_not(has_objects_in_relative_direction)(
            vehicles, peds, log_dir, direction='forward', within_distance=10)
    """
    _check_predicate(func, "scenario_not")

    @wraps(func)
    def negated(track_candidates: Scenario, *args: Any, **kwargs: Any) -> Scenario:
        if not isinstance(track_candidates, Scenario):
            raise TypeError(
                f"scenario_not({getattr(func, '__name__', 'f')})(...): the first argument must be a scenario "
                f"(the track candidates), got {type(track_candidates).__name__}"
            )
        result = _check_result(func(track_candidates, *args, **kwargs), func, "scenario_not")
        return track_candidates.restrict(~result.referred)

    return negated


def reverse_relationship(func: Callable[..., Scenario] | Scenario) -> Callable[..., Scenario] | Scenario:
    """Swap referred and related objects of a relational predicate's result.

    ``reverse_relationship(f)(track_candidates, related_candidates, log_dir, ...)`` calls the
    relational predicate ``f`` unchanged and returns its RELATED objects as the referred objects,
    each with the track candidate it was related to as its related object. Given a scenario
    instead of a function, it reverses that scenario directly.

    Args:
        func: a relational predicate (two scenario arguments: track candidates, related
            candidates), or a scenario.

    Returns:
        A function with the same arguments as ``func`` returning the reversed scenario (or,
        for a scenario argument, the reversed scenario).

    Example:
        # pedestrians (referred) that have a vehicle within 5 m of them (related)
        peds_near_vehicle = reverse_relationship(near_objects)(vehicles, peds, log_dir, distance_thresh=5)
    """
    if isinstance(func, Scenario):
        return func.reversed()
    _check_predicate(func, "reverse_relationship")

    @wraps(func)
    def reversed_func(*args: Any, **kwargs: Any) -> Scenario:
        return _check_result(func(*args, **kwargs), func, "reverse_relationship").reversed()

    return reversed_func


def postprocess_scenario(scenario: Scenario, config: MiningConfig | None = None) -> Scenario:
    """RefAV's clean-up of a program's output before it is stored or evaluated.

    1. Relations between two tracks whose centres never come closer than
       ``postprocess_max_relation_distance_m`` at the relation's timestamps are dropped (RefAV's
       ``filter_by_relationship_distance``). A referred object is referred *because of* its
       related objects, so, as in RefAV (whose referred timestamps are those of the remaining
       related objects), a cell that had related objects and has none left is no longer referred,
       and a track that had relations and has none left is dropped altogether. Cells that never
       had a related object (a non-relational scenario) are kept.
    2. Referred tracks referred at fewer than ``postprocess_min_timestamps`` timestamps are
       dropped (one-frame hits are annotation noise).
    3. A run of ``k`` referred timestamps shorter than ``m = postprocess_min_run_timestamps`` is
       widened by ``(m - k) // 2`` timestamps on both sides (inside the track's observations), so
       a single-frame hit becomes a three-frame run for ``m = 3``.

    Args:
        scenario: a program's result.
        config: thresholds; defaults to the scenario's context config.
    """
    cfg = config or scenario.context.config
    ctx = scenario.context
    referred = scenario.referred.copy()

    rel = scenario.relations
    if rel.shape[0]:
        x, y = ctx.center_xy_m
        d = np.hypot(
            x[rel[:, 0], rel[:, 1]] - x[rel[:, 2], rel[:, 1]],
            y[rel[:, 0], rel[:, 1]] - y[rel[:, 2], rel[:, 1]],
        )
        pairs, inverse = np.unique(rel[:, [0, 2]], axis=0, return_inverse=True)
        close = np.zeros(pairs.shape[0], dtype=bool)
        np.logical_or.at(close, inverse.reshape(-1), d < cfg.postprocess_max_relation_distance_m)
        kept = rel[close[inverse.reshape(-1)]]
        had = np.zeros_like(referred)
        had[rel[:, 0], rel[:, 1]] = True
        has = np.zeros_like(referred)
        has[kept[:, 0], kept[:, 1]] = True
        referred &= ~(had & ~has)
        referred[had.any(axis=1) & ~has.any(axis=1)] = False
        rel = kept

    counts = referred.sum(axis=1)
    referred[counts < cfg.postprocess_min_timestamps] = False
    if rel.shape[0]:
        rel = rel[referred[rel[:, 0], rel[:, 1]]]

    min_run = cfg.postprocess_min_run_timestamps
    if min_run > 1 and referred.any():
        n, t = referred.shape
        padded = np.zeros((n, t + 2), dtype=np.int8)
        padded[:, 1:-1] = referred
        edges = np.diff(padded, axis=1)
        r_start, c_start = np.nonzero(edges == 1)
        r_end, c_end = np.nonzero(edges == -1)  # exclusive end; rows ordered identically
        length = c_end - c_start
        short = length < min_run
        if short.any():
            grow = (min_run - length[short]) // 2
            lo = np.maximum(c_start[short] - grow, 0)
            hi = np.minimum(c_end[short] + grow, t)
            delta = np.zeros((n, t + 1), dtype=np.int64)
            np.add.at(delta, (r_start[short], lo), 1)
            np.add.at(delta, (r_start[short], hi), -1)
            referred |= (np.cumsum(delta, axis=1)[:, :t] > 0) & ctx.valid
    return Scenario.from_mask(ctx, referred, rel)
