"""One limiter per model endpoint: adaptive concurrency, pauses on rate limits, request and token budgets.

Every role whose model lives at the same endpoint (:func:`pare.agents.models.client.endpoint_key`) shares
one :class:`EndpointLimiter` per event loop. A call waits in the limiter's queue until all of these allow
it to start:

* **concurrency**: fewer calls in flight than the current limit. The limit starts at ``max_concurrency``,
  is cut by :data:`DECREASE_FACTOR` (never below 1) when the provider answers 429 (rate limited), and grows
  by one after as many successes in a row as the limit itself (additive increase, about one step per
  round of calls), back up to ``max_concurrency``. The calls that were already in flight when the limit was
  cut answer under the old limit, so their 429s do not cut it again: one cut per round, as TCP does.
* **the provider's pause**: a 429 with Retry-After pauses the whole endpoint until then, so the calls
  queued behind it (from every role and episode) wait too instead of meeting the same 429.
* **budgets** (optional): ``requests_per_minute`` and ``tokens_per_minute``, each paced evenly: a call may
  start once the previous ones' share of the budget has elapsed (the generic cell rate algorithm without
  burst), so no 60 seconds ever see more than ``requests_per_minute`` calls start, and tokens are spent at
  the budget's pace. Tokens are counted before the call from an estimate (:func:`estimate_prompt_tokens`
  plus the mean completion reported at this endpoint so far) and corrected to the usage the provider
  reports once it answers.

The queue is fair: calls start in the order they first asked (a retried call keeps its place, so an
unlucky call is not sent to the back after each 429), and the head of the queue is never overtaken (a
large call waiting for the token budget is not starved by small ones). A cancelled waiter leaves the queue,
and a slot granted to a call that was cancelled at that moment is given back.

The budgets and the adaptive limit are one queue rather than several stacked limiters, which is why they
are written here: stacked limiters would each queue on their own, losing the order, and none would know
why the others hold a call (which the progress bar shows).
"""

from __future__ import annotations

import asyncio
import heapq
import itertools
import json
import math
import time
from collections.abc import AsyncIterator, Callable, Mapping, Sequence
from contextlib import asynccontextmanager
from dataclasses import dataclass, field
from typing import Any, Literal

DECREASE_FACTOR = 0.75
"""What a 429 multiplies the endpoint's concurrency limit by (rounded down, at least 1)."""

CHARACTERS_PER_TOKEN = 4
"""The usual rule of thumb for English text with the BPE tokenizers of current models."""
TOKENS_PER_MESSAGE = 4
"""What the chat format adds per message (role and separators), as OpenAI's documentation counts it."""

HeldBy = Literal["pause", "limit", "max_concurrency", "requests_per_minute", "tokens_per_minute"]
"""Why the call at the head of the queue cannot start: the provider's pause after a 429, the concurrency
limit while it is cut below ``max_concurrency``, ``max_concurrency`` itself (not throttling), a budget."""

THROTTLING: frozenset[str] = frozenset({"pause", "limit", "requests_per_minute", "tokens_per_minute"})
"""The reasons that count as throttling (time lost to rate limits), unlike the configured concurrency."""


def estimate_prompt_tokens(messages: Sequence[Mapping[str, Any]], tools: Sequence[Any] | None = None) -> int:
    """Estimate the prompt tokens of a request: a quarter of its characters plus four per message.

    ``messages`` are in the OpenAI chat format; the characters are the messages' text, their tool calls
    and the tool schemas (as JSON). The estimate only paces a token budget before the provider reports the
    real count, which then replaces it.
    """
    characters = 0
    for message in messages:
        content = message.get("content")
        if isinstance(content, str):
            characters += len(content)
        elif content is not None:
            characters += len(json.dumps(content, ensure_ascii=False))
        if message.get("tool_calls"):
            characters += len(json.dumps(message["tool_calls"], ensure_ascii=False))
    if tools:
        characters += len(json.dumps(list(tools), ensure_ascii=False))
    return math.ceil(characters / CHARACTERS_PER_TOKEN) + TOKENS_PER_MESSAGE * len(messages)


