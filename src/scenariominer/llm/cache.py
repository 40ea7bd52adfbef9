"""On-disk cache of chat answers and embedding vectors (SQLite, safe across threads and processes).

Keys are SHA-256 digests of everything that determines a result (backend, model, full messages,
schema, parameters; or backend, model, text for a vector), computed by the callers. The database
runs in WAL mode so several processes can read while one writes; within a process one connection
is shared under a lock.
"""

from __future__ import annotations

import sqlite3
import threading
import time
from collections.abc import Iterable, Sequence
from pathlib import Path

import numpy as np
import numpy.typing as npt

from scenariominer.llm.base import Completion

__all__ = ["CACHE_FILENAME", "ResponseCache", "resolve_cache_dir"]

CACHE_FILENAME = "llm-cache.sqlite3"
_SQLITE_MAX_VARS = 500

_SCHEMA = """
CREATE TABLE IF NOT EXISTS chat (
    key TEXT PRIMARY KEY,
    backend TEXT NOT NULL,
    model TEXT NOT NULL,
    completion TEXT NOT NULL,
    created_s REAL NOT NULL
);
CREATE TABLE IF NOT EXISTS embedding (
    key TEXT PRIMARY KEY,
    backend TEXT NOT NULL,
    model TEXT NOT NULL,
    dim INTEGER NOT NULL,
    vector BLOB NOT NULL,
    created_s REAL NOT NULL
);
"""


def resolve_cache_dir(cache_dir: str | Path = "") -> Path:
    """Return the configured cache directory, or ``platformdirs.user_cache_dir("scenariominer")/llm``."""
    if str(cache_dir):
        return Path(cache_dir).expanduser()
    import platformdirs

    return Path(platformdirs.user_cache_dir("scenariominer")) / "llm"


class ResponseCache:
    """A key-value store of completions and float32 vectors in one SQLite file.

    Args:
        path: database file (created with its parent directories when missing).
    """

    def __init__(self, path: str | Path) -> None:
        self.path = Path(path)
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self._lock = threading.Lock()
        self._conn = sqlite3.connect(self.path, timeout=30.0, check_same_thread=False, isolation_level=None)
        with self._lock:
            self._conn.execute("PRAGMA journal_mode=WAL")
            self._conn.execute("PRAGMA synchronous=NORMAL")
            self._conn.executescript(_SCHEMA)

    @classmethod
    def in_dir(cls, cache_dir: str | Path = "") -> ResponseCache:
        """Open ``CACHE_FILENAME`` in :func:`resolve_cache_dir` of ``cache_dir``."""
        return cls(resolve_cache_dir(cache_dir) / CACHE_FILENAME)

    # -- chat ---------------------------------------------------------------------------------

    def get_completion(self, key: str) -> Completion | None:
        """Return the cached completion for ``key`` (marked ``cached=True``), or ``None``."""
        with self._lock:
            row = self._conn.execute("SELECT completion FROM chat WHERE key = ?", (key,)).fetchone()
        return None if row is None else Completion.from_json(row[0], cached=True)

    def put_completion(self, key: str, backend: str, model: str, completion: Completion) -> None:
        """Store ``completion`` under ``key`` (replacing an older entry)."""
        with self._lock:
            self._conn.execute(
                "INSERT OR REPLACE INTO chat (key, backend, model, completion, created_s) VALUES (?,?,?,?,?)",
                (key, backend, model, completion.to_json(), time.time()),
            )

    # -- embeddings ---------------------------------------------------------------------------

    def get_vectors(self, keys: Sequence[str]) -> dict[str, npt.NDArray[np.float32]]:
        """Return the cached vectors for those of ``keys`` that are present; each ``(D,)`` float32."""
        found: dict[str, npt.NDArray[np.float32]] = {}
        unique = list(dict.fromkeys(keys))
        for start in range(0, len(unique), _SQLITE_MAX_VARS):
            chunk = unique[start : start + _SQLITE_MAX_VARS]
            marks = ",".join("?" * len(chunk))
            with self._lock:
                rows = self._conn.execute(
                    f"SELECT key, dim, vector FROM embedding WHERE key IN ({marks})", chunk
                ).fetchall()
            for key, dim, blob in rows:
                vec = np.frombuffer(blob, dtype=np.float32)
                if vec.shape != (dim,):  # a truncated row: treat as a miss, it will be rewritten
                    continue
                found[key] = vec.copy()
        return found

    def put_vectors(
        self, backend: str, model: str, items: Iterable[tuple[str, npt.NDArray[np.float32]]]
    ) -> None:
        """Store ``(key, vector)`` pairs; vectors are ``(D,)`` and stored as float32."""
        now = time.time()
        rows = [
            (key, backend, model, int(v.shape[0]), np.ascontiguousarray(v, dtype=np.float32).tobytes(), now)
            for key, v in items
        ]
        if not rows:
            return
        with self._lock:
            self._conn.execute("BEGIN")
            try:
                self._conn.executemany(
                    "INSERT OR REPLACE INTO embedding (key, backend, model, dim, vector, created_s) "
                    "VALUES (?,?,?,?,?,?)",
                    rows,
                )
            except BaseException:
                self._conn.execute("ROLLBACK")
                raise
            self._conn.execute("COMMIT")

    # -- maintenance --------------------------------------------------------------------------

    def counts(self) -> tuple[int, int]:
        """Return the number of cached ``(completions, vectors)``."""
        with self._lock:
            n_chat = self._conn.execute("SELECT COUNT(*) FROM chat").fetchone()[0]
            n_vec = self._conn.execute("SELECT COUNT(*) FROM embedding").fetchone()[0]
        return int(n_chat), int(n_vec)

    def clear(self) -> None:
        """Delete every cached entry."""
        with self._lock:
            self._conn.execute("DELETE FROM chat")
            self._conn.execute("DELETE FROM embedding")

    def close(self) -> None:
        """Close the database connection."""
        with self._lock:
            self._conn.close()

    def __enter__(self) -> ResponseCache:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
