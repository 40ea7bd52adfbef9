"""Evaluation of CBR recommendations on the hold-out split (paper Tables 3-6 layout).

For each prompt configuration (risk-aware or not x zero-shot, random k-shot or similarity k-shot)
every hold-out case is answered once; the answer is stored in the corpus table ``<table>_eval``
under (model, prompt version, case-base version, configuration, case), so an interrupted grid
continues where it stopped and a finished one is only re-scored. Scores per configuration:

* micro-accuracy of the manoeuvre, overall and per risk type (invalid answers count as wrong);
* BLEU-4 (sacrebleu), ROUGE-L F (rouge-score), METEOR and CIDEr (pycocoevalcap; METEOR runs its
  Java jar, so it is reported unavailable, with the reason, when Java or the package is missing)
  of the event context and the justification against the hold-out references (all x100);
* rollout success: the share of answers whose manoeuvre avoids the conflict on the case's scene;
* seconds per recommendation (fresh model calls only).

Two model-free baselines are scored beside the grid, so a figure can be read against what needs no
model at all: ``baseline/majority`` answers the case base's most frequent manoeuvre of the query's
risk type, ``baseline/vote/k5`` the most frequent manoeuvre among the five most similar cases of that
risk type (ties go to the better-ranked case).
"""

from __future__ import annotations

import math
import time
from collections import Counter, defaultdict
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from scenariominer.cbr.build import HoldoutCase
from scenariominer.cbr.cases import CaseBase
from scenariominer.cbr.prompts import PROMPT_VERSION
from scenariominer.cbr.recommend import Query, RecommendSettings, recommend
from scenariominer.cbr.retrieve import retrieve
from scenariominer.cbr.vocab import CbrError
from scenariominer.llm.client import ChatClient
from scenariominer.llm.embeddings import Embedder
from scenariominer.llm.errors import LLMError
from scenariominer.progress import NullProgress, Progress
from scenariominer.store.corpus import CorpusTable

__all__ = [
    "CbrEvaluation",
    "ConfigResult",
    "baseline_rows",
    "default_grid",
    "evaluate_cbr_grid",
    "plot_evaluation",
    "TextScorer",
    "text_metrics",
]

EVAL_SCHEMA_VERSION = 1
TEXT_FIELDS = ("event_context", "justification")


def default_grid(
    ks: Sequence[int] = (0, 1, 3, 5), seed: int = 0, max_field_chars: int = 120, max_tokens: int = 256
) -> list[RecommendSettings]:
    """Every configuration, most informative first (so a cut-short run has the key comparisons).

    Order: risk-aware zero-shot, similarity k=3, random k=3, risk-unaware zero-shot, then the
    remaining risk-aware k, then the remaining risk-unaware ones.
    """

    def s(aware: bool, sel: str, k: int) -> RecommendSettings:
        return RecommendSettings(k, sel, aware, seed, max_field_chars, max_tokens)

    shots = [k for k in ks if k > 0]
    mid = 3 if 3 in shots else (shots[0] if shots else 0)
    first = [s(True, "similarity", 0)]
    if shots:
        first += [s(True, "similarity", mid), s(True, "random", mid)]
    first.append(s(False, "similarity", 0))
    rest = [
        s(aware, sel, k)
        for aware in (True, False)
        for sel in ("similarity", "random")
        for k in shots
        if not (aware and k == mid)
    ]
    out: list[RecommendSettings] = []
    for x in first + rest:
        if x.label not in {y.label for y in out} and (0 in ks or x.k > 0):
            out.append(x)
    return out


@dataclass(frozen=True)
class ConfigResult:
    """Scores of one prompt configuration.

    Attributes:
        label: e.g. ``aware/similarity/k3``.
        n_cases: hold-out cases; ``n_answered``: answered so far (cached rows).
        accuracy: micro-accuracy over the answered cases (NaN if none).
        per_type: accuracy per risk type.
        n_invalid: answers that failed the schema or the backend.
        rollout_success: share of answered cases whose manoeuvre avoids the conflict.
        seconds_per_call: mean seconds of fresh model calls (NaN if all were cached).
        text: field -> metric -> score (x100); missing metrics are absent.
    """

    label: str
    n_cases: int
    n_answered: int
    accuracy: float
    per_type: dict[str, float]
    n_invalid: int
    rollout_success: float
    seconds_per_call: float
    text: dict[str, dict[str, float]] = field(default_factory=dict)

    @property
    def complete(self) -> bool:
        """Every hold-out case is answered."""
        return self.n_answered == self.n_cases


