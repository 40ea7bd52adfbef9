"""Text from outside (programs, logs, file names, log ids, error messages) printed as data.

Such text may hold Rich markup (``[/x]`` crashes Rich's parser, ``[link=...]`` forges a link),
terminal escape sequences (CSI colour or cursor codes, OSC titles and OSC-8 hyperlinks), other
control characters, or lone surrogates that cannot be encoded. :func:`plain` makes it inert and
visible; :func:`safe` also escapes markup, for interpolation into a markup string.
"""

from __future__ import annotations

import re

__all__ = ["plain", "safe"]

# ESC [ ... final byte (CSI); ESC ] ... BEL or ESC \ (OSC, e.g. OSC-8 links); ESC P/X/^/_ ... ESC \
# (DCS, SOS, PM, APC); the 8-bit forms of CSI (0x9b) and OSC (0x9d); any other two-byte ESC sequence.
_ESCAPES = re.compile(
    r"(?:\x1b\[|\x9b)[0-?]*[ -/]*[@-~]"
    r"|(?:\x1b\]|\x9d).*?(?:\x07|\x1b\\|\x9c|$)"
    r"|\x1b[PX^_].*?(?:\x1b\\|\x9c|$)"
    r"|\x1b[@-Z\\-_]",
    re.DOTALL,
)
# C0 controls except tab and newline, DEL, C1 controls, and the bidirectional overrides.
_CONTROLS = re.compile(r"[\x00-\x08\x0b-\x1f\x7f-\x9f\u202a-\u202e\u2066-\u2069]")


def _visible(match: re.Match[str]) -> str:
    return match.group(0).encode("unicode_escape").decode("ascii")


def plain(text: object) -> str:
    """``str(text)`` with escape sequences and control characters shown as hex escapes.

    Lone surrogates become ``?`` so the result always encodes as UTF-8.
    """
    s = str(text)
    s = s.encode("utf-8", "surrogatepass").decode("utf-8", "replace") if _has_surrogate(s) else s
    s = _ESCAPES.sub(_visible, s)
    return _CONTROLS.sub(_visible, s)


def safe(text: object) -> str:
    """:func:`plain`, then Rich markup escaped: safe inside ``console.print(f"[red]{safe(x)}[/red]")``."""
    from rich.markup import escape

    s = plain(text)
    body = s.rstrip("\\")
    # Rich reads 2k backslashes before a tag as k literal ones, so a trailing run is doubled here
    # (rich.markup.escape does that for a single backslash only).
    return escape(body) + "\\" * (2 * (len(s) - len(body)))


def _has_surrogate(s: str) -> bool:
    return any("\ud800" <= ch <= "\udfff" for ch in s)
