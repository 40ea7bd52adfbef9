"""One root exception and one family per layer.

Every error the package raises on purpose derives from :class:`ScenarioMinerError`, so a caller (the
CLI, the HTTP server, a user's script) can tell "the input, the configuration or the environment is
wrong, here is what to do" from a bug. Each family also derives from the built-in exception its
members always were (``ValueError``, ``LookupError``, ...), so ``except ValueError`` keeps working.

Messages say what is wrong, where (file, key, log, track, timestamp) and, where it is not obvious,
how to fix it. The CLI prints such an error as one line and exits with status 2; anything else is a
bug and gets a traceback (``--debug`` shows the traceback for every error).

Families (module → family):

=====================  ===================================================================
family                 raised by
=====================  ===================================================================
ConfigError            config/: a TOML file, key or value that cannot be used
DataError              data/, synth/: unreadable or malformed logs, maps, categories
StoreError             store/: missing or corrupt store, unknown log or table, bad query
LLMError               llm/: missing model or extra, unreachable server, unusable answers
TagError               tags/, events/: tag tables that do not fit the log
ExplainError           explain/: category files, unknown events, nothing to search
MiningError            mine/: example banks, camera frames, maps a program needs, exports
EvaluationError        eval/: label and ground-truth files, predictions that do not match
=====================  ===================================================================
"""

from __future__ import annotations

__all__ = [
    "ConfigError",
    "DataError",
    "EmbeddingMismatchError",
    "EvaluationError",
    "ExplainError",
    "LLMError",
    "MissingExtraError",
    "MiningError",
    "ScenarioMinerError",
    "StoreError",
    "TagError",
]


class ScenarioMinerError(Exception):
    """Root of every error the package raises on purpose: the message tells the user what to do."""


class ConfigError(ScenarioMinerError, ValueError):
    """A configuration file, key or value cannot be used (the message names file and key)."""


class DataError(ScenarioMinerError, ValueError):
    """Input data (a log, a map, a category name) is unreadable or malformed."""


class StoreError(ScenarioMinerError):
    """The scenario store is missing, corrupt, or asked for something it does not hold."""


class LLMError(ScenarioMinerError):
    """A language-model or embedding backend cannot be used or gave an unusable answer."""


class TagError(ScenarioMinerError, ValueError):
    """Activity and interaction tags, or events built on them, do not fit their log."""


class ExplainError(ScenarioMinerError):
    """Why-braking analysis: a category file, an event or a search that cannot be served."""


class MiningError(ScenarioMinerError):
    """Scenario mining: example banks, maps and camera frames a program needs, exports."""


class EvaluationError(ScenarioMinerError, ValueError):
    """Labels, ground truth or predictions handed to an evaluation cannot be used."""


class EmbeddingMismatchError(ScenarioMinerError, ValueError):
    """Vectors of different models or dimensions were about to be mixed or compared.

    Shared by the embedding backends (llm/) and the vector tables and index (store/, retrieval/), so
    one ``except`` clause catches a mismatch wherever it is detected.
    """


class MissingExtraError(ScenarioMinerError, ImportError):
    """An optional dependency is not installed; the message gives the command that installs it."""

    def __init__(self, module: str, extra: str, purpose: str) -> None:
        self.module = module
        self.extra = extra
        super().__init__(
            f"{purpose} needs the Python package {module!r}, which is not installed: "
            f"pip install 'scenariominer[{extra}]'"
        )


class ExecutorError(ScenarioMinerError):
    """The executor itself cannot run (an unknown backend, an unreachable Ray cluster, ...)."""


class TransientError(ScenarioMinerError):
    """A failure worth retrying (a dropped connection, a busy service); executors retry it."""
