"""A run against a provider that rate limits: every episode completes, and the run says it was throttled."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import pytest

from pare.agents.models.limiter import LimiterState
from pare.bench.runner import NoProgress
from pare.cli import main
from pare.results.run_folder import load_run
from pare.testing import ChatServer, RateLimited, proactive_play
from pare.testing.chat_server import completion

SCENARIOS = ("dentist_moves_checkup", "five_a_side_kickoff_moved")


class FakeClock:
    def __init__(self) -> None:
        self.now = 0.0

    def __call__(self) -> float:
        return self.now


def test_the_rate_limited_responder_lets_through_its_rate_and_says_when_to_come_back() -> None:
    clock = FakeClock()
    limited = RateLimited(lambda body: completion("ok"), per_second=4, burst=2, clock=clock)
    statuses = [limited({}).status for _ in range(3)]
    assert statuses == [200, 200, 429]  # the bucket holds two
    refused = limited({})
    assert refused.headers["retry-after-ms"] == "250" and refused.headers["retry-after"] == "1"
    clock.now = 0.25
    assert limited({}).status == 200 and limited({}).status == 429
    assert (limited.answered, limited.rejected) == (3, 3)


class RecordingProgress(NoProgress):
    def __init__(self) -> None:
        self.seen: list[LimiterState] = []

    def throttling(self, endpoints: Sequence[LimiterState]) -> None:
        self.seen.extend(endpoints)


def test_a_run_against_a_rate_limiting_provider_completes_every_episode(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    limited = RateLimited(proactive_play(), per_second=15, burst=2, latency_s=0.02)
    out = tmp_path / "run"
    with ChatServer(limited) as server:
        argv = ["run", "--output", str(out), "--no-progress", "--runs", "3", "--concurrency", "6"]
        for scenario in SCENARIOS:
            argv += ["-s", scenario]
        argv += ["--user-model", "u", "--user-endpoint", server.base_url]
        argv += ["--assistant-model", "a", "--assistant-endpoint", server.base_url]
        for role in ("user", "assistant"):
            for setting in (
                "api_key_env=null",
                "retry_initial_s=0.01",
                "retry_max_s=0.2",
                "max_retries=10",
                "max_concurrency=6",
                "prices={input: 1.0, output: 2.0}",
            ):
                argv += ["--set", f"models.{role}.{setting}"]
        assert main(argv) == 0

    records = load_run(out).records
    assert len(records) == len(SCENARIOS) * 3
    assert all(record.complete for record in records)
    assert limited.rejected > 0  # the provider did rate limit the run
    printed = capsys.readouterr().out
    # the judge (the user's model) calls the same endpoint, under the same limiter
    assert f"throttling: user+assistant+judge endpoint: {limited.rejected} rate-limit answer" in printed


def test_the_runner_reports_the_endpoints_limiter_while_models_are_called(tmp_path: Path) -> None:
    from pare.bench.runconfig import build_config
    from pare.bench.runner import run_benchmark

    limited = RateLimited(proactive_play(), per_second=40, burst=40, latency_s=0.05)
    progress = RecordingProgress()
    with ChatServer(limited) as server:
        model = {
            "model": "m",
            "api_base": server.base_url,
            "api_key_env": None,
            "requests_per_minute": 6000,
            "prices": {"input": 1.0, "output": 2.0},
        }
        config = build_config(
            {
                "scenarios": {"ids": list(SCENARIOS)},
                "runs": 2,
                "models": {"user": model, "observe": model, "execute": model},
                "output": str(tmp_path / "run"),
            }
        )
        summary = run_benchmark(config, progress=progress)
    assert summary.complete == len(SCENARIOS) * 2
    (state,) = summary.throttling  # one endpoint, one limiter for every role (the judge is the user's model)
    assert state.roles == ("user", "observe", "execute", "judge") and state.requests_per_minute == 6000
    assert (state.in_flight, state.waiting) == (0, 0)
    assert progress.seen and {seen.roles for seen in progress.seen} == {state.roles}
