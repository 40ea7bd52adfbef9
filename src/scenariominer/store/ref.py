"""A picklable reference to a store, for work done in other processes or on other machines."""

from __future__ import annotations

import threading
from dataclasses import dataclass

from scenariominer.data.log import Log
from scenariominer.store.store import ScenarioStore

__all__ = ["StoreRef"]

_OPEN: dict[str, ScenarioStore] = {}
_LOCK = threading.Lock()


@dataclass(frozen=True)
class StoreRef:
    """The root of an existing store; :meth:`open` gives this process's handle on it.

    A worker opens the store once and keeps the handle for its later tasks. The root must be the
    same path for the driver and every worker (a shared file system on a cluster).
    """

    root: str

    @classmethod
    def of(cls, store: ScenarioStore) -> StoreRef:
        """The reference of an open store."""
        return cls(str(store.root))

    def open(self) -> ScenarioStore:
        """The handle of this process on the store (never creates one)."""
        with _LOCK:
            store = _OPEN.get(self.root)
            if store is None:
                store = _OPEN[self.root] = ScenarioStore.open(self.root, create=False)
            return store

    def load_log(self, log_id: str) -> Log:
        """Load one log from the store (a picklable ``log id → log`` function for workers)."""
        return self.open().load_log(log_id)

    def __call__(self) -> ScenarioStore:
        """Same as :meth:`open` (a ``Callable[[], LogSink]`` for the ingestion loop)."""
        return self.open()