@dataclass(frozen=True)
class CbrEvaluation:
    """The grid's results and what it ran on."""

    configs: tuple[ConfigResult, ...]
    risk_types: tuple[str, ...]
    n_holdout: int
    n_case_base: int
    model: str
    metric_notes: tuple[str, ...]
    fresh_calls: int
    seconds: float
    baselines: tuple[ConfigResult, ...] = ()
    picture: Path | None = None

    def to_json_dict(self) -> dict[str, Any]:
        """JSON-ready form (NaN as ``None``)."""

        def clean(x: Any) -> Any:
            if isinstance(x, float):
                return None if math.isnan(x) else x
            if isinstance(x, dict):
                return {k: clean(v) for k, v in x.items()}
            return x

        return {
            "model": self.model,
            "n_holdout": self.n_holdout,
            "n_case_base": self.n_case_base,
            "fresh_calls": self.fresh_calls,
            "seconds": self.seconds,
            "metric_notes": list(self.metric_notes),
            "configs": [clean(dict(c.__dict__, complete=c.complete)) for c in self.configs],
            "baselines": [clean(dict(c.__dict__, complete=c.complete)) for c in self.baselines],
            "picture": None if self.picture is None else str(self.picture),
        }


def _mean(xs: Sequence[float]) -> float:
    return sum(xs) / len(xs) if xs else math.nan


def _clean_text(s: str) -> str:
    return " ".join(s.replace("|", " ").split()).lower() or "-"


class TextScorer:
    """BLEU-4, ROUGE-L (F), METEOR and CIDEr (x100) of hypotheses against one reference each.

    METEOR runs pycocoevalcap's Java jar; it is started on the first call and kept for the next ones
    (a grid scores 28 field x configuration pairs, and each jar start costs seconds), so call
    :meth:`close` when done, or use the scorer as a context manager.
    """

    def __init__(self) -> None:
        self._meteor: Any = None
        self._meteor_note = ""

    def __enter__(self) -> TextScorer:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def close(self) -> None:
        """Stop METEOR's jar if it was started."""
        if self._meteor is not None:
            _close_meteor(self._meteor)
            self._meteor = None

    def score(self, hyps: Sequence[str], refs: Sequence[str]) -> tuple[dict[str, float], list[str]]:
        """Scores of ``hyps`` against ``refs``.

        Returns:
            ``(scores, notes)``: a metric whose package or runtime is missing is left out and named in
            ``notes`` with the reason.
        """
        notes: list[str] = []
        scores: dict[str, float] = {}
        if not hyps:
            return scores, notes
        try:
            import sacrebleu

            scores["BLEU4"] = float(sacrebleu.corpus_bleu(list(hyps), [list(refs)]).score)
        except ImportError:
            notes.append("BLEU4 unavailable: sacrebleu is not installed (pip install 'scenariominer[cbr]')")
        try:
            from rouge_score import rouge_scorer

            scorer = rouge_scorer.RougeScorer(["rougeL"], use_stemmer=True)
            scores["ROUGE_L"] = 100.0 * _mean(
                [scorer.score(r, h)["rougeL"].fmeasure for h, r in zip(hyps, refs, strict=True)]
            )
        except ImportError:
            notes.append(
                "ROUGE_L unavailable: rouge-score is not installed (pip install 'scenariominer[cbr]')"
            )
        gts = {str(i): [_clean_text(r)] for i, r in enumerate(refs)}
        res = {str(i): [_clean_text(h)] for i, h in enumerate(hyps)}
        try:
            from pycocoevalcap.cider.cider import Cider

            scores["CIDEr"] = 100.0 * float(Cider().compute_score(gts, res)[0])
        except ImportError:
            notes.append(
                "CIDEr unavailable: pycocoevalcap is not installed (pip install 'scenariominer[cbr]')"
            )
        meteor = self._meteor_scorer()
        if meteor is None:
            notes.append(self._meteor_note)
        else:
            try:
                scores["METEOR"] = 100.0 * float(meteor.compute_score(gts, res)[0])
            except (OSError, ValueError) as exc:  # the jar died mid-way: report it, do not retry
                self.close()
                self._meteor_note = f"METEOR unavailable: pycocoevalcap's METEOR jar failed ({exc})"
                notes.append(self._meteor_note)
        return scores, notes

    def _meteor_scorer(self) -> Any:
        if self._meteor is None and not self._meteor_note:
            try:
                from pycocoevalcap.meteor.meteor import Meteor

                self._meteor = Meteor()
            except ImportError:
                self._meteor_note = (
                    "METEOR unavailable: pycocoevalcap is not installed (pip install 'scenariominer[cbr]')"
                )
            except OSError as exc:
                self._meteor_note = (
                    f"METEOR unavailable: pycocoevalcap's METEOR needs Java to run its jar ({exc})"
                )
        return self._meteor


