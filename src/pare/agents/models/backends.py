"""The two ways to reach a model (OpenAI SDK, litellm) behind one small async protocol.

Both SDKs are imported inside functions, so ``import pare`` and the command line stay fast. Both raise
exceptions from the OpenAI SDK's tree (litellm's exceptions subclass the OpenAI SDK's), which
:func:`classify_error` sorts into transient failures (retried) and permanent ones (reported at once).
"""

from __future__ import annotations

import email.utils
import json
import math
import os
import re
import time
import warnings
from collections.abc import Mapping
from dataclasses import dataclass
from types import ModuleType
from typing import Any, Literal, Protocol

from pare.agents.models.config import ModelConfig
from pare.agents.models.reasoning import join_reasoning, split_reasoning
from pare.agents.models.text import valid_text
from pare.agents.models.types import ToolCall, Usage
from pare.errors import UserInputError
from pare.install import install_command

NO_KEY = "EMPTY"
"""Sent as the API key to servers that need none (vLLM, Ollama): the OpenAI SDK insists on one."""

TRANSIENT_STATUS = frozenset({408, 409, 425, 429, 500, 502, 503, 504, 520, 521, 522, 523, 524, 529})
"""HTTP statuses worth retrying: timeouts, conflicts, rate limits, server errors and overload."""


@dataclass(frozen=True)
class BackendResponse:
    """What a backend extracted from one successful response."""

    text: str
    tool_calls: tuple[ToolCall, ...]
    usage: Usage
    usage_reported: bool
    model: str
    finish_reason: str | None
    reasoning: str | None = None
    """A thinking model's reasoning, from the message's reasoning field and its text's think blocks."""


class MalformedResponse(Exception):
    """The provider answered 200 but with nothing usable (no choice, a body that is not JSON or not UTF-8,
    impossible usage); a provider fault, treated as a transient failure.
    """


UNDECODABLE_BODY = (json.JSONDecodeError, UnicodeDecodeError)
"""What the SDKs raise reading a 200 response whose body is truncated, empty or not UTF-8."""


class ModelBackend(Protocol):
    """Sends one chat request; raises the SDK's exceptions unchanged (see :func:`classify_error`)."""

    name: str

    async def complete(
        self,
        messages: list[dict[str, Any]],
        tools: list[dict[str, Any]] | None,
        params: Mapping[str, Any] | None = None,
    ) -> BackendResponse:
        """Send the conversation (OpenAI chat format) with the request parameters ``params`` (default:
        the configuration's own) and return the parsed first choice.
        """
        ...

    async def prepare(self) -> None:
        """Do the one-off work (imports, clients) that should not count in the first call's latency."""
        ...

    async def aclose(self) -> None:
        """Release connections held by the backend."""
        ...


class OpenAIBackend:
    """The OpenAI SDK: OpenAI itself and every OpenAI-compatible server (vLLM, Ollama, OpenRouter)."""

    name = "openai"

    def __init__(self, config: ModelConfig, api_key: str | None) -> None:
        self.config = config
        self._api_key = api_key if api_key is not None else NO_KEY
        self._client: Any = None

    def _get_client(self) -> Any:
        if self._client is None:
            import openai

            # Retries are ours (tenacity, with Retry-After and a clear final error), never the SDK's.
            self._client = openai.AsyncOpenAI(
                base_url=self.config.api_base,
                api_key=self._api_key,
                max_retries=0,
                timeout=self.config.timeout_s,
            )
        return self._client

    async def prepare(self) -> None:
        """Create the SDK client (importing the SDK) so that the first request's latency excludes it."""
        self._get_client()

    async def complete(
        self,
        messages: list[dict[str, Any]],
        tools: list[dict[str, Any]] | None,
        params: Mapping[str, Any] | None = None,
    ) -> BackendResponse:
        """Send one chat completion request through the SDK's client.

        The body is posted as it is (``AsyncOpenAI.post``, the SDK's documented way to send a request it
        does not type): ``chat.completions.create`` would first walk every message against the SDK's
        typed-dict schemas, CPU work that grows with PARE's long conversations and caps throughput
        against a fast local server. Our messages are plain JSON already.
        """
        from openai.types.chat import ChatCompletion

        client = self._get_client()
        sent = self.config.request_params() if params is None else params
        body: dict[str, Any] = {"model": self.config.model, "messages": messages, **body_params(sent)}
        if tools:
            body["tools"] = tools
        # ``extra_headers`` (the SDK's name, as in litellm) are HTTP headers, never a body field.
        headers = body.pop("extra_headers", None)
        options: Any = (
            {"headers": {str(k): str(v) for k, v in headers.items()}} if isinstance(headers, dict) else {}
        )
        try:
            response = await client.post(
                "/chat/completions", body=body, cast_to=ChatCompletion, options=options
            )
        except UNDECODABLE_BODY as error:
            raise MalformedResponse(f"the provider's response body is not valid JSON ({error})") from error
        return parse_response(response, self.config.model)

    async def aclose(self) -> None:
        """Close the SDK's HTTP client."""
        if self._client is not None:
            client, self._client = self._client, None
            await client.close()


