"""Trajectory-embedding speed (issue 13): windows embedded per second, training time for 500 windows.

Data: the windows of a store (``--store``; windows already cut there), or by default the two real
Argoverse 2 logs (``../shared/data`` and ``tests/real_data``) ingested into a temporary store and
cut into 5 s and 15 s windows of every vehicle with half overlap (445 windows). Windows are repeated
to ``--embed-windows`` for the throughput figure and drawn (with repetition when fewer) to
``--train-windows`` for the training figure. Every figure is printed with a baseline measured in the
same run:

* embedding: windows/s of ``TrajectoryEmbedder.transform`` (torch on ``--threads`` threads, the
  default network) against windows/s of reading the same windows back from the store
  (``load_windows``: SQLite rows + ``.npz`` blobs) and against the goal of 1,000/s;
* cutting: windows/s of ``extract_windows`` on the stored logs against loading those logs;
* training: seconds to train the default network (``[represent.embedder]``, 40 epochs) on
  ``--train-windows`` windows with each loss, against ``python -c pass`` start-up and the goal of
  600 s.

    nice -n 5 .venv/bin/python benchmarks/embedding.py --threads 2
"""

from __future__ import annotations

import argparse
import dataclasses
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from scenariominer.api import ingest, open_store
from scenariominer.config import load_config
from scenariominer.config.represent import WindowConfig
from scenariominer.represent.pipeline import build_store_windows
from scenariominer.represent.vrae import TrajectoryEmbedder
from scenariominer.represent.window_table import load_windows
from scenariominer.represent.windows import WindowSet, extract_windows
from scenariominer.store import ScenarioStore

ROOT = Path(__file__).resolve().parents[1]
AV2_LOGS = (
    ROOT.parent / "shared" / "data" / "av2" / "3b3570b4-7b0b-3268-a571-b0889dbf40b6",
    ROOT / "tests" / "real_data" / "av2" / "adcf7d18-0510-35b0-a2fa-b4cea13a6d76",
)
DEFAULT_WINDOWS = WindowConfig(lengths_s=(5.0, 15.0), overlap=0.5, agents="vehicles")


def _best_of(n: int, fn: object) -> float:
    assert callable(fn)
    times = []
    for _ in range(n):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return min(times)


def _av2_store(tmp: Path) -> ScenarioStore:
    store = open_store(tmp / "store")
    ingest([p for p in AV2_LOGS if p.is_dir()], store, load_config())
    build_store_windows(store, DEFAULT_WINDOWS)
    return store


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--store", type=Path, help="store whose windows to use (default: the AV2 logs)")
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--embed-windows", type=int, default=20_000)
    parser.add_argument("--train-windows", type=int, default=500)
    parser.add_argument("--losses", nargs="+", default=["hausdorff", "mse"])
    args = parser.parse_args()
    cfg = dataclasses.replace(load_config().represent.embedder, threads=args.threads)
    with tempfile.TemporaryDirectory() as tmp:
        store = ScenarioStore.open(args.store, create=False) if args.store else _av2_store(Path(tmp))
        source = str(args.store) if args.store else "2 real AV2 logs, 5 s + 15 s windows of every vehicle"
        ws = load_windows(store)
        print(f"data: {len(ws)} windows ({ws.n_agents} agents x {ws.n_steps} steps) from {source}")

        # ---------------------------------------------------------------- cutting windows
        log_ids = sorted(set(ws.log_ids.tolist()))
        load_s = _best_of(3, lambda: [store.load_log(i) for i in log_ids])
        logs = [store.load_log(i) for i in log_ids]
        wcfg = DEFAULT_WINDOWS if not args.store else None
        if wcfg is not None:
            cut_s = _best_of(3, lambda: [extract_windows(log, wcfg) for log in logs])
            print(
                f"cut windows: {len(ws) / cut_s:,.0f} windows/s ({cut_s * 1e3:.1f} ms for {len(logs)} logs); "
                f"loading those logs {load_s * 1e3:.1f} ms: cut/load time ratio {cut_s / load_s:.2f}"
            )

        # ---------------------------------------------------------------- embedding throughput
        read_s = _best_of(3, lambda: load_windows(store))
        reps = int(np.ceil(args.embed_windows / len(ws)))
        big = ws.select(np.tile(np.arange(len(ws)), reps)[: args.embed_windows])
        model = TrajectoryEmbedder(dataclasses.replace(cfg, epochs=1)).fit(
            ws.select(np.arange(min(64, len(ws))))
        )
        embed_s = _best_of(3, lambda: model.transform(big))
        embed_rate, read_rate = len(big) / embed_s, len(ws) / read_s
        print(
            f"embed: {embed_rate:,.0f} windows/s on {args.threads} threads ({len(big):,} windows in "
            f"{embed_s:.2f} s); store read baseline {read_rate:,.0f} windows/s: embed/read rate "
            f"{embed_rate / read_rate:.2f}; goal 1,000/s: {embed_rate / 1000:.1f}x"
        )

        # ---------------------------------------------------------------- training time
        startup_s = _best_of(3, lambda: subprocess.run([sys.executable, "-c", "pass"], check=True))
        rng = np.random.default_rng(0)
        pick = rng.choice(len(ws), size=args.train_windows, replace=len(ws) < args.train_windows)
        train_ws: WindowSet = ws.select(np.sort(pick))
        for loss in args.losses:
            est = TrajectoryEmbedder(dataclasses.replace(cfg, loss=loss))
            t0 = time.perf_counter()
            est.fit(train_ws)
            train_s = time.perf_counter() - t0
            assert est.summary_ is not None
            hist = est.summary_.loss_history
            print(
                f"train {loss}: {len(train_ws)} windows x {cfg.epochs} epochs in {train_s:.1f} s "
                f"(loss {hist[0]:.4f} -> {hist[-1]:.4f}); python start-up {startup_s * 1e3:.0f} ms: "
                f"ratio {train_s / startup_s:,.0f}; goal 600 s: {train_s / 600:.3f} of it"
            )


if __name__ == "__main__":
    main()
