from __future__ import annotations

import asyncio
import json
import socket
import time
from typing import Any

import pytest

from pare.agents.models import ChatMessage, Completion, ModelClient, ModelConfig, Prices, UsageLedger
from pare.errors import ModelRequestError, ProviderUnavailable, UserInputError

from .conftest import BACKENDS, KEY, KEY_VARIABLE, ConfigFactory
from .fake_server import (
    BAD_KEY,
    BAD_PARAM,
    NO_ACCESS,
    NO_MODEL,
    NO_QUOTA,
    OVERLOADED,
    RATE_LIMITED,
    SERVER_ERROR,
    TOO_LONG,
    FakeChatServer,
    Reply,
    answer,
    error,
    tool_call,
)

HELLO = [ChatMessage.system("You are terse."), ChatMessage.user("Say hello.")]


def run(client: ModelClient, messages: list[ChatMessage] = HELLO, tools: Any = None) -> Completion:
    async def call() -> Completion:
        async with client:
            return await client.complete(messages, tools)

    return asyncio.run(call())


# --- a normal call -------------------------------------------------------------------------------


@pytest.mark.parametrize("backend", BACKENDS)
def test_normal_call_returns_text_usage_latency_and_cost_from_config_prices(
    backend: str, server: FakeChatServer, make_config: ConfigFactory
) -> None:
    server.push(answer("Hello.", prompt_tokens=1000, completion_tokens=100, cached_tokens=400))
    prices = Prices(input=2.0, output=8.0, cached_input=0.5)
    ledger = UsageLedger()
    config = make_config(backend, prices=prices, seed=7, max_tokens=64, temperature=0.3)
    completion = run(ModelClient(config, role="user", ledger=ledger))

    assert completion.text == "Hello."
    assert completion.usage.prompt_tokens == 1000
    assert completion.usage.completion_tokens == 100
    assert completion.usage.cached_tokens == 400
    assert completion.cost_usd == pytest.approx((600 * 2.0 + 400 * 0.5 + 100 * 8.0) / 1e6)
    assert 0 < completion.latency_s < 5
    assert completion.model == "pare-test-model"
    assert completion.finish_reason == "stop"
    assert not completion.from_cache

    assert server.count == 1
    sent = server.requests[0]
    assert sent["path"] == "/v1/chat/completions"
    assert sent["model"] == "pare-test-model"
    assert sent["messages"] == [
        {"role": "system", "content": "You are terse."},
        {"role": "user", "content": "Say hello."},
    ]
    assert sent["temperature"] == 0.3
    assert sent["seed"] == 7
    assert sent["max_tokens"] == 64
    assert "tools" not in sent
    assert server.headers[0]["authorization"] == f"Bearer {KEY}"

    usage = ledger.role("user")
    assert (usage.calls, usage.prompt_tokens, usage.completion_tokens, usage.cached_tokens) == (
        1,
        1000,
        100,
        400,
    )
    assert usage.cost_usd == pytest.approx(completion.cost_usd)
    assert ledger.cost_usd == pytest.approx(completion.cost_usd)


@pytest.mark.parametrize("backend", BACKENDS)
def test_unknown_price_gives_unknown_cost_never_zero(
    backend: str, server: FakeChatServer, make_config: ConfigFactory
) -> None:
    server.push(answer("a"), answer("b"))
    ledger = UsageLedger()
    unpriced = ModelClient(make_config(backend, model="pare-unpriced-model"), role="judge", ledger=ledger)
    priced = ModelClient(make_config(backend, prices=Prices(input=1, output=1)), role="user", ledger=ledger)

    assert run(unpriced).cost_usd is None
    assert run(priced).cost_usd == pytest.approx(1100 / 1e6)

    assert ledger.role("judge").cost_usd is None
    assert ledger.role("judge").unknown_cost_calls == 1
    assert ledger.role("user").cost_usd == pytest.approx(1100 / 1e6)
    assert ledger.cost_usd is None  # one unknown call makes the total unknown
    summary = json.loads(json.dumps(ledger.summary()))
    assert summary["total"]["cost_usd"] is None
    assert summary["total"]["cost"].startswith("unknown (1 of 2 calls unpriced")
    assert summary["roles"]["user"]["cost"] == "$0.0011"


