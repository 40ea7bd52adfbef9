"""Use cases over the corpus as a whole: ``ingest``, ``info``, ``synth`` (and opening a store).

Typical use::

    from scenariominer import api
    store = api.open_store("~/scenarios")
    report = api.ingest(["/data/av2/train"], store)
    print(report.summary())
"""

from __future__ import annotations

import json
import time
from collections.abc import Sequence
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

from scenariominer.api._exec import executor_for
from scenariominer.config import Config, load_config
from scenariominer.data.ingest import SourceResult, ingest_sources
from scenariominer.data.sources import LogReader
from scenariominer.progress import NullProgress, Progress, step
from scenariominer.store import ScenarioStore, StoreCheck, StoreInfo, StoreRef, resolve_store_path

#: The default process executor starts a pool for ``ingest`` only with at least this many workers.
_POOL_MIN_WORKERS = 3

if TYPE_CHECKING:
    from scenariominer.exec import Executor
    from scenariominer.synth import SynthResult

__all__ = [
    "IngestReport",
    "SourceResult",
    "find_sample_av2",
    "info",
    "ingest",
    "open_existing_store",
    "open_store",
    "store_check",
    "store_vacuum",
    "synth",
]


def open_store(path: str | Path | None = None, config: Config | None = None) -> ScenarioStore:
    """Open (creating if needed) the scenario store at ``path``.

    ``None`` resolves, in order, ``$SCENARIOMINER_STORE``, ``config.store.path`` and the
    per-user data directory.
    """
    config = config or load_config()
    return ScenarioStore.open(resolve_store_path(path, config.store.path), create=True)


def open_existing_store(path: str | Path | None = None, config: Config | None = None) -> ScenarioStore:
    """Open the scenario store at ``path`` (resolved as in :func:`open_store`) without creating it.

    Raises:
        NotAStoreError: there is no store at the resolved path (read-only commands never create one).
    """
    config = config or load_config()
    return ScenarioStore.open(resolve_store_path(path, config.store.path), create=False)


@dataclass(frozen=True)
class IngestReport:
    """Result of :func:`ingest`: one entry per source plus a summary of the store afterwards."""

    sources: tuple[SourceResult, ...]
    store: StoreInfo
    seconds: float
    n_frames_ingested: int = 0
    n_logs_ingested: int = 0
    failed: tuple[SourceResult, ...] = field(default_factory=tuple)

    @property
    def n_ingested(self) -> int:
        """Sources (re)written in this run."""
        return sum(r.status == "ingested" for r in self.sources)

    @property
    def n_skipped(self) -> int:
        """Sources skipped because their content hash is unchanged."""
        return sum(r.status == "skipped" for r in self.sources)

    def to_json(self) -> str:
        """The report as JSON (for scripts)."""
        return json.dumps(asdict(self), default=str, indent=2)


def ingest(
    paths: Sequence[str | Path],
    store: ScenarioStore,
    config: Config | None = None,
    *,
    force: bool = False,
    readers: Sequence[LogReader] | None = None,
    progress: Progress | None = None,
    executor: Executor | None = None,
) -> IngestReport:
    """Read, validate, preprocess and store every log found under ``paths``.

    Ingestion is incremental and atomic per source: a source whose content hash (and the
    preprocessing settings) is unchanged is skipped; a source that fails to read is reported
    and leaves the store untouched, while the rest of the batch still lands.

    Args:
        paths: Argoverse 2 log folders or dataset roots, highD recordings, tabular files.
        store: destination store.
        config: configuration (defaults to :func:`load_config`).
        force: re-ingest even when the content hash is unchanged.
        readers: log readers to try (defaults to the built-in adapters).
        progress: progress sink (a Rich bar in the CLI).
        executor: where sources are read and committed (default: ``config.exec``, a local
            process pool, or this process for a batch under ``exec.min_ingest_bytes``); see
            :mod:`scenariominer.exec`.

    Bad input never aborts the batch: a missing path, a path with nothing recognisable, and a source
    that cannot be read or fails validation are reported in ``failed`` with the cause, and every
    other source still lands.
    """
    config = config or load_config()
    t0 = time.perf_counter()
    default_pool = executor is None and config.exec.executor == "process"
    # A small batch runs here unless the caller chose the executor: workers take longer to start.
    small_below = config.exec.min_ingest_bytes if default_pool else 0
    with executor_for(config, executor) as runner:
        # Two workers gain nothing over this process, which overlaps each commit with the next read
        # (benchmarks/ingest.py: 100 real logs in 5.2 s here, 5.4-5.7 s with two workers).
        in_process = default_pool and runner.workers < _POOL_MIN_WORKERS
        results = ingest_sources(
            paths, store, config, force=force, readers=readers, progress=progress,
            executor=None if in_process else runner, reopen=StoreRef.of(store), min_pool_bytes=small_below,
        )  # fmt: skip
    written = [r for r in results if r.status == "ingested"]
    return IngestReport(
        sources=tuple(results),
        store=store.info(),
        seconds=time.perf_counter() - t0,
        n_frames_ingested=sum(r.n_frames for r in written),
        n_logs_ingested=sum(len(r.log_ids) for r in written),
        failed=tuple(r for r in results if r.status == "failed"),
    )


def info(store: ScenarioStore) -> StoreInfo:
    """Summary of what a store holds."""
    return store.info()


def synth(
    out_dir: str | Path,
    n: int,
    *,
    seed: int = 0,
    categories: Sequence[str] | None = None,
    progress: Progress | None = None,
) -> SynthResult:
    """Write ``n`` labelled synthetic scenarios in the Argoverse 2 format plus ``labels.csv``.

    See :func:`scenariominer.synth.generate`; categories cycle through ``categories``
    (all of cut_in, lead_brake, approach_stop, ped_crossing, obj_crossing, left_oppo,
    right_ped, not_relevant by default).
    """
    from scenariominer.synth import generate

    if n < 1:
        raise ValueError(f"n must be at least 1, got {n}")
    progress = progress or NullProgress()
    with step(progress, "synthesise", n) as bar:
        return generate(
            Path(out_dir), n, seed=seed, categories=categories, progress=lambda _done: bar.advance(1)
        )


def find_sample_av2() -> Path | None:
    """The Argoverse 2 sample data shipped beside a source checkout (``../shared/data/av2``), if any.

    Looked up relative to the current directory and to the package's source tree.
    """
    here = Path(__file__).resolve()
    candidates = [Path.cwd().parent / "shared" / "data" / "av2", Path.cwd() / "shared" / "data" / "av2"]
    candidates += [parent.parent / "shared" / "data" / "av2" for parent in here.parents[:4]]
    for c in candidates:
        if c.is_dir() and any(c.glob("*/city_SE3_egovehicle.feather")):
            return c
    return None


def store_check(path: str | Path | None = None, config: Config | None = None) -> StoreCheck:
    """Leftovers of killed writers and missing files of the store at ``path`` (changes nothing)."""
    return open_existing_store(path, config).check()


def store_vacuum(path: str | Path | None = None, config: Config | None = None) -> int:
    """Remove the leftovers :func:`store_check` lists; returns how many paths were removed."""
    return open_existing_store(path, config).vacuum()
