"""Provider profiles for :class:`~pare.testing.ChatServer`: answer as the major providers document.

A profile wraps any responder (``profile(responder) -> responder``), so profiles compose with each
other and with :func:`~pare.testing.proactive_play`::

    responder = openai_reasoning(rate_limited(proactive_play(), every=3))

* :func:`openai_reasoning` — OpenAI's parameter rules: reasoning models (``o1``, ``o3``, ``o4-mini``,
  ``gpt-5*`` but the ``-chat`` models) refuse a temperature other than 1, ``top_p``, the penalties,
  log-probabilities and ``max_tokens`` (take ``max_completion_tokens``), and take ``reasoning_effort``;
  chat models refuse ``reasoning_effort``. Refusals are HTTP 400 in OpenAI's error format, naming the
  parameter in ``param``.
* :func:`rate_limited` — every n-th request is refused with 429, ``Retry-After`` and OpenAI's
  ``rate_limit_exceeded`` error.
* :func:`tool_calls_only` — an answer in PARE's action format to a request that offered tools becomes
  a tool call with ``content: null``, as function-calling models answer.
* :func:`cached_prompts` — usage reports part of the prompt as served from the provider's cache
  (``prompt_tokens_details.cached_tokens``).
* :func:`context_limit` — a prompt over the limit is refused with 400 ``context_length_exceeded``.
* :func:`anthropic_messages` — with :class:`AnthropicChatServer`, Anthropic's Messages API
  (``POST /v1/messages``) as litellm's ``anthropic/`` models call it: ``max_tokens`` required, unknown
  fields such as ``seed`` refused, answers and errors in Anthropic's format.

:data:`PROFILES` names them for parametrised tests.
"""

from __future__ import annotations

import itertools
import json
import re
import threading
from collections.abc import Callable, Mapping
from typing import Any

from pare.testing.chat_server import ChatServer, Reply, Responder, failure

__all__ = [
    "PROFILES",
    "AnthropicChatServer",
    "anthropic_messages",
    "cached_prompts",
    "context_limit",
    "openai_reasoning",
    "rate_limited",
    "tool_calls_only",
]

_REASONING_MODEL = re.compile(r"^(?:o[1-9]\d*(?:-.*)?|gpt-5(?:\.\d+)?(?:-.*)?)$")
_REFUSED_BY_REASONING = ("top_p", "presence_penalty", "frequency_penalty", "logprobs", "top_logprobs")
REASONING_EFFORTS = ("minimal", "low", "medium", "high")


def _reasoning(model: object) -> bool:
    name = str(model or "").rsplit("/", 1)[-1].lower()
    return _REASONING_MODEL.match(name) is not None and "-chat" not in name


def _refusal(message: str, param: str, code: str) -> Reply:
    body = {"error": {"message": message, "type": "invalid_request_error", "param": param, "code": code}}
    return Reply(400, body)


def openai_reasoning(responder: Responder, *, reasoning: Callable[[str], bool] | None = None) -> Responder:
    """``responder`` behind OpenAI's parameter rules for reasoning and chat models (see the module).

    ``reasoning`` tells from the request's model name whether it is a reasoning model (default: OpenAI's
    names); a deployment with a name of its own (Azure, a proxy) needs it said.
    """
    is_reasoning = reasoning or _reasoning

    def respond(body: dict[str, Any]) -> Reply:
        if not is_reasoning(str(body.get("model") or "")):
            if "reasoning_effort" in body:
                return _refusal(
                    "Unsupported parameter: 'reasoning_effort' is not supported with this model.",
                    "reasoning_effort",
                    "unsupported_parameter",
                )
            return responder(body)
        temperature = body.get("temperature")
        if temperature is not None and temperature != 1:
            return _refusal(
                f"Unsupported value: 'temperature' does not support {float(temperature)} with this model. "
                "Only the default (1) value is supported.",
                "temperature",
                "unsupported_value",
            )
        if "max_tokens" in body:
            return _refusal(
                "Unsupported parameter: 'max_tokens' is not supported with this model. "
                "Use 'max_completion_tokens' instead.",
                "max_tokens",
                "unsupported_parameter",
            )
        for name in _REFUSED_BY_REASONING:
            if name in body:
                return _refusal(
                    f"Unsupported parameter: '{name}' is not supported with this model.",
                    name,
                    "unsupported_parameter",
                )
        effort = body.get("reasoning_effort")
        if effort is not None and effort not in REASONING_EFFORTS:
            return _refusal(
                f"Unsupported value: 'reasoning_effort' does not support {effort!r} with this model. "
                f"Supported values are: {', '.join(repr(e) for e in REASONING_EFFORTS)}.",
                "reasoning_effort",
                "unsupported_value",
            )
        reply = responder(body)
        usage = reply.body.get("usage") if reply.status == 200 else None
        if isinstance(usage, dict):  # reasoning models count their hidden reasoning as completion tokens
            details = {"reasoning_tokens": 0, **(usage.get("completion_tokens_details") or {})}
            usage = {**usage, "completion_tokens_details": details}
            return Reply(reply.status, {**reply.body, "usage": usage}, reply.headers, reply.raw)
        return reply

    return respond


