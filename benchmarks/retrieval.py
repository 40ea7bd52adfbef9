"""Exact vs approximate (faiss HNSW) vector search at 1k / 10k / 100k vectors, in one run.

Vectors are clustered random 384-dimensional rows (the MiniLM size). For each size the script builds
both indexes, times a batch of single queries (median per query) and measures the approximate
index's recall@10 against the exact answer, then prints the exact/approximate time ratio. The size
from which ``make_index`` switches to HNSW (``DEFAULT_ANN_THRESHOLD``) is set from these figures.

    .venv/bin/python benchmarks/retrieval.py --sizes 1000 10000 100000 --queries 50
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

from scenariominer.retrieval import DEFAULT_ANN_THRESHOLD, ExactCosineIndex, HnswIndex, VectorIndex


def _data(rng: np.random.Generator, n: int, dim: int) -> np.ndarray:
    centres = rng.normal(size=(max(8, n // 100), dim)).astype(np.float32)
    return centres[rng.integers(0, len(centres), n)] + 0.5 * rng.normal(size=(n, dim)).astype(np.float32)


def _per_query_s(index: VectorIndex, queries: np.ndarray) -> float:
    times = []
    for q in queries:
        t0 = time.perf_counter()
        index.search(q, 10)
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[1000, 10000, 100000])
    parser.add_argument("--queries", type=int, default=50)
    parser.add_argument("--dim", type=int, default=384)
    args = parser.parse_args()
    rng = np.random.default_rng(0)
    cols = ("vectors", "exact ms", "hnsw ms", "exact/hnsw", "recall@10", "build s")
    print(" ".join(f"{c:>11s}" for c in cols))
    for n in args.sizes:
        data = _data(rng, n, args.dim)
        ids = [str(i) for i in range(n)]
        queries = _data(rng, args.queries, args.dim)
        exact = ExactCosineIndex(args.dim)
        exact.add(ids, data)
        t0 = time.perf_counter()
        approx = HnswIndex(args.dim)
        approx.add(ids, data)
        build_s = time.perf_counter() - t0
        t_exact, t_ann = _per_query_s(exact, queries), _per_query_s(approx, queries)
        truth = exact.search_batch(queries, 10)
        found = approx.search_batch(queries, 10)
        recall = np.mean(
            [len({h.id for h in a} & {h.id for h in e}) / 10 for a, e in zip(found, truth, strict=True)]
        )
        row = (
            f"{n:d}",
            f"{t_exact * 1e3:.2f}",
            f"{t_ann * 1e3:.2f}",
            f"{t_exact / t_ann:.1f}",
            f"{recall:.3f}",
        )
        print(" ".join(f"{c:>11s}" for c in (*row, f"{build_s:.1f}")))
    print(f"\nmake_index switches to HNSW at {DEFAULT_ANN_THRESHOLD:,} vectors")


if __name__ == "__main__":
    main()
