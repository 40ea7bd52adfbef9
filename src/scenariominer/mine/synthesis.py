"""Program synthesis: few-shot example choice, one model call, and code extraction.

* :class:`ExampleSelector` picks the example programs whose descriptions are most similar to the
  query (cosine similarity of sentence embeddings), from the shipped bank plus user bank files;
  a bank entry with the query's own description is left out (leave-one-out), so evaluating on
  the bank measures generation, not recall of the answer.
* :class:`ProgramSynthesizer` composes the prompt (:mod:`scenariominer.mine.prompts`), calls the
  chat client and extracts the program from the answer (:func:`extract_program`).

The repair loop around it (check, run, feed the error back) is :mod:`scenariominer.mine.loop`.
"""

from __future__ import annotations

import ast
import re
import time
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from scenariominer.config.mining import GenerationConfig
from scenariominer.llm.base import GenerationOverrides, Message
from scenariominer.llm.client import ChatClient
from scenariominer.llm.embeddings import Embedder, Embeddings
from scenariominer.llm.errors import StructuredOutputError
from scenariominer.mine.grammar import program_grammar
from scenariominer.mine.plan import extract_plan, plan_text
from scenariominer.mine.plan_documents import request_text
from scenariominer.mine.plan_reader import read_plan
from scenariominer.mine.plan_reword import reword, reword_again, reworded_plan
from scenariominer.mine.programs import ExampleProgram
from scenariominer.mine.prompts import build_messages
from scenariominer.retrieval import rank

__all__ = [
    "ExampleSelector",
    "Generation",
    "ProgramSynthesizer",
    "extract_program",
    "normalize_description",
]

_FENCE = re.compile(r"```[ \t]*([A-Za-z0-9_+-]*)[ \t]*\n(.*?)(?:\n[ \t]*```|\Z)", re.DOTALL)
_CODE_LANGS = frozenset({"", "python", "py", "python3"})
_MAX_TRIM_LINES = 200


def normalize_description(text: str) -> str:
    """Lower-case, single-spaced, without trailing punctuation: the identity of a description."""
    return " ".join(text.lower().split()).rstrip(".!?;: ")


def _parses(source: str) -> bool:
    try:
        ast.parse(source)
    except (SyntaxError, ValueError):
        return False
    return True


def _trim_prose(text: str) -> str:
    """The longest run of lines of ``text`` that parses as Python, trimming prose at both ends."""
    lines = text.strip().splitlines()
    if _parses("\n".join(lines)):
        return "\n".join(lines)
    n = min(len(lines), _MAX_TRIM_LINES)
    for start in range(n):
        for stop in range(len(lines), start, -1):
            chunk = "\n".join(lines[start:stop]).strip()
            if chunk and _parses(chunk) and "(" in chunk:
                return chunk
    return text.strip()


def extract_program(reply: str) -> str:
    """The program in a model's answer.

    Code fences are preferred: the first fenced block (```python, ```py or a bare ```) that
    calls ``output_scenario``, else the longest fenced code block; a fence left open because the
    answer was cut off counts up to the end of the text. Without fences the answer is taken as
    bare code, with leading and trailing prose lines dropped until the rest parses. When nothing
    parses, the stripped answer is returned so the checker can report the syntax error.

    Args:
        reply: the model's answer text.

    Returns:
        The program text (possibly empty).
    """
    blocks = [body.strip("\n") for lang, body in _FENCE.findall(reply) if lang.lower() in _CODE_LANGS]
    blocks = [b for b in blocks if b.strip()]
    if blocks:
        with_output = [b for b in blocks if "output_scenario" in b]
        chosen: str = with_output[0] if with_output else max(blocks, key=len)
        return chosen.strip() + "\n"
    bare = _trim_prose(reply.replace("```", ""))
    return bare + "\n" if bare else ""