def rate_limited(responder: Responder, *, every: int = 2, retry_after_ms: int = 20) -> Responder:
    """``responder`` behind a rate limit: every ``every``-th request (the 2nd, 4th, ... by default) is
    refused with 429, a ``Retry-After`` (and ``retry-after-ms``) header and OpenAI's
    ``rate_limit_exceeded`` error; the others are answered by ``responder``. Thread-safe.
    """
    if every < 1:
        raise ValueError("every must be at least 1")
    counter = itertools.count(1)
    lock = threading.Lock()

    def respond(body: dict[str, Any]) -> Reply:
        with lock:
            number = next(counter)
        if number % every:
            return responder(body)
        model = body.get("model") or "the model"
        return failure(
            429,
            f"Rate limit reached for {model} in organization org-pare-test on requests per min (RPM): "
            f"Limit {every - 1}, Used {every - 1}, Requested 1. Please try again in {retry_after_ms}ms.",
            type_="requests",
            code="rate_limit_exceeded",
            headers={
                "Retry-After": str(max(1, -(-retry_after_ms // 1000))),
                "retry-after-ms": str(retry_after_ms),
                "x-ratelimit-limit-requests": str(every - 1),
                "x-ratelimit-remaining-requests": "0",
                "x-ratelimit-reset-requests": f"{retry_after_ms}ms",
            },
        )

    return respond


def tool_calls_only(responder: Responder) -> Responder:
    """``responder`` as a function-calling model answers: when the request offers tools and the answer is
    one action in PARE's text format, it comes back as a tool call with ``content: null`` and finish
    reason ``tool_calls``.
    """
    from pare.agents.actions import parse_action
    from pare.errors import ActionFormatError

    def respond(body: dict[str, Any]) -> Reply:
        reply = responder(body)
        if reply.status != 200 or not body.get("tools"):
            return reply
        choices = reply.body.get("choices") or []
        message = choices[0].get("message") if choices else None
        text = message.get("content") if isinstance(message, dict) else None
        if not isinstance(text, str):
            return reply
        try:
            action = parse_action(text)
        except ActionFormatError:
            return reply
        call = {
            "id": f"call_{len(body.get('messages') or ())}",
            "type": "function",
            "function": {"name": action.tool, "arguments": json.dumps(action.args)},
        }
        choice = {
            **choices[0],
            "message": {"role": "assistant", "content": None, "tool_calls": [call]},
            "finish_reason": "tool_calls",
        }
        return Reply(200, {**reply.body, "choices": [choice, *choices[1:]]}, reply.headers)

    return respond


def cached_prompts(responder: Responder, *, share: float = 0.5) -> Responder:
    """``responder`` with ``share`` of each answer's prompt tokens reported as served from the provider's
    prompt cache (``usage.prompt_tokens_details.cached_tokens``, as OpenAI reports it).
    """
    if not 0.0 <= share <= 1.0:
        raise ValueError("share must be between 0 and 1")

    def respond(body: dict[str, Any]) -> Reply:
        reply = responder(body)
        usage = reply.body.get("usage") if reply.status == 200 else None
        if not isinstance(usage, dict):
            return reply
        cached = int(int(usage.get("prompt_tokens") or 0) * share)
        details = {**(usage.get("prompt_tokens_details") or {}), "cached_tokens": cached}
        return Reply(200, {**reply.body, "usage": {**usage, "prompt_tokens_details": details}}, reply.headers)

    return respond


def prompt_tokens(body: Mapping[str, Any]) -> int:
    """The prompt's size in tokens as these profiles count it: a quarter of its characters."""
    total = 0
    for message in body.get("messages") or ():
        content = message.get("content") if isinstance(message, dict) else None
        if isinstance(content, str):
            total += len(content)
        elif isinstance(content, list):
            total += sum(len(str(part.get("text", ""))) for part in content if isinstance(part, dict))
    return total // 4


def context_limit(responder: Responder, *, max_prompt_tokens: int) -> Responder:
    """``responder`` behind a context window: a prompt over ``max_prompt_tokens`` (by
    :func:`prompt_tokens`) is refused with 400 ``context_length_exceeded``, as OpenAI refuses it.
    """

    def respond(body: dict[str, Any]) -> Reply:
        size = prompt_tokens(body)
        if size > max_prompt_tokens:
            return failure(
                400,
                f"This model's maximum context length is {max_prompt_tokens} tokens. However, your "
                f"messages resulted in {size} tokens. Please reduce the length of the messages.",
                code="context_length_exceeded",
            )
        return responder(body)

    return respond


# -- Anthropic's Messages API -------------------------------------------------------------------------------
ANTHROPIC_FIELDS = frozenset(
    {
        "model",
        "messages",
        "system",
        "max_tokens",
        "temperature",
        "top_p",
        "top_k",
        "stop_sequences",
        "stream",
        "tools",
        "tool_choice",
        "metadata",
        "thinking",
        "service_tier",
    }
)
"""The request fields Anthropic's Messages API knows; any other is refused ("Extra inputs are not
permitted")."""


def _anthropic_error(status: int, message: str, type_: str = "invalid_request_error") -> Reply:
    return Reply(status, {"type": "error", "error": {"type": type_, "message": message}})


def _openai_messages(body: Mapping[str, Any]) -> list[dict[str, Any]]:
    """Anthropic's system text and messages as an OpenAI-format conversation (text parts only)."""
    messages: list[dict[str, Any]] = []
    system = body.get("system")
    if isinstance(system, list):
        system = "\n".join(str(part.get("text", "")) for part in system if isinstance(part, dict))
    if isinstance(system, str) and system:
        messages.append({"role": "system", "content": system})
    for message in body.get("messages") or ():
        if not isinstance(message, dict):
            continue
        content = message.get("content")
        if isinstance(content, list):
            texts = []
            for part in content:
                if not isinstance(part, dict):
                    continue
                if part.get("type") == "text":
                    texts.append(str(part.get("text", "")))
                elif part.get("type") == "tool_result":
                    inner = part.get("content")
                    texts.append(inner if isinstance(inner, str) else json.dumps(inner))
            content = "\n".join(texts)
        messages.append({"role": message.get("role", "user"), "content": content})
    return messages


def anthropic_messages(responder: Responder) -> Responder:
    """Anthropic's Messages API in front of ``responder`` (an OpenAI-format responder): the request is
    checked as Anthropic checks it (``max_tokens`` required, unknown fields such as ``seed`` refused,
    ``temperature`` within 0 to 1), translated for ``responder``, and its answer translated back (text
    content blocks, ``stop_reason``, ``usage.input_tokens`` / ``output_tokens``). Serve it with
    :class:`AnthropicChatServer`, which routes ``POST /v1/messages`` here.
    """

    def respond(body: dict[str, Any]) -> Reply:
        if "max_tokens" not in body:
            return _anthropic_error(400, "max_tokens: Field required")
        extra = sorted(set(body) - ANTHROPIC_FIELDS)
        if extra:
            return _anthropic_error(400, f"{extra[0]}: Extra inputs are not permitted")
        temperature = body.get("temperature")
        if isinstance(temperature, int | float) and not 0 <= temperature <= 1:
            return _anthropic_error(400, "temperature: Input should be less than or equal to 1")
        reply = responder({"model": body.get("model"), "messages": _openai_messages(body)})
        if reply.status != 200:
            error = reply.body.get("error")
            error = error if isinstance(error, dict) else {}
            return _anthropic_error(reply.status, str(error.get("message", "error")), "api_error")
        choice = (reply.body.get("choices") or [{}])[0]
        text = (choice.get("message") or {}).get("content") or ""
        usage = reply.body.get("usage") or {}
        cached = (usage.get("prompt_tokens_details") or {}).get("cached_tokens") or 0
        return Reply(
            200,
            {
                "id": "msg_pare_testing",
                "type": "message",
                "role": "assistant",
                "model": body.get("model"),
                "content": [{"type": "text", "text": text}],
                "stop_reason": "end_turn",
                "stop_sequence": None,
                "usage": {
                    "input_tokens": int(usage.get("prompt_tokens") or 0) - int(cached),
                    "output_tokens": int(usage.get("completion_tokens") or 0),
                    "cache_read_input_tokens": int(cached),
                    "cache_creation_input_tokens": 0,
                },
            },
        )

    return respond


class AnthropicChatServer(ChatServer):
    """A :class:`ChatServer` that answers Anthropic's ``POST /v1/messages`` through ``responder`` (wrap an
    OpenAI-format responder with :func:`anthropic_messages`); :attr:`anthropic_base_url` is what
    litellm's ``api_base`` takes for an ``anthropic/`` model.
    """

    @property
    def anthropic_base_url(self) -> str:
        """The base URL litellm's Anthropic client appends ``/v1/messages`` to."""
        return f"http://127.0.0.1:{self.port}"

    def _answer(self, path: str, headers: dict[str, str], raw: bytes) -> Reply:
        route = path.split("?", 1)[0].rstrip("/")
        if route.endswith("/v1/messages"):
            # the parent answers only chat completions: hand it this request under that route
            return super()._answer("/v1/chat/completions", headers, raw)
        return _anthropic_error(
            404, f"no route {path}: this server only answers POST /v1/messages", "not_found_error"
        )


PROFILES: dict[str, Callable[[Responder], Responder]] = {
    "openai-reasoning": openai_reasoning,
    "rate-limited": rate_limited,
    "tool-calls-only": tool_calls_only,
    "cached-prompts": cached_prompts,
}
"""The OpenAI-format profiles that take no setting, by name (context limits need their size:
:func:`context_limit`; Anthropic needs its own server: :class:`AnthropicChatServer`)."""
