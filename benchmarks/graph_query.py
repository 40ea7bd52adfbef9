"""Graph + vector part of an ``ask`` query at 1k / 10k / 100k windows, against plain vector search.

A synthetic :class:`~scenariominer.represent.ask.GraphIndex` with the proportions of a real SUMO
highway graph (per window: one description, about 8 embedded relationships; a few hundred shared
entities; one summary per 30 windows), 384-dimensional clustered unit vectors (the MiniLM size).
For each size it times the fused graph search (``AskSettings()``) and the plain vector search over
the descriptions (``graph = False``) on the same query vectors (median per query) and prints the
ratio. Embedding the question and the LLM answer are not included (reported by ``ask`` itself).

    .venv/bin/python benchmarks/graph_query.py --sizes 1000 10000 100000 --queries 30
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

from scenariominer.represent.ask import AskSettings, GraphIndex

RELATIONSHIPS_PER_WINDOW = 8
ENTITIES = 400
WINDOWS_PER_SUMMARY = 30


def _unit(rng: np.random.Generator, n: int, dim: int) -> np.ndarray:
    centres = rng.normal(size=(max(8, n // 100), dim)).astype(np.float32)
    x = centres[rng.integers(0, len(centres), n)] + 0.5 * rng.normal(size=(n, dim)).astype(np.float32)
    return x / np.linalg.norm(x, axis=1, keepdims=True)


def _index(rng: np.random.Generator, n: int, dim: int) -> GraphIndex:
    n_rel = n * RELATIONSHIPS_PER_WINDOW
    n_sum = max(1, n // WINDOWS_PER_SUMMARY)
    members = rng.integers(0, n, size=(ENTITIES, max(1, n // 50)))
    return GraphIndex(
        [f"w{i}" for i in range(n)],
        _unit(rng, n, dim),
        [f"E{i}" for i in range(ENTITIES)],
        _unit(rng, ENTITIES, dim),
        [sorted(set(m.tolist())) for m in members],
        [f"R{i}" for i in range(n_rel)],
        _unit(rng, n_rel, dim),
        rng.integers(0, n, size=n_rel).tolist(),
        [f"C{i}" for i in range(n_sum)],
        _unit(rng, n_sum, dim),
        [rng.integers(0, n, size=5).tolist() for _ in range(n_sum)],
    )


def _median_ms(index: GraphIndex, queries: np.ndarray, settings: AskSettings) -> float:
    times = []
    for q in queries:
        t0 = time.perf_counter()
        index.search(q, settings)
        times.append(time.perf_counter() - t0)
    return 1e3 * statistics.median(times)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[1000, 10000, 100000])
    parser.add_argument("--queries", type=int, default=30)
    parser.add_argument("--dim", type=int, default=384)
    args = parser.parse_args()
    rng = np.random.default_rng(0)
    print(f"{'windows':>8} {'relationships':>13} {'graph ms':>9} {'vector ms':>10} {'ratio':>6}")
    for n in args.sizes:
        index = _index(rng, n, args.dim)
        queries = _unit(rng, args.queries, args.dim)
        graph_ms = _median_ms(index, queries, AskSettings())
        vector_ms = _median_ms(index, queries, AskSettings(graph=False))
        print(
            f"{n:>8} {n * RELATIONSHIPS_PER_WINDOW:>13} {graph_ms:>9.2f} {vector_ms:>10.2f} "
            f"{graph_ms / vector_ms:>6.1f}"
        )


if __name__ == "__main__":
    main()
