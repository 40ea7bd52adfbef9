"""Rule-based tagging of one log: the per-log ``N × T`` tag matrices of Table II.

:func:`tag_log` is a pure function from a preprocessed :class:`~scenariominer.data.log.Log` to a
:class:`LogTags`; :meth:`LogTags.to_arrow` and :meth:`LogTags.from_arrow` are the matching
save/load pair used by the store (one row per observed track-timestamp cell).
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from enum import StrEnum
from typing import Any

import numpy as np
import pyarrow as pa
from numpy.typing import NDArray

from scenariominer import errors as _errors
from scenariominer.config.tags import TagConfig
from scenariominer.data.categories import EGO_CATEGORY
from scenariominer.data.log import Log
from scenariominer.tags.actor import latitude_tags, longitude_tags
from scenariominer.tags.interaction import (
    collision_tags,
    distance_tags,
    heading_tags,
    position_tags,
    traj_overlap_tags,
)
from scenariominer.tags.vocab import ABSENT, TAG_FAMILIES, codes_to_names, names_to_codes

__all__ = ["LogTags", "TagTableError", "tag_log"]

CodeArray = NDArray[np.int8]
FloatArray = NDArray[np.float64]

_META_LOG_ID = b"scenariominer.log_id"
_META_TIMESTAMPS = b"scenariominer.timestamps_ns"


class TagTableError(_errors.TagError):
    """A tag table cannot be turned back into :class:`LogTags`; the message names the problem."""


@dataclass(frozen=True, eq=False)
class LogTags:
    """Activity and interaction tags of one log as dense ``tracks × timestamps`` matrices (Table II).

    Tag matrices hold ``int8`` codes into the enums of :mod:`scenariominer.tags.vocab`
    (:data:`~scenariominer.tags.vocab.ABSENT` = -1 where undefined). Interaction tags describe
    each object relative to the ego; the ego's own row is ABSENT for them.

    Attributes:
        log_id: the tagged log.
        track_ids: ``(N,)`` str, ``track_ids[ego_index]`` is the ego.
        categories: ``(N,)`` str, Argoverse 2 category names.
        timestamps_ns: ``(T,)`` int64.
        longitude: ``(N, T)`` :class:`~scenariominer.tags.vocab.LongitudeTag` codes, every track.
        latitude: ``(N, T)`` :class:`~scenariominer.tags.vocab.LatitudeTag` codes, every track.
        collision: ``(N, T)`` :class:`~scenariominer.tags.vocab.CollisionTag` codes.
        heading: ``(N, T)`` :class:`~scenariominer.tags.vocab.HeadingTag` codes.
        position: ``(N, T)`` :class:`~scenariominer.tags.vocab.PositionTag` codes.
        distance: ``(N, T)`` :class:`~scenariominer.tags.vocab.DistanceTag` codes.
        traj_overlap: ``(N, T)`` :class:`~scenariominer.tags.vocab.TrajOverlapTag` codes.
        ttc_s: ``(N, T)`` CTRV time-to-collision with the ego, seconds; ``inf`` when none is
            predicted within the horizon, NaN where undefined.
        distance_m: ``(N, T)`` box-to-box distance to the ego, metres; NaN where undefined.
        ego_index: row of the ego (0 for logs built by this package).
    """

    log_id: str
    track_ids: NDArray[np.str_]
    categories: NDArray[np.str_]
    timestamps_ns: NDArray[np.int64]
    longitude: CodeArray
    latitude: CodeArray
    collision: CodeArray
    heading: CodeArray
    position: CodeArray
    distance: CodeArray
    traj_overlap: CodeArray
    ttc_s: FloatArray
    distance_m: FloatArray
    ego_index: int = 0

    def __post_init__(self) -> None:
        shape = (self.track_ids.shape[0], self.timestamps_ns.shape[0])
        if self.categories.shape != shape[:1]:
            raise ValueError(
                f"LogTags {self.log_id}: categories shape {self.categories.shape} != {shape[:1]}"
            )
        for name in (*TAG_FAMILIES, "ttc_s", "distance_m"):
            arr = getattr(self, name)
            if arr.shape != shape:
                raise ValueError(f"LogTags {self.log_id}: {name} has shape {arr.shape}, expected {shape}")

    @property
    def n_tracks(self) -> int:
        """Number of tracks ``N``, the ego included."""
        return int(self.track_ids.shape[0])

    @property
    def n_timestamps(self) -> int:
        """Number of timestamps ``T``."""
        return int(self.timestamps_ns.shape[0])

    @property
    def valid(self) -> NDArray[np.bool_]:
        """``(N, T)`` True where the track is observed (its actor tags are defined)."""
        return np.asarray(self.longitude != ABSENT, dtype=bool)

    def codes(self, family: str) -> CodeArray:
        """``(N, T)`` codes of a tag family (``longitude``, ``latitude``, ``collision``, ...)."""
        if family not in TAG_FAMILIES:
            raise KeyError(f"unknown tag family {family!r}; known: {list(TAG_FAMILIES)}")
        return getattr(self, family)  # type: ignore[no-any-return]

    def names(self, family: str) -> NDArray[np.object_]:
        """``(N, T)`` tag names (``str``) of a family, ``None`` where undefined."""
        return codes_to_names(TAG_FAMILIES[family], self.codes(family))

    def track_index(self, track_id: str) -> int:
        """Row of ``track_id``; raises ``KeyError`` naming the log when absent."""
        hits = np.flatnonzero(self.track_ids == track_id)
        if hits.size == 0:
            raise KeyError(f"track {track_id!r} is not in the tags of log {self.log_id}")
        return int(hits[0])

    # ------------------------------------------------------------------ long-table round trip
    def to_arrow(self) -> pa.Table:
        """Long table, one row per observed (track, timestamp) cell.

        Columns: ``track_id``, ``category``, ``is_ego``, ``timestamp_ns``, one dictionary-encoded
        string column per tag family (null where undefined, e.g. interaction tags of the ego),
        ``ttc_s`` and ``distance_m``. The log id and the full timestamp axis travel in the schema
        metadata. See :meth:`from_arrow`.
        """
        rows, cols = np.nonzero(self.valid)
        data: dict[str, Any] = {
            "track_id": pa.array(self.track_ids[rows].astype(str)),
            "category": pa.array(self.categories[rows].astype(str)),
            "is_ego": pa.array(rows == self.ego_index),
            "timestamp_ns": pa.array(self.timestamps_ns[cols], type=pa.int64()),
        }
        for family, enum_cls in TAG_FAMILIES.items():
            codes = self.codes(family)[rows, cols]
            indices = pa.array(codes, type=pa.int8(), mask=codes == ABSENT)
            data[family] = pa.DictionaryArray.from_arrays(indices, pa.array([m.value for m in enum_cls]))
        for name in ("ttc_s", "distance_m"):
            values = getattr(self, name)[rows, cols]
            data[name] = pa.array(values, type=pa.float64(), mask=np.isnan(values))
        metadata = {
            _META_LOG_ID: self.log_id.encode(),
            _META_TIMESTAMPS: json.dumps(self.timestamps_ns.tolist()).encode(),
        }
        return pa.table(data).replace_schema_metadata(metadata)

    @classmethod
    def from_arrow(
        cls,
        table: pa.Table,
        *,
        log_id: str | None = None,
        timestamps_ns: NDArray[np.int64] | None = None,
    ) -> LogTags:
        """Rebuild tags from a table written by :meth:`to_arrow` (plain string tag columns work too).

        Args:
            table: the long table.
            log_id: log id; defaults to the schema metadata.
            timestamps_ns: ``(T,)`` timestamp axis; defaults to the schema metadata, else the
                distinct timestamps of the table.

        Raises:
            TagTableError: a column is missing, a tag name is unknown, or no log id is known.
        """
        required = ["track_id", "category", "timestamp_ns", *TAG_FAMILIES, "ttc_s", "distance_m"]
        missing = [c for c in required if c not in table.column_names]
        if missing:
            raise TagTableError(f"tag table lacks column(s) {missing}")
        meta = table.schema.metadata or {}
        if log_id is None:
            if _META_LOG_ID not in meta:
                raise TagTableError("tag table has no log id in its metadata; pass log_id=")
            log_id = meta[_META_LOG_ID].decode()
        track = np.asarray(table.column("track_id").to_numpy(zero_copy_only=False)).astype(str)
        category = np.asarray(table.column("category").to_numpy(zero_copy_only=False)).astype(str)
        ts = np.asarray(table.column("timestamp_ns").to_numpy(zero_copy_only=False)).astype(np.int64)
        if timestamps_ns is None:
            if _META_TIMESTAMPS in meta:
                timestamps_ns = np.asarray(json.loads(meta[_META_TIMESTAMPS].decode()), dtype=np.int64)
            else:
                timestamps_ns = np.unique(ts)
        axis = np.asarray(timestamps_ns, dtype=np.int64)
        col = np.searchsorted(axis, ts)
        if np.any(col >= axis.size) or np.any(axis[np.minimum(col, axis.size - 1)] != ts):
            raise TagTableError(f"log {log_id}: tag table has timestamps outside the timestamp axis")

        # Track order: the ego first, then first appearance (the writer's row order).
        names, first = np.unique(track, return_index=True)
        order = names[np.argsort(first)]
        is_ego = (
            np.asarray(table.column("is_ego").to_numpy(zero_copy_only=False), dtype=bool)
            if "is_ego" in table.column_names
            else category == EGO_CATEGORY
        )
        if is_ego.any():
            ego = track[np.flatnonzero(is_ego)[0]]
            order = np.concatenate([[ego], order[order != ego]])
        row = np.searchsorted(names, track)
        rank = np.empty(names.size, dtype=np.intp)
        rank[np.searchsorted(names, order)] = np.arange(order.size)
        row = rank[row]
        n, t = order.size, axis.size
        cats = np.empty(n, dtype=object)
        cats[row] = category

        arrays: dict[str, Any] = {}
        for family, enum_cls in TAG_FAMILIES.items():
            dense = np.full((n, t), ABSENT, dtype=np.int8)
            dense[row, col] = _column_codes(table.column(family), enum_cls, family)
            arrays[family] = dense
        for name in ("ttc_s", "distance_m"):
            dense_f = np.full((n, t), np.nan)
            dense_f[row, col] = np.asarray(
                table.column(name).to_numpy(zero_copy_only=False), dtype=np.float64
            )
            arrays[name] = dense_f
        return cls(
            log_id=log_id,
            track_ids=order.astype(str),
            categories=cats.astype(str),
            timestamps_ns=axis,
            ego_index=0,
            **arrays,
        )


def _column_codes(column: pa.ChunkedArray, enum_cls: type[StrEnum], family: str) -> CodeArray:
    """Codes of one tag column, dictionary-encoded or plain strings (nulls → ABSENT)."""
    encoded = column.combine_chunks()
    if not pa.types.is_dictionary(encoded.type):
        encoded = encoded.dictionary_encode()
    dictionary = np.asarray(encoded.dictionary.to_pylist(), dtype=object)
    try:
        known = names_to_codes(enum_cls, dictionary, what=f"column {family!r}")
    except ValueError as exc:
        raise TagTableError(str(exc)) from None
    mapped = np.append(known, np.int8(ABSENT))
    indices = encoded.indices.fill_null(len(dictionary)).to_numpy(zero_copy_only=False)
    return np.asarray(mapped[indices], dtype=np.int8)


def tag_log(log: Log, cfg: TagConfig | None = None) -> LogTags:
    """Compute every activity and interaction tag of a preprocessed log.

    Args:
        log: a log after :func:`scenariominer.data.preprocess.preprocess` (smoothed kinematics).
        cfg: thresholds; defaults to :class:`TagConfig` (the paper's values).

    Returns:
        The ``N × T`` tag matrices of Table II.
    """
    cfg = cfg or TagConfig()
    collision, ttc = collision_tags(log, cfg)
    distance, distance_m = distance_tags(log, cfg)
    return LogTags(
        log_id=log.log_id,
        track_ids=log.track_ids,
        categories=log.categories,
        timestamps_ns=log.timestamps_ns,
        longitude=longitude_tags(log, cfg),
        latitude=latitude_tags(log, cfg),
        collision=collision,
        heading=heading_tags(log),
        position=position_tags(log),
        distance=distance,
        traj_overlap=traj_overlap_tags(log, cfg),
        ttc_s=ttc,
        distance_m=distance_m,
        ego_index=log.ego_index,
    )
