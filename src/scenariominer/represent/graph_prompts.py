"""Prompts and answer schemas of the graph's language-model calls (stages 2-3 and the answer).

* cluster summary (stage 2): the 5 samples nearest to the cluster's centre describe what the
  cluster has in common;
* cluster contrast (stage 3): 5 random samples of other clusters, compared with the cluster;
* community report: the facts of one Leiden community (counts, relationships);
* answer: a question, the retrieved samples, relationships and reports with short ids to cite.

Every answer is schema-constrained JSON with short fields (the embedded 1.5B model writes about
10-20 tokens a second on 2 cores). :data:`PROMPT_VERSION` is part of every cached answer's key.
"""

from __future__ import annotations

from collections.abc import Sequence

from pydantic import BaseModel, Field

__all__ = [
    "PROMPT_VERSION",
    "AnswerOut",
    "ClusterContrastOut",
    "ClusterSummaryOut",
    "ReportOut",
    "answer_messages",
    "cluster_contrast_messages",
    "cluster_summary_messages",
    "report_messages",
    "shorten",
]

PROMPT_VERSION = "graph-1"

_ROLE = (
    "You analyse highway and urban driving data for scenario-based testing. Samples are 15 s "
    "windows of a chosen vehicle and the road users around it; lanes are numbered as in the data. "
    "Use only the facts given; keep every field short."
)


class ClusterSummaryOut(BaseModel):
    """What the samples of one cluster have in common."""

    title: str = Field(max_length=80, description="a few words naming the behaviour")
    traffic: str = Field(max_length=160, description="traffic density, lanes and speeds")
    behaviour: str = Field(max_length=240, description="manoeuvres and interactions the samples share")


class ClusterContrastOut(BaseModel):
    """How a cluster differs from samples of other clusters."""

    others: str = Field(max_length=200, description="what the other samples show")
    difference: str = Field(max_length=240, description="how the cluster differs from them")


class ReportOut(BaseModel):
    """Report of a graph community."""

    title: str = Field(max_length=80, description="a few words naming the community")
    summary: str = Field(max_length=300, description="what the samples and vehicles in it do")


class AnswerOut(BaseModel):
    """Answer to a question over the retrieved context."""

    answer: str = Field(max_length=700, description="answer naming vehicle ids, lanes and frames or times")
    samples: list[int] = Field(max_length=5, description="numbers of the samples [S#] that match best")
    relationships: list[int] = Field(max_length=8, description="numbers of the relationships [R#] used")
    reports: list[int] = Field(max_length=3, description="numbers of the reports [C#] used")


def shorten(text: str, max_chars: int) -> str:
    """``text`` cut to ``max_chars`` at a word boundary (with an ellipsis)."""
    if len(text) <= max_chars:
        return text
    return text[: max_chars - 3].rsplit(" ", 1)[0] + "..."


def _numbered(prefix: str, texts: Sequence[str], max_chars: int) -> str:
    return "\n".join(f"[{prefix}{i}] {shorten(t, max_chars)}" for i, t in enumerate(texts, 1))


def cluster_summary_messages(
    cluster: str, samples: Sequence[str], max_chars: int = 600
) -> list[dict[str, str]]:
    """Stage 2: describe ``cluster`` from its samples nearest to the cluster centre."""
    return [
        {"role": "system", "content": _ROLE},
        {
            "role": "user",
            "content": f"These samples are the ones nearest to the centre of {cluster} of the trajectory "
            f"embedding:\n{_numbered('S', samples, max_chars)}\n\nDescribe what they have in common: "
            "traffic, lanes and speed, then the manoeuvres and interactions.",
        },
    ]


def cluster_contrast_messages(
    cluster: str, summary: str, others: Sequence[str], max_chars: int = 400
) -> list[dict[str, str]]:
    """Stage 3: compare ``cluster`` (its summary) with random samples of other clusters."""
    return [
        {"role": "system", "content": _ROLE},
        {
            "role": "user",
            "content": f"{cluster}: {summary}\n\nRandom samples of other clusters:\n"
            f"{_numbered('O', others, max_chars)}\n\nSay briefly what the other samples show and how "
            f"{cluster} differs from them.",
        },
    ]


def report_messages(community: str, facts: str, relationships: Sequence[str]) -> list[dict[str, str]]:
    """A community report from its counted facts and some of its relationships."""
    return [
        {"role": "system", "content": _ROLE},
        {
            "role": "user",
            "content": f"Community {community} of the scenario knowledge graph.\nFacts: {facts}\n"
            f"Relationships:\n{_numbered('R', relationships, 200)}\n\nName the community and summarise "
            "what its samples and vehicles do.",
        },
    ]


def answer_messages(
    question: str, samples: Sequence[str], relationships: Sequence[str], reports: Sequence[str]
) -> list[dict[str, str]]:
    """The question with the retrieved, numbered context to cite."""
    return [
        {"role": "system", "content": _ROLE},
        {
            "role": "user",
            "content": f"Question: {question}\n\nSamples:\n{_numbered('S', samples, 500)}\n\n"
            f"Relationships:\n{_numbered('R', relationships, 200)}\n\nReports:\n"
            f"{_numbered('C', reports, 300)}\n\nAnswer the question from these facts only. Name the "
            "concrete vehicle ids, lanes and frames (or times), and list the numbers of the samples, "
            "relationships and reports you used.",
        },
    ]
