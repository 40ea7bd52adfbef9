"""ChatClient: structured output, the repair round, caching, accounting, batching (scripted backend)."""

from __future__ import annotations

import threading
from typing import Literal

import pytest
from pydantic import BaseModel, Field

from scenariominer.llm import (
    BackendHTTPError,
    ChatClient,
    Completion,
    GenerationParams,
    ResponseCache,
    StructuredOutputError,
    UsageCounter,
    system,
    user,
)
from scenariominer.testing import ScriptedBackend, ScriptExhaustedError


class Verdict(BaseModel):
    label: Literal["braking", "not_braking"]
    decel_mps2: float = Field(ge=0)


VERDICT_SCHEMA = {
    "title": "Verdict",
    "type": "object",
    "properties": {"label": {"enum": ["braking", "not_braking"]}, "decel_mps2": {"type": "number"}},
    "required": ["label", "decel_mps2"],
    "additionalProperties": False,
}

VALID = '{"label": "braking", "decel_mps2": 5.5}'
MESSAGES = [system("You judge braking."), user("v: 14 -> 3 m/s in 2 s")]


@pytest.fixture
def cache(tmp_path):
    with ResponseCache(tmp_path / "cache.sqlite3") as c:
        yield c


def test_valid_answer_returns_the_model_instance_after_one_call():
    backend = ScriptedBackend([VALID])
    value = ChatClient(backend).chat(MESSAGES, Verdict)
    assert value == Verdict(label="braking", decel_mps2=5.5)
    assert len(backend.requests) == 1
    request = backend.requests[0]
    assert request.json_schema == Verdict.model_json_schema()
    assert request.schema_name == "Verdict"
    assert request.params == GenerationParams(temperature=0.0, top_p=1.0, top_k=1)


def test_schema_is_appended_to_the_system_message_or_added_as_one():
    backend = ScriptedBackend([VALID, VALID])
    client = ChatClient(backend)
    client.chat(MESSAGES, Verdict)
    client.chat([user("v: 14 -> 3 m/s in 2 s")], Verdict)
    first, second = backend.requests
    assert len(first.messages) == 2
    assert first.messages[0].content.startswith("You judge braking.\n\n")
    assert '"decel_mps2"' in first.messages[0].content
    assert [m.role.value for m in second.messages] == ["system", "user"]
    assert '"decel_mps2"' in second.messages[0].content


def test_schema_in_prompt_can_be_disabled():
    backend = ScriptedBackend([VALID])
    ChatClient(backend, schema_in_prompt=False).chat(MESSAGES, Verdict)
    assert backend.requests[0].messages[0].content == "You judge braking."


def test_invalid_then_valid_answer_succeeds_with_two_calls_and_shows_the_error():
    backend = ScriptedBackend(['{"label": "braking", "decel_mps2": -2}', VALID])
    result = ChatClient(backend).chat_result(MESSAGES, Verdict)
    assert result.value == Verdict(label="braking", decel_mps2=5.5)
    assert result.attempts == 2
    assert result.raw_outputs == ('{"label": "braking", "decel_mps2": -2}', VALID)
    repair = backend.requests[1].messages
    assert repair[:2] == backend.requests[0].messages
    assert repair[2].role.value == "assistant"
    assert repair[2].content == '{"label": "braking", "decel_mps2": -2}'
    assert repair[3].role.value == "user"
    assert "decel_mps2" in repair[3].content
    assert "greater than or equal to 0" in repair[3].content


def test_invalid_twice_raises_structured_output_error_with_raw_outputs():
    backend = ScriptedBackend(["I think it is braking.", '{"label": "stopping", "decel_mps2": 1}'])
    with pytest.raises(StructuredOutputError) as info:
        ChatClient(backend).chat(MESSAGES, Verdict)
    err = info.value
    assert err.schema_name == "Verdict"
    assert err.raw_outputs == ("I think it is braking.", '{"label": "stopping", "decel_mps2": 1}')
    assert "not valid JSON" in err.errors[0]
    assert "label" in err.errors[1]
    assert len(backend.requests) == 2


