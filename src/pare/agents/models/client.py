"""The one way every actor calls its model: cache, rate limits, retries, errors, usage, cost."""

from __future__ import annotations

import asyncio
import dataclasses
import logging
import os
import time
import weakref
from collections.abc import Sequence
from typing import Any

from tenacity import (
    AsyncRetrying,
    RetryCallState,
    retry_if_exception,
    stop_after_attempt,
    wait_exponential,
    wait_random,
)

from pare.agents.models.backends import (
    BackendResponse,
    Failure,
    ModelBackend,
    classify_error,
    import_litellm,
    litellm_available,
    make_backend,
)
from pare.agents.models.cache import ModelCallCache, cache_key, request_record
from pare.agents.models.capabilities import Adjustment
from pare.agents.models.config import ModelConfig
from pare.agents.models.ledger import UsageLedger
from pare.agents.models.limiter import EndpointLimiter, Permit, estimate_prompt_tokens
from pare.agents.models.pricing import call_cost
from pare.agents.models.refusals import refused_parameter
from pare.agents.models.request_params import RequestParams
from pare.agents.models.secrets import scrub, secret_values
from pare.agents.models.text import cap_answer
from pare.agents.models.types import ChatMessage, Completion
from pare.errors import CacheMiss, ModelRequestError, ProviderUnavailable

logger = logging.getLogger("pare.models")

_LIMITERS: weakref.WeakKeyDictionary[asyncio.AbstractEventLoop, dict[tuple[str, str], EndpointLimiter]] = (
    weakref.WeakKeyDictionary()
)


def endpoint_key(config: ModelConfig) -> tuple[str, str]:
    """Return the key under which calls to the same endpoint share one limiter."""
    if config.api_base:
        return (config.backend, config.api_base.rstrip("/"))
    if config.backend == "litellm" and "/" in config.model:
        return (config.backend, "provider:" + config.model.split("/", 1)[0])
    return (config.backend, "default")


def endpoint_limiter(config: ModelConfig, role: str) -> EndpointLimiter:
    """Return the running loop's limiter for ``config``'s endpoint, with ``role`` among its users.

    Every role reaching the endpoint in this event loop shares it, and the strictest of their settings
    applies (the lowest ``max_concurrency``, ``requests_per_minute`` and ``tokens_per_minute``). Limiters
    wait on their loop, so each loop has its own registry.
    """
    loop = asyncio.get_running_loop()
    registry = _LIMITERS.setdefault(loop, {})
    key = endpoint_key(config)
    limiter = registry.get(key)
    if limiter is None:
        limiter = registry[key] = EndpointLimiter(config.endpoint(), config.max_concurrency)
    limiter.adopt(role, config.max_concurrency, config.requests_per_minute, config.tokens_per_minute)
    return limiter


_IMPORTED: set[str] = set()


async def _import_sdks(config: ModelConfig) -> None:
    """Import the SDKs a call will need in a worker thread, so the event loop (other episodes) never stalls.

    The OpenAI SDK takes about a second to import and litellm a few; both are imported once per process.
    """
    needed = {"openai"}
    if config.backend == "litellm" or (config.prices is None and litellm_available()):
        needed.add("litellm")  # the backend, or the price table
    missing = needed - _IMPORTED
    if not missing:
        return

    def load() -> None:
        if "openai" in missing:
            import openai  # noqa: F401
        if "litellm" in missing:
            import_litellm()

    await asyncio.to_thread(load)
    _IMPORTED.update(missing)


class _Backoff:
    """Exponential backoff with jitter, stretched to the provider's Retry-After, capped at retry_max_s."""

    def __init__(self, config: ModelConfig) -> None:
        self._cap = config.retry_max_s
        # initial * 2^(n-1), plus up to one initial wait of random jitter so clients do not retry in step.
        self._exponential = wait_exponential(
            multiplier=config.retry_initial_s, max=config.retry_max_s
        ) + wait_random(0, config.retry_initial_s)

    def __call__(self, state: RetryCallState) -> float:
        wait = self._exponential(state)
        outcome = state.outcome
        error = outcome.exception() if outcome is not None and outcome.failed else None
        if error is not None:
            failure = classify_error(error)
            if failure is not None and failure.retry_after_s is not None:
                wait = max(wait, failure.retry_after_s)
        return min(wait, self._cap)


def _is_transient(error: BaseException) -> bool:
    failure = classify_error(error)
    return failure is not None and failure.transient


