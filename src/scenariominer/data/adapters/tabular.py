"""Generic tabular adapter: fleet data as a long table in Parquet or CSV (``docs/tabular-schema.md``).

One row is one object observed at one timestamp. A file may hold many logs (split by ``log_id``);
every log needs exactly one ego track, marked by ``is_ego`` or by the category ``EGO_VEHICLE``.
Positions are in any fixed right-handed world frame of the log, in metres; yaw is counter-clockwise
from that frame's x axis.

Reading goes through :func:`~scenariominer.data.log.build_log`, so every file gets the same checks
and documented repairs as the other formats: unsorted rows are sorted, rows with a NaN position,
yaw or size are dropped (with a note), tracks with fewer than ``min_track_frames`` observations are
dropped (with a note), conflicting duplicate (track, timestamp) rows and unknown categories are
errors naming the file and the log.
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator, Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np
import pyarrow as pa
import pyarrow.compute as pc
import pyarrow.csv as pacsv
import pyarrow.parquet as pq
from numpy.typing import NDArray

from scenariominer.config import Config
from scenariominer.data.categories import EGO_CATEGORY, UnknownCategoryError, canonical_category
from scenariominer.data.log import STATE_FIELDS, Log, LogFormatError, build_log
from scenariominer.data.sources import LogSource, check_delimiter

__all__ = [
    "OPTIONAL_COLUMNS",
    "REQUIRED_COLUMNS",
    "TABULAR_SUFFIXES",
    "TabularReader",
    "read_tabular",
    "write_tabular",
]

#: Columns every tabular file must have (plus one of ``timestamp_ns`` / ``timestamp_s``).
REQUIRED_COLUMNS: tuple[str, ...] = (
    "log_id",
    "track_id",
    "category",
    "x_m",
    "y_m",
    "yaw_rad",
    "length_m",
    "width_m",
)
#: Time columns: ``timestamp_ns`` (int64 nanoseconds) is preferred over ``timestamp_s`` (float seconds).
TIME_COLUMNS: tuple[str, ...] = ("timestamp_ns", "timestamp_s")
#: Columns read when present; velocities/accelerations are derived from positions when absent.
OPTIONAL_COLUMNS: tuple[str, ...] = (
    "z_m",
    "height_m",
    "vx_mps",
    "vy_mps",
    "ax_mps2",
    "ay_mps2",
    "is_ego",
)
#: File name endings recognised as tabular logs.
TABULAR_SUFFIXES: tuple[str, ...] = (".parquet", ".pq", ".csv")

_STRING_COLUMNS = ("log_id", "track_id", "category")
_FLOAT_COLUMNS = tuple(
    c for c in (*REQUIRED_COLUMNS, *OPTIONAL_COLUMNS) if c.endswith(("_m", "_rad", "_mps", "_mps2"))
)
_SCHEMA_HINT = (
    f"expected columns {list(REQUIRED_COLUMNS)} and one of {list(TIME_COLUMNS)}; optional "
    f"{list(OPTIONAL_COLUMNS)} (see docs/tabular-schema.md)"
)
# highD's own CSVs are read by the highD adapter, never as tabular files.
_HIGHD_ENDINGS = ("_tracks.csv", "_tracksMeta.csv", "_recordingMeta.csv")


def _is_tabular_file(path: Path) -> bool:
    name = path.name
    if not name.lower().endswith(TABULAR_SUFFIXES) or name.startswith("."):
        return False
    prefix, _, _rest = name.partition("_")
    return not (prefix.isdigit() and name.endswith(_HIGHD_ENDINGS))


def _column_names(path: Path) -> list[str]:
    if path.suffix.lower() in (".parquet", ".pq"):
        try:
            return list(pq.read_schema(path).names)
        except (pa.ArrowInvalid, OSError) as exc:
            raise LogFormatError(path, f"not a readable Parquet file ({exc})") from None
    try:
        with path.open(encoding="utf-8-sig", newline="") as fh:
            line = fh.readline()
    except OSError as exc:
        raise LogFormatError(path, f"cannot read file ({exc.strerror or exc})") from None
    except UnicodeDecodeError:
        raise LogFormatError(path, "not a text CSV file (cannot decode as UTF-8)") from None
    if not line.strip():
        raise LogFormatError(path, f"empty file: {_SCHEMA_HINT}")
    check_delimiter(path, line)
    names = [c.strip("\r\n").strip('"') for c in line.split(",")]
    known = {*REQUIRED_COLUMNS, *TIME_COLUMNS, *OPTIONAL_COLUMNS}
    for name in names:
        if name != name.strip() and name.strip() in known:
            # the CSV reader matches names exactly: the column would be missing or misread
            raise LogFormatError(path, f"column name {name!r} has spaces around it; name it {name.strip()!r}")
    return names


def _read_table(path: Path) -> pa.Table:
    """Read the schema's columns of ``path`` with canonical Arrow types."""
    names = _column_names(path)
    missing = [c for c in REQUIRED_COLUMNS if c not in names]
    if not any(c in names for c in TIME_COLUMNS):
        missing.append("timestamp_ns (or timestamp_s)")
    if missing:
        raise LogFormatError(path, f"missing column(s) {missing}; {_SCHEMA_HINT}")
    time_col = "timestamp_ns" if "timestamp_ns" in names else "timestamp_s"
    wanted = [c for c in (*REQUIRED_COLUMNS, time_col, *OPTIONAL_COLUMNS) if c in names]
    types: dict[str, Any] = {c: pa.string() for c in _STRING_COLUMNS}
    types.update({c: pa.float64() for c in _FLOAT_COLUMNS})
    types.update(timestamp_ns=pa.int64(), timestamp_s=pa.float64(), is_ego=pa.bool_())
    try:
        if path.suffix.lower() in (".parquet", ".pq"):
            table = pq.read_table(path, columns=wanted)
            table = pa.table({c: table.column(c).cast(types[c]) for c in wanted})
        else:
            table = pacsv.read_csv(
                path,
                convert_options=pacsv.ConvertOptions(
                    include_columns=wanted,
                    column_types={c: types[c] for c in wanted},
                    strings_can_be_null=True,
                ),
            )
    except (pa.ArrowInvalid, pa.ArrowNotImplementedError, pa.ArrowKeyError, OSError) as exc:
        raise LogFormatError(path, f"cannot read the table ({exc}); {_SCHEMA_HINT}") from None
    if table.num_rows == 0:
        raise LogFormatError(path, "the table has no rows")
    for name in ("log_id", "track_id", "category", time_col):
        nulls = table.column(name).null_count
        if nulls:
            raise LogFormatError(path, f"column {name!r} has {nulls} empty value(s)")
    return table