def text_metrics(hyps: Sequence[str], refs: Sequence[str]) -> tuple[dict[str, float], list[str]]:
    """One-off :meth:`TextScorer.score` (starts and stops METEOR's jar)."""
    with TextScorer() as scorer:
        return scorer.score(hyps, refs)


def _close_meteor(meteor: Any) -> None:
    proc = getattr(meteor, "meteor_p", None)
    if proc is None:
        return
    with meteor.lock:
        if proc.stdin:
            proc.stdin.close()
        proc.kill()
        proc.wait()
    if proc.stdout:
        proc.stdout.close()
    if proc.stderr:
        proc.stderr.close()
    # The finished process stays on the object: pycocoevalcap's own __del__ closes and kills it
    # again, which is harmless on a closed, reaped process (and raised when it found None).


def _vote(ranked: Sequence[str]) -> str:
    """Most frequent manoeuvre of ``ranked`` (best first); a tie goes to the better-ranked one."""
    counts = Counter(ranked)
    return max(ranked, key=lambda m: (counts[m], -ranked.index(m))) if ranked else ""


def baseline_rows(
    base: CaseBase, holdout: Sequence[HoldoutCase], embedder: Embedder, k: int = 5
) -> dict[str, dict[str, dict[str, Any]]]:
    """Answers of the model-free baselines: label -> case id -> row (as the grid stores them)."""
    majority: dict[str, str] = {}
    out: dict[str, dict[str, dict[str, Any]]] = {"baseline/majority": {}, f"baseline/vote/k{k}": {}}
    for hc in holdout:
        rt = hc.case.risk_type
        if rt not in majority:
            names = sorted(c.manoeuvre for c in base.cases(rt))
            majority[rt] = _vote(names)
        near = retrieve(base, hc.case.caption, rt, k, selection="similarity", embedder=embedder)
        for label, choice in (
            ("baseline/majority", majority[rt]),
            (f"baseline/vote/k{k}", _vote([r.case.manoeuvre for r in near])),
        ):
            out[label][hc.case.case_id] = {"manoeuvre": choice, "answer": {}, "error": "", "cached": True}
    return out


def _key(model: str, base_version: int, label: str, case_id: str) -> str:
    return f"{model}|{PROMPT_VERSION}|cb{base_version}|{label}|{case_id}"


def _answer_row(
    hc: HoldoutCase, base: CaseBase, client: ChatClient, embedder: Embedder, settings: RecommendSettings
) -> dict[str, Any]:
    q = Query(hc.case.case_id, hc.case.caption, hc.case.risk_type)
    try:
        rec = recommend(q, base, client, embedder, settings)
    except (CbrError, LLMError) as exc:
        return {
            "manoeuvre": "",
            "answer": {},
            "error": str(exc)[:500],
            "latency_s": math.nan,
            "cached": False,
        }
    return {
        "manoeuvre": rec.manoeuvre,
        "answer": rec.answer,
        "error": "",
        "latency_s": rec.latency_s,
        "cached": rec.cached,
        "attempts": rec.attempts,
        "retrieved": [r.case.case_id for r in rec.retrieved],
    }