def test_provider_without_usage_gives_unknown_cost(
    server: FakeChatServer, make_config: ConfigFactory
) -> None:
    server.push(answer("no usage here", usage=False))
    completion = run(ModelClient(make_config(prices=Prices(input=1, output=1)), role="user"))
    assert completion.text == "no usage here"
    assert completion.cost_usd is None


def test_litellm_price_table_prices_a_known_model(server: FakeChatServer, make_config: ConfigFactory) -> None:
    litellm = pytest.importorskip("litellm")
    server.push(
        answer("hi", prompt_tokens=1000, completion_tokens=100, cached_tokens=500, model="gpt-4o-mini")
    )
    completion = run(ModelClient(make_config(model="gpt-4o-mini"), role="user"))
    info = litellm.get_model_info("gpt-4o-mini")
    expected = (
        500 * info["input_cost_per_token"]
        + 500 * info["cache_read_input_token_cost"]
        + 100 * info["output_cost_per_token"]
    )
    assert completion.cost_usd == pytest.approx(expected)


def test_config_prices_win_over_the_price_table(server: FakeChatServer, make_config: ConfigFactory) -> None:
    server.push(answer("hi", prompt_tokens=1_000_000, completion_tokens=0))
    completion = run(
        ModelClient(make_config(model="gpt-4o-mini", prices=Prices(input=3, output=0)), role="user")
    )
    assert completion.cost_usd == pytest.approx(3.0)


def test_extra_parameters_are_sent(server: FakeChatServer, make_config: ConfigFactory) -> None:
    server.push(answer())
    run(ModelClient(make_config(extra={"top_p": 0.5, "top_k": 20, "stop": ["<end_action>"]}), role="user"))
    sent = server.requests[0]
    assert (sent["top_p"], sent["top_k"], sent["stop"]) == (0.5, 20, ["<end_action>"])


def test_keyless_local_server_gets_a_dummy_key(server: FakeChatServer, make_config: ConfigFactory) -> None:
    server.push(answer())
    run(ModelClient(make_config(api_key_env=None), role="user"))
    assert server.headers[0]["authorization"] == "Bearer EMPTY"


# --- transient errors: retried -------------------------------------------------------------------


@pytest.mark.parametrize("backend", BACKENDS)
def test_transient_errors_are_retried_then_succeed(
    backend: str, server: FakeChatServer, make_config: ConfigFactory
) -> None:
    server.push(RATE_LIMITED, SERVER_ERROR, OVERLOADED, answer("finally"))
    ledger = UsageLedger()
    completion = run(ModelClient(make_config(backend, max_retries=3), role="observe", ledger=ledger))
    assert completion.text == "finally"
    assert server.count == 4
    assert ledger.role("observe").calls == 1
    assert ledger.role("observe").failed_calls == 0


@pytest.mark.parametrize("backend", BACKENDS)
def test_retry_after_is_honoured(backend: str, server: FakeChatServer, make_config: ConfigFactory) -> None:
    waiting = error(429, "slow down", code="rate_limit_exceeded", headers={"Retry-After": "0.25"})
    server.push(waiting, answer("ok"))
    config = make_config(backend, retry_initial_s=0.001, retry_max_s=2.0)
    started = time.perf_counter()
    assert run(ModelClient(config, role="user")).text == "ok"
    assert time.perf_counter() - started >= 0.25
    assert server.count == 2


@pytest.mark.parametrize("backend", BACKENDS)
def test_a_slow_answer_times_out_and_is_retried(
    backend: str, server: FakeChatServer, make_config: ConfigFactory
) -> None:
    server.push(answer("too late", delay_s=1.0), answer("in time"))
    completion = run(ModelClient(make_config(backend, timeout_s=0.3), role="user"))
    assert completion.text == "in time"
    assert server.count == 2


@pytest.mark.parametrize("backend", BACKENDS)
def test_retries_exhausted_raise_provider_unavailable(
    backend: str, server: FakeChatServer, make_config: ConfigFactory
) -> None:
    server.default = OVERLOADED
    ledger = UsageLedger()
    config = make_config(backend, max_retries=2)
    with pytest.raises(ProviderUnavailable) as raised:
        run(ModelClient(config, role="execute", ledger=ledger))
    assert server.count == 3
    assert raised.value.attempts == 3
    assert raised.value.status_code == 503
    message = str(raised.value)
    assert "execute" in message and config.model in message and server.base_url in message
    assert "3 attempts" in message and "503" in message
    assert ledger.role("execute").failed_calls == 1
    assert ledger.role("execute").calls == 0