class ExampleSelector:
    """Chooses few-shot example programs by embedding similarity of their descriptions.

    The bank's descriptions are embedded once (lazily, on the first query); each query costs
    one embedding.

    Args:
        examples: the example bank (:func:`~scenariominer.mine.programs.load_examples`).
        embedder: any :class:`~scenariominer.llm.embeddings.Embedder`.
    """

    def __init__(self, examples: Sequence[ExampleProgram], embedder: Embedder) -> None:
        self.examples = tuple(examples)
        self.embedder = embedder
        self._bank: Embeddings | None = None

    def _bank_vectors(self) -> Embeddings:
        if self._bank is None:
            self._bank = self.embedder.embed([e.description for e in self.examples])
        return self._bank

    def similarities(self, description: str) -> np.ndarray:
        """``(len(examples),)`` cosine similarity of every bank description to ``description``."""
        if not self.examples:
            return np.zeros(0, dtype=np.float32)
        query = self.embedder.embed([description])
        return np.asarray(self._bank_vectors().cosine(query)[:, 0])

    def select(self, description: str, k: int, *, leave_one_out: bool = True) -> list[ExampleProgram]:
        """The ``k`` examples most similar to ``description``, most similar first.

        Args:
            description: the query.
            k: how many examples (fewer when the bank is smaller).
            leave_one_out: skip bank entries whose description equals the query (after
                :func:`normalize_description`).
        """
        if k <= 0 or not self.examples:
            return []
        query = self.embedder.embed([description])
        key = normalize_description(description)
        chosen: list[ExampleProgram] = []
        for hit in rank(self._bank_vectors().vectors, query.vectors[0]):
            ex = self.examples[int(hit.id)]
            if leave_one_out and normalize_description(ex.description) == key:
                continue
            chosen.append(ex)
            if len(chosen) == k:
                break
        return chosen


@dataclass(frozen=True)
class Generation:
    """One answer of the model and the program extracted from it.

    Attributes:
        program: the extracted program text.
        reply: the raw answer.
        latency_s: seconds the call took (of the original call when served from the cache).
        cached: whether the answer came from the LLM response cache.
        prompt_tokens: prompt tokens as counted by the backend.
        completion_tokens: generated tokens.
        finish_reason: why generation stopped (``"length"`` means cut off at ``max_tokens``).
    """

    program: str
    reply: str
    latency_s: float
    cached: bool = False
    prompt_tokens: int = 0
    completion_tokens: int = 0
    finish_reason: str = ""


