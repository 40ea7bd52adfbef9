"""llama.cpp's log lines reach Python logging: errors as errors, the rest as debug, none on stderr."""

from __future__ import annotations

import logging

import pytest

from scenariominer.llm.llama_log import LOGGER_NAME, route


def test_warnings_become_debug_records_and_errors_stay_errors(
    caplog: pytest.LogCaptureFixture, capfd: pytest.CaptureFixture[str]
) -> None:
    caplog.set_level(logging.DEBUG, logger=LOGGER_NAME)
    route(3, b"llama_context: n_ctx_per_seq (8192) < n_ctx_train (32768) -- ...\n")  # ggml warning
    route(2, b"llama_model_loader: loaded meta data\n")  # info
    route(4, b"parse: error parsing grammar: expecting name at 1 +\n")  # error
    route(5, b"  continued\n")  # continuation of the error line
    route(3, b"\n")  # an empty line is dropped
    records = [(r.levelno, r.getMessage()) for r in caplog.records if r.name == LOGGER_NAME]
    assert records == [
        (logging.DEBUG, "llama_context: n_ctx_per_seq (8192) < n_ctx_train (32768) -- ..."),
        (logging.DEBUG, "llama_model_loader: loaded meta data"),
        (logging.ERROR, "parse: error parsing grammar: expecting name at 1 +"),
        (logging.ERROR, "  continued"),
    ]
    assert capfd.readouterr().err == ""  # caplog's handler took the records; nothing printed directly


def test_undecodable_bytes_are_replaced(caplog: pytest.LogCaptureFixture) -> None:
    caplog.set_level(logging.DEBUG, logger=LOGGER_NAME)
    route(4, b"bad \xff byte")
    assert [r.getMessage() for r in caplog.records if r.name == LOGGER_NAME] == ["bad \ufffd byte"]