def body_params(params: Mapping[str, Any]) -> dict[str, Any]:
    """The request parameters as top-level body fields; an ``extra_body`` mapping in them (the OpenAI
    SDK's name for server-specific fields such as vLLM's ``top_k``) is merged in as well.
    """
    fields: dict[str, Any] = dict(params)
    extra_body = fields.pop("extra_body", None)
    if isinstance(extra_body, dict):
        fields.update(extra_body)
    elif extra_body is not None:
        fields["extra_body"] = extra_body
    return fields


class LiteLLMBackend:
    """litellm: providers reached natively (Anthropic, Gemini, Bedrock, ...); the ``litellm`` extra."""

    name = "litellm"

    def __init__(self, config: ModelConfig, api_key: str | None) -> None:
        self.config = config
        self._api_key = api_key
        self._litellm = import_litellm()

    async def complete(
        self,
        messages: list[dict[str, Any]],
        tools: list[dict[str, Any]] | None,
        params: Mapping[str, Any] | None = None,
    ) -> BackendResponse:
        """Send one request through ``litellm.acompletion`` with litellm's own retries switched off."""
        kwargs: dict[str, Any] = {
            "model": self.config.model,
            "messages": messages,
            "timeout": self.config.timeout_s,
            "max_retries": 0,
            "num_retries": 0,
        }
        kwargs.update(self.config.request_params() if params is None else params)
        if self.config.api_base is not None:
            kwargs["api_base"] = self.config.api_base
        if self._api_key is not None:
            kwargs["api_key"] = self._api_key
        if tools:
            kwargs["tools"] = tools
            # PARE sends plain function tools, never MCP servers. litellm (1.106) otherwise routes every
            # request with tools through its MCP gateway, which imports the optional `mcp` package and
            # fails without it; litellm strips this internal flag before calling the provider.
            kwargs["_skip_mcp_handler"] = True
        try:
            response = await self._litellm.acompletion(**kwargs)
        except UNDECODABLE_BODY as error:
            raise MalformedResponse(f"the provider's response body is not valid JSON ({error})") from error
        return parse_response(response, self.config.model)

    async def prepare(self) -> None:
        """Nothing to prepare: litellm was imported when the backend was made."""

    async def aclose(self) -> None:
        """Nothing to release: litellm keeps its own client cache."""


def make_backend(config: ModelConfig, api_key: str | None) -> ModelBackend:
    """Return the backend named by ``config.backend``."""
    if config.backend == "litellm":
        return LiteLLMBackend(config, api_key)
    return OpenAIBackend(config, api_key)


def litellm_available() -> bool:
    """Whether the optional litellm extra is installed (without importing it)."""
    import importlib.util

    return importlib.util.find_spec("litellm") is not None


def import_litellm() -> ModuleType:
    """Import litellm on first use, quietly and with its bundled price table.

    litellm otherwise downloads its price table from GitHub at import time; the bundled copy keeps a
    run's prices tied to the installed litellm version (recorded in provenance) and works offline. Set
    ``LITELLM_LOCAL_MODEL_COST_MAP=False`` to let it download the latest table.
    """
    if not litellm_available():
        raise UserInputError(
            f"the litellm backend needs the optional litellm package: {install_command('litellm')} "
            "(or use backend 'openai' for OpenAI and OpenAI-compatible endpoints)"
        )
    os.environ.setdefault("LITELLM_LOCAL_MODEL_COST_MAP", "True")
    # litellm (1.110) declares TypedDicts with ReadOnly items in a module it imports on the first
    # request; pydantic warns about them each run. The warning is about litellm's own types and says
    # nothing a PARE user can act on.
    warnings.filterwarnings("ignore", message=r".*using the `ReadOnly` qualifier", category=UserWarning)
    import litellm

    litellm.suppress_debug_info = True
    return litellm


