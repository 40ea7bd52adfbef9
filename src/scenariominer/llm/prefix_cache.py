"""Evaluated prompt prefixes of the embedded model, kept on disk across processes.

Every feature sends a long fixed system message (the mining reference is about 4,500 tokens, the
braking guide about 1,000) followed by a short per-call part. llama.cpp already reuses the longest
common token prefix of consecutive calls *within* a process; this module makes the first call of a
*new* process as cheap as a later one: the context state after the system part (its KV cache plus
the token ids) is written once with llama.cpp's own state file format, keyed by everything that
makes the state valid, and restored in any later process before the call, so only the per-call
tokens are evaluated.

Key (SHA-256 of): the model identity (content hash of the GGUF file, or its name, size and mtime),
the context size, the KV-cache types, the llama.cpp build, and the prefix's token ids. A file whose
key differs is never loaded; a file llama.cpp refuses is deleted and the prefix is evaluated again.
Files are written to a temporary name and renamed, so a crash never leaves a half-written state
under a valid key; the directory is pruned to ``max_bytes`` (least recently used first).
"""

from __future__ import annotations

import contextlib
import ctypes
import hashlib
import json
import os
import tempfile
from collections.abc import Sequence
from dataclasses import dataclass
from enum import StrEnum
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt

__all__ = [
    "PREFIX_DIRNAME",
    "PrefixOutcome",
    "PrefixSource",
    "PrefixStateStore",
    "common_prefix_len",
]

#: Sub-directory of the LLM cache directory holding the state files.
PREFIX_DIRNAME = "prefix-states"
_SUFFIX = ".llstate"


class PrefixSource(StrEnum):
    """Where the evaluated system prefix of a call came from.

    Attributes:
        MEMORY: the context already held it (an earlier call of this process).
        DISK: restored from a state file written by an earlier process.
        EVALUATED: evaluated now (and saved for later processes when the store is on).
        NONE: no reusable prefix (no system message, or shorter than the minimum).
    """

    MEMORY = "memory"
    DISK = "disk"
    EVALUATED = "evaluated"
    NONE = "none"


@dataclass(frozen=True)
class PrefixOutcome:
    """What preparing the prefix of one call did.

    Attributes:
        source: see :class:`PrefixSource`.
        n_tokens: tokens of the shared prefix.
        seconds: wall time spent restoring or evaluating it (0 for ``MEMORY``/``NONE``).
        saved_bytes: size of the state file written (0 when none was written).
    """

    source: PrefixSource
    n_tokens: int = 0
    seconds: float = 0.0
    saved_bytes: int = 0


def common_prefix_len(
    a: Sequence[int] | npt.NDArray[np.intc], b: Sequence[int] | npt.NDArray[np.intc]
) -> int:
    """Number of leading tokens ``a`` and ``b`` share."""
    x, y = np.asarray(a, dtype=np.int64), np.asarray(b, dtype=np.int64)
    n = min(x.size, y.size)
    differ = np.flatnonzero(x[:n] != y[:n])
    return int(differ[0]) if differ.size else n


class PrefixStateStore:
    """A directory of llama.cpp context states, one per (model, settings, prefix tokens).

    Args:
        directory: where the state files live (created on the first save).
        model_identity: identity of the model file (content hash preferred).
        settings: anything else that makes a state valid (context size, KV types, build).
        max_bytes: prune least-recently-used files beyond this total size.
    """

    def __init__(
        self,
        directory: Path,
        model_identity: str,
        settings: dict[str, Any],
        *,
        max_bytes: int = 4 << 30,
    ) -> None:
        self.directory = Path(directory)
        self.model_identity = model_identity
        self.settings = dict(settings)
        self.max_bytes = max_bytes

    def key(self, tokens: Sequence[int]) -> str:
        """SHA-256 (hex) of the model identity, the settings and the token ids."""
        head = json.dumps([self.model_identity, self.settings], sort_keys=True, default=str)
        h = hashlib.sha256(head.encode("utf-8"))
        h.update(b"\0")
        h.update(",".join(str(int(t)) for t in tokens).encode("ascii"))
        return h.hexdigest()

    def path(self, tokens: Sequence[int]) -> Path:
        """File that holds (or would hold) the state after ``tokens``."""
        return self.directory / f"{self.key(tokens)[:32]}{_SUFFIX}"

    def restore(self, llama: Any, tokens: Sequence[int]) -> bool:
        """Load the state after ``tokens`` into ``llama`` (a ``llama_cpp.Llama``); ``False`` if absent.

        On success the context holds exactly ``tokens``: llama-cpp-python's own prefix matching
        then evaluates only what follows them. A file llama.cpp refuses (another build, a torn
        write from an old version) is deleted.
        """
        import llama_cpp

        path = self.path(tokens)
        if not path.is_file():
            return False
        capacity = len(tokens)
        out = (llama_cpp.llama_token * capacity)()
        n_out = ctypes.c_size_t(0)
        ok = llama_cpp.llama_state_load_file(llama.ctx, os.fsencode(path), out, capacity, ctypes.byref(n_out))
        restored = list(out[: n_out.value]) if ok else []
        if not ok or restored != [int(t) for t in tokens]:
            with contextlib.suppress(OSError):
                path.unlink()
            llama.reset()
            return False
        llama.input_ids[: len(tokens)] = tokens
        llama.n_tokens = len(tokens)
        with contextlib.suppress(OSError):
            os.utime(path)  # least-recently-used order for pruning
        return True

    def save(self, llama: Any, tokens: Sequence[int]) -> int:
        """Write the state of ``llama``, which must hold exactly ``tokens``; returns the file size.

        Failures to write (full disk, read-only cache) are not errors: the next process evaluates
        the prefix again.
        """
        import llama_cpp

        self.directory.mkdir(parents=True, exist_ok=True)
        target = self.path(tokens)
        arr = (llama_cpp.llama_token * len(tokens))(*[int(t) for t in tokens])
        fd, tmp = tempfile.mkstemp(dir=self.directory, prefix=".tmp-", suffix=_SUFFIX)
        os.close(fd)
        try:
            if not llama_cpp.llama_state_save_file(llama.ctx, os.fsencode(tmp), arr, len(tokens)):
                return 0
            os.replace(tmp, target)
        except OSError:
            return 0
        finally:
            with contextlib.suppress(OSError):
                os.unlink(tmp)
        size = target.stat().st_size
        self.prune(keep=target)
        return size

    def files(self) -> list[Path]:
        """State files in the directory, most recently used first."""
        if not self.directory.is_dir():
            return []
        found = [p for p in self.directory.iterdir() if p.suffix == _SUFFIX and not p.name.startswith(".")]
        return sorted(found, key=lambda p: p.stat().st_mtime, reverse=True)

    def prune(self, keep: Path | None = None) -> int:
        """Delete least-recently-used files until the total is within ``max_bytes``; returns the count."""
        total = 0
        removed = 0
        for p in self.files():
            size = p.stat().st_size
            if total + size > self.max_bytes and p != keep:
                with contextlib.suppress(OSError):
                    p.unlink()
                    removed += 1
                continue
            total += size
        return removed