class ModelClient:
    """Calls one role's model: ``await client.complete(messages)`` returns a :class:`Completion`.

    Each call goes through the record/replay ``cache`` when one is given, waits for a slot of its
    endpoint's limiter (:mod:`pare.agents.models.limiter`: adaptive concurrency, the provider's pauses,
    budgets), retries transient provider errors with backoff (raising
    :class:`~pare.errors.ProviderUnavailable` when they persist), raises
    :class:`~pare.errors.ModelRequestError` at once for errors retrying cannot fix, and records tokens,
    latency and cost in the ``ledger``.
    """

    def __init__(
        self,
        config: ModelConfig,
        role: str,
        cache: ModelCallCache | None = None,
        ledger: UsageLedger | None = None,
        *,
        params: RequestParams | None = None,
    ) -> None:
        self.config = config
        self.role = role
        self.cache = cache
        self.ledger = ledger if ledger is not None else UsageLedger()
        self.params = params if params is not None else RequestParams(config, role)
        """What the requests carry; clients of one role in one run share one, so what one learns, all
        know."""
        self._backend: ModelBackend | None = None
        self._backend_loop: weakref.ref[asyncio.AbstractEventLoop] | None = None

    def __repr__(self) -> str:
        return (
            f"ModelClient(role={self.role!r}, model={self.config.model!r}, backend={self.config.backend!r})"
        )

    def sent_params(self) -> dict[str, Any]:
        """The request parameters each call carries now: the configured ones, renamed or dropped where the
        model is known (or was found) to refuse them.
        """
        return self.params.sent()

    @property
    def adjustments(self) -> list[Adjustment]:
        """How the parameters sent differ from the configured ones, and why (known, then learned)."""
        return self.params.adjustments

    def _where(self) -> str:
        return f"{self.role} model '{self.config.model}' at {self.config.endpoint()}"

    def api_key(self) -> str | None:
        """Return the API key from the configured variable; raise a clear error when it is not set.

        ``None`` means no key is sent (a local server; or, with litellm, the provider's usual variable,
        which is checked here too).
        """
        variable = self.config.api_key_env
        if variable is not None:
            value = os.environ.get(variable, "").strip()
            if not value:
                raise ModelRequestError(
                    f"{self._where()}: the environment variable {variable} holding the API key is not set. "
                    f"Set it (export {variable}=...), name another variable with api_key_env, or set "
                    "api_key_env to null for a local server that needs no key.",
                    kind="missing_api_key",
                )
            return value
        if self.config.backend == "litellm" and self.config.api_base is None:
            found = import_litellm().validate_environment(model=self.config.model)
            missing = [str(name) for name in found.get("missing_keys", [])]
            if missing:
                raise ModelRequestError(
                    f"{self._where()}: litellm needs {', '.join(missing)} in the environment for this "
                    "provider. Set it, or name the variable holding the key with api_key_env.",
                    kind="missing_api_key",
                )
        return None

    def _get_backend(self) -> ModelBackend:
        loop = asyncio.get_running_loop()
        if self._backend is None or self._backend_loop is None or self._backend_loop() is not loop:
            # HTTP clients are bound to the loop they were first used in: one backend per loop.
            self._backend = make_backend(self.config, self.api_key())
            self._backend_loop = weakref.ref(loop)
        return self._backend

    async def aclose(self) -> None:
        """Close the backend's connections (the client can still be used afterwards)."""
        backend, self._backend = self._backend, None
        if backend is not None:
            await backend.aclose()

    async def __aenter__(self) -> ModelClient:
        return self

    async def __aexit__(self, *exc_info: object) -> None:
        await self.aclose()

    async def complete(
        self,
        messages: Sequence[ChatMessage],
        tools: Sequence[dict[str, Any]] | None = None,
        *,
        namespace: str | None = None,
        ledger: UsageLedger | None = None,
    ) -> Completion:
        """Return the model's answer to ``messages``.

        ``tools`` are OpenAI function schemas; they are sent (and the model's tool calls returned) only
        when the configuration has ``native_tools`` on, otherwise the prompt is expected to describe them.
        ``namespace`` keeps the cache entries of independent samples apart (one per benchmark run);
        ``ledger``, when given, records the call too (an episode's own usage, beside the client's).
        """
        ledgers = (self.ledger,) if ledger is None else (self.ledger, ledger)
        messages = list(messages)
        if not messages:
            raise ValueError("complete() needs at least one message")
        sent_tools = [dict(tool) for tool in tools] if tools and self.config.native_tools else None
        cache = self.cache if self.cache is not None and self.cache.mode != "off" else None
        record: dict[str, Any] = {}
        key = ""
        if cache is not None:
            record = request_record(self.config, messages, sent_tools, namespace)
            key = cache_key(record)
            hit = await asyncio.to_thread(cache.get, key)
            if hit is not None:
                hit = cap_answer(hit, self.config.max_answer_chars)  # recorded before the cap was set
                for book in ledgers:
                    book.record(self.role, hit)
                return hit
            if cache.mode == "replay":
                raise CacheMiss(
                    f"{self.role} model '{self.config.model}': this call is not in the model-call cache "
                    f"{cache.path} (key {key[:12]}). A replay run needs the cache recorded by the same run "
                    "(same prompts, model and sampling settings); record it with cache mode read_write."
                )
        try:
            # Capped before it is stored or sent on: a runaway answer must not fill the cache and every
            # later request of the conversation.
            completion = cap_answer(await self._call(messages, sent_tools), self.config.max_answer_chars)
        except (ModelRequestError, ProviderUnavailable):
            for book in ledgers:
                book.record_failure(self.role)
            raise
        if cache is not None and cache.writes:
            stored = await asyncio.to_thread(cache.put, key, completion, request=record, role=self.role)
            if not stored:  # another task or process stored this request first: its answer is the record
                winner = await asyncio.to_thread(cache.get, key)
                if winner is not None:
                    completion = winner.model_copy(update={"from_cache": False})
        for book in ledgers:
            book.record(self.role, completion)
        return completion

    def complete_sync(
        self, messages: Sequence[ChatMessage], tools: Sequence[dict[str, Any]] | None = None
    ) -> Completion:
        """Blocking :meth:`complete` for scripts and notebooks without an event loop of their own."""
        try:
            asyncio.get_running_loop()
        except RuntimeError:
            pass
        else:
            raise RuntimeError(
                "ModelClient.complete_sync() cannot run inside a running event loop: use "
                "'await client.complete(...)' there"
            )

        async def complete_and_close() -> Completion:
            try:
                return await self.complete(messages, tools)
            finally:
                await self.aclose()

        return asyncio.run(complete_and_close())

    async def _call(self, messages: list[ChatMessage], tools: list[dict[str, Any]] | None) -> Completion:
        """Send the request with the parameters the model accepts; when the provider refuses one of them
        by name, learn it (for every later call of the role) and send the request again without it.
        """
        if self.config.api_key_env is not None:
            self.api_key()  # a missing variable fails here, before any import or request
        await _import_sdks(self.config)
        while True:
            params = self.params.sent()
            try:
                return await self._send(messages, tools, params)
            except ModelRequestError as error:
                if error.kind != "bad_request":
                    raise
                adjustment = refused_parameter(error.__cause__, params)
                if adjustment is None:
                    raise
                self.params.learn(dataclasses.replace(adjustment, why=self._scrub(adjustment.why)))
                if self.params.sent() == params:  # nothing changed: sending again would fail the same way
                    raise

    async def _send(
        self, messages: list[ChatMessage], tools: list[dict[str, Any]] | None, params: dict[str, Any]
    ) -> Completion:
        backend = self._get_backend()  # resolves the key (litellm: checks the provider's own variable)
        await backend.prepare()
        payload = [message.to_openai() for message in messages]
        limiter = self.limiter()
        ticket = limiter.ticket()  # every attempt keeps the call's place in the endpoint's queue
        tokens = 0
        if limiter.counts_tokens:
            tokens = estimate_prompt_tokens(payload, tools) + limiter.expected_completion_tokens()
        attempts = 0
        retrying = AsyncRetrying(
            stop=stop_after_attempt(self.config.max_retries + 1),
            wait=_Backoff(self.config),
            retry=retry_if_exception(_is_transient),
            before_sleep=self._log_retry,
            reraise=True,
        )
        try:
            async for attempt in retrying:
                with attempt:
                    async with limiter.slot(tokens, ticket=ticket) as permit:
                        attempts += 1
                        started = time.perf_counter()
                        try:
                            response = await backend.complete(payload, tools, params)
                        except Exception as error:
                            self._note_rate_limit(permit, error)
                            raise
                        latency = time.perf_counter() - started
                        usage = response.usage
                        if response.usage_reported:
                            permit.succeeded(usage.total_tokens, usage.completion_tokens)
                        else:
                            permit.succeeded()
        except Exception as error:
            failure = classify_error(error)
            if failure is None:
                raise
            raise self._failure_error(self._scrubbed(failure), attempts, messages) from error
        return self._completion(response, latency)

    def limiter(self) -> EndpointLimiter:
        """The limiter of this client's endpoint in the running event loop (shared with other roles)."""
        return endpoint_limiter(self.config, self.role)

    def _note_rate_limit(self, permit: Permit, error: BaseException) -> None:
        """Tell the endpoint's limiter about a rate-limit answer (429), with the pause it asked for."""
        failure = classify_error(error)
        if failure is None or not failure.transient or failure.status_code != 429:
            return
        pause = failure.retry_after_s
        permit.rate_limited(min(pause, self.config.retry_max_s) if pause is not None else None)

    def _completion(self, response: BackendResponse, latency: float) -> Completion:
        return Completion(
            text=response.text,
            tool_calls=response.tool_calls,
            usage=response.usage,
            cost_usd=call_cost(self.config, response.usage, usage_reported=response.usage_reported),
            latency_s=latency,
            model=response.model,
            finish_reason=response.finish_reason,
            reasoning=response.reasoning,
        )

    def _scrubbed(self, failure: Failure) -> Failure:
        """``failure`` without the key or secret ``extra`` values a provider may echo in its message."""
        return dataclasses.replace(failure, detail=self._scrub(failure.detail))

    def _scrub(self, text: str) -> str:
        """``text`` without the key or the secret ``extra`` values."""
        key = os.environ.get(self.config.api_key_env or "", "") if self.config.api_key_env else None
        return scrub(text, [key, *secret_values(self.config.extra)])

    def _log_retry(self, state: RetryCallState) -> None:
        outcome = state.outcome
        error = outcome.exception() if outcome is not None else None
        failure = classify_error(error) if error is not None else None
        wait = state.next_action.sleep if state.next_action is not None else 0.0
        # a rate-limit answer is expected when a run meets the provider's limits; the endpoint's limiter
        # adapts and the progress bar shows it, so it is no warning
        rate_limited = failure is not None and failure.transient and failure.status_code == 429
        logger.log(
            logging.INFO if rate_limited else logging.WARNING,
            "%s: attempt %d failed (%s); retrying in %.2fs",
            self._where(),
            state.attempt_number,
            _describe(self._scrubbed(failure)) if failure is not None else "an unexpected error",
            wait,
        )

    def _failure_error(
        self, failure: Failure, attempts: int, messages: list[ChatMessage]
    ) -> ModelRequestError | ProviderUnavailable:
        where = self._where()
        status = _describe(failure)
        if failure.transient:
            hint = (
                f"is the server running at {self.config.endpoint()}?"
                if failure.status_code is None and failure.detail.startswith("cannot connect")
                else "the provider is down or rate-limiting; try again later, or lower max_concurrency or "
                "set requests_per_minute / tokens_per_minute to the provider's limits"
            )
            return ProviderUnavailable(
                f"{where}: still failing after {_count(attempts, 'attempt')} ({status}); "
                f"{hint}. This is an infrastructure failure, not the model's.",
                attempts=attempts,
                status_code=failure.status_code,
            )
        variable = self.config.api_key_env
        size = f"{_count(len(messages), 'message')}, {sum(len(m.content or '') for m in messages)} characters"
        advice = {
            "authentication": (
                f"the provider refused the API key ({status}). Set {variable} to a valid key for this "
                "endpoint."
                if variable
                else f"the provider refused the request for lack of a valid key ({status}). Name the "
                "variable holding the key with api_key_env."
            ),
            "permission": f"the API key has no access to this model ({status}). Use a key with access or "
            "another model.",
            "not_found": f"the endpoint does not know this model ({status}). Check the model name (for vLLM "
            "the served model name; for litellm the provider prefix such as 'openai/') and that api_base "
            "points at the right server (usually ending in /v1).",
            "context_length": f"the prompt is longer than the model's context ({size}; {status}). Shorten "
            "the conversation or use a model with a longer context.",
            "quota": f"the account has no quota left ({status}). Add credit or use another key.",
            "bad_request": f"the provider rejected the request ({status}). Check the request parameters "
            "(extra, max_tokens, tools) against what this model accepts.",
        }[failure.kind]
        return ModelRequestError(f"{where}: {advice}", kind=failure.kind, status_code=failure.status_code)


def _describe(failure: Failure) -> str:
    detail = failure.detail.strip().replace("\n", " ")
    if len(detail) > 300:
        detail = detail[:297] + "..."
    return f"HTTP {failure.status_code}: {detail}" if failure.status_code is not None else detail


def _count(number: int, noun: str) -> str:
    return f"{number} {noun}{'' if number == 1 else 's'}"
