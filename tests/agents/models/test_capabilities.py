"""Which parameters a request carries: known per model family, learned from a provider's refusal by name.

The requests go through the real clients (the OpenAI SDK, and litellm with an ``openai/`` prefix) to a
:class:`~pare.testing.ChatServer` that answers as OpenAI's reasoning and chat models do
(:func:`~pare.testing.openai_reasoning`), or as Anthropic's Messages API does.
"""

from __future__ import annotations

import asyncio
import logging
from typing import Any

import httpx
import openai
import pytest

from pare.agents.models import ChatMessage, Completion, ModelClient, ModelConfig, litellm_available
from pare.agents.models.capabilities import (
    Adjustment,
    apply_adjustments,
    is_reasoning_model,
    known_adjustments,
)
from pare.agents.models.refusals import refused_parameter
from pare.agents.models.request_params import RequestParams
from pare.agents.models.secrets import redact_secrets
from pare.errors import ModelRequestError
from pare.testing import (
    AnthropicChatServer,
    ChatServer,
    Reply,
    anthropic_messages,
    completion,
    failure,
    openai_reasoning,
)

from .conftest import BACKENDS, KEY_VARIABLE

HELLO = [ChatMessage.system("You are terse."), ChatMessage.user("Say hello.")]


def hello(body: dict[str, Any]) -> Reply:
    return completion("Hello.", model=str(body.get("model")))


def config(model: str, backend: str = "openai", api_base: str | None = None, **settings: Any) -> ModelConfig:
    return ModelConfig(
        model=f"openai/{model}" if backend == "litellm" and api_base else model,
        backend=backend,  # type: ignore[arg-type]
        api_base=api_base,
        api_key_env=KEY_VARIABLE,
        max_retries=0,
        timeout_s=5.0,
        **settings,
    )


def call(client: ModelClient, times: int = 1) -> list[Completion]:
    async def calls() -> list[Completion]:
        async with client:
            return [await client.complete(HELLO) for _ in range(times)]

    return asyncio.run(calls())


def sent(server: ChatServer) -> list[dict[str, Any]]:
    """The request parameters of each request the server received (model and messages left out)."""
    return [{k: v for k, v in body.items() if k not in ("model", "messages")} for body in server.requests]


def warnings_about(caplog: pytest.LogCaptureFixture, param: str) -> list[str]:
    return [
        r.getMessage() for r in caplog.records if r.name == "pare.models" and f"{param}" in r.getMessage()
    ]


# --- what is known beforehand -------------------------------------------------------------------------------


@pytest.mark.parametrize(
    "model",
    ["o1", "o1-mini", "o3", "o3-mini", "o4-mini", "gpt-5", "gpt-5-mini", "gpt-5-nano-2025-08-07", "gpt-5.1"],
)
def test_openai_reasoning_models_are_recognised(model: str) -> None:
    assert is_reasoning_model(model) and is_reasoning_model(f"openai/{model}")


@pytest.mark.parametrize(
    "model", ["gpt-5-chat-latest", "gpt-4o", "gpt-4.1-mini", "Qwen/Qwen3-4B-Instruct-2507", "llama3", "omni"]
)
def test_chat_and_unknown_models_are_not_reasoning_models(model: str) -> None:
    assert not is_reasoning_model(model)


def test_a_reasoning_model_is_sent_no_temperature_and_max_tokens_under_its_name() -> None:
    settings = ModelConfig(
        model="gpt-5-mini", temperature=0.0, max_tokens=2048, extra={"top_p": 0.9, "reasoning_effort": "low"}
    )
    adjustments = known_adjustments(settings)
    assert {(a.param, a.action, a.to) for a in adjustments} == {
        ("temperature", "dropped", None),
        ("top_p", "dropped", None),
        ("max_tokens", "renamed", "max_completion_tokens"),
    }
    assert apply_adjustments(settings.request_params(), adjustments) == {
        "max_completion_tokens": 2048,
        "reasoning_effort": "low",
    }
    # the default temperature is what reasoning models accept: sent as configured
    assert known_adjustments(ModelConfig(model="o3", temperature=1.0)) == []


def test_chat_models_keep_their_sampling_and_refuse_reasoning_effort() -> None:
    settings = ModelConfig(
        model="gpt-5-chat-latest", temperature=0.2, max_tokens=64, extra={"reasoning_effort": "low"}
    )
    assert [(a.param, a.action) for a in known_adjustments(settings)] == [("reasoning_effort", "dropped")]
    unknown = ModelConfig(model="Qwen/Qwen3-4B", temperature=0.2, max_tokens=64, extra={"top_k": 20})
    assert known_adjustments(unknown) == []  # a model not known is sent what is configured


