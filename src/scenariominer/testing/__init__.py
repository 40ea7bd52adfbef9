"""Fakes and builders shipped for tests, ours and users' (every swappable backend has a fake here).

* :class:`ScriptedBackend`: a chat backend returning canned replies (the LLM fake).
* :class:`HashingEmbedder`: a deterministic, model-free text embedder (the embedder fake; also a
  configurable backend, ``[embedding] backend = "hashing"``).
* :class:`FakeClock`: virtual time for code that waits.
* :class:`LogBuilder`, :func:`integrate`, :func:`braking_speed`, :func:`times`: hand-built logs
  with known answers.
"""

from scenariominer.llm.embeddings import HashingEmbedder
from scenariominer.testing.builders import BuiltTrack, LogBuilder, braking_speed, integrate, times
from scenariominer.testing.clock import FakeClock
from scenariominer.testing.llm import ScriptedBackend, ScriptedReply, ScriptExhaustedError

__all__ = [
    "BuiltTrack",
    "FakeClock",
    "HashingEmbedder",
    "LogBuilder",
    "ScriptExhaustedError",
    "ScriptedBackend",
    "ScriptedReply",
    "braking_speed",
    "integrate",
    "times",
]
