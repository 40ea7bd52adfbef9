"""Persisted prompt prefixes: a fresh backend restores the evaluated system prompt from disk.

The unit tests cover keys, pruning and the prefix arithmetic; the slow tests run the real bundled
model: a second backend (an empty context, as in a new process) must restore the state instead of
evaluating it, answer exactly as without the cache, and survive a corrupt state file.
"""

from __future__ import annotations

import importlib.util
import os

import pytest

from scenariominer.llm import ChatRequest, GenerationParams, LlamaCppBackend, ModelFile, system, user
from scenariominer.llm.cache import resolve_cache_dir
from scenariominer.llm.model_files import ensure_model_file
from scenariominer.llm.prefix_cache import PrefixSource, PrefixStateStore, common_prefix_len


def test_common_prefix_len():
    assert common_prefix_len([1, 2, 3], [1, 2, 4, 5]) == 2
    assert common_prefix_len([1, 2], [1, 2, 3]) == 2
    assert common_prefix_len([], [1]) == 0
    assert common_prefix_len([7], [8]) == 0


def test_key_depends_on_model_settings_and_tokens(tmp_path):
    a = PrefixStateStore(tmp_path, "m@sha256:aa", {"n_ctx": 8192})
    assert a.key([1, 2, 3]) == PrefixStateStore(tmp_path, "m@sha256:aa", {"n_ctx": 8192}).key([1, 2, 3])
    assert a.key([1, 2, 3]) != a.key([1, 2, 4])
    assert a.key([1, 2, 3]) != PrefixStateStore(tmp_path, "m@sha256:bb", {"n_ctx": 8192}).key([1, 2, 3])
    assert a.key([1, 2, 3]) != PrefixStateStore(tmp_path, "m@sha256:aa", {"n_ctx": 4096}).key([1, 2, 3])
    assert a.key([12, 3]) != a.key([1, 23])  # token boundaries are part of the key


def test_prune_keeps_the_most_recent_files_within_the_bound(tmp_path):
    store = PrefixStateStore(tmp_path, "m", {}, max_bytes=250)
    paths = [store.path([i]) for i in range(4)]
    for age, p in enumerate(paths):
        p.write_bytes(b"x" * 100)
        os.utime(p, (1000 + age, 1000 + age))  # paths[3] is the newest
    assert store.prune() == 2
    assert [p.exists() for p in paths] == [False, False, True, True]


@pytest.fixture(scope="module")
def model_file() -> ModelFile:
    if importlib.util.find_spec("llama_cpp") is None:
        pytest.skip("llama-cpp-python is not installed (pip install 'scenariominer[llm]')")
    return ensure_model_file(resolve_cache_dir())


SYSTEM = (
    "You are a driving-scenario assistant. You read short descriptions of traffic scenes recorded by "
    "an automated vehicle and answer questions about them with one word. "
) * 6


def _request(question: str) -> ChatRequest:
    return ChatRequest((system(SYSTEM), user(question)), GenerationParams(max_tokens=6))


def _backend(model_file: ModelFile, prefix_dir) -> LlamaCppBackend:
    return LlamaCppBackend(model_file, n_ctx=2048, prefix_dir=prefix_dir, prefix_min_tokens=32)


@pytest.mark.slow
def test_a_fresh_backend_restores_the_prefix_and_answers_the_same(model_file, tmp_path):
    first = _backend(model_file, tmp_path)
    a = first.complete(_request("A car brakes hard ahead. Is this a risk?"))
    assert first.last_prefix.source is PrefixSource.EVALUATED
    assert first.last_prefix.saved_bytes > 0
    b = first.complete(_request("A pedestrian waits at the kerb. Is this a risk?"))
    assert first.last_prefix.source is PrefixSource.MEMORY
    assert b.reused_prompt_tokens >= first.last_prefix.n_tokens
    first.close()

    fresh = _backend(model_file, tmp_path)  # an empty context, as in a new process
    c = fresh.complete(_request("A car brakes hard ahead. Is this a risk?"))
    assert fresh.last_prefix.source is PrefixSource.DISK
    assert c.reused_prompt_tokens >= fresh.last_prefix.n_tokens > 32
    assert c.text == a.text  # the restored state is the evaluated one: greedy answers agree

    plain = _backend(model_file, None)  # no persisted prefixes at all
    d = plain.complete(_request("A car brakes hard ahead. Is this a risk?"))
    assert plain.last_prefix.source is PrefixSource.NONE
    assert d.text == a.text and d.reused_prompt_tokens == 0
    fresh.close()
    plain.close()


@pytest.mark.slow
def test_a_corrupt_state_file_is_discarded_and_the_prefix_evaluated(model_file, tmp_path):
    first = _backend(model_file, tmp_path)
    a = first.complete(_request("Is a red light a reason to brake?"))
    first.close()
    (state,) = list(tmp_path.glob("*.llstate"))
    state.write_bytes(b"not a llama state" * 10)
    again = _backend(model_file, tmp_path)
    b = again.complete(_request("Is a red light a reason to brake?"))
    assert again.last_prefix.source is PrefixSource.EVALUATED
    assert b.text == a.text
    assert state.stat().st_size > 1000  # rewritten with a valid state
    again.close()