def _score(
    label: str,
    holdout: Sequence[HoldoutCase],
    rows: dict[str, dict[str, Any]],
    text_scorer: TextScorer | None,
) -> tuple[ConfigResult, list[str]]:
    per_type: dict[str, list[bool]] = defaultdict(list)
    correct: list[bool] = []
    success: list[bool] = []
    latencies: list[float] = []
    invalid = 0
    hyps: dict[str, list[str]] = {f: [] for f in TEXT_FIELDS}
    refs: dict[str, list[str]] = {f: [] for f in TEXT_FIELDS}
    for hc in holdout:
        row = rows.get(hc.case.case_id)
        if row is None:
            continue
        ok = row["manoeuvre"] == hc.case.manoeuvre
        correct.append(ok)
        per_type[hc.case.risk_type].append(ok)
        if row["error"]:
            invalid += 1
            success.append(False)
        else:
            success.append(bool(hc.avoided.get(row["manoeuvre"], False)))
            for f in TEXT_FIELDS:
                hyps[f].append(str(row["answer"].get(f, "")))
                refs[f].append(str(getattr(hc.case, f)))
        lat = row.get("latency_s")
        if not row.get("cached") and isinstance(lat, float) and math.isfinite(lat):
            latencies.append(lat)
    text: dict[str, dict[str, float]] = {}
    notes: list[str] = []
    if text_scorer is not None:
        for f in TEXT_FIELDS:
            text[f], n = text_scorer.score(hyps[f], refs[f])
            notes += n
    result = ConfigResult(
        label=label,
        n_cases=len(holdout),
        n_answered=len(correct),
        accuracy=_mean([float(c) for c in correct]),
        per_type={rt: _mean([float(c) for c in v]) for rt, v in sorted(per_type.items())},
        n_invalid=invalid,
        rollout_success=_mean([float(s) for s in success]),
        seconds_per_call=_mean(latencies),
        text=text,
    )
    return result, notes


def interleaved(holdout: Sequence[HoldoutCase]) -> list[HoldoutCase]:
    """The hold-out cases in rounds over the risk types, each type's cases in their given order."""
    seen: dict[str, int] = {}
    order = []
    for i, hc in enumerate(holdout):
        rank = seen.get(hc.case.risk_type, 0)
        seen[hc.case.risk_type] = rank + 1
        order.append((rank, hc.case.risk_type, i))
    return [holdout[i] for _, _, i in sorted(order)]