def parse_response(response: Any, requested_model: str) -> BackendResponse:
    """Extract the first choice, the usage and the model's name from an OpenAI-format response.

    Works on the OpenAI SDK's ``ChatCompletion`` and on litellm's ``ModelResponse`` alike. A thinking
    model's reasoning, whether in a field of the message or in think blocks of its text, is taken apart
    from the answer (:mod:`pare.agents.models.reasoning`): ``text`` holds the answer only.
    """
    choices = getattr(response, "choices", None)
    if not choices:
        raise MalformedResponse("the provider's response has no choices")
    choice = choices[0]
    message = getattr(choice, "message", None)
    if message is None:
        raise MalformedResponse("the provider's response has no message")
    calls: list[ToolCall] = []
    for call in getattr(message, "tool_calls", None) or ():
        function = getattr(call, "function", None)
        if function is None:  # not a function call (e.g. a custom tool): not something we sent
            continue
        arguments = getattr(function, "arguments", None)
        calls.append(
            ToolCall(
                id=valid_text(str(getattr(call, "id", None) or f"call_{len(calls)}")),
                name=valid_text(str(getattr(function, "name", ""))),
                arguments=valid_text(arguments) if isinstance(arguments, str) else "{}",
            )
        )
    usage_object = getattr(response, "usage", None)
    usage = Usage()
    if usage_object is not None:
        details = getattr(usage_object, "prompt_tokens_details", None)
        usage = Usage(
            prompt_tokens=_token_count(usage_object, "prompt_tokens"),
            completion_tokens=_token_count(usage_object, "completion_tokens"),
            cached_tokens=_token_count(details, "cached_tokens") if details is not None else 0,
        )
    content = getattr(message, "content", None)
    text, inline_reasoning = split_reasoning(valid_text(content) if isinstance(content, str) else "")
    field_reasoning = _reasoning_field(message)
    if any(isinstance(getattr(message, name, None), str) for name in _REASONING_FIELDS):
        # The answer stripped, as split_reasoning leaves it: litellm takes think blocks out itself (into
        # reasoning_content, empty for an empty block) and leaves the blank lines that followed them.
        text = text.strip()
    model = getattr(response, "model", None)
    finish = getattr(choice, "finish_reason", None)
    return BackendResponse(
        text=text,
        tool_calls=tuple(calls),
        usage=usage,
        usage_reported=usage_object is not None,
        model=valid_text(model) if isinstance(model, str) and model else requested_model,
        finish_reason=valid_text(finish) if isinstance(finish, str) else None,
        reasoning=join_reasoning(field_reasoning, inline_reasoning),
    )


_REASONING_FIELDS = ("reasoning_content", "reasoning")


def _reasoning_field(message: Any) -> str | None:
    """The reasoning a server returned beside the answer: ``reasoning_content`` (vLLM's reasoning parsers,
    DeepSeek, and litellm for every provider it maps) or ``reasoning`` (newer vLLM, OpenRouter). The
    OpenAI SDK keeps such unknown fields as attributes of the message.
    """
    for name in _REASONING_FIELDS:
        value = getattr(message, name, None)
        if isinstance(value, str) and value.strip():
            return valid_text(value)
    return None


def _token_count(usage: Any, name: str) -> int:
    """A token count from the response's usage: missing is 0; negative, fractional or not a number is a
    provider fault (the SDKs build responses without validating them).
    """
    value = getattr(usage, name, None)
    if value is None:
        return 0
    number = isinstance(value, int | float) and not isinstance(value, bool) and math.isfinite(value)
    if not number or value < 0 or value != int(value):
        raise MalformedResponse(f"the provider reported an impossible usage: {name}={value!r}")
    return int(value)


