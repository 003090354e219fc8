"""ModelClient and its endpoint's limiter: shared by the roles of one endpoint, paused by a 429, budgets."""

from __future__ import annotations

import asyncio
from collections.abc import Callable

import pytest

from pare.agents.models import ChatMessage, ModelClient, UsageLedger
from pare.errors import ProviderUnavailable

from .conftest import ConfigFactory
from .fake_server import FakeChatServer, answer, error

HELLO = [ChatMessage.user("Say hello.")]


async def until(condition: Callable[[], bool], what: str) -> None:
    """Wait (at most 10 s) until ``condition()`` holds."""
    for _ in range(1000):
        if condition():
            return
        await asyncio.sleep(0.01)
    raise AssertionError(f"never happened: {what}")


def test_two_roles_on_one_endpoint_share_one_limiter(
    server: FakeChatServer, make_config: ConfigFactory
) -> None:
    other = FakeChatServer().start()
    try:
        user = ModelClient(make_config(max_concurrency=8, requests_per_minute=600), role="user")
        observe = ModelClient(make_config(max_concurrency=3), role="observe")
        elsewhere = ModelClient(make_config(api_base=other.base_url), role="execute")

        async def limiters() -> None:
            assert user.limiter() is observe.limiter()
            assert elsewhere.limiter() is not user.limiter()
            state = user.limiter().state()
            assert state.roles == ("user", "observe")
            assert (state.max_concurrency, state.requests_per_minute) == (3, 600)  # the strictest of the two

        asyncio.run(limiters())
    finally:
        other.stop()


def test_a_429_with_retry_after_pauses_the_other_calls_to_the_endpoint(
    server: FakeChatServer, make_config: ConfigFactory
) -> None:
    server.push(error(429, "slow down", code="rate_limit_exceeded", headers={"Retry-After": "60"}))
    server.default = answer("too early")
    config = make_config(max_retries=0, retry_max_s=120.0)
    user, observe = ModelClient(config, role="user"), ModelClient(config, role="observe")

    async def scenario() -> None:
        with pytest.raises(ProviderUnavailable):
            await user.complete(HELLO)  # met the limit; no retries left
        limiter = observe.limiter()
        later = asyncio.ensure_future(observe.complete([ChatMessage.user("Another question.")]))
        await until(lambda: limiter.state().waiting == 1, "the second call queued")
        state = limiter.state()
        assert server.count == 1  # the second call was not sent: the endpoint is paused for a minute
        assert state.held_by == "pause" and state.paused_s > 50 and state.rate_limited == 1
        later.cancel()
        with pytest.raises(asyncio.CancelledError):
            await later
        state = limiter.state()
        assert (state.waiting, state.in_flight) == (0, 0)  # leaving the queue leaked no slot
        await user.aclose()
        await observe.aclose()

    asyncio.run(scenario())
    assert server.count == 1


def test_the_pause_is_capped_at_retry_max_s(server: FakeChatServer, make_config: ConfigFactory) -> None:
    server.push(error(429, "slow down", code="rate_limit_exceeded", headers={"Retry-After": "3600"}))
    client = ModelClient(make_config(max_retries=0, retry_max_s=30.0), role="user")

    async def scenario() -> None:
        with pytest.raises(ProviderUnavailable):
            await client.complete(HELLO)
        assert 25 < client.limiter().state().paused_s <= 30
        await client.aclose()

    asyncio.run(scenario())


def test_concurrent_calls_after_429s_are_answered_and_the_limit_was_cut(
    server: FakeChatServer, make_config: ConfigFactory
) -> None:
    limited = error(429, "slow down", code="rate_limit_exceeded", headers={"retry-after-ms": "20"})
    server.push(limited, limited, limited)
    server.default = answer("ok", delay_s=0.01)
    ledger = UsageLedger()
    client = ModelClient(make_config(max_concurrency=8, max_retries=5), role="user", ledger=ledger)

    async def many() -> None:
        results = await asyncio.gather(*(client.complete([ChatMessage.user(f"q{i}")]) for i in range(12)))
        assert {result.text for result in results} == {"ok"}
        state = client.limiter().state()
        assert state.rate_limited == 3 and 1 <= state.cuts <= 3 and state.limit < 8
        assert (state.in_flight, state.waiting) == (0, 0)
        await client.aclose()

    asyncio.run(many())
    assert ledger.role("user").calls == 12 and ledger.role("user").failed_calls == 0


def test_the_token_budget_counts_the_usage_the_provider_reports(
    server: FakeChatServer, make_config: ConfigFactory
) -> None:
    server.default = answer("ok", prompt_tokens=4000, completion_tokens=2000)
    client = ModelClient(make_config(tokens_per_minute=60_000), role="user")  # 1000 tokens a second

    async def scenario() -> None:
        await client.complete(HELLO)
        limiter = client.limiter()
        assert limiter.expected_completion_tokens() == 2000
        later = asyncio.ensure_future(client.complete([ChatMessage.user("Next.")]))
        await until(lambda: limiter.state().waiting == 1, "the second call queued")
        # the first call used 6000 tokens: six seconds of the budget, whatever its estimate was
        assert limiter.state().held_by == "tokens_per_minute"
        assert server.count == 1
        later.cancel()
        with pytest.raises(asyncio.CancelledError):
            await later
        await client.aclose()

    asyncio.run(scenario())
