"""The runner's less travelled paths: a judge model, a prompt beyond the context, Ctrl-C, the progress bar."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import pytest
from rich.console import Console

from pare.agents.llm import LLMAssistant
from pare.agents.models.types import ChatMessage, Completion, Usage
from pare.agents.policy import WAIT
from pare.bench import EpisodeSettings, arun_episode, build_config, run_benchmark
from pare.bench.progress import RichProgress
from pare.errors import ModelRequestError
from pare.results.records import EpisodeRecord
from pare.results.run_folder import EPISODES, load_run, read_records
from pare.scenarios import OracleUser
from pare.testing import ChatServer, Reply, completion
from tests.scenarios.helpers import base, parse, to_yaml


def test_a_judge_model_judges_free_text_checks_and_its_usage_is_recorded(tmp_path: Path) -> None:
    data = base()
    data["goals"] = [
        {
            "id": "g",
            "description": "replied yes",
            "checks": [
                {
                    "judge": {
                        "criterion": "says yes to Thursday",
                        "action": {"tool": "email__reply_to_email"},
                        "fallback": {"contains": "thursday"},
                    }
                }
            ],
        }
    ]
    folder = tmp_path / "scenarios"
    folder.mkdir()
    (folder / "tiny_reply.yaml").write_text(to_yaml(data))
    asked: list[dict[str, Any]] = []

    def judge(body: dict[str, Any]) -> Reply:
        asked.append(body)
        return completion("NO", prompt_tokens=50, completion_tokens=1)

    with ChatServer(judge) as server:
        judge_model = {
            "model": "judge-model",
            "api_base": server.base_url,
            "api_key_env": None,
            "prices": {"input": 1.0, "output": 1.0},
        }
        config = build_config(
            {
                "scenarios": {"paths": [str(folder)]},
                "runs": 2,
                "output": str(tmp_path / "run"),
                "models": {"judge": judge_model},
            }
        )
        run_benchmark(config)
    records = load_run(tmp_path / "run").records
    assert len(asked) == 2  # one judgement per episode; the runs are cached apart
    assert all(not r.success for r in records)  # the judge said no, though the fallback would pass
    usage = records[0].usage["judge"]
    assert (usage.calls, usage.prompt_tokens, usage.completion_tokens) == (1, 50, 1)
    assert usage.cost_usd == pytest.approx(51 / 1e6)


class TooLong:
    """A model whose context the conversation outgrows at its second call."""

    def __init__(self) -> None:
        self.calls = 0

    async def complete(
        self, messages: Sequence[ChatMessage], tools: Sequence[dict[str, Any]] | None = None
    ) -> Completion:
        self.calls += 1
        if self.calls > 1:
            raise ModelRequestError("prompt too long", kind="context_length")
        text = 'Action: {"action": "email__list_emails", "action_input": {}}<end_action>'
        return Completion(text=text, usage=Usage(), cost_usd=0.0, latency_s=0.0, model="m")


def test_a_prompt_beyond_the_context_ends_the_episode_and_it_is_judged() -> None:
    import asyncio

    scenario = parse(base())
    result = asyncio.run(
        arun_episode(scenario, OracleUser(scenario), LLMAssistant(TooLong()), EpisodeSettings())
    )
    assert result.ended == "context_limit"
    assert result.turns == 1 and not result.success
    assert [s.action.tool for s in result.steps if s.actor == "assistant"] == ["email__list_emails"]
    assert result.steps[0].action.tool == WAIT


def test_ctrl_c_keeps_what_finished_and_says_how_to_resume(tmp_path: Path) -> None:
    args = [
        "run",
        "--runs",
        "12",
        "--set",
        "world.noise_rate_per_minute=2",
        "--no-progress",
        "-o",
        str(tmp_path),
    ]
    process = subprocess.Popen(
        [sys.executable, "-m", "pare", *args],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        env={**os.environ, "COLUMNS": "200"},
        text=True,
    )
    episodes = tmp_path / EPISODES
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline and process.poll() is None:
        if episodes.exists() and episodes.read_text().count("\n") >= 20:
            break
        time.sleep(0.002)
    process.send_signal(signal.SIGINT)
    out, err = process.communicate(timeout=60)
    assert process.returncode == 130, (out, err)
    assert "interrupted" in out and "run the same command again to resume" in out
    assert "Traceback" not in err
    recorded = read_records(episodes)
    assert 20 <= len(recorded) < 12 * 24 and all(r.complete for r in recorded)


def _record(success: bool, cost: float | None) -> EpisodeRecord:
    usage = {
        "observe": {
            "calls": 2,
            "known_cost_usd": cost or 0.0,
            "unknown_cost_calls": 0 if cost is not None else 2,
        }
    }
    return EpisodeRecord.model_validate(
        {
            "scenario_id": "s",
            "run": 1,
            "status": "complete",
            "scenario_hash": "h",
            "seed": 1,
            "success": success,
            "usage": usage,
        }
    )


def test_progress_bar_shows_done_successes_failures_and_cost() -> None:
    console = Console(record=True, width=200, force_terminal=False)
    progress = RichProgress(console)
    progress.started(10, 4, "gpt-4o")
    progress.finished(_record(True, 0.25))
    progress.finished(_record(False, 0.5))
    progress.finished(
        EpisodeRecord.model_validate(
            {
                "scenario_id": "s",
                "run": 2,
                "status": "failed",
                "scenario_hash": "h",
                "seed": 1,
                "failure": {"kind": "provider_unavailable", "message": "503"},
            }
        )
    )
    progress.stopped()
    text = console.export_text()
    assert "resuming: 4 of 10 episodes are already recorded" in text
    assert "7/10" in text and "1 succeeded" in text and "1 failed (missing coverage)" in text
    assert "cost $0.7500" in text
    progress = RichProgress(Console(record=True, width=200))
    progress.started(2, 0, "x")
    progress.finished(_record(True, None))
    progress.stopped()
    assert "unpriced" in progress.console.export_text()
