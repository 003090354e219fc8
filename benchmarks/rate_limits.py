"""Rate limits at scale: how much of a provider's allowed rate a model-backed run gets, and what it loses.

    python benchmarks/rate_limits.py [--rate 20] [--latency 0.25] [--episodes 60] [--concurrency 48]
                                     [--max-concurrency 32] [--requests-per-minute N] [--runs 1]

A local ChatServer answers as a rate-limiting provider would (``pare.testing.RateLimited``): at most
``--rate`` requests a second (a token bucket of one request, so no burst), each answered by
``proactive_play()`` after ``--latency`` seconds; a request beyond the rate is answered 429 at once, with
``retry-after-ms`` / ``Retry-After`` saying when the next one would pass. ``run_benchmark`` plays
``--episodes`` episodes (library scenarios x runs) with the user and the assistant both pointed at it (one
endpoint, one limiter), ``--concurrency`` episodes in flight and the endpoint's ``max_concurrency`` at
``--max-concurrency``: above what the rate allows (rate x latency calls in flight), so the run meets the
limit and must adapt. The default retry settings are kept (5 retries, exponential backoff from 1 s).
``--requests-per-minute`` also sets the models' request budget (the client then paces itself).

Printed: the allowed rate; the achieved rate of successful requests (answered requests / the time from
the first request to the last answer) and its share of the allowed rate, and the share of the requests
the server would have answered in that time (the rate times the time, plus the burst its full bucket
allows at the start); the 429s the server sent; the
episodes completed, failed (missing coverage) and missing (planned but not stored); the endpoint's limiter
at the end (concurrency, cuts, time calls were held back by rate limiting); the wall time. The target is
at least 90 % of the allowed rate with no episode failed or missing. Each episode's calls are sequential,
so the last seconds of a run, when fewer episodes are left than the rate needs, lower the share a little.

A server with no burst at all (``--burst 1``: any two requests closer than 1 / rate apart, refused) is met
less well by the adaptive limit alone, since calls that end close together start their successors close
together; a request budget a little below the rate (``--requests-per-minute``) paces them instead.

Prints numbers only; no assertion.
"""

from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path

from pare.bench.runconfig import build_config
from pare.bench.runner import run_benchmark
from pare.bench.throttling import endpoint_name
from pare.results.run_folder import load_run
from pare.scenarios import load_scenarios
from pare.testing import ChatServer, RateLimited, proactive_play


def rate_limited_run(options: argparse.Namespace) -> None:
    library = sorted(scenario.id for scenario in load_scenarios())
    runs = options.runs
    scenarios = min(len(library), -(-options.episodes // runs))
    import openai  # noqa: F401 - the SDK import (about a second) is not the run's cost

    burst = options.burst if options.burst is not None else options.rate
    limited = RateLimited(proactive_play(), options.rate, burst=burst, latency_s=options.latency)
    with ChatServer(limited) as server, tempfile.TemporaryDirectory() as folder:
        model: dict[str, object] = {
            "model": "pare-rate-limited-model",
            "api_base": server.base_url,
            "api_key_env": None,
            "max_concurrency": options.max_concurrency,
            "requests_per_minute": options.requests_per_minute,
            "prices": {"input": 1.0, "output": 2.0},  # no price table to load (litellm, seconds)
        }
        config = build_config(
            {
                "scenarios": {"ids": library[:scenarios]},
                "runs": runs,
                "concurrency": options.concurrency,
                "models": {"user": model, "assistant": model},
                "output": str(Path(folder) / "run"),
            }
        )
        began = time.perf_counter()
        summary = run_benchmark(config)
        wall = time.perf_counter() - began
        stored = load_run(summary.path).records
    planned = summary.planned
    complete = sum(record.complete for record in stored)
    failed = sum(not record.complete for record in stored)
    first, last = limited.first_request_at, limited.last_answer_at
    span = (last - first) if first is not None and last is not None and last > first else float("nan")
    achieved = limited.answered / span
    budget = f", requests_per_minute {options.requests_per_minute}" if options.requests_per_minute else ""
    print(
        f"rate-limited run: {scenarios} scenarios x {runs} runs, {options.concurrency} episodes in flight, "
        f"max_concurrency {options.max_concurrency}{budget}, latency {options.latency} s"
    )
    print(
        f"  allowed rate: {options.rate:g} requests/s, bursts of {burst:g} (at most "
        f"{options.rate * options.latency:.1f} in flight)"
    )
    print(
        f"  achieved: {limited.answered} successful requests in {span:.2f} s = {achieved:.2f} requests/s "
        f"= {achieved / options.rate:.1%} of the allowed rate"
    )
    allowed = options.rate * span + burst  # the bucket starts full: its burst is allowed on top
    print(
        f"  share of the requests the server would answer in that time (rate x time + burst): "
        f"{limited.answered / allowed:.1%}"
    )
    share = limited.rejected / max(limited.answered, 1)
    print(f"  429s received: {limited.rejected} ({share:.1%} of the successful requests)")
    missing = planned - len(stored)
    print(f"  episodes: {planned} planned, {complete} completed, {failed} failed, {missing} missing")
    for state in summary.throttling:
        print(
            f"  limiter ({endpoint_name(state)}): concurrency {state.limit}/{state.max_concurrency} at the "
            f"end, cut {state.cuts} times, {state.rate_limited} 429s seen, calls held back by rate limiting "
            f"{state.throttled_s:.1f} s"
        )
    print(f"  wall time: {wall:.2f} s")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rate", type=float, default=20.0, help="requests per second the server allows")
    parser.add_argument(
        "--burst", type=float, default=None, help="requests the server's bucket holds (default: --rate)"
    )
    parser.add_argument("--latency", type=float, default=0.25, help="seconds an answered request takes")
    parser.add_argument("--episodes", type=int, default=60)
    parser.add_argument("--runs", type=int, default=1, help="runs per scenario")
    parser.add_argument("--concurrency", type=int, default=48, help="episodes in flight")
    parser.add_argument("--max-concurrency", type=int, default=32, help="the endpoint's max_concurrency")
    parser.add_argument("--requests-per-minute", type=int, default=None, help="the models' request budget")
    rate_limited_run(parser.parse_args())


if __name__ == "__main__":
    main()