class ProgramSynthesizer:
    """Writes mining programs with a chat model: prompt composition, call, code extraction.

    Args:
        client: the chat client (its cache makes repeated prompts free).
        selector: few-shot example selector; ``None`` for zero-shot prompts.
        config: generation settings (``few_shot_k``, ``reference_style``, ``max_tokens``).
        leave_one_out: never show an example with the query's own description.
    """

    def __init__(
        self,
        client: ChatClient,
        selector: ExampleSelector | None = None,
        config: GenerationConfig | None = None,
        *,
        leave_one_out: bool = True,
    ) -> None:
        self.client = client
        self.selector = selector
        self.config = config or GenerationConfig()
        self.leave_one_out = leave_one_out
        self.plans: dict[str, dict[str, Any]] = {}
        self.rewordings: dict[str, dict[str, str]] = {}

    @property
    def model(self) -> str:
        """Identity of the model behind the client (backend and model name)."""
        return f"{self.client.backend.name}:{self.client.backend.model}"

    def examples_for(self, description: str) -> list[ExampleProgram]:
        """The few-shot examples the prompt for ``description`` shows, most similar first."""
        if self.selector is None:
            return []
        return self.selector.select(description, self.config.few_shot_k, leave_one_out=self.leave_one_out)

    def plan_for(self, description: str) -> dict[str, Any] | None:
        """The description's plan (kept per description); ``None`` when planning is off.

        With ``plan_rules`` on, the phrase rules read it first (no model call); failing that, with
        ``plan_reword`` they read the model's plain rewording of it when they can read all of it
        and it keeps the description's numbers and road users
        (:mod:`scenariominer.mine.plan_reword`); failing that, with ``plan_partial``, they read
        the description in part when some of its words are not their phrases, as long as they
        read the subject (the plan lists the words left out under ``unread``); failing that,
        with both, they read the rewording in part under the same checks (its subject read; on
        the spent splits this agreed with the references about twice as well as the model's own
        plans, docs/mining.md). Otherwise one model call does. A plan the model cannot produce in
        a valid form is recorded as ``{"error": ...}`` and the program is written without it.
        """
        if not self.config.plan:
            return None
        if description not in self.plans and self.config.plan_rules:
            read = read_plan(description)
            if read is None and self.config.plan_reword:
                read = self._reworded(description)
            if read is None and self.config.plan_partial:
                read = read_plan(description, partial=True)
            if read is None and self.config.plan_partial and description in self.rewordings:
                # not even in part: the rules' partial reading of the rewording, if it passes
                rewording = self.rewordings[description]
                read, reason = reworded_plan(description, rewording["text"], partial=True)
                rewording["in_part"] = reason or "used"
            if read is not None:
                self.plans[description] = read
        if description not in self.plans:
            try:
                self.plans[description] = extract_plan(self.client, description)
            except StructuredOutputError as exc:
                self.plans[description] = {"error": str(exc)[:300]}
        return self.plans[description]

    def _reworded(self, description: str) -> dict[str, Any] | None:
        """The rules' reading of the model's plain rewording of ``description``, if it passes.

        The rewording and why it was refused are kept in :attr:`rewordings` (for the report).
        """
        rewording = reword(self.client, description)
        plan, reason = reworded_plan(description, rewording)
        self.rewordings[description] = {"text": rewording, "refused": reason}
        for _ in range(self.config.plan_reword_tries - 1):
            if plan is not None:
                break
            # the next request shows the refused rewording and why (the words not read, ...)
            again, hint = reword_again(self.client, description, rewording)
            if not hint:
                break  # refused for a reason a second request does not mend
            rewording = again
            plan, reason = reworded_plan(description, rewording)
            earlier = self.rewordings[description]
            self.rewordings[description] = {"text": rewording, "refused": reason, "earlier": earlier["text"]}
        return plan

    def first_messages(self, description: str) -> list[Message]:
        """The first request for ``description`` (system message, examples, description, plan)."""
        plan = self.plan_for(description)
        shown = plan_text(plan) if plan and "error" not in plan else None
        # the request as written, without a ticket's key or a clause's number around it
        text = request_text(description)
        return build_messages(text, self.examples_for(description), self.config.reference_style, shown)

    def generate(
        self, messages: Sequence[Message], *, temperature: float | None = None, seed: int | None = None
    ) -> Generation:
        """Call the model once and extract the program from its answer.

        Args:
            messages: the request.
            temperature: sampling temperature for this call (default: the client's, greedy).
            seed: sampling seed for this call (matters only when sampling).

        Raises:
            BackendError: the backend call failed.
        """
        overrides: GenerationOverrides = {"max_tokens": self.config.max_tokens}
        if temperature is not None:
            overrides["temperature"] = temperature
            if temperature > 0:
                overrides["top_k"] = 0  # the client's greedy default top_k = 1 would undo sampling
        if seed is not None:
            overrides["seed"] = seed
        t0 = time.perf_counter()
        grammar = program_grammar() if self.config.grammar else None
        completion = self.client.completion(list(messages), grammar=grammar, **overrides)
        elapsed = time.perf_counter() - t0
        return Generation(
            program=extract_program(completion.text),
            reply=completion.text,
            latency_s=completion.latency_s if completion.cached else elapsed,
            cached=completion.cached,
            prompt_tokens=completion.prompt_tokens,
            completion_tokens=completion.completion_tokens,
            finish_reason=completion.finish_reason,
        )
