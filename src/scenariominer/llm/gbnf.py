"""Check a text against a llama.cpp grammar (GBNF) exactly as constrained decoding would.

:class:`GbnfMatcher` loads only a model's vocabulary (a fraction of a second, no weights) and
feeds a text's tokens through llama.cpp's own grammar sampler, one candidate at a time: a token
the grammar forbids gets a logit of minus infinity and is never accepted, so the check is safe
(llama.cpp aborts the process when a forbidden token is *accepted*) and says where the text
leaves the grammar. It answers "could the model have produced this text under the grammar?",
which tests use to check that a generated grammar admits the programs it should and refuses the
ones it should not.
"""

from __future__ import annotations

import ctypes
import threading
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from scenariominer import _optional
from scenariominer.llm import llama_log
from scenariominer.llm.errors import BackendError

__all__ = ["GbnfMatch", "GbnfMatcher", "GrammarSyntaxError"]


class GrammarSyntaxError(BackendError):
    """llama.cpp could not parse the grammar (its parser printed the reason to stderr)."""


@dataclass(frozen=True)
class GbnfMatch:
    """Outcome of :meth:`GbnfMatcher.match`.

    Attributes:
        accepted: the whole text, followed by end-of-text, is allowed by the grammar.
        rejected_at: character offset where the first forbidden token starts (``None`` if accepted;
            ``len(text)`` when the text is a valid prefix that the grammar does not let end there).
    """

    accepted: bool
    rejected_at: int | None = None


class GbnfMatcher:
    """Grammar checks with a GGUF model's vocabulary (thread-safe, one loaded vocabulary).

    Args:
        model_path: the GGUF file whose tokenizer decoding uses (the embedded model's file).
    """

    def __init__(self, model_path: str | Path) -> None:
        self.model_path = Path(model_path)
        self._lock = threading.Lock()
        self._llama: Any = None

    def _load(self) -> Any:
        if self._llama is None:
            llama_cpp = _optional.require("llama_cpp", extra="llm", purpose="grammar checks")
            llama_log.install()
            self._llama = llama_cpp.Llama(model_path=str(self.model_path), vocab_only=True, verbose=False)
        return self._llama

    def match(self, grammar: str, text: str, *, root: str = "root") -> GbnfMatch:
        """Whether ``grammar`` admits ``text`` as a complete answer.

        Raises:
            GrammarSyntaxError: the grammar does not parse.
        """
        import llama_cpp

        with self._lock:
            llama = self._load()
            vocab = llama_cpp.llama_model_get_vocab(llama.model)
            sampler = llama_cpp.llama_sampler_init_grammar(vocab, grammar.encode(), root.encode())
            if not sampler:
                raise GrammarSyntaxError("llama.cpp could not parse the grammar (see its message above)")
            try:
                return self._feed(llama, sampler, text)
            finally:
                llama_cpp.llama_sampler_free(sampler)

    @staticmethod
    def _feed(llama: Any, sampler: Any, text: str) -> GbnfMatch:
        import llama_cpp

        eos = llama.token_eos()
        tokens = [*llama.tokenize(text.encode("utf-8"), add_bos=False, special=False), eos]
        candidate = (llama_cpp.llama_token_data * 1)()
        consumed = b""
        for token in tokens:
            candidate[0].id, candidate[0].logit, candidate[0].p = token, 0.0, 0.0
            array = llama_cpp.llama_token_data_array(data=candidate, size=1, selected=-1, sorted=False)
            llama_cpp.llama_sampler_apply(sampler, ctypes.byref(array))
            if candidate[0].logit == float("-inf"):
                return GbnfMatch(False, len(consumed.decode("utf-8", errors="replace")))
            if token != eos:
                llama_cpp.llama_sampler_accept(sampler, token)
                consumed += llama.detokenize([token])
        return GbnfMatch(True)
