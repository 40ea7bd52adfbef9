"""Few-shot case selection (section 3.2 and 4.5): similarity within the risk type, or random.

Similarity ranks the captions of the stored cases of the query's risk type by cosine similarity
with the query caption (through :func:`scenariominer.retrieval.rank`); the random arm draws ``k``
cases of the same risk type with a generator seeded by the configured seed and the query caption,
so a query always draws the same cases. Cases whose id is in ``exclude`` (the query itself when it
is stored) are never returned.
"""

from __future__ import annotations

import hashlib
from collections.abc import Collection
from dataclasses import dataclass

import numpy as np

from scenariominer.cbr.cases import Case, CaseBase
from scenariominer.cbr.vocab import CbrError
from scenariominer.llm.embeddings import Embedder
from scenariominer.retrieval import rank

__all__ = ["Retrieved", "retrieve"]


@dataclass(frozen=True)
class Retrieved:
    """One few-shot case and its caption similarity to the query (NaN for random draws)."""

    case: Case
    score: float


def retrieve(
    base: CaseBase,
    caption: str,
    risk_type: str,
    k: int,
    *,
    selection: str,
    embedder: Embedder,
    seed: int = 0,
    exclude: Collection[str] = (),
) -> list[Retrieved]:
    """The ``k`` cases of ``risk_type`` to show as examples, best first.

    Raises:
        CbrError: ``selection`` is neither ``similarity`` nor ``random``.
        EmbeddingMismatchError: the case base was embedded with another model.
    """
    if k <= 0:
        return []
    if selection == "random":
        pool = [c for c in base.cases(risk_type) if c.case_id not in exclude]
        digest = hashlib.sha256(f"{seed}\n{caption}".encode()).digest()
        rng = np.random.default_rng(int.from_bytes(digest[:8], "little"))
        if not pool:
            return []
        picks = rng.choice(len(pool), size=min(k, len(pool)), replace=False)
        return [Retrieved(pool[int(i)], float("nan")) for i in picks]
    if selection != "similarity":
        raise CbrError(f"unknown selection {selection!r}; use similarity or random")
    query = embedder.embed([caption])
    cases, vectors = base.vectors(query.model, risk_type)
    keep = [i for i, c in enumerate(cases) if c.case_id not in exclude]
    if not keep:
        return []
    hits = rank(vectors[keep], query.vectors[0], [cases[i].case_id for i in keep])[:k]
    by_id = {c.case_id: c for c in cases}
    return [Retrieved(by_id[h.id], float(h.score)) for h in hits]
