"""llama.cpp's log lines go to Python logging, not straight to the terminal.

llama-cpp-python 0.3.16 filters llama.cpp's log with a table of levels that ggml has since
renumbered (now 1 debug, 2 info, 3 warning, 4 error, 5 continuation of the previous line), so
with ``verbose=False`` llama.cpp's warnings still reach stderr, e.g. ``llama_context: n_ctx_per_seq
(8192) < n_ctx_train (32768) -- the full capacity of the model will not be utilized`` in the middle
of ``scenariominer demo``'s output (the context size is our deliberate choice). :func:`install`
replaces that filter: every line goes to the ``scenariominer.llm.llama_cpp`` logger, errors at
``ERROR`` (shown by Python's default handler when logging is not configured) and the rest at
``DEBUG``.
"""

from __future__ import annotations

import ctypes
import logging
import threading
from typing import Any

__all__ = ["LOGGER_NAME", "install", "route"]

LOGGER_NAME = "scenariominer.llm.llama_cpp"
_logger = logging.getLogger(LOGGER_NAME)

#: ggml's log levels (ggml.h ``enum ggml_log_level``) that matter here.
_GGML_ERROR = 4
_GGML_CONTINUATION = 5

_lock = threading.Lock()
_state: dict[str, Any] = {"last": logging.DEBUG, "callback": None}


def route(level: int, text: bytes) -> None:
    """Log one llama.cpp message (``level``: ggml's log level) to the module's logger."""
    with _lock:
        if level == _GGML_CONTINUATION:
            python_level = _state["last"]
        else:
            python_level = logging.ERROR if level == _GGML_ERROR else logging.DEBUG
        _state["last"] = python_level
    message = text.decode("utf-8", errors="replace").rstrip("\n")
    if message.strip():
        _logger.log(python_level, "%s", message)


def install() -> None:
    """Send llama.cpp's log to :func:`route` from now on (idempotent).

    Call it after importing ``llama_cpp``: importing ``llama_cpp.llama`` installs the library's own
    callback, which this one replaces.
    """
    with _lock:
        if _state["callback"] is not None:
            return
        import llama_cpp

        @llama_cpp.llama_log_callback  # type: ignore[untyped-decorator,unused-ignore]
        def _callback(level: int, text: bytes, user_data: ctypes.c_void_p) -> None:
            route(level, text)

        llama_cpp.llama_log_set(_callback, ctypes.c_void_p(0))
        _state["callback"] = _callback  # kept alive: llama.cpp holds only a C pointer to it
