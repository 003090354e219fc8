"""Batch runner timings: how close concurrent model-backed episodes come to the ideal, and oracle throughput.

    python benchmarks/runner.py [--episodes 100] [--concurrency 32] [--delay 0.5] [--calls 300] [--parts abc]

(a) A local ChatServer answers every model call with ``proactive_play()`` after a fixed delay (a stand-in
for a model's latency). ``run_benchmark`` plays about ``--episodes`` episodes (library scenarios x runs,
chosen so the count is exact when it can be) with the user and the assistant pointed at it, into a
temporary folder, with the default cache (read_write) and ``--concurrency`` episodes in flight. The ideal
wall time is the larger of: every call's delay spread over the concurrency (total calls x delay /
concurrency), and the longest episode's chain of calls (its calls x delay: an episode's calls are
sequential). Efficiency is ideal / measured. Also printed: the makespans of two zero-overhead schedules on
``--concurrency`` slots, each episode taking its calls x delay: the plan's order (run-major), and longest
first with every length known in advance (the runner learns lengths from each scenario's first finished
run and plays the longest expected first), and the mean latency of a call as the client measured it (the
delay plus HTTP, JSON and event-loop waiting). The server runs in this process (its threads share the GIL
with the runner). The OpenAI SDK is imported before timing (a one-off cost).

(b) The oracle (no models) over the whole library, with 1 and with 4 runs per scenario: episodes/s,
including opening the store and writing every record and trajectory.

(c) The cost of one model call besides the model, against a ChatServer that answers at once
(``--calls`` sequential calls of a prompt the size of an observe-mode prompt, each distinct): a plain
HTTP POST to the server (httpx: the server's own cost), ``ModelClient.complete`` without a cache,
with a ``read_write`` cache where every call misses (the call plus storing it), and with a ``replay``
cache where every call hits (the cache alone: keying the request, reading and decoding the answer).
Medians per call, in ms.

Prints numbers only; no assertion.
"""

from __future__ import annotations

import argparse
import asyncio
import heapq
import statistics
import tempfile
import time
from pathlib import Path
from typing import Any

import httpx

from pare.agents.models.cache import ModelCallCache
from pare.agents.models.client import ModelClient
from pare.agents.models.config import ModelConfig
from pare.agents.models.types import ChatMessage
from pare.bench.runconfig import build_config
from pare.bench.runner import run_benchmark
from pare.results.run_folder import load_run
from pare.scenarios import load_scenarios
from pare.testing import ChatServer, proactive_play
from pare.testing.chat_server import Reply, completion


