"""Language-model and text-embedding backends shared by every feature.

* :class:`ChatClient` - structured output (pydantic model or JSON schema) with one repair round,
  free-text completion, on-disk cache, usage accounting, bounded concurrency for batches.
* Chat backends (:class:`ChatBackend`): :class:`LlamaCppBackend` (embedded, offline default),
  :class:`OpenAICompatBackend` (any OpenAI-compatible server); the scripted fake for tests is
  :class:`scenariominer.testing.ScriptedBackend`.
* Embedders (:class:`Embedder`): :class:`SentenceTransformerEmbedder` (offline default),
  :class:`OpenAICompatEmbedder`, :class:`HashingEmbedder` (tests); results are :class:`Embeddings`.
* :func:`make_chat_client` and :func:`make_embedder` build them from the configuration.

Heavy dependencies (llama-cpp-python, sentence-transformers) are imported only when a model is
loaded; a missing one raises :class:`MissingDependencyError` with the install command.
"""

from scenariominer.llm.base import (
    ChatBackend,
    ChatRequest,
    Completion,
    GenerationOverrides,
    GenerationParams,
    Message,
    MessageLike,
    Role,
    assistant,
    system,
    user,
)
from scenariominer.llm.cache import ResponseCache, resolve_cache_dir
from scenariominer.llm.client import ChatClient, OutputSpec, StructuredResult
from scenariominer.llm.embeddings import (
    Embedder,
    Embeddings,
    HashingEmbedder,
    OpenAICompatEmbedder,
    SentenceTransformerEmbedder,
    l2_normalize,
)
from scenariominer.llm.errors import (
    BackendConnectionError,
    BackendError,
    BackendHTTPError,
    BackendResponseError,
    BackendTimeoutError,
    EmbeddingMismatchError,
    LLMError,
    MissingDependencyError,
    ModelIntegrityError,
    ModelNotAvailableError,
    StructuredOutputError,
)
from scenariominer.llm.factory import generation_params, make_chat_backend, make_chat_client, make_embedder
from scenariominer.llm.llamacpp import LlamaCppBackend
from scenariominer.llm.model_files import DEFAULT_MODEL, BundledModel, ModelFile, resolve_model_file
from scenariominer.llm.openai_compat import OpenAICompatBackend, OpenAIHTTP
from scenariominer.llm.usage import CallKind, UsageCounter, UsageReport, UsageRow, print_usage

__all__ = [
    "DEFAULT_MODEL",
    "BackendConnectionError",
    "BackendError",
    "BackendHTTPError",
    "BackendResponseError",
    "BackendTimeoutError",
    "BundledModel",
    "CallKind",
    "ChatBackend",
    "ChatClient",
    "ChatRequest",
    "Completion",
    "Embedder",
    "EmbeddingMismatchError",
    "Embeddings",
    "GenerationOverrides",
    "GenerationParams",
    "HashingEmbedder",
    "LLMError",
    "LlamaCppBackend",
    "Message",
    "MessageLike",
    "MissingDependencyError",
    "ModelFile",
    "ModelIntegrityError",
    "ModelNotAvailableError",
    "OpenAICompatBackend",
    "OpenAICompatEmbedder",
    "OpenAIHTTP",
    "OutputSpec",
    "ResponseCache",
    "Role",
    "SentenceTransformerEmbedder",
    "StructuredOutputError",
    "StructuredResult",
    "UsageCounter",
    "UsageReport",
    "UsageRow",
    "assistant",
    "generation_params",
    "l2_normalize",
    "make_chat_backend",
    "make_chat_client",
    "make_embedder",
    "print_usage",
    "resolve_cache_dir",
    "resolve_model_file",
    "system",
    "user",
]
