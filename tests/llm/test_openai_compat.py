"""The OpenAI-compatible backend against a real HTTP server on loopback (see conftest)."""

from __future__ import annotations

import time

import pytest
from pydantic import BaseModel

from scenariominer.config.llm import StructuredMode
from scenariominer.llm import (
    BackendConnectionError,
    BackendHTTPError,
    BackendResponseError,
    BackendTimeoutError,
    ChatClient,
    ChatRequest,
    GenerationParams,
    OpenAICompatBackend,
    OpenAIHTTP,
    StructuredOutputError,
    system,
    user,
)
from scenariominer.llm.openai_compat import resolve_api_key
from scenariominer.testing import FakeClock

CHAT = "/v1/chat/completions"


class Maneuver(BaseModel):
    maneuver: str
    confidence: float


def make_backend(url: str, **kw: object) -> OpenAICompatBackend:
    http_kw = {k: kw.pop(k) for k in ("api_key", "timeout_s", "max_retries", "sleep") if k in kw}
    http = OpenAIHTTP(url, **http_kw)  # type: ignore[arg-type]
    return OpenAICompatBackend(http, "qwen2.5-coder:1.5b", **kw)  # type: ignore[arg-type]


def test_structured_call_sends_model_messages_params_and_json_schema(openai_server):
    backend = make_backend(openai_server.base_url, api_key="sk-test")
    client = ChatClient(backend)
    value = client.chat([system("You label manoeuvres."), user("Speed fell 14 -> 3 m/s.")], Maneuver)

    assert value == Maneuver(maneuver="braking", confidence=0.9)
    (body,) = openai_server.bodies(CHAT)
    assert body["model"] == "qwen2.5-coder:1.5b"
    assert body["temperature"] == 0.0
    assert body["top_p"] == 1.0
    assert body["top_k"] == 1
    assert body["stream"] is False
    assert [m["role"] for m in body["messages"]] == ["system", "user"]
    assert body["messages"][0]["content"].startswith("You label manoeuvres.")
    assert '"maneuver"' in body["messages"][0]["content"]  # the schema is also stated in the prompt
    assert body["messages"][1] == {"role": "user", "content": "Speed fell 14 -> 3 m/s."}
    fmt = body["response_format"]
    assert fmt["type"] == "json_schema"
    assert fmt["json_schema"]["name"] == "Maneuver"
    assert fmt["json_schema"]["schema"] == Maneuver.model_json_schema()
    headers = openai_server.requests[0][2]
    assert headers["authorization"] == "Bearer sk-test"


def test_free_text_call_has_no_response_format_and_reports_usage(openai_server):
    openai_server.push_chat("def add(a, b):\n    return a + b\n", prompt_tokens=20, completion_tokens=11)
    backend = make_backend(openai_server.base_url)
    completion = backend.complete(
        ChatRequest((user("write add"),), GenerationParams(max_tokens=64, stop=("\n\n",)))
    )
    assert completion.text == "def add(a, b):\n    return a + b\n"
    assert (completion.prompt_tokens, completion.completion_tokens) == (20, 11)
    assert completion.finish_reason == "stop"
    (body,) = openai_server.bodies(CHAT)
    assert "response_format" not in body
    assert body["max_tokens"] == 64
    assert body["stop"] == ["\n\n"]
    assert "authorization" not in openai_server.requests[0][2]  # no key configured: no header


@pytest.mark.parametrize(
    ("mode", "expected"),
    [(StructuredMode.JSON_OBJECT, {"type": "json_object"}), (StructuredMode.PROMPT, None)],
)
def test_structured_mode_controls_response_format(openai_server, mode, expected):
    client = ChatClient(make_backend(openai_server.base_url, structured_mode=mode))
    client.chat([user("label it")], Maneuver)
    (body,) = openai_server.bodies(CHAT)
    assert body.get("response_format") == expected


def test_send_top_k_false_omits_the_field(openai_server):
    ChatClient(make_backend(openai_server.base_url, send_top_k=False)).complete([user("hi")])
    assert "top_k" not in openai_server.bodies(CHAT)[0]


def test_schema_name_is_sanitised_for_the_api(openai_server):
    schema = {"title": "Scenario tag (v2)", "type": "object"}
    ChatClient(make_backend(openai_server.base_url)).chat([user("x")], schema)
    body = openai_server.bodies(CHAT)[0]
    assert body["response_format"]["json_schema"]["name"] == "Scenario_tag__v2_"


@pytest.mark.parametrize("status", [400, 401, 404, 422])
def test_http_error_status_raises_with_status_and_body(openai_server, status):
    openai_server.push({"error": {"message": "model 'nope' not found"}}, status=status)
    backend = make_backend(openai_server.base_url, max_retries=2)
    with pytest.raises(BackendHTTPError) as info:
        backend.complete(ChatRequest((user("hi"),)))
    assert info.value.status_code == status
    assert "model 'nope' not found" in str(info.value)
    assert CHAT in str(info.value)
    assert len(openai_server.bodies(CHAT)) == 1  # client errors are not retried