def plan_shape(episodes: int, available: int) -> tuple[int, int]:
    """(scenarios, runs): exactly ``episodes`` with as many scenarios as possible, when that is at least
    half the library; otherwise the whole library with enough runs to pass ``episodes``.
    """
    for scenarios in range(min(episodes, available), 0, -1):
        if episodes % scenarios == 0 and scenarios * 2 >= min(episodes, available):
            return scenarios, episodes // scenarios
    return available, -(-episodes // available)


def model_run(episodes: int, concurrency: int, delay: float) -> None:
    library = sorted(scenario.id for scenario in load_scenarios())
    scenarios, runs = plan_shape(episodes, len(library))
    import openai  # noqa: F401 - the SDK import (about a second) is not the runner's cost

    with ChatServer(proactive_play(), delay_s=delay) as server, tempfile.TemporaryDirectory() as folder:
        model = {
            "model": "pare-bench-model",
            "api_base": server.base_url,
            "api_key_env": None,
            "max_concurrency": concurrency,
            "prices": {"input": 1.0, "output": 2.0},
        }
        config = build_config(
            {
                "scenarios": {"ids": library[:scenarios]},
                "runs": runs,
                "concurrency": concurrency,
                "models": {"user": model, "assistant": model},
                "output": str(Path(folder) / "run"),
            }
        )
        began = time.perf_counter()
        summary = run_benchmark(config)
        wall = time.perf_counter() - began
        records = load_run(summary.path).records
        chains = [sum(usage.calls for usage in record.usage.values()) for record in records]
        latency = sum(usage.latency_s for record in records for usage in record.usage.values())
        fifo = schedule_bound(
            summary.path, runs, library[:scenarios], concurrency, delay, longest_first=False
        )
        lpt = schedule_bound(summary.path, runs, library[:scenarios], concurrency, delay, longest_first=True)
        calls = server.request_count
        peak = server.max_in_flight
    spread = calls * delay / concurrency
    longest = max(chains, default=0)
    chain = longest * delay
    ideal = max(spread, chain)
    episodes = max(len(records), 1)
    shape = f"{scenarios} scenarios x {runs} runs, concurrency {concurrency}, delay {delay} s"
    print(f"(a) model-backed run: {shape}")
    print(f"  episodes: {len(records)} ({summary.complete} complete, {len(summary.failed)} failed)")
    print(f"  model calls: {calls} (per episode: mean {calls / episodes:.1f}, max {longest})")
    print(f"  most calls in flight at once: {peak}")
    print(f"  wall time: {wall:.2f} s")
    print(
        f"  ideal wall time: {ideal:.2f} s = max(calls x delay / concurrency = {spread:.2f} s, "
        f"longest episode's chain {longest} x delay = {chain:.2f} s)"
    )
    print(f"  efficiency (ideal / wall): {ideal / wall:.1%}")
    print(
        f"  zero-overhead schedules on {concurrency} slots: plan order {fifo:.2f} s, "
        f"longest first with lengths known in advance {lpt:.2f} s (wall / the latter: {wall / lpt:.2f})"
    )
    mean_latency = latency / max(calls, 1) * 1000
    print(f"  mean call latency seen by the client: {mean_latency:.0f} ms (delay {delay * 1000:.0f} ms)")


def schedule_bound(
    run_dir: Path, runs: int, scenario_ids: list[str], slots: int, delay: float, *, longest_first: bool
) -> float:
    """The makespan of starting the episodes greedily on ``slots``, each taking its own calls x ``delay``:
    in the plan's order (run-major), or longest first with every length known in advance (what the
    runner's longest-first queue approaches once it has seen one run of each scenario).
    """
    by_key = {record.key: record for record in load_run(run_dir).records}
    lengths = []
    for run in range(1, runs + 1):
        for scenario_id in sorted(scenario_ids):
            record = by_key.get((scenario_id, run))
            lengths.append(sum(usage.calls for usage in record.usage.values()) * delay if record else 0.0)
    if longest_first:
        lengths.sort(reverse=True)
    free = [0.0] * slots
    for length in lengths:
        heapq.heappush(free, heapq.heappop(free) + length)
    return max(free)


def oracle_run(runs: int) -> None:
    with tempfile.TemporaryDirectory() as folder:
        config = build_config({"runs": runs, "output": str(Path(folder) / "run")})
        began = time.perf_counter()
        summary = run_benchmark(config)
        wall = time.perf_counter() - began
    episodes = len(summary.records)
    print(f"  runs {runs}: {episodes} episodes in {wall:.2f} s = {episodes / wall:.1f} episodes/s")


def prompt(index: int) -> list[ChatMessage]:
    """A conversation the size of an observe-mode prompt (about 24,000 characters), distinct per index."""
    system = "You are a proactive assistant on the user's phone. " * 480
    return [
        ChatMessage(role="system", content=system),
        ChatMessage(role="user", content=f"Observation {index}: the user opened the email app."),
    ]


def call_costs(calls: int) -> None:
    def answer(body: dict[str, Any]) -> Reply:
        return completion('Thought: nothing to do.\n\nAction:\n{"action": "wait", "action_input": {}}')

    def report(label: str, seconds: list[float]) -> None:
        print(f"  {label:56s} {statistics.median(seconds) * 1000:6.2f} ms")

    with ChatServer(answer) as server, tempfile.TemporaryDirectory() as folder:
        with httpx.Client(base_url=server.base_url) as http:
            body = {"model": "m", "messages": [m.to_openai() for m in prompt(0)]}
            http.post("/chat/completions", json=body)  # the connection is opened outside the timing
            times = []
            for _ in range(calls):
                began = time.perf_counter()
                http.post("/chat/completions", json=body).raise_for_status()
                times.append(time.perf_counter() - began)
        report("HTTP POST to the server (httpx)", times)
        config = ModelConfig(model="m", api_base=server.base_url, api_key_env=None)

        async def timed(client: ModelClient, first: int) -> list[float]:
            await client.complete(prompt(-1 - first))  # the SDK and the connection are set up untimed
            times = []
            for index in range(first, first + calls):
                began = time.perf_counter()
                await client.complete(prompt(index))
                times.append(time.perf_counter() - began)
            await client.aclose()
            return times

        report("ModelClient, no cache", asyncio.run(timed(ModelClient(config, "observe"), 0)))
        path = Path(folder) / "calls.sqlite"
        writing = ModelCallCache(path, "read_write")
        report(
            "ModelClient, read_write cache, every call a miss",
            asyncio.run(timed(ModelClient(config, "observe", writing), calls)),
        )
        writing.close()
        replaying = ModelCallCache(path, "replay")
        hits = asyncio.run(timed(ModelClient(config, "observe", replaying), calls))
        replaying.close()
        report("ModelClient, replay cache, every call a hit (the cache)", hits)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--episodes", type=int, default=100)
    parser.add_argument("--concurrency", type=int, default=32)
    parser.add_argument("--delay", type=float, default=0.5, help="seconds the server takes per answer")
    parser.add_argument("--calls", type=int, default=300, help="sequential calls timed in (c)")
    parser.add_argument("--parts", default="abc", help="which parts to run, e.g. 'c' or 'bc' (default all)")
    options = parser.parse_args()

    if "a" in options.parts:
        model_run(options.episodes, options.concurrency, options.delay)
    if "b" in options.parts:
        print("(b) oracle run of the whole library (no models):")
        for runs in (1, 4):
            oracle_run(runs)
    if "c" in options.parts:
        print(f"(c) one model call besides the model, answered at once ({options.calls} calls, median):")
        call_costs(options.calls)


if __name__ == "__main__":
    main()