def test_repair_rounds_zero_fails_after_the_first_invalid_answer():
    backend = ScriptedBackend(["{}", VALID])
    with pytest.raises(StructuredOutputError):
        ChatClient(backend, repair_rounds=0).chat(MESSAGES, Verdict)
    assert backend.remaining == 1


def test_truncated_answer_error_mentions_max_tokens():
    cut = Completion('{"label": "brak', finish_reason="length")
    backend = ScriptedBackend([cut, cut])
    with pytest.raises(StructuredOutputError, match="cut off at max_tokens"):
        ChatClient(backend).chat(MESSAGES, Verdict)


@pytest.mark.parametrize(
    "answer",
    [
        f"```json\n{VALID}\n```",
        f"Here is the answer:\n{VALID}",
        f"  {VALID}  \n",
    ],
)
def test_fenced_or_prefixed_json_is_accepted(answer):
    assert ChatClient(ScriptedBackend([answer])).chat(MESSAGES, Verdict).label == "braking"


def test_json_schema_dict_returns_validated_data():
    backend = ScriptedBackend(['{"label": "braking"}', '{"label": "not_braking", "decel_mps2": 0.5}'])
    value = ChatClient(backend).chat(MESSAGES, VERDICT_SCHEMA)
    assert value == {"label": "not_braking", "decel_mps2": 0.5}
    assert "'decel_mps2' is a required property" in backend.requests[1].messages[-1].content
    assert backend.requests[0].schema_name == "Verdict"


def test_invalid_json_schema_is_rejected_before_any_call():
    backend = ScriptedBackend([VALID])
    with pytest.raises(ValueError, match="invalid JSON schema"):
        ChatClient(backend).chat(MESSAGES, {"type": "no-such-type"})
    assert backend.requests == []


def test_complete_returns_free_text_with_overrides():
    backend = ScriptedBackend(["def f():\n    return 1\n"])
    text = ChatClient(backend).complete([user("write f")], max_tokens=50, stop=("```",))
    assert text == "def f():\n    return 1\n"
    request = backend.requests[0]
    assert request.json_schema is None
    assert request.params.max_tokens == 50
    assert request.params.stop == ("```",)
    assert request.params.temperature == 0.0


def test_unknown_override_is_a_type_error():
    with pytest.raises(TypeError):
        ChatClient(ScriptedBackend(["x"])).complete([user("hi")], temprature=1.0)  # type: ignore[call-arg]


def test_identical_call_is_served_from_cache_and_changed_parameter_misses(cache):
    backend = ScriptedBackend([VALID, '{"label": "not_braking", "decel_mps2": 0}'])
    usage = UsageCounter()
    client = ChatClient(backend, cache=cache, usage=usage)
    first = client.chat(MESSAGES, Verdict)
    second = client.chat(MESSAGES, Verdict)
    assert first == second
    assert len(backend.requests) == 1
    changed = client.chat(MESSAGES, Verdict, temperature=0.7)
    assert changed.label == "not_braking"
    assert len(backend.requests) == 2
    report = usage.report()
    assert (report.calls, report.cache_hits) == (2, 1)


def test_cache_survives_a_new_client_and_key_includes_model_and_messages(tmp_path):
    path = tmp_path / "c.sqlite3"
    with ResponseCache(path) as c1:
        ChatClient(ScriptedBackend([VALID]), cache=c1).chat(MESSAGES, Verdict)
    with ResponseCache(path) as c2:
        again = ScriptedBackend([])
        assert ChatClient(again, cache=c2).chat(MESSAGES, Verdict).decel_mps2 == 5.5
        assert again.requests == []
        other_model = ScriptedBackend([VALID], model="another-model")
        ChatClient(other_model, cache=c2).chat(MESSAGES, Verdict)
        assert len(other_model.requests) == 1
        other_text = ScriptedBackend([VALID])
        ChatClient(other_text, cache=c2).chat([*MESSAGES[:1], user("v: 20 -> 3 m/s")], Verdict)
        assert len(other_text.requests) == 1


