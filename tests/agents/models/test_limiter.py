"""The endpoint limiter: adaptive concurrency, the provider's pauses, budgets, fairness and cancellation.

Everything here runs on a fake clock that the test moves by hand (then calls ``wake()``), so nothing
depends on how fast the machine is.
"""

from __future__ import annotations

import asyncio
from collections.abc import Awaitable, Callable
from typing import Any

import pytest

from pare.agents.models import ModelConfig
from pare.agents.models.limiter import AdaptiveLimit, EndpointLimiter, Pace, Permit, estimate_prompt_tokens
from pare.bench.runconfig import build_config, parse_assignment
from pare.bench.throttling import throttling_status, throttling_summary
from pare.errors import UserInputError


class FakeClock:
    def __init__(self) -> None:
        self.now = 1000.0

    def __call__(self) -> float:
        return self.now


def limiter(max_concurrency: int = 4, **budgets: Any) -> tuple[EndpointLimiter, FakeClock]:
    clock = FakeClock()
    return EndpointLimiter("http://127.0.0.1:1/v1", max_concurrency, clock=clock, **budgets), clock


async def settle() -> None:
    """Let every task that can run, run."""
    for _ in range(5):
        await asyncio.sleep(0)


def run(test: Callable[[], Awaitable[None]]) -> None:
    asyncio.run(test())


# --- additive increase, multiplicative decrease ------------------------------------------------------------


def test_a_429_cuts_the_limit_by_a_quarter_and_never_below_one() -> None:
    adaptive = AdaptiveLimit(16)
    seen = []
    while adaptive.limit > 1:
        assert adaptive.rate_limited(adaptive.epoch)
        seen.append(adaptive.limit)
    assert seen == [12, 9, 7, 5, 4, 3, 2, 1]
    assert adaptive.rate_limited(adaptive.epoch) and adaptive.limit == 1  # the floor
    assert adaptive.cuts == 9


def test_429s_of_calls_sent_before_the_cut_do_not_cut_again() -> None:
    adaptive = AdaptiveLimit(16)
    sent_together = adaptive.epoch  # many calls went out under the old limit and all meet the limit
    assert adaptive.rate_limited(sent_together)
    for _ in range(10):
        assert not adaptive.rate_limited(sent_together)
    assert adaptive.limit == 12 and adaptive.cuts == 1
    assert adaptive.rate_limited(adaptive.epoch)  # a call sent under the new limit still meets it
    assert adaptive.limit == 9


def test_the_limit_recovers_by_one_after_as_many_successes_as_it_allows() -> None:
    adaptive = AdaptiveLimit(6)
    adaptive.rate_limited(adaptive.epoch)
    adaptive.rate_limited(adaptive.epoch)
    assert adaptive.limit == 3
    steps = []
    for _ in range(3 + 4 + 5 + 20):
        adaptive.succeeded()
        steps.append(adaptive.limit)
    assert steps[:3] == [3, 3, 4]  # three successes at 3 allow 4
    assert steps[3:7] == [4, 4, 4, 5]
    assert steps[7:12] == [5, 5, 5, 5, 6]
    assert set(steps[12:]) == {6}  # never above max_concurrency


def test_a_429_restarts_the_run_of_successes() -> None:
    adaptive = AdaptiveLimit(8)
    adaptive.rate_limited(adaptive.epoch)  # 6
    for _ in range(5):
        adaptive.succeeded()
    old_epoch = adaptive.epoch - 1
    adaptive.rate_limited(old_epoch)  # an echo of the earlier overload: no cut, but the run starts over
    for _ in range(5):
        adaptive.succeeded()
    assert adaptive.limit == 6
    adaptive.succeeded()
    assert adaptive.limit == 7


# --- budgets -----------------------------------------------------------------------------------------------


def test_a_request_budget_never_lets_more_than_its_number_start_in_a_minute() -> None:
    pace = Pace(per_minute=30)
    clock = 0.0
    starts = []
    while clock < 300:  # a caller that always wants to start, polling every 10 ms
        if pace.ready_in(clock) == 0:
            pace.take(clock, 1)
            starts.append(clock)
        clock = round(clock + 0.01, 2)
    windows = [sum(start <= s < start + 60 for s in starts) for start in starts]
    assert max(windows) == 30
    assert len(starts) == 150  # and the budget is used in full


def test_a_token_budget_is_paced_by_the_usage_reported() -> None:
    pace = Pace(per_minute=6000)
    pace.take(0.0, 500)  # estimated 500 tokens: the next call may start after 5 s
    assert pace.ready_in(0.0) == pytest.approx(5.0)
    pace.adjust(1500 - 500)  # the provider reported 1500
    assert pace.ready_in(0.0) == pytest.approx(15.0)
    pace.adjust(-1400)  # a later correction downwards gives the time back
    assert pace.ready_in(0.0) == pytest.approx(1.0)


