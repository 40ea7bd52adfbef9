"""The embedded chat backend: llama-cpp-python running a GGUF file on the CPU.

Structured requests are decoded under a grammar compiled from the JSON schema, so the answer is
always syntactically valid JSON of the requested shape (the client still validates it). The
model is loaded on the first call; llama.cpp is not thread-safe, so calls are serialised.

Prompt prefixes: before each call the leading system message(s) are rendered with the model's
chat template and tokenised; when the context does not already hold them, their evaluated state
is restored from :class:`~scenariominer.llm.prefix_cache.PrefixStateStore` (written by an earlier
process) or evaluated once and saved there. llama-cpp-python then evaluates only the tokens after
the longest prefix the context holds, so the first call of a process costs what a later one does.
"""

from __future__ import annotations

import os
import threading
import time
from pathlib import Path
from typing import Any

from scenariominer.llm import llama_log
from scenariominer.llm.base import ChatRequest, Completion
from scenariominer.llm.errors import INSTALL_LLM_HINT, BackendError, MissingDependencyError
from scenariominer.llm.model_files import ModelFile
from scenariominer.llm.prefix_cache import PrefixOutcome, PrefixSource, PrefixStateStore, common_prefix_len

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
        prefix_dir: directory of persisted prompt-prefix states; ``None`` keeps prefixes in
            memory only (llama.cpp's own reuse within the process).
        prefix_min_tokens: system prefixes shorter than this are not persisted.
        prefix_max_bytes: size bound of ``prefix_dir`` (least recently used files go first).

    Attributes:
        load_time_s: seconds the model took to load (``None`` before the first call).
        last_prefix: what preparing the prefix of the latest call did.
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
        prefix_dir: Path | None = None,
        prefix_min_tokens: int = 256,
        prefix_max_bytes: int = 4 << 30,
    ) -> None:
        self.model_file = model_file
        self.model_name = model_name or model_file.path.stem
        self.n_ctx = n_ctx
        self.n_threads = n_threads or default_n_threads()
        self.seed = seed
        self.load_time_s: float | None = None
        self.prefix_dir = prefix_dir
        self.prefix_min_tokens = prefix_min_tokens
        self.prefix_max_bytes = prefix_max_bytes
        self.last_prefix = PrefixOutcome(PrefixSource.NONE)
        self._prefix_store: PrefixStateStore | None = None
        self._formatter: Any = None
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
        llama_log.install()
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
        self._formatter = _chat_formatter(self._llama)
        if self.prefix_dir is not None and self._formatter is not None:
            import llama_cpp

            settings = {
                "n_ctx": self.n_ctx,
                "n_batch": int(self._llama.n_batch),
                "llama_cpp": getattr(llama_cpp, "__version__", ""),
                "template": self._llama.chat_format,
            }
            self._prefix_store = PrefixStateStore(
                self.prefix_dir, self.model, settings, max_bytes=self.prefix_max_bytes
            )
        return self.load_time_s

    def _render_tokens(self, messages: list[dict[str, str]]) -> list[int]:
        result = self._formatter(messages=messages)
        tokens = self._llama.tokenize(
            result.prompt.encode("utf-8"), add_bos=not result.added_special, special=True
        )
        return [int(t) for t in tokens]

    def _system_prefix(self, request: ChatRequest) -> list[int]:
        """Tokens shared by every call with this request's leading system message(s)."""
        messages = request.messages_as_dicts()
        n_sys = 0
        while n_sys < len(messages) and messages[n_sys]["role"] == "system":
            n_sys += 1
        if n_sys == 0 or self._formatter is None:
            return []
        full = self._render_tokens(messages)
        probe = self._render_tokens([*messages[:n_sys], {"role": "user", "content": "\u2063"}])
        return full[: common_prefix_len(full, probe)]

    def _prepare_prefix(self, request: ChatRequest) -> PrefixOutcome:
        """Make the context hold the request's system prefix: kept, restored from disk, or evaluated."""
        if self._prefix_store is None:
            return PrefixOutcome(PrefixSource.NONE)
        prefix = self._system_prefix(request)
        if len(prefix) < self.prefix_min_tokens:
            return PrefixOutcome(PrefixSource.NONE, len(prefix))
        llama = self._llama
        have = common_prefix_len(llama.input_ids[: llama.n_tokens], prefix)
        if have >= len(prefix):
            return PrefixOutcome(PrefixSource.MEMORY, len(prefix))
        t0 = time.perf_counter()
        if self._prefix_store.restore(llama, prefix):
            return PrefixOutcome(PrefixSource.DISK, len(prefix), time.perf_counter() - t0)
        llama.n_tokens = min(have, llama.n_tokens)
        llama.eval(prefix[llama.n_tokens :])
        seconds = time.perf_counter() - t0
        saved = self._prefix_store.save(llama, prefix)
        return PrefixOutcome(PrefixSource.EVALUATED, len(prefix), seconds, saved)

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
        if request.grammar is not None:
            from llama_cpp.llama_grammar import LlamaGrammar

            kwargs["grammar"] = LlamaGrammar.from_string(request.grammar, verbose=False)
        with self._lock:
            self._load_locked()
            t0 = time.perf_counter()
            try:
                self.last_prefix = prefix = self._prepare_prefix(request)
                _reset_perf(self._llama)
                result = self._llama.create_chat_completion(**kwargs)
            except ValueError as exc:  # context overflow, grammar compilation
                raise BackendError(f"llama.cpp rejected the request: {exc}") from None
            latency = time.perf_counter() - t0
            eval_s, eval_tokens = _prompt_eval(self._llama)
        choice = result["choices"][0]
        usage = result.get("usage") or {}
        prompt_tokens = int(usage.get("prompt_tokens", 0))
        evaluated = eval_tokens + (prefix.n_tokens if prefix.source is PrefixSource.EVALUATED else 0)
        return Completion(
            text=choice["message"]["content"] or "",
            prompt_tokens=prompt_tokens,
            completion_tokens=int(usage.get("completion_tokens", 0)),
            latency_s=latency,
            finish_reason=str(choice.get("finish_reason") or ""),
            prompt_eval_s=eval_s + prefix.seconds,
            reused_prompt_tokens=max(0, prompt_tokens - evaluated),
        )

    def close(self) -> None:
        """Free the model's memory."""
        with self._lock:
            if self._llama is not None:
                self._llama.close()
                self._llama = None


def _chat_formatter(llama: Any) -> Any:
    """The formatter of the model's own chat template (``None`` for a model without one)."""
    template = (llama.metadata or {}).get("tokenizer.chat_template")
    if not template or llama.chat_format != "chat_template.default":
        return None
    from llama_cpp.llama_chat_format import Jinja2ChatFormatter

    def text(token_id: int) -> str:
        return str(llama._model.token_get_text(token_id)) if token_id != -1 else ""

    eos, bos = llama.token_eos(), llama.token_bos()
    return Jinja2ChatFormatter(
        template=template, eos_token=text(eos), bos_token=text(bos), stop_token_ids=[eos]
    )


def _reset_perf(llama: Any) -> None:
    import llama_cpp

    llama_cpp.llama_perf_context_reset(llama.ctx)


def _prompt_eval(llama: Any) -> tuple[float, int]:
    """Seconds and tokens of prompt evaluation since the last reset (llama.cpp's counters)."""
    import llama_cpp

    perf = llama_cpp.llama_perf_context(llama.ctx)
    return float(perf.t_p_eval_ms) / 1000.0, int(perf.n_p_eval)