FailureKind = Literal[
    "transient", "authentication", "permission", "not_found", "context_length", "quota", "bad_request"
]


@dataclass(frozen=True)
class Failure:
    """What went wrong with one request, as far as retrying is concerned."""

    kind: FailureKind
    status_code: int | None
    detail: str
    retry_after_s: float | None = None

    @property
    def transient(self) -> bool:
        """Whether trying again may help."""
        return self.kind == "transient"


def classify_error(error: BaseException) -> Failure | None:
    """Sort an exception from either SDK; ``None`` when it is not a provider error (a bug: re-raise it)."""
    if isinstance(error, MalformedResponse):
        return Failure("transient", None, str(error))
    import openai

    if not isinstance(error, openai.APIError):
        return None
    detail = _detail(error)
    if isinstance(error, openai.APIConnectionError):  # includes APITimeoutError and litellm's Timeout
        is_timeout = isinstance(error, openai.APITimeoutError)
        return Failure(
            "transient", None, "the request timed out" if is_timeout else f"cannot connect: {detail}"
        )
    status = getattr(error, "status_code", None)
    status = status if isinstance(status, int) else None
    codes = _codes(error)
    lowered = detail.lower()
    if status == 429 and ("insufficient_quota" in codes or "insufficient_quota" in lowered):
        return Failure("quota", status, detail)
    if status is None or status in TRANSIENT_STATUS or status >= 500 or status < 400:
        return Failure("transient", status, detail, retry_after(error))
    if _is_context_error(error, codes, lowered):
        return Failure("context_length", status, detail)
    if status == 401:
        return Failure("authentication", status, detail)
    if status == 403:
        return Failure("permission", status, detail)
    if status == 404:
        return Failure("not_found", status, detail)
    return Failure("bad_request", status, detail)


def _codes(error: BaseException) -> set[str]:
    """The error's code and type, from the exception and from the body (with or without its 'error')."""
    found = {str(getattr(error, name, None) or "") for name in ("code", "type")}
    body = getattr(error, "body", None)
    if isinstance(body, dict):
        for part in (body, body.get("error")):
            if isinstance(part, dict):
                found.update(str(part.get(name) or "") for name in ("code", "type"))
    found.discard("")
    return found


def _is_context_error(error: BaseException, codes: set[str], lowered: str) -> bool:
    if type(error).__name__ == "ContextWindowExceededError" or "context_length_exceeded" in codes:
        return True
    return any(
        phrase in lowered
        for phrase in (
            "context_length_exceeded",
            "maximum context length",
            "context window",
            "too many tokens",
        )
    )


_SDK_PREFIX = re.compile(r"^(?:litellm\.\w+: |\w+(?:Error|Exception)(?: -|:) )+")


def _detail(error: BaseException) -> str:
    body = getattr(error, "body", None)
    if isinstance(body, dict):
        inner = body.get("error", body)
        if isinstance(inner, dict) and isinstance(inner.get("message"), str):
            return str(inner["message"])
    message = getattr(error, "message", None)
    text = message if isinstance(message, str) and message else str(error)
    # litellm stacks the names of the exceptions it mapped in front of the provider's message.
    return _SDK_PREFIX.sub("", text).strip() or text


def retry_after(error: BaseException) -> float | None:
    """Return the wait the provider asked for (``retry-after-ms`` or ``Retry-After``), in seconds."""
    # The OpenAI SDK keeps the HTTP response; litellm keeps the provider's headers beside its own response.
    for headers in (
        getattr(getattr(error, "response", None), "headers", None),
        getattr(error, "litellm_response_headers", None),
    ):
        if headers is None:
            continue
        try:
            milliseconds = headers.get("retry-after-ms")
            if milliseconds is not None:
                return max(float(milliseconds) / 1000.0, 0.0)
            value = headers.get("retry-after")
        except (AttributeError, TypeError, ValueError):
            continue
        if value is not None:
            return _seconds(value)
    return None


def _seconds(value: object) -> float | None:
    try:
        return max(float(str(value)), 0.0)
    except (TypeError, ValueError):
        pass
    try:  # an HTTP date
        moment = email.utils.parsedate_to_datetime(str(value))
    except (TypeError, ValueError, IndexError):
        return None
    return max(moment.timestamp() - time.time(), 0.0)