def test_server_errors_are_retried_then_succeed(openai_server):
    openai_server.push({"error": "overloaded"}, status=503)
    openai_server.push({"error": "rate limit"}, status=429, content_type="application/json")
    clock = FakeClock()
    backend = make_backend(openai_server.base_url, max_retries=2, sleep=clock.sleep)
    completion = backend.complete(ChatRequest((user("hi"),)))
    assert completion.text == '{"maneuver": "braking", "confidence": 0.9}'
    assert len(openai_server.bodies(CHAT)) == 3
    assert clock.sleeps == [0.5, 1.0]  # exponential back-off, without really waiting


def test_server_error_after_retries_raises_http_error(openai_server):
    openai_server.push({"error": "boom"}, status=500)
    openai_server.push({"error": "boom"}, status=500)
    clock = FakeClock()
    backend = make_backend(openai_server.base_url, max_retries=1, sleep=clock.sleep)
    with pytest.raises(BackendHTTPError) as info:
        backend.complete(ChatRequest((user("hi"),)))
    assert info.value.status_code == 500
    assert len(openai_server.bodies(CHAT)) == 2
    assert clock.sleeps == [0.5]


def test_timeout_raises_timeout_error_naming_the_limit(openai_server):
    openai_server.push_chat("late")
    openai_server.queue[-1].delay_s = 1.5
    backend = make_backend(openai_server.base_url, timeout_s=0.3)
    t0 = time.perf_counter()
    with pytest.raises(BackendTimeoutError) as info:
        backend.complete(ChatRequest((user("hi"),)))
    assert time.perf_counter() - t0 < 1.4
    assert info.value.timeout_s == 0.3
    assert "0.3 s" in str(info.value)


def test_non_json_body_raises_response_error(openai_server):
    openai_server.push(raw="<html><body>502 Bad Gateway</body></html>", status=200)
    with pytest.raises(BackendResponseError, match="not JSON.*text/html.*Bad Gateway"):
        make_backend(openai_server.base_url).complete(ChatRequest((user("hi"),)))


def test_json_without_choices_raises_response_error(openai_server):
    openai_server.push({"object": "chat.completion", "choices": []})
    with pytest.raises(BackendResponseError, match="choices"):
        make_backend(openai_server.base_url).complete(ChatRequest((user("hi"),)))


def test_refusal_without_content_raises_response_error(openai_server):
    body = {"choices": [{"message": {"role": "assistant", "content": None, "refusal": "I can't"}}]}
    openai_server.push(body)
    with pytest.raises(BackendResponseError, match='refusal: "I can\'t"'):
        make_backend(openai_server.base_url).complete(ChatRequest((user("hi"),)))


def test_connection_refused_raises_connection_error(unused_url):
    backend = make_backend(unused_url, max_retries=0)
    with pytest.raises(BackendConnectionError, match="is it running"):
        backend.complete(ChatRequest((user("hi"),)))


def test_invalid_answer_twice_over_http_raises_structured_output_error(openai_server):
    openai_server.push_chat('{"maneuver": "braking"}')
    openai_server.push_chat('{"maneuver": "braking", "confidence": "high"}')
    client = ChatClient(make_backend(openai_server.base_url))
    with pytest.raises(StructuredOutputError) as info:
        client.chat([user("label")], Maneuver)
    assert len(info.value.raw_outputs) == 2
    second = openai_server.bodies(CHAT)[1]["messages"]
    assert second[-2] == {"role": "assistant", "content": '{"maneuver": "braking"}'}
    assert "confidence" in second[-1]["content"]


def test_chat_many_runs_concurrently_but_bounded(openai_server):
    client = ChatClient(make_backend(openai_server.base_url), max_concurrency=3)
    values = client.chat_many([[user(f"case {i}")] for i in range(9)], Maneuver)
    assert values == [Maneuver(maneuver="braking", confidence=0.9)] * 9
    prompts = sorted(b["messages"][-1]["content"] for b in openai_server.bodies(CHAT))
    assert prompts == sorted(f"case {i}" for i in range(9))
    assert 2 <= openai_server.max_in_flight <= 3


def test_base_url_must_be_http():
    with pytest.raises(ValueError, match="http"):
        OpenAIHTTP("127.0.0.1:11434/v1")


def test_api_key_comes_from_config_then_environment():
    env = {"OPENAI_API_KEY": "from-env", "OTHER": "other"}
    assert resolve_api_key("from-config", "OPENAI_API_KEY", env) == "from-config"
    assert resolve_api_key("", "OPENAI_API_KEY", env) == "from-env"
    assert resolve_api_key("", "OTHER", env) == "other"
    assert resolve_api_key("", "UNSET_VAR", env) == ""
