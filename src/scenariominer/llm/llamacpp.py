"""The embedded chat backend: llama-cpp-python running a GGUF file on the CPU.

Structured requests are decoded under a grammar compiled from the JSON schema, so the answer is
always syntactically valid JSON of the requested shape (the client still validates it). The
model is loaded on the first call; llama.cpp is not thread-safe, so calls are serialised.
"""

from __future__ import annotations

import os
import threading
import time
from typing import Any

from scenariominer.llm.base import ChatRequest, Completion
from scenariominer.llm.errors import INSTALL_LLM_HINT, BackendError, MissingDependencyError
from scenariominer.llm.model_files import ModelFile

__all__ = ["LlamaCppBackend", "default_n_threads"]


def default_n_threads() -> int:
    """CPU cores this process may run on."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # pragma: no cover - not Linux
        return max(1, os.cpu_count() or 1)


class LlamaCppBackend:
    """Chat backend over a GGUF model loaded in-process with llama-cpp-python.

    Args:
        model_file: the GGUF file (see :func:`~scenariominer.llm.model_files.resolve_model_file`).
        model_name: display label of the model.
        n_ctx: context window in tokens (prompt plus answer).
        n_threads: CPU threads; 0 uses every core the process may run on.
        seed: sampling seed of the context.

    Attributes:
        load_time_s: seconds the model took to load (``None`` before the first call).
    """

    name = "llamacpp"
    concurrent = False

    def __init__(
        self,
        model_file: ModelFile,
        *,
        model_name: str = "",
        n_ctx: int = 8192,
        n_threads: int = 0,
        seed: int = 0,
    ) -> None:
        self.model_file = model_file
        self.model_name = model_name or model_file.path.stem
        self.n_ctx = n_ctx
        self.n_threads = n_threads or default_n_threads()
        self.seed = seed
        self.load_time_s: float | None = None
        self._llama: Any = None
        self._lock = threading.Lock()

    @property
    def model(self) -> str:
        """Model identity for cache keys: label plus content hash (or size and mtime if not hashed)."""
        f = self.model_file
        if f.sha256:
            return f"{self.model_name}@sha256:{f.sha256[:16]}"
        st = f.path.stat()
        return f"{self.model_name}@{f.path.name}:{st.st_size}:{st.st_mtime_ns}"

    def load(self) -> float:
        """Load the model now (otherwise the first call does); returns the load time in seconds.

        Raises:
            MissingDependencyError: llama-cpp-python is not installed.
            BackendError: llama.cpp could not load the file.
        """
        with self._lock:
            return self._load_locked()

    def _load_locked(self) -> float:
        if self._llama is not None:
            return self.load_time_s or 0.0
        # llama.cpp's OpenMP workers spin while idle by default; on a shared or oversubscribed CPU
        # that is several times slower (measured 11.3 s vs 4.4 s for a 35-token prompt at load 5 on
        # 2 cores). Passive waiting costs little on an idle machine. Read when libgomp starts.
        os.environ.setdefault("OMP_WAIT_POLICY", "PASSIVE")
        try:
            from llama_cpp import Llama
        except ImportError:
            raise MissingDependencyError("llama_cpp", "the embedded LLM backend", INSTALL_LLM_HINT) from None
        t0 = time.perf_counter()
        try:
            self._llama = Llama(
                model_path=str(self.model_file.path),
                n_ctx=self.n_ctx,
                n_threads=self.n_threads,
                n_threads_batch=self.n_threads,
                n_gpu_layers=0,
                seed=self.seed,
                verbose=False,
            )
        except (ValueError, RuntimeError, OSError) as exc:
            raise BackendError(f"llama.cpp could not load {self.model_file.path}: {exc}") from None
        self.load_time_s = time.perf_counter() - t0
        return self.load_time_s

    def count_tokens(self, text: str) -> int:
        """Count the tokens of ``text`` for this model (loads the model)."""
        with self._lock:
            self._load_locked()
            return len(self._llama.tokenize(text.encode("utf-8"), add_bos=False, special=True))

    def complete(self, request: ChatRequest) -> Completion:
        """Generate greedily (by default) under the request's JSON-schema grammar, if any.

        Raises:
            BackendError: the prompt does not fit ``n_ctx`` or the schema cannot become a grammar.
        """
        p = request.params
        kwargs: dict[str, Any] = {
            "messages": request.messages_as_dicts(),
            "temperature": p.temperature,
            "top_p": p.top_p,
            "top_k": p.top_k,
            "max_tokens": p.max_tokens,
            "seed": p.seed,
            "stop": list(p.stop) or None,
        }
        if request.json_schema is not None:
            kwargs["response_format"] = {"type": "json_object", "schema": dict(request.json_schema)}
        with self._lock:
            self._load_locked()
            t0 = time.perf_counter()
            try:
                result = self._llama.create_chat_completion(**kwargs)
            except ValueError as exc:  # context overflow, grammar compilation
                raise BackendError(f"llama.cpp rejected the request: {exc}") from None
            latency = time.perf_counter() - t0
        choice = result["choices"][0]
        usage = result.get("usage") or {}
        return Completion(
            text=choice["message"]["content"] or "",
            prompt_tokens=int(usage.get("prompt_tokens", 0)),
            completion_tokens=int(usage.get("completion_tokens", 0)),
            latency_s=latency,
            finish_reason=str(choice.get("finish_reason") or ""),
        )

    def close(self) -> None:
        """Free the model's memory."""
        with self._lock:
            if self._llama is not None:
                self._llama.close()
                self._llama = None
