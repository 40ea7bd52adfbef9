"""Texts of structured answers: a length-capped field the model filled to its bound, ended cleanly."""

from __future__ import annotations

import re

__all__ = ["tidy_cut_text"]

_SENTENCE_END = re.compile(r"[.;](?=\s|$)")  # not the point of "3.2"
_CLAUSE_END = re.compile(r",(?=\s)")


def tidy_cut_text(text: str, max_chars: int) -> str:
    """A text the schema's length bound cut off, ended at its last full sentence or clause.

    Small models write up to the bound; a cut-off text is trimmed back to its last ``.``/``;``
    (else its last comma, if that keeps half of it) and marked with ``…``. Texts shorter than the
    bound are returned unchanged.
    """
    text = text.strip()
    if len(text) < max_chars - 1:
        return text
    for pattern, end in ((_SENTENCE_END, "."), (_CLAUSE_END, " …")):
        cuts = [m.start() for m in pattern.finditer(text)]
        if cuts and cuts[-1] >= len(text) // 2:
            return text[: cuts[-1]].rstrip() + end
    return text.rstrip() + " …"