@pytest.mark.parametrize("backend", BACKENDS)
def test_the_readme_setup_reaches_a_reasoning_model_without_a_refusal(
    backend: str, caplog: pytest.LogCaptureFixture
) -> None:
    with ChatServer(openai_reasoning(hello)) as server:
        settings = config("gpt-5-mini", backend, server.base_url, temperature=0.0, max_tokens=2048)
        client = ModelClient(settings, "user")
        assert [c.text for c in call(client, times=2)] == ["Hello.", "Hello."]
        assert sent(server) == [{"max_completion_tokens": 2048}] * 2  # no failed round trip at all
    assert client.sent_params() == {"max_completion_tokens": 2048}
    assert [a.learned for a in client.adjustments] == [False, False]
    (warning,) = warnings_about(caplog, "temperature")
    assert "temperature=0.0" in warning and "not honoured" in warning


@pytest.mark.skipif(not litellm_available(), reason="the litellm extra is not installed")
def test_litellm_knows_what_anthropic_takes_and_its_required_max_tokens_is_left_alone(
    caplog: pytest.LogCaptureFixture,
) -> None:
    with AnthropicChatServer(anthropic_messages(hello)) as server:
        settings = ModelConfig(
            model="anthropic/claude-3-5-haiku-latest",
            backend="litellm",
            api_base=server.anthropic_base_url,
            api_key_env=KEY_VARIABLE,
            max_retries=0,
            seed=7,
            temperature=0.2,
        )
        client = ModelClient(settings, "user")
        assert call(client)[0].text == "Hello."
        (body,) = server.requests
    assert "seed" not in body and body["temperature"] == 0.2
    assert isinstance(body["max_tokens"], int) and body["max_tokens"] > 0  # litellm's default, untouched
    assert [(a.param, a.action) for a in client.adjustments] == [("seed", "dropped")]
    assert len(warnings_about(caplog, "seed=7")) == 1


# --- what is learned from a refusal -------------------------------------------------------------------------


def deployment(model: str) -> bool:
    """An Azure-style deployment named by its owner: a reasoning model PARE cannot recognise by name."""
    return model.endswith("paper-user")


@pytest.mark.parametrize("backend", BACKENDS)
def test_a_refused_parameter_is_learned_once_and_the_call_goes_through(
    backend: str, caplog: pytest.LogCaptureFixture
) -> None:
    with ChatServer(openai_reasoning(hello, reasoning=deployment)) as server:
        settings = config("paper-user", backend, server.base_url, temperature=0.0, max_tokens=64)
        learned: list[dict[str, Any]] = []
        params = RequestParams(settings, "user")
        params.subscribe(lambda p: learned.append(p.sent()))
        client = ModelClient(settings, "user", params=params)
        assert [c.text for c in call(client, times=3)] == ["Hello."] * 3
        requests = sent(server)
    # the first call paid two refusals (temperature, then max_tokens); every later call none
    assert requests == [
        {"temperature": 0.0, "max_tokens": 64},
        {"max_tokens": 64},
        {"max_completion_tokens": 64},
        {"max_completion_tokens": 64},
        {"max_completion_tokens": 64},
    ]
    assert [(a.param, a.action, a.to, a.learned) for a in client.adjustments] == [
        ("temperature", "dropped", None, True),
        ("max_tokens", "renamed", "max_completion_tokens", True),
    ]
    assert learned == [{"max_tokens": 64}, {"max_completion_tokens": 64}]
    assert "unsupported_value" in client.adjustments[0].why
    (warning,) = warnings_about(caplog, "temperature=0.0")
    assert "not honoured" in warning and "rest of the run" in warning
    assert len(warnings_about(caplog, "max_tokens=64 is sent as max_completion_tokens")) == 1


@pytest.mark.parametrize("backend", BACKENDS)
def test_a_refusal_of_something_not_sent_is_still_an_error(backend: str) -> None:
    refusal = failure(400, "Invalid value for 'messages[1].role'.", code="invalid_value")
    with ChatServer(
        lambda body: Reply(refusal.status, {"error": {**refusal.body["error"], "param": "messages"}})
    ) as server:
        client = ModelClient(config("m", backend, server.base_url, temperature=0.5), "user")
        with pytest.raises(ModelRequestError) as raised:
            call(client)
        assert raised.value.kind == "bad_request"
        assert server.request_count == 1  # not sent again: no parameter of ours was named
    assert client.adjustments == []


