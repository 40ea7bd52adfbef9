"""The on-disk answer and vector cache (SQLite)."""

from __future__ import annotations

import threading
from pathlib import Path

import numpy as np

from scenariominer.llm import Completion, ResponseCache
from scenariominer.llm.cache import resolve_cache_dir


def test_completion_round_trip_marks_hits(tmp_path):
    with ResponseCache(tmp_path / "sub" / "c.sqlite3") as cache:
        assert cache.get_completion("k") is None
        cache.put_completion("k", "openai", "m", Completion("txt", 5, 3, 1.25, "stop"))
        assert cache.get_completion("k") == Completion("txt", 5, 3, 1.25, "stop", cached=True)
        assert cache.counts() == (1, 0)
        cache.clear()
        assert cache.counts() == (0, 0)


def test_vectors_round_trip_as_float32(tmp_path):
    with ResponseCache(tmp_path / "c.sqlite3") as cache:
        v = np.array([0.6, 0.8, 0.0], dtype=np.float32)
        cache.put_vectors("hashing", "m", [("a", v), ("b", -v)])
        got = cache.get_vectors(["b", "missing", "a", "a"])
        assert sorted(got) == ["a", "b"]
        np.testing.assert_array_equal(got["b"], -v)
        assert got["a"].dtype == np.float32


def test_many_keys_are_looked_up_in_chunks(tmp_path):
    with ResponseCache(tmp_path / "c.sqlite3") as cache:
        items = [(f"k{i}", np.full(2, i, dtype=np.float32)) for i in range(1200)]
        cache.put_vectors("b", "m", items)
        got = cache.get_vectors([k for k, _ in items])
        assert len(got) == 1200
        assert got["k1199"][0] == 1199


def test_concurrent_threads_and_connections_share_one_file(tmp_path):
    path = tmp_path / "c.sqlite3"
    caches = [ResponseCache(path), ResponseCache(path)]
    errors: list[BaseException] = []

    def work(t: int) -> None:
        try:
            cache = caches[t % 2]
            for i in range(25):
                cache.put_completion(f"{t}-{i}", "b", "m", Completion(f"text {t} {i}"))
                assert cache.get_completion(f"{t}-{i}") is not None
        except BaseException as exc:  # reported below
            errors.append(exc)

    threads = [threading.Thread(target=work, args=(t,)) for t in range(8)]
    for th in threads:
        th.start()
    for th in threads:
        th.join()
    assert errors == []
    assert caches[0].counts() == (200, 0)
    assert caches[1].get_completion("7-24") == Completion("text 7 24", cached=True)
    for c in caches:
        c.close()


def test_default_cache_dir_is_the_user_cache_dir(monkeypatch, tmp_path):
    import platformdirs

    monkeypatch.setattr(platformdirs, "user_cache_dir", lambda app: str(tmp_path / app))
    assert resolve_cache_dir("") == tmp_path / "scenariominer" / "llm"
    assert resolve_cache_dir("~/x") == Path.home() / "x"
    assert ResponseCache.in_dir(tmp_path / "mine").path == tmp_path / "mine" / "llm-cache.sqlite3"