def test_the_limiter_holds_calls_for_the_request_budget() -> None:
    async def scenario() -> None:
        limiter_, clock = limiter(max_concurrency=10, requests_per_minute=60)
        first = await limiter_.acquire()
        second = asyncio.ensure_future(limiter_.acquire())
        await settle()
        assert not second.done()
        state = limiter_.state()
        assert (state.waiting, state.held_by, state.throttled) == (1, "requests_per_minute", True)
        limiter_.release(first)
        clock.now += 0.5
        limiter_.wake()
        await settle()
        assert not second.done()  # a slot is free, but the budget allows one call a second
        clock.now += 0.5
        limiter_.wake()
        await settle()
        limiter_.release(second.result())
        assert limiter_.state().throttled_s == pytest.approx(1.0)

    run(scenario)


def test_the_token_budget_uses_the_estimate_then_the_reported_usage() -> None:
    async def scenario() -> None:
        limiter_, clock = limiter(max_concurrency=10, tokens_per_minute=60_000)  # 1000 tokens a second
        assert limiter_.counts_tokens and limiter_.expected_completion_tokens() == 0
        permit = await limiter_.acquire(2000)
        permit.succeeded(total_tokens=5000, completion_tokens=300)
        limiter_.release(permit)
        assert limiter_.expected_completion_tokens() == 300
        waiting = asyncio.ensure_future(limiter_.acquire(100))
        clock.now += 4.9  # 5000 tokens take 5 s of the budget, not the 2 s of the estimate
        limiter_.wake()
        await settle()
        assert not waiting.done() and limiter_.state().held_by == "tokens_per_minute"
        clock.now += 0.1
        limiter_.wake()
        await settle()
        assert waiting.done()

    run(scenario)


def test_the_prompt_estimate_is_a_quarter_of_the_characters_plus_four_per_message() -> None:
    messages = [{"role": "system", "content": "x" * 400}, {"role": "user", "content": "y" * 40}]
    assert estimate_prompt_tokens(messages) == 110 + 8
    tools = [{"type": "function", "function": {"name": "f"}}]
    assert estimate_prompt_tokens(messages, tools) > estimate_prompt_tokens(messages)


# --- the provider's pause, fairness, cancellation ----------------------------------------------------------


def test_a_429_with_retry_after_pauses_every_other_call_to_the_endpoint() -> None:
    async def scenario() -> None:
        limiter_, clock = limiter(max_concurrency=8)
        limiter_.adopt("user", 8)
        first, other = await limiter_.acquire(), await limiter_.acquire()
        first.rate_limited(retry_after_s=2.0)
        limiter_.release(first)
        queued = [asyncio.ensure_future(limiter_.acquire()) for _ in range(3)]
        await settle()
        state = limiter_.state()
        assert not any(task.done() for task in queued)  # slots are free, but the endpoint is paused
        assert (state.held_by, state.waiting, state.rate_limited, state.limit) == ("pause", 3, 1, 6)
        assert state.paused_s == pytest.approx(2.0)
        assert throttling_status([state]) == (
            "throttled: user endpoint at 6/8, 3 queued, waiting 2.0 s for rate limit"
        )
        other.succeeded()
        limiter_.release(other)  # a call in flight during the pause ends normally
        clock.now += 2.0
        limiter_.wake()
        await settle()
        assert all(task.done() for task in queued)
        state = limiter_.state()
        assert state.throttled_s == pytest.approx(2.0) and state.in_flight == 3

    run(scenario)


def test_calls_start_in_the_order_they_first_asked_and_a_retry_keeps_its_place() -> None:
    async def scenario() -> None:
        limiter_, _ = limiter(max_concurrency=1)
        retried = limiter_.ticket()  # a call that asked first and is now retrying
        holder = await limiter_.acquire()
        started: list[str] = []

        async def call(name: str, ticket: int | None = None) -> None:
            permit = await limiter_.acquire(ticket=ticket)
            started.append(name)
            limiter_.release(permit)

        tasks = [asyncio.ensure_future(call(name)) for name in ("b", "c")]
        await settle()
        tasks.append(asyncio.ensure_future(call("a (retry)", retried)))
        await settle()
        limiter_.release(holder)
        await asyncio.gather(*tasks)
        assert started == ["a (retry)", "b", "c"]

    run(scenario)