def test_no_retries_means_one_request(server: FakeChatServer, make_config: ConfigFactory) -> None:
    server.default = RATE_LIMITED
    with pytest.raises(ProviderUnavailable):
        run(ModelClient(make_config(max_retries=0), role="user"))
    assert server.count == 1


def test_a_server_that_is_not_running_is_unavailable(make_config: ConfigFactory) -> None:
    with socket.socket() as probe:  # a port nothing listens on
        probe.bind(("127.0.0.1", 0))
        port = probe.getsockname()[1]
    config = make_config(api_base=f"http://127.0.0.1:{port}/v1", max_retries=1)
    with pytest.raises(ProviderUnavailable, match=r"is the server running at http://127\.0\.0\.1"):
        run(ModelClient(config, role="user"))


# --- permanent errors: raised at once ------------------------------------------------------------

PERMANENT = [
    pytest.param(BAD_KEY, "authentication", 401, f"Set {KEY_VARIABLE} to a valid key", id="401"),
    pytest.param(NO_ACCESS, "permission", 403, "no access to this model", id="403"),
    pytest.param(NO_MODEL, "not_found", 404, "does not know this model", id="404"),
    pytest.param(TOO_LONG, "context_length", 400, "longer than the model's context", id="400-context"),
    pytest.param(BAD_PARAM, "bad_request", 400, "rejected the request", id="400"),
    pytest.param(NO_QUOTA, "quota", 429, "no quota left", id="429-quota"),
]


@pytest.mark.parametrize("backend", BACKENDS)
@pytest.mark.parametrize(("reply", "kind", "status", "hint"), PERMANENT)
def test_permanent_errors_raise_at_once_with_advice(
    backend: str,
    reply: Reply,
    kind: str,
    status: int,
    hint: str,
    server: FakeChatServer,
    make_config: ConfigFactory,
) -> None:
    server.default = reply
    config = make_config(backend)
    with pytest.raises(ModelRequestError) as raised:
        run(ModelClient(config, role="judge"))
    assert server.count == 1
    assert raised.value.kind == kind
    assert raised.value.status_code == status
    assert isinstance(raised.value, UserInputError)
    message = str(raised.value)
    assert message.startswith(f"judge model '{config.model}' at {server.base_url}: ")
    assert hint in message
    assert reply.body["error"]["message"][:30] in message  # the provider's own words are kept