def _numpy(table: pa.Table, name: str) -> NDArray[Any]:
    col = table.column(name)
    if pa.types.is_boolean(col.type):
        return np.asarray(pc.fill_null(col, False).to_numpy(zero_copy_only=False), dtype=bool)
    return np.asarray(col.to_numpy(zero_copy_only=False))


def read_tabular(
    path: str | Path,
    *,
    min_track_frames: int = 2,
    source_hash: str = "",
    category_aliases: Mapping[str, str] | None = None,
) -> Iterator[Log]:
    """Read every log of a tabular file, in ascending ``log_id`` order.

    Args:
        path: a ``.parquet``/``.pq`` or ``.csv`` file following ``docs/tabular-schema.md``.
        min_track_frames: tracks with fewer observations are dropped (with a note).
        source_hash: content hash stored on each log.
        category_aliases: extra lower-case alias → Argoverse 2 category mapping.

    Raises:
        LogFormatError: naming the file (and log) for missing columns, unreadable values, empty
            ids or times, no or several egos, conflicting duplicates or unknown categories.
    """
    path = Path(path)
    table = _read_table(path)
    cols = {name: _numpy(table, name) for name in table.column_names}
    if "timestamp_ns" in cols:
        t_ns = cols["timestamp_ns"].astype(np.int64)
    else:
        t_s = cols["timestamp_s"].astype(np.float64)
        if not np.all(np.isfinite(t_s)):
            raise LogFormatError(
                path, f"column 'timestamp_s' has {int((~np.isfinite(t_s)).sum())} NaN value(s)"
            )
        t_ns = np.rint(t_s * 1e9).astype(np.int64)
    log_ids = cols["log_id"].astype(str)
    track_ids = cols["track_id"].astype(str)
    categories = cols["category"].astype(str)
    is_ego = cols.get("is_ego")
    fields = {name: cols[name].astype(np.float64) for name in STATE_FIELDS if name in cols}

    names, inverse = np.unique(log_ids, return_inverse=True)
    order = np.argsort(inverse, kind="stable")
    bounds = np.searchsorted(inverse[order], np.arange(names.size + 1))
    for k, log_id in enumerate(names.tolist()):
        rows = order[bounds[k] : bounds[k + 1]]
        ego_id = _ego_track(
            path, log_id, track_ids[rows], categories[rows], None if is_ego is None else is_ego[rows]
        )
        try:
            yield build_log(
                log_id=log_id,
                track_id=track_ids[rows],
                category=categories[rows],
                timestamp_ns=t_ns[rows],
                fields={name: values[rows] for name, values in fields.items()},
                ego_track_id=ego_id,
                source=path,
                dataset="tabular",
                source_hash=source_hash,
                category_aliases=category_aliases,
                min_track_frames=min_track_frames,
            )
        except LogFormatError as exc:
            raise LogFormatError(path, f"log {log_id!r}: {exc.problem}") from None