# -- the parts, without an event loop (tested with a fake clock) --------------------------------------------
class AdaptiveLimit:
    """Additive increase, multiplicative decrease of a concurrency limit between 1 and ``maximum``.

    Each call notes the :attr:`epoch` it started in; a 429 cuts the limit only when its call started after
    the last cut (calls sent under the old limit say nothing about the new one).
    """

    def __init__(self, maximum: int) -> None:
        if maximum < 1:
            raise ValueError(f"the concurrency limit must be at least 1, not {maximum}")
        self.maximum = maximum
        self.limit = maximum
        self.epoch = 0
        self.cuts = 0
        self._successes = 0

    def set_maximum(self, maximum: int) -> None:
        """Lower (or raise) the ceiling; the current limit stays under it."""
        self.maximum = maximum
        self.limit = min(self.limit, maximum)

    def rate_limited(self, started_epoch: int) -> bool:
        """A call that started in ``started_epoch`` was answered 429; return whether the limit was cut."""
        self._successes = 0
        if started_epoch != self.epoch:
            return False
        # at least one less, so that small limits still come down; never below one
        self.limit = max(1, min(self.limit - 1, round(self.limit * DECREASE_FACTOR)))
        self.epoch += 1
        self.cuts += 1
        return True

    def succeeded(self) -> None:
        """A call succeeded: after as many successes in a row as the limit, raise it by one."""
        if self.limit >= self.maximum:
            return
        self._successes += 1
        if self._successes >= self.limit:
            self.limit += 1
            self._successes = 0


class Pace:
    """An even pace of ``per_minute`` units a minute: after a call of ``n`` units, the next may start
    ``n * 60 / per_minute`` seconds later (the generic cell rate algorithm with no burst).
    """

    def __init__(self, per_minute: int) -> None:
        if per_minute < 1:
            raise ValueError(f"a budget per minute must be at least 1, not {per_minute}")
        self.per_minute = per_minute
        self._next_at = -math.inf

    def ready_in(self, now: float) -> float:
        """Seconds until the next call may start (0 when it may start now)."""
        return max(0.0, self._next_at - now)

    def take(self, now: float, units: float) -> None:
        """A call of ``units`` starts now."""
        self._next_at = max(self._next_at, now) + units * 60.0 / self.per_minute

    def adjust(self, units: float) -> None:
        """Correct a call's units after it started (the usage reported against the estimate)."""
        if math.isfinite(self._next_at):
            self._next_at += units * 60.0 / self.per_minute


# -- the limiter ---------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class LimiterState:
    """A snapshot of one endpoint's limiter, for progress displays and run summaries."""

    endpoint: str
    roles: tuple[str, ...]
    limit: int
    """The concurrency allowed now."""
    max_concurrency: int
    in_flight: int
    waiting: int
    """Calls queued for a slot."""
    paused_s: float
    """Seconds left of the provider's pause (0 when not paused)."""
    held_by: HeldBy | None
    """Why the first queued call waits (``None`` when none waits)."""
    rate_limited: int
    """429 (rate limited) answers received."""
    cuts: int
    """Times the concurrency limit was cut."""
    throttled_s: float
    """Seconds during which a call waited because of rate limiting (a pause, a cut limit, a budget)."""
    requests_per_minute: int | None
    tokens_per_minute: int | None

    @property
    def throttled(self) -> bool:
        """Whether the endpoint is held back by rate limiting now."""
        return self.limit < self.max_concurrency or self.paused_s > 0 or self.held_by in THROTTLING


@dataclass(order=True)
class _Waiter:
    ticket: int
    tokens: int = field(compare=False)
    future: asyncio.Future[Permit] = field(compare=False)


class Permit:
    """A slot of an endpoint: tell it how the call went (:meth:`succeeded`, :meth:`rate_limited`) before
    it is released; a call released without either (another error, a cancellation) changes no limit.
    """

    def __init__(self, epoch: int, tokens: int, ticket: int) -> None:
        self.epoch = epoch
        self.tokens = tokens
        self.ticket = ticket
        self.outcome: Literal["ok", "rate_limited"] | None = None
        self.used_tokens: int | None = None
        self.completion_tokens: int | None = None
        self.retry_after_s: float | None = None
        self.released = False

    def succeeded(self, total_tokens: int | None = None, completion_tokens: int | None = None) -> None:
        """The call succeeded; ``total_tokens`` is the usage the provider reported (None: not reported)."""
        self.outcome = "ok"
        self.used_tokens = total_tokens
        self.completion_tokens = completion_tokens

    def rate_limited(self, retry_after_s: float | None) -> None:
        """The provider answered 429, asking (or not) to wait ``retry_after_s`` seconds."""
        self.outcome = "rate_limited"
        self.retry_after_s = retry_after_s


