"""The embedded model behind llama-cpp-python's OpenAI-compatible server, used end to end.

A real server subprocess on loopback serves the bundled GGUF; ``analyze`` (hybrid judgement) and
``mine`` (program generation) then run through the ``openai`` chat backend against it.
"""

from __future__ import annotations

import importlib.util
from collections.abc import Iterator
from pathlib import Path

import pytest

from scenariominer import api
from scenariominer.config import Config
from scenariominer.config.llm import EmbeddingConfig, LLMConfig
from scenariominer.llm.cache import resolve_cache_dir
from scenariominer.llm.model_files import ensure_model_file
from scenariominer.llm.server import ServedModel, ServeSettings, free_port, server_command
from scenariominer.llm.usage import UsageCounter
from scenariominer.mine.loop import GenerationStatus
from scenariominer.mine.query import ProgramSource
from scenariominer.store import ScenarioStore


def test_server_command_names_the_model_alias_and_port(tmp_path: Path) -> None:
    if importlib.util.find_spec("llama_cpp") is None:
        pytest.skip("llama-cpp-python is not installed")
    cmd = server_command(ServeSettings(tmp_path / "m.gguf", port=9123, n_threads=3))
    assert cmd[1:3] == ["-m", "llama_cpp.server"]
    assert cmd[cmd.index("--model") + 1] == str(tmp_path / "m.gguf")
    assert cmd[cmd.index("--port") + 1] == "9123" and cmd[cmd.index("--n_threads") + 1] == "3"
    assert cmd[cmd.index("--host") + 1] == "127.0.0.1"  # loopback unless asked otherwise


@pytest.fixture(scope="module")
def served(tmp_path_factory: pytest.TempPathFactory) -> Iterator[ServedModel]:
    if importlib.util.find_spec("llama_cpp") is None:
        pytest.skip("llama-cpp-python is not installed (pip install 'scenariominer[llm]')")
    model = ensure_model_file(resolve_cache_dir())
    log = tmp_path_factory.mktemp("server") / "server.log"
    with ServedModel(ServeSettings(model.path, port=free_port()), log_path=log) as server:
        yield server


def _config(server: ServedModel, tmp_path: Path) -> Config:
    llm = LLMConfig(
        backend="openai",  # type: ignore[arg-type]
        base_url=server.base_url,
        model="scenariominer",
        structured_mode="json_object_schema",  # type: ignore[arg-type]
        cache=False,
        timeout_s=600.0,
        max_tokens=400,
    )
    return Config(llm=llm, embedding=EmbeddingConfig(backend="hashing"))  # type: ignore[arg-type]


@pytest.mark.slow
def test_analyze_and_mine_through_the_served_model(served: ServedModel, tmp_path: Path) -> None:
    cfg = _config(served, tmp_path)
    api.synth(tmp_path / "synth", 2, seed=5, categories=["right_ped", "not_relevant"])
    store = ScenarioStore.open(tmp_path / "store")
    assert not api.ingest([tmp_path / "synth"], store, cfg).failed

    usage = UsageCounter()
    report = api.analyze(store, api.AnalyzeRequest(judge="hybrid"), cfg, usage=usage)
    assert report.n_failed == 0 and report.n_events > 0
    assert report.n_llm_calls == report.n_events and report.n_invalid == 0
    events = store.read_table("events").to_pylist()
    assert all(e["llm_status"] in ("ok", "repaired") and e["explanation"] for e in events)
    assert all(e["llm_model"] == f"scenariominer@{served.base_url}" for e in events)
    chat_rows = [r for r in usage.report().rows if r.kind == "chat"]
    assert chat_rows and chat_rows[0].backend == "openai" and chat_rows[0].calls >= report.n_events

    # the default generation: the served model reads the description into a plan (one
    # schema-constrained call); the program is built from it, or written by the model
    calls_before = sum(r.calls for r in usage.report().rows if r.kind == "chat")
    query = "a unicyclist darting out in front of the ego vehicle"  # the phrase rules do not read its subject
    request = api.MineRequest(query, store=store, use_bank=False, force=True)
    result = api.mine(request, cfg, usage)
    mined = result.report
    assert mined.source is ProgramSource.GENERATED
    assert sum(r.calls for r in usage.report().rows if r.kind == "chat") > calls_before
    assert mined.generation is not None and mined.generation.plan is not None
    assert "error" not in mined.generation.plan, mined.generation.plan
    assert mined.status is GenerationStatus.OK, mined.generation
    assert mined.program is not None and "output_scenario" in mined.program
    assert not mined.failures