def evaluate_cbr_grid(
    base: CaseBase,
    holdout: Sequence[HoldoutCase],
    results: CorpusTable,
    client: ChatClient,
    embedder: Embedder,
    grid: Sequence[RecommendSettings],
    *,
    time_budget_s: float | None = None,
    with_text: bool = True,
    progress: Progress | None = None,
    clock: Callable[[], float] = time.monotonic,
) -> CbrEvaluation:
    """Answer every (configuration, hold-out case) not yet stored, then score what is stored.

    Cases are answered in rounds over the risk types (the first case of each type, then the
    second, ...), every configuration for one case before the next, so a run stopped by its time
    budget leaves all configurations answered on the same cases, balanced over the risk types.

    Args:
        base: the case base (never holds a hold-out case).
        holdout: the hold-out cases with their rollout outcomes.
        results: corpus table where answers are kept (the resume point).
        client: the chat model.
        embedder: the caption embedder.
        grid: configurations, in the order to run them.
        time_budget_s: stop asking the model after this many seconds (what is stored is scored).
        with_text: compute the text metrics.
        progress: progress sink.
        clock: time source (tests).

    Raises:
        CbrError: the hold-out set is empty, or one of its cases is in the case base.
    """
    if not holdout:
        raise CbrError("the hold-out split is empty; run `scenariominer cbr build` first")
    leaked = {hc.case.case_id for hc in holdout} & set(base.table.keys())
    if leaked:
        raise CbrError(f"hold-out case(s) {sorted(leaked)[:3]} are in the case base; rebuild the split")
    start = clock()
    model = client.backend.model
    version = base.table.info().version
    prog = progress or NullProgress()
    fresh = 0
    prog.start("cbr evaluation", len(grid) * len(holdout))
    stopped = False
    for hc in interleaved(holdout):
        for settings in grid:
            key = _key(model, version, settings.label, hc.case.case_id)
            if not stopped and time_budget_s is not None and clock() - start > time_budget_s:
                stopped = True
            if stopped or results.get(key) is not None:
                prog.advance(1)
                continue
            row = _answer_row(hc, base, client, embedder, settings)
            results.upsert({key: row})
            fresh += 0 if row.get("cached") else 1
            prog.advance(1, f"{settings.label} {hc.case.case_id}")
    prog.finish()
    configs = []
    all_notes: list[str] = []
    text_scorer = TextScorer() if with_text else None
    try:
        for settings in grid:
            prefix = _key(model, version, settings.label, "")
            rows = {
                r.key[len(prefix) :]: dict(r.data)
                for r in results.rows([prefix + hc.case.case_id for hc in holdout])
            }
            result, notes = _score(settings.label, holdout, rows, text_scorer)
            configs.append(result)
            all_notes += [n for n in notes if n not in all_notes]
    finally:
        if text_scorer is not None:
            text_scorer.close()
    baselines = tuple(
        _score(label, holdout, rows, None)[0]
        for label, rows in baseline_rows(base, holdout, embedder).items()
    )
    risk_types = tuple(sorted({hc.case.risk_type for hc in holdout}))
    return CbrEvaluation(
        tuple(configs),
        risk_types,
        len(holdout),
        len(base),
        model,
        tuple(all_notes),
        fresh,
        clock() - start,
        baselines,
    )


#: The paper's best micro-accuracy (GPT-4o, risk-aware, similarity k=3), drawn for reference.
PAPER_BEST_ACCURACY = 0.941


def plot_evaluation(ev: CbrEvaluation, out: Path) -> Path:
    """Write a PNG of the grid: accuracy and rollout success per configuration, baselines as lines.

    Configurations run top to bottom in the grid's order; an unfinished one is marked ``*``. The
    model-free baselines and the paper's best accuracy are vertical lines.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    configs = list(ev.configs)
    fig, ax = plt.subplots(figsize=(8, 0.42 * len(configs) + 1.8))
    try:
        y = np.arange(len(configs))
        acc = [0.0 if math.isnan(c.accuracy) else c.accuracy for c in configs]
        roll = [c.rollout_success for c in configs]  # NaN (no answer) draws no dot
        ax.barh(y, acc, height=0.6, color="#4c72b0", label="manoeuvre accuracy")
        ax.plot(roll, y, "o", color="#dd8452", label="rollout success (avoids the conflict)")
        styles = ("--", ":")
        for b, style in zip(ev.baselines, styles * len(ev.baselines), strict=False):
            ax.axvline(
                b.accuracy, color="#55a868", linestyle=style, label=f"{b.label} (no model) {b.accuracy:.2f}"
            )
        ax.axvline(
            PAPER_BEST_ACCURACY,
            color="#999999",
            linestyle="-.",
            label=f"paper (GPT-4o, its own cases) {PAPER_BEST_ACCURACY}",
        )
        ax.set_yticks(y, [c.label + ("" if c.complete else " *") for c in configs])
        ax.invert_yaxis()
        ax.set_xlim(0, 1)
        ax.set_xlabel("share of hold-out cases")
        answered = max((c.n_answered for c in configs), default=0)
        share = f"{answered}" if answered == ev.n_holdout else f"{answered} of {ev.n_holdout}"
        model = ev.model.split("@")[0]
        ax.set_title(
            f"CBR on {share} hold-out cases, {ev.n_case_base} cases in the base ({model})", fontsize=10
        )
        ax.legend(loc="lower center", bbox_to_anchor=(0.5, 1.06), fontsize=8, ncol=2, frameon=False)
        fig.tight_layout()
        out.parent.mkdir(parents=True, exist_ok=True)
        fig.savefig(out, dpi=110)
    finally:
        plt.close(fig)
    return out
