"""A small real store (3 synthetic logs + a log with hostile names) and real servers on loopback."""

from __future__ import annotations

import csv
import socket
import threading
import time
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

import httpx
import pytest

#: A log id and a track id that are markup: the UI must show them as text, never run them.
HOSTILE_LOG_ID = 'evil<img src=x onerror="window.__pwned=1">log'
HOSTILE_TRACK_ID = "<b>bold</b><script>window.__pwned=2</script>"


@dataclass(frozen=True)
class BuiltStore:
    """The session's store and what it was built from."""

    root: Path
    config: Path
    data_root: Path
    synth_dir: Path


def _write_hostile_log(path: Path) -> None:
    """A tabular log: the ego and one vehicle whose ids are HTML/JavaScript."""
    with path.open("w", newline="") as f:
        w = csv.writer(f)
        w.writerow(
            ["log_id", "track_id", "category", "timestamp_ns", "x_m", "y_m", "yaw_rad", "length_m", "width_m"]
        )
        for i in range(30):
            t_ns = i * 100_000_000
            w.writerow([HOSTILE_LOG_ID, "ego", "EGO_VEHICLE", t_ns, i * 1.0, 0.0, 0.0, 4.5, 2.0])
            w.writerow(
                [HOSTILE_LOG_ID, HOSTILE_TRACK_ID, "REGULAR_VEHICLE", t_ns, 10 + i * 0.8, 3.5, 0.0, 4.5, 2.0]
            )


@pytest.fixture(scope="session")
def built_store(tmp_path_factory: pytest.TempPathFactory) -> BuiltStore:
    """3 synthetic AV2 logs (with maps) and the hostile log, ingested and analysed by the rules."""
    from scenariominer import api
    from scenariominer.config import load_config

    base = tmp_path_factory.mktemp("server")
    data = base / "data"
    data.mkdir()
    cache = base / "cache"
    config = base / "config.toml"
    config.write_text(
        f'[embedding]\nbackend = "hashing"\ncache_dir = "{cache}"\n[llm]\ncache_dir = "{cache}"\n',
        encoding="utf-8",
    )
    cfg = load_config(config)
    synth_dir = data / "synth"
    api.synth(synth_dir, 3, seed=0)
    (data / "hostile").mkdir()
    _write_hostile_log(data / "hostile" / "hostile.csv")
    store = api.open_store(base / "store", cfg)
    report = api.ingest([synth_dir, data / "hostile"], store, cfg)
    assert not report.failed, report.failed
    api.analyze(store, api.AnalyzeRequest(judge="rules"), cfg)
    return BuiltStore(store.root, config, data, synth_dir)


class LiveServer:
    """A uvicorn server in a thread on a free loopback port."""

    def __init__(self, settings: object) -> None:
        import uvicorn

        from scenariominer.server import ServerSettings, create_app

        assert isinstance(settings, ServerSettings)
        self.app = create_app(settings)
        self.sock = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
        self.sock.bind(("127.0.0.1", 0))
        self.port = self.sock.getsockname()[1]
        self.url = f"http://127.0.0.1:{self.port}"
        config = uvicorn.Config(self.app, log_level="warning", lifespan="on")
        self.server = uvicorn.Server(config)
        self.thread = threading.Thread(target=self.server.run, kwargs={"sockets": [self.sock]}, daemon=True)

    def __enter__(self) -> LiveServer:
        self.thread.start()
        deadline = time.monotonic() + 30
        while not self.server.started:
            if time.monotonic() > deadline or not self.thread.is_alive():
                raise RuntimeError("the test server did not start")
            time.sleep(0.05)
        return self

    def __exit__(self, *exc: object) -> None:
        self.server.should_exit = True
        self.thread.join(timeout=30)
        self.sock.close()


def make_settings(store: BuiltStore, tmp: Path, **options: object) -> object:
    from scenariominer.server import ServerSettings

    options.setdefault("config_path", store.config)
    return ServerSettings.create(store.root, [store.data_root], jobs_db=tmp / "jobs.sqlite", **options)


@pytest.fixture(scope="session")
def live(built_store: BuiltStore, tmp_path_factory: pytest.TempPathFactory) -> Iterator[LiveServer]:
    """One server without a token for the whole session."""
    with LiveServer(make_settings(built_store, tmp_path_factory.mktemp("jobs"), max_queued=4)) as server:
        yield server


@pytest.fixture()
def client(live: LiveServer) -> Iterator[httpx.Client]:
    with httpx.Client(base_url=live.url, timeout=60) as c:
        yield c


@dataclass(frozen=True)
class Servers:
    """Builds more servers over the session's store (token, limits, a fresh job table)."""

    store: BuiltStore
    tmp: pytest.TempPathFactory

    def settings(self, **options: object) -> object:
        return make_settings(self.store, self.tmp.mktemp("jobs"), **options)

    def start(self, settings: object) -> LiveServer:
        return LiveServer(settings)


@pytest.fixture(scope="session")
def servers(built_store: BuiltStore, tmp_path_factory: pytest.TempPathFactory) -> Servers:
    return Servers(built_store, tmp_path_factory)


@pytest.fixture(scope="session")
def hostile_ids() -> tuple[str, str]:
    """(log id, track id) of the hostile log."""
    return HOSTILE_LOG_ID, HOSTILE_TRACK_ID