@pytest.mark.parametrize("backend", BACKENDS)
def test_missing_api_key_variable_fails_before_any_request(
    backend: str, server: FakeChatServer, make_config: ConfigFactory, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.delenv(KEY_VARIABLE)
    with pytest.raises(ModelRequestError) as raised:
        run(ModelClient(make_config(backend), role="user"))
    assert raised.value.kind == "missing_api_key"
    assert f"environment variable {KEY_VARIABLE}" in str(raised.value)
    assert f"export {KEY_VARIABLE}=" in str(raised.value)
    assert server.count == 0


def test_default_key_variable_is_openai_api_key(server: FakeChatServer) -> None:
    config = ModelConfig(model="gpt-4o-mini", api_base=server.base_url)
    with pytest.raises(ModelRequestError, match="OPENAI_API_KEY"):
        run(ModelClient(config, role="user"))
    assert server.count == 0


def test_litellm_checks_the_providers_own_variable(server: FakeChatServer) -> None:
    pytest.importorskip("litellm")
    config = ModelConfig(model="anthropic/claude-3-5-haiku-latest", backend="litellm")
    with pytest.raises(ModelRequestError, match="ANTHROPIC_API_KEY"):
        run(ModelClient(config, role="user"))


def test_missing_litellm_extra_is_a_clear_error(
    monkeypatch: pytest.MonkeyPatch, make_config: ConfigFactory
) -> None:
    from pare.agents.models import backends

    monkeypatch.setattr(backends, "litellm_available", lambda: False)
    with pytest.raises(UserInputError, match=r"pip install .*\[litellm\]"):
        run(ModelClient(make_config("litellm"), role="user"))


# --- tools ---------------------------------------------------------------------------------------

SEND_EMAIL = {
    "type": "function",
    "function": {
        "name": "email__send_email",
        "description": "Send an email.",
        "parameters": {
            "type": "object",
            "properties": {"to": {"type": "string"}, "subject": {"type": "string"}},
            "required": ["to", "subject"],
        },
    },
}


@pytest.mark.parametrize("backend", BACKENDS)
def test_native_tool_calls_round_trip(
    backend: str, server: FakeChatServer, make_config: ConfigFactory
) -> None:
    call = tool_call("call_1", "email__send_email", {"to": "bob@x.example", "subject": "Lunch"})
    server.push(answer("", tool_calls=[call]), answer("Sent."))
    client = ModelClient(make_config(backend, native_tools=True), role="execute")

    first = run(client, HELLO, [SEND_EMAIL])
    assert server.requests[0]["tools"] == [SEND_EMAIL]
    assert first.finish_reason == "tool_calls"
    assert len(first.tool_calls) == 1
    made = first.tool_calls[0]
    assert (made.id, made.name, json.loads(made.arguments)) == (
        "call_1",
        "email__send_email",
        {"to": "bob@x.example", "subject": "Lunch"},
    )

    conversation = [
        *HELLO,
        first.message(),
        ChatMessage.tool("call_1", "Email sent.", name="email__send_email"),
    ]
    second = run(client, conversation, [SEND_EMAIL])
    assert second.text == "Sent."
    sent = server.requests[1]["messages"]
    assert sent[2]["role"] == "assistant"
    assert sent[2]["tool_calls"][0]["id"] == "call_1"
    assert sent[2]["tool_calls"][0]["function"]["name"] == "email__send_email"
    assert json.loads(sent[2]["tool_calls"][0]["function"]["arguments"]) == {
        "to": "bob@x.example",
        "subject": "Lunch",
    }
    assert sent[3]["role"] == "tool"
    assert sent[3]["tool_call_id"] == "call_1"
    assert sent[3]["content"] == "Email sent."


def test_tools_are_not_sent_without_native_tools(server: FakeChatServer, make_config: ConfigFactory) -> None:
    server.push(answer("Thought: ...\nAction: {}<end_action>"))
    run(ModelClient(make_config(native_tools=False), role="execute"), HELLO, [SEND_EMAIL])
    assert "tools" not in server.requests[0]


# --- concurrency and the sync wrapper ------------------------------------------------------------


@pytest.mark.parametrize("backend", BACKENDS)
def test_concurrency_limit_per_endpoint_holds(
    backend: str, server: FakeChatServer, make_config: ConfigFactory
) -> None:
    server.default = answer("ok", delay_s=0.03)
    first = ModelClient(make_config(backend, max_concurrency=3), role="user")
    second = ModelClient(make_config(backend, max_concurrency=3), role="observe")  # same endpoint

    async def many() -> list[Completion]:
        calls = [
            client.complete([ChatMessage.user(f"question {i}")])
            for i in range(8)
            for client in (first, second)
        ]
        try:
            return await asyncio.gather(*calls)
        finally:
            await first.aclose()
            await second.aclose()

    results = asyncio.run(many())
    assert len(results) == 16
    assert server.count == 16
    assert server.max_in_flight == 3


def test_complete_sync(server: FakeChatServer, make_config: ConfigFactory) -> None:
    server.push(answer("one"), answer("two"))
    client = ModelClient(make_config(), role="user")
    assert client.complete_sync(HELLO).text == "one"
    assert client.complete_sync(HELLO).text == "two"  # a fresh event loop each time works


def test_complete_sync_refuses_a_running_loop(make_config: ConfigFactory) -> None:
    client = ModelClient(make_config(), role="user")

    async def inside() -> None:
        client.complete_sync(HELLO)

    with pytest.raises(RuntimeError, match=r"await client\.complete"):
        asyncio.run(inside())


def test_no_messages_is_an_error(make_config: ConfigFactory) -> None:
    with pytest.raises(ValueError, match="at least one message"):
        run(ModelClient(make_config(), role="user"), [])


def test_the_network_guard_blocks_real_hosts() -> None:
    with pytest.raises(OSError, match=r"only 127\.0\.0\.1"):
        socket.create_connection(("api.openai.com", 443), timeout=1)