def test_a_cancelled_waiter_leaves_the_queue_without_a_slot() -> None:
    async def scenario() -> None:
        limiter_, _ = limiter(max_concurrency=1)
        holder = await limiter_.acquire()
        cancelled = asyncio.ensure_future(limiter_.acquire())
        behind = asyncio.ensure_future(limiter_.acquire())
        await settle()
        cancelled.cancel()
        await settle()
        assert limiter_.state().waiting == 1
        limiter_.release(holder)
        await settle()
        assert behind.done() and cancelled.cancelled()
        limiter_.release(behind.result())
        state = limiter_.state()
        assert (state.in_flight, state.waiting) == (0, 0)

    run(scenario)


def test_a_slot_granted_to_a_call_cancelled_at_that_moment_is_given_back() -> None:
    async def scenario() -> None:
        limiter_, _ = limiter(max_concurrency=1)
        holder = await limiter_.acquire()
        waiter = asyncio.ensure_future(limiter_.acquire())
        await settle()
        limiter_.release(holder)  # grants the slot to the waiter, which has not run yet...
        assert limiter_.state().in_flight == 1
        waiter.cancel()  # ...and is cancelled before it does
        await settle()
        assert waiter.cancelled()
        assert limiter_.state().in_flight == 0
        permit = await asyncio.wait_for(limiter_.acquire(), timeout=5)  # the slot is free again
        assert isinstance(permit, Permit)

    run(scenario)


def test_a_call_cancelled_in_flight_gives_its_slot_back_and_changes_no_limit() -> None:
    async def scenario() -> None:
        limiter_, _ = limiter(max_concurrency=2)
        entered = asyncio.Event()

        async def call() -> None:
            async with limiter_.slot():
                entered.set()
                await asyncio.sleep(3600)

        task = asyncio.ensure_future(call())
        await entered.wait()
        task.cancel()
        await settle()
        state = limiter_.state()
        assert (state.in_flight, state.limit, state.rate_limited) == (0, 2, 0)

    run(scenario)


# --- sharing and settings ----------------------------------------------------------------------------------


def test_the_strictest_setting_of_the_roles_sharing_an_endpoint_applies() -> None:
    limiter_, _ = limiter(max_concurrency=16)
    limiter_.adopt("user", 16, requests_per_minute=600)
    limiter_.adopt("observe", 4, requests_per_minute=None, tokens_per_minute=90_000)
    limiter_.adopt("execute", 8, requests_per_minute=1200)
    state = limiter_.state()
    assert state.roles == ("user", "observe", "execute")
    assert (state.max_concurrency, state.requests_per_minute, state.tokens_per_minute) == (4, 600, 90_000)


def test_the_run_summary_says_how_much_time_throttling_took() -> None:
    limiter_, clock = limiter(max_concurrency=8)
    limiter_.adopt("observe", 8)
    limiter_.adopt("execute", 8)
    assert throttling_summary([limiter_.state()], 10.0) == []  # nothing to say when nothing was limited

    async def scenario() -> None:
        permit = await limiter_.acquire()
        permit.rate_limited(retry_after_s=3.0)
        limiter_.release(permit)
        waiting = asyncio.ensure_future(limiter_.acquire())
        await settle()
        clock.now += 3.0
        limiter_.wake()
        await settle()
        limiter_.release(waiting.result())

    run(scenario)
    (line,) = throttling_summary([limiter_.state()], 10.0)
    assert line == (
        "throttling: assistant endpoint: 1 rate-limit answer (429), calls held back for 3.0 s (30% of the "
        "session); concurrency 6/8 at the end, cut 1 time"
    )


@pytest.mark.parametrize("field", ["requests_per_minute", "tokens_per_minute"])
@pytest.mark.parametrize("value", [0, -5, True, 10**13])
def test_a_budget_out_of_range_is_refused_with_its_place(field: str, value: object) -> None:
    with pytest.raises(UserInputError, match=rf"models\.user: {field}: .*must be a whole number from 1 to"):
        ModelConfig.parse({"model": "m", field: value}, where="models.user")


def test_budgets_are_set_from_a_run_configuration() -> None:
    overrides = [
        ("models.user.model", "u"),
        parse_assignment("models.user.requests_per_minute=500"),
        parse_assignment("models.user.tokens_per_minute=200000"),
    ]
    config = build_config({}, overrides=overrides)
    assert config.models.user is not None
    assert (config.models.user.requests_per_minute, config.models.user.tokens_per_minute) == (500, 200_000)
    with pytest.raises(UserInputError, match=r"models\.user\.requests_per_minute: .*no budget"):
        build_config({}, overrides=[("models.user.model", "u"), ("models.user.requests_per_minute", 0)])
    # a budget is machinery, like max_concurrency: a resumed run may change it
    assert build_config({}, overrides=overrides[:1]).identity_hash() == config.identity_hash()