def test_cached_completion_keeps_tokens_but_is_flagged(cache):
    client = ChatClient(ScriptedBackend(["a b c"]), cache=cache)
    fresh = client.completion([user("one two")])
    hit = client.completion([user("one two")])
    assert (fresh.cached, hit.cached) == (False, True)
    assert (hit.text, hit.prompt_tokens, hit.completion_tokens) == ("a b c", 2, 3)


def test_usage_counts_calls_tokens_and_failures():
    backend = ScriptedBackend(["x y", BackendHTTPError("http://h/v1", 500, "boom")])
    usage = UsageCounter()
    client = ChatClient(backend, usage=usage)
    client.complete([user("a b c")])
    with pytest.raises(BackendHTTPError):
        client.complete([user("d")])
    (row,) = usage.report().rows
    assert (row.backend, row.model) == ("scripted", "scripted-model")
    assert (row.requests, row.calls, row.failures) == (2, 1, 1)
    assert (row.prompt_tokens, row.completion_tokens) == (3, 2)
    assert row.latency_s >= 0


def test_chat_many_keeps_input_order():
    replies = {f"case {i}": f'{{"label": "braking", "decel_mps2": {i}}}' for i in range(6)}
    backend = ScriptedBackend([lambda r: replies[r.messages[-1].content]] * 6)
    values = ChatClient(backend, max_concurrency=3).chat_many([[user(k)] for k in replies], Verdict)
    assert [v.decel_mps2 for v in values] == [0, 1, 2, 3, 4, 5]


def test_chat_many_runs_sequentially_on_a_non_concurrent_backend():
    active = 0
    peak = 0
    lock = threading.Lock()

    class Serial(ScriptedBackend):
        concurrent = False

        def complete(self, request):  # type: ignore[no-untyped-def]
            nonlocal active, peak
            with lock:
                active += 1
                peak = max(peak, active)
            try:
                return super().complete(request)
            finally:
                with lock:
                    active -= 1

    backend = Serial([VALID] * 5)
    ChatClient(backend, max_concurrency=4).chat_many([[user(str(i))] for i in range(5)], Verdict)
    assert peak == 1
    assert [r.messages[-1].content for r in backend.requests] == ["0", "1", "2", "3", "4"]


def test_chat_many_return_exceptions_puts_errors_in_place():
    backend = ScriptedBackend(
        [lambda r: "nope" if any(m.content == "bad" for m in r.messages) else VALID] * 4
    )
    out = ChatClient(backend, max_concurrency=1).chat_many(
        [[user("ok")], [user("bad")], [user("ok2")]], Verdict, return_exceptions=True
    )
    assert isinstance(out[0], Verdict)
    assert isinstance(out[1], StructuredOutputError)
    assert isinstance(out[2], Verdict)


def test_chat_many_without_return_exceptions_raises():
    backend = ScriptedBackend(["nope", "nope"])
    with pytest.raises(StructuredOutputError):
        ChatClient(backend).chat_many([[user("x")]], Verdict)


def test_complete_many_returns_texts_in_order():
    backend = ScriptedBackend([lambda r: r.messages[-1].content.upper()] * 3)
    assert ChatClient(backend).complete_many([[user("a")], [user("b")], [user("c")]]) == ["A", "B", "C"]


def test_scripted_backend_runs_out_loudly():
    with pytest.raises(ScriptExhaustedError, match="holds only 0 replies"):
        ChatClient(ScriptedBackend([])).complete([user("hi")])


@pytest.mark.parametrize(
    ("messages", "error"),
    [
        ([], "at least one message"),
        ([{"role": "robot", "content": "x"}], "unknown role 'robot'"),
        ([{"content": "x"}], "must have 'role' and 'content'"),
    ],
)
def test_bad_messages_are_rejected(messages, error):
    with pytest.raises(ValueError, match=error):
        ChatClient(ScriptedBackend([VALID])).complete(messages)


def test_wire_form_dict_messages_are_accepted():
    backend = ScriptedBackend(["ok"])
    ChatClient(backend).complete([{"role": "user", "content": "hi"}])
    assert backend.requests[0].messages_as_dicts() == [{"role": "user", "content": "hi"}]
