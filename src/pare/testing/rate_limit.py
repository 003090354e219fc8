"""A responder wrapper that rate limits like a provider: a token bucket, 429 with Retry-After beyond it.

.. code-block:: python

    from pare.testing import ChatServer, RateLimited, proactive_play

    limited = RateLimited(proactive_play(), per_second=20, latency_s=0.2)
    with ChatServer(limited) as server:
        ...  # at most 20 requests a second are answered; the rest get 429 at once
    print(limited.answered, limited.rejected)
"""

from __future__ import annotations

import math
import threading
import time
from collections.abc import Callable
from typing import Any

from pare.testing.chat_server import Reply, Responder, failure


class RateLimited:
    """Answers through ``responder`` at most ``per_second`` requests a second (a token bucket holding at
    most ``burst`` requests, full at the start); a request beyond that is answered 429 at once, with
    ``retry-after-ms`` and ``Retry-After`` saying when the next request would be let through. An answered
    request takes ``latency_s`` seconds (the model's time; a 429 takes none, as with real providers).

    Thread-safe (the server answers each request in its own thread); counts what it answered and refused.
    """

    def __init__(
        self,
        responder: Responder,
        per_second: float,
        *,
        burst: float = 1.0,
        latency_s: float = 0.0,
        clock: Callable[[], float] = time.monotonic,
        sleep: Callable[[float], None] = time.sleep,
    ) -> None:
        if per_second <= 0 or burst < 1:
            raise ValueError(f"per_second must be above 0 and burst at least 1 (got {per_second}, {burst})")
        self.responder = responder
        self.per_second = per_second
        self.burst = burst
        self.latency_s = latency_s
        self._clock = clock
        self._sleep = sleep
        self._lock = threading.Lock()
        self._tokens = burst
        self._filled_at = clock()
        self.answered = 0
        """Requests let through (and answered by the wrapped responder)."""
        self.rejected = 0
        """Requests answered 429."""
        self.first_request_at: float | None = None
        self.last_answer_at: float | None = None

    def __call__(self, body: dict[str, Any]) -> Reply:
        """Let the request through when the bucket holds a token; otherwise answer 429."""
        with self._lock:
            now = self._clock()
            if self.first_request_at is None:
                self.first_request_at = now
            self._tokens = min(self.burst, self._tokens + (now - self._filled_at) * self.per_second)
            self._filled_at = now
            if self._tokens < 1:
                self.rejected += 1
                wait = (1 - self._tokens) / self.per_second
                return failure(
                    429,
                    f"Rate limit reached: {self.per_second:g} requests per second. Try again in "
                    f"{wait:.3f} s.",
                    type_="requests",
                    code="rate_limit_exceeded",
                    headers={
                        "retry-after-ms": str(math.ceil(wait * 1000)),
                        "retry-after": str(math.ceil(wait)),
                    },
                )
            self._tokens -= 1
        if self.latency_s > 0:
            self._sleep(self.latency_s)
        reply = self.responder(body)
        with self._lock:
            self.answered += 1
            self.last_answer_at = self._clock()
        return reply