def test_concurrent_calls_meeting_the_same_refusal_learn_it_once(caplog: pytest.LogCaptureFixture) -> None:
    with ChatServer(openai_reasoning(hello, reasoning=deployment), delay_s=0.05) as server:
        client = ModelClient(config("paper-user", "openai", server.base_url, temperature=0.3), "user")

        async def calls() -> list[Completion]:
            async with client:
                return list(await asyncio.gather(*(client.complete(HELLO) for _ in range(4))))

        assert len(asyncio.run(calls())) == 4
        bodies = sent(server)
    # each call refused sends again once, without it; a call sent after the first refusal never carries it
    refused = sum("temperature" in body for body in bodies)
    assert refused >= 1 and len(bodies) == 4 + refused
    assert [(a.param, a.action) for a in client.adjustments] == [("temperature", "dropped")]
    assert len(warnings_about(caplog, "temperature=0.3")) == 1


def openai_error(body: dict[str, Any], status: int = 400) -> openai.APIStatusError:
    response = httpx.Response(status, request=httpx.Request("POST", "http://127.0.0.1/v1/chat/completions"))
    error_class = openai.BadRequestError if status == 400 else openai.UnprocessableEntityError
    return error_class(str(body), response=response, body=body.get("error", body))


@pytest.mark.parametrize(
    ("body", "expected"),
    [
        pytest.param(
            {
                "error": {
                    "message": "Unsupported value: 'temperature' does not support 0.0 with this model.",
                    "param": "temperature",
                    "code": "unsupported_value",
                }
            },
            ("temperature", "dropped", None),
            id="openai-param",
        ),
        pytest.param(
            {
                "error": {
                    "message": "Unsupported parameter: 'max_tokens' is not supported with this model. "
                    "Use 'max_completion_tokens' instead.",
                    "param": None,
                    "code": None,
                }
            },
            ("max_tokens", "renamed", "max_completion_tokens"),
            id="openai-message-only",
        ),
        pytest.param(
            {
                "type": "error",
                "error": {
                    "type": "invalid_request_error",
                    "message": "top_k: Extra inputs are not permitted",
                },
            },
            ("top_k", "dropped", None),
            id="anthropic",
        ),
        pytest.param(
            {
                "type": "error",
                "error": {
                    "type": "invalid_request_error",
                    "message": "`temperature` and `top_p` cannot both be specified for this model. "
                    "Please use only one.",
                },
            },
            ("top_p", "dropped", None),
            id="anthropic-either",
        ),
        pytest.param(
            {
                "object": "error",
                "message": "[{'type': 'extra_forbidden', 'loc': ('body', 'top_k'), "
                "'msg': 'Extra inputs are not permitted', 'input': 20}]",
                "code": 400,
            },
            ("top_k", "dropped", None),
            id="vllm",
        ),
    ],
)
def test_refusals_are_read_from_each_providers_answer(
    body: dict[str, Any], expected: tuple[str, str, str | None]
) -> None:
    sent_params = {"temperature": 0.0, "max_tokens": 64, "top_k": 20, "top_p": 0.9}
    adjustment = refused_parameter(openai_error(body), sent_params)
    assert adjustment is not None and adjustment.learned
    assert (adjustment.param, adjustment.action, adjustment.to) == expected
    # only a parameter the request carried counts
    assert refused_parameter(openai_error(body), {"seed": 1}) is None


def test_litellms_own_refusals_are_read_too() -> None:
    litellm = pytest.importorskip("litellm")
    error = litellm.UnsupportedParamsError(
        message="litellm.UnsupportedParamsError: anthropic does not support parameters: ['seed'], for "
        "model=claude-3-5-haiku-latest. To drop these, set `litellm.drop_params=True`",
        llm_provider="anthropic",
        model="claude-3-5-haiku-latest",
    )
    adjustment = refused_parameter(error, {"seed": 1, "temperature": 0.1})
    assert adjustment is not None and (adjustment.param, adjustment.action) == ("seed", "dropped")


def test_adjustments_survive_the_manifest() -> None:
    adjustment = Adjustment("max_tokens", "renamed", "the provider refused it", "max_completion_tokens", True)
    assert Adjustment.from_json(adjustment.to_json()) == adjustment
    with pytest.raises(ValueError, match="not a recorded parameter adjustment"):
        Adjustment.from_json({"param": "x", "action": "bent"})


def test_learned_refusals_given_up_front_are_applied_from_the_first_call(
    caplog: pytest.LogCaptureFixture,
) -> None:
    caplog.set_level(logging.WARNING, "pare.models")
    settings = config("paper-user", temperature=0.0)
    params = RequestParams(settings, "user", [Adjustment("temperature", "dropped", "refused", learned=True)])
    assert params.sent() == {} and params.sent() == {}
    assert len(warnings_about(caplog, "temperature=0.0")) == 1


def test_token_counts_are_settings_and_tokens_are_secrets() -> None:
    masked = redact_secrets(
        {"max_tokens": 64, "max_completion_tokens": 64, "access_token": "abc", "token": "d"}
    )
    assert masked == {"max_tokens": 64, "max_completion_tokens": 64, "access_token": "***", "token": "***"}