def _ego_track(
    path: Path,
    log_id: str,
    track_ids: NDArray[np.str_],
    categories: NDArray[np.str_],
    is_ego: NDArray[np.bool_] | None,
) -> str | None:
    """Return the ego's track id from ``is_ego`` (``None``: let the category ``EGO_VEHICLE`` decide)."""
    if is_ego is None or not is_ego.any():
        return None
    marked = np.unique(track_ids[is_ego])
    if marked.size > 1:
        raise LogFormatError(path, f"log {log_id!r}: is_ego marks several tracks {marked[:5].tolist()}")
    ego = str(marked[0])
    uniq = np.unique(categories)
    ego_named = []
    for name in uniq.tolist():
        try:
            if canonical_category(name) == EGO_CATEGORY:
                ego_named.append(name)
        except UnknownCategoryError:
            continue  # reported with the file name by build_log
    if ego_named:
        others = np.unique(track_ids[np.isin(categories, ego_named) & (track_ids != ego)])
        if others.size:
            raise LogFormatError(
                path,
                f"log {log_id!r}: is_ego marks track {ego!r} but track(s) {others[:5].tolist()} "
                f"have category {EGO_CATEGORY}",
            )
    return ego


class TabularReader:
    """Reads long-format Parquet/CSV fleet data (``docs/tabular-schema.md``); one source per file."""

    format = "tabular"

    def discover(self, path: Path) -> list[LogSource]:
        """Find ``.parquet``/``.pq``/``.csv`` files: ``path`` itself or every one under the folder.

        highD's own files (``NN_tracks.csv`` and its meta files) and hidden files are skipped.
        """
        if path.is_file():
            files = [path] if _is_tabular_file(path) else []
        elif path.is_dir():
            files = sorted(
                p
                for p in path.rglob("*")
                if p.is_file()
                and _is_tabular_file(p)
                and not any(part.startswith(".") for part in p.relative_to(path).parts)
            )
        else:
            files = []
        out = []
        for f in files:
            resolved = f.resolve()
            out.append(LogSource(key=str(resolved), format=self.format, path=resolved, files=(resolved,)))
        return out

    def read(self, source: LogSource, config: Config) -> Iterator[Log]:
        """Yield the logs of the file, in ascending ``log_id`` order."""
        yield from read_tabular(
            source.path,
            min_track_frames=config.ingest.min_track_frames,
            source_hash=source.content_hash(),
        )


def write_tabular(logs: Iterable[Log], path: str | Path) -> Path:
    """Write logs as one long table (Parquet for ``.parquet``/``.pq``, else ``.csv``).

    Columns: ``log_id, track_id, timestamp_ns, category, is_ego`` and every state field
    (``x_m`` ... ``ay_mps2``), one row per valid (track, timestamp) cell. Reading the file back
    with :func:`read_tabular` gives the same logs (categories, positions, sizes, kinematics).

    Raises:
        ValueError: no logs, duplicate log ids, or an unsupported file suffix.
    """
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix not in TABULAR_SUFFIXES:
        raise ValueError(
            f"unsupported tabular file suffix {path.suffix!r}; use one of {list(TABULAR_SUFFIXES)}"
        )
    tables = []
    seen: set[str] = set()
    for log in logs:
        if log.log_id in seen:
            raise ValueError(f"log id {log.log_id!r} occurs twice")
        seen.add(log.log_id)
        t = log.to_arrow()
        t = t.add_column(0, "log_id", pa.array([log.log_id] * t.num_rows, type=pa.string()))
        tables.append(t.select(_WRITE_ORDER))
    if not tables:
        raise ValueError("write_tabular needs at least one log")
    table = pa.concat_tables(tables)
    path.parent.mkdir(parents=True, exist_ok=True)
    if suffix == ".csv":
        pacsv.write_csv(table, path)
    else:
        pq.write_table(table, path)
    return path


_WRITE_ORDER: Sequence[str] = ("log_id", "track_id", "timestamp_ns", "category", "is_ego", *STATE_FIELDS)