class EndpointLimiter:
    """The queue every call to one endpoint waits in (see the module docstring).

    ``clock`` gives seconds (monotonic); tests pass a fake one and call :meth:`wake` after moving it.
    """

    def __init__(
        self,
        endpoint: str,
        max_concurrency: int,
        *,
        requests_per_minute: int | None = None,
        tokens_per_minute: int | None = None,
        clock: Callable[[], float] = time.monotonic,
    ) -> None:
        self.endpoint = endpoint
        self.roles: list[str] = []
        self._clock = clock
        self._adaptive = AdaptiveLimit(max_concurrency)
        self._requests = Pace(requests_per_minute) if requests_per_minute is not None else None
        self._tokens = Pace(tokens_per_minute) if tokens_per_minute is not None else None
        self._waiters: list[_Waiter] = []
        self._tickets = itertools.count()
        self._in_flight = 0
        self._paused_until = -math.inf
        self._held_by: HeldBy | None = None
        self._timer: asyncio.TimerHandle | None = None
        self._timer_at = math.inf
        self._rate_limited = 0
        self._throttled_s = 0.0
        self._accounted_at = clock()
        self._completions = 0
        self._completion_tokens = 0

    # -- settings --------------------------------------------------------------------------------------
    def adopt(
        self,
        role: str,
        max_concurrency: int,
        requests_per_minute: int | None = None,
        tokens_per_minute: int | None = None,
    ) -> None:
        """Add a role that calls this endpoint; the strictest of the roles' settings applies."""
        if role not in self.roles:
            self.roles.append(role)
        if max_concurrency < self._adaptive.maximum:
            self._adaptive.set_maximum(max_concurrency)
        if requests_per_minute is not None and (
            self._requests is None or requests_per_minute < self._requests.per_minute
        ):
            self._requests = Pace(requests_per_minute)
        if tokens_per_minute is not None and (
            self._tokens is None or tokens_per_minute < self._tokens.per_minute
        ):
            self._tokens = Pace(tokens_per_minute)

    @property
    def counts_tokens(self) -> bool:
        """Whether a token budget applies (then callers pass an estimate to :meth:`acquire`)."""
        return self._tokens is not None

    def expected_completion_tokens(self) -> int:
        """The mean completion tokens reported at this endpoint so far (0 before the first answer)."""
        return round(self._completion_tokens / self._completions) if self._completions else 0

    # -- waiting for a slot ----------------------------------------------------------------------------
    def ticket(self) -> int:
        """A place in the queue; pass it to every attempt of one call so a retry keeps its place."""
        return next(self._tickets)

    async def acquire(self, tokens: int = 0, *, ticket: int | None = None) -> Permit:
        """Wait until a call of ``tokens`` estimated tokens may start; return its permit."""
        waiter = _Waiter(
            self.ticket() if ticket is None else ticket, tokens, asyncio.get_running_loop().create_future()
        )
        heapq.heappush(self._waiters, waiter)
        self.wake()
        try:
            return await waiter.future
        except asyncio.CancelledError:
            if waiter.future.done() and not waiter.future.cancelled():
                self.release(waiter.future.result())  # granted as it was cancelled: give the slot back
            else:  # left while queued: wake() drops it when it reaches the head
                waiter.future.cancel()
                self.wake()
            raise

    @asynccontextmanager
    async def slot(self, tokens: int = 0, *, ticket: int | None = None) -> AsyncIterator[Permit]:
        """``async with limiter.slot(...) as permit``: a slot for the block, released however it ends."""
        permit = await self.acquire(tokens, ticket=ticket)
        try:
            yield permit
        finally:
            self.release(permit)

    def release(self, permit: Permit) -> None:
        """Give back ``permit``'s slot, learning from its outcome; releasing twice does nothing."""
        if permit.released:
            return
        permit.released = True
        now = self._clock()
        self._account(now)
        self._in_flight -= 1
        if permit.outcome == "ok":
            self._adaptive.succeeded()
            if permit.completion_tokens is not None:
                self._completions += 1
                self._completion_tokens += permit.completion_tokens
            if self._tokens is not None and permit.used_tokens is not None:
                self._tokens.adjust(permit.used_tokens - permit.tokens)
        elif permit.outcome == "rate_limited":
            self._rate_limited += 1
            self._adaptive.rate_limited(permit.epoch)
            if permit.retry_after_s is not None and permit.retry_after_s > 0:
                self._paused_until = max(self._paused_until, now + permit.retry_after_s)
        self.wake()

    def wake(self) -> None:
        """Start every queued call that may start now, in order; set a timer for the first that may not."""
        now = self._clock()
        self._account(now)
        self._held_by = None
        while self._waiters:
            head = self._waiters[0]
            if head.future.done():  # cancelled while queued
                heapq.heappop(self._waiters)
                continue
            held_by, wait = self._hold(now, head.tokens)
            if held_by is not None:
                self._held_by = held_by
                if math.isfinite(wait):
                    self._wake_in(wait)
                break
            heapq.heappop(self._waiters)
            head.future.set_result(self._start(now, head.tokens, head.ticket))

    def _hold(self, now: float, tokens: int) -> tuple[HeldBy | None, float]:
        """What keeps a call of ``tokens`` from starting now, and for how long (infinite: until a slot is
        released); ``(None, 0)`` when it may start.
        """
        if now < self._paused_until:
            return "pause", self._paused_until - now
        if self._in_flight >= self._adaptive.limit:
            held: HeldBy = "limit" if self._adaptive.limit < self._adaptive.maximum else "max_concurrency"
            return held, math.inf
        if self._requests is not None and (wait := self._requests.ready_in(now)) > 0:
            return "requests_per_minute", wait
        if self._tokens is not None and (wait := self._tokens.ready_in(now)) > 0:
            return "tokens_per_minute", wait
        return None, 0.0

    def _start(self, now: float, tokens: int, ticket: int) -> Permit:
        self._in_flight += 1
        if self._requests is not None:
            self._requests.take(now, 1)
        if self._tokens is not None:
            self._tokens.take(now, tokens)
        return Permit(self._adaptive.epoch, tokens, ticket)

    def _wake_in(self, seconds: float) -> None:
        try:
            loop = asyncio.get_running_loop()
        except RuntimeError:  # driven by hand (a test with a fake clock): it calls wake() itself
            return
        at = loop.time() + seconds
        if self._timer is not None and not self._timer.cancelled() and self._timer_at <= at:
            return  # an earlier wake-up is already set; it sets the next
        if self._timer is not None:
            self._timer.cancel()
        self._timer, self._timer_at = loop.call_at(at, self._on_timer), at

    def _on_timer(self) -> None:
        self._timer, self._timer_at = None, math.inf
        self.wake()

    def _account(self, now: float) -> None:
        """Add the time since the last event to the throttled time when a call was held by rate limiting."""
        since, self._accounted_at = self._accounted_at, now
        if now <= since or self._held_by not in THROTTLING:
            return
        until = min(now, self._paused_until) if self._held_by == "pause" else now
        self._throttled_s += max(0.0, until - since)

    # -- what it is doing ------------------------------------------------------------------------------
    def state(self) -> LimiterState:
        """A snapshot of the limiter now."""
        now = self._clock()
        self._account(now)
        return LimiterState(
            endpoint=self.endpoint,
            roles=tuple(self.roles),
            limit=self._adaptive.limit,
            max_concurrency=self._adaptive.maximum,
            in_flight=self._in_flight,
            waiting=sum(not waiter.future.done() for waiter in self._waiters),
            paused_s=max(0.0, self._paused_until - now),
            held_by=self._held_by,
            rate_limited=self._rate_limited,
            cuts=self._adaptive.cuts,
            throttled_s=self._throttled_s,
            requests_per_minute=self._requests.per_minute if self._requests is not None else None,
            tokens_per_minute=self._tokens.per_minute if self._tokens is not None else None,
        )
