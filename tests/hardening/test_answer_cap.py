"""Answers have a bound: one longer than its role's ``max_answer_chars`` (64k characters by default) is
cut to it in the records, the cache and the conversation, and is a format error for the model, so a
runaway model cannot make one episode write gigabytes (each later request repeats every earlier answer).
"""

from __future__ import annotations

import json
import sqlite3
from pathlib import Path
from typing import Any

import pytest

from pare.agents.models import ModelConfig
from pare.agents.models.config import DEFAULT_MAX_ANSWER_CHARS
from pare.cli import main
from pare.errors import UserInputError
from pare.results.trajectory import read_trajectory
from pare.testing import ChatServer, Reply, completion, conversation_role, proactive_play
from tests.hardening.conftest import KEY_VARIABLE

RUNAWAY = 1_000_000


def runaway_then_play(every: int) -> tuple[Any, dict[str, int]]:
    """A server whose observe-mode assistant answers 1 MB of text on every ``every``-th call."""
    play = proactive_play()
    seen = {"observe": 0, "huge": 0}

    def answer(body: dict[str, Any]) -> Reply:
        if conversation_role(body.get("messages") or []) == "observe":
            seen["observe"] += 1
            if seen["observe"] % every == 1:
                seen["huge"] += 1
                return completion("Thought: " + "blah " * (RUNAWAY // 5))
        return play(body)

    return answer, seen


def run(output: Path, scenario: Path, server: ChatServer, *extra: str) -> int:
    argv = ["run", "--output", str(output), "--no-progress", "--runs", "1", "--scenario-path", str(scenario)]
    argv += ["--assistant-model", "a", "--assistant-endpoint", server.base_url]
    argv += ["--user-model", "u", "--user-endpoint", server.base_url]
    for role in ("user", "assistant"):
        argv += ["--set", f"models.{role}.api_key_env={KEY_VARIABLE}"]
    return main([*argv, *extra])


def test_the_default_cap_is_documented_and_configurable_per_role() -> None:
    assert ModelConfig(model="m").max_answer_chars == DEFAULT_MAX_ANSWER_CHARS == 65_536
    assert ModelConfig(model="m", max_answer_chars=1000).max_answer_chars == 1000
    with pytest.raises(UserInputError, match="max_answer_chars"):
        ModelConfig.parse({"model": "m", "max_answer_chars": 0})


def test_a_runaway_answer_is_cut_and_a_format_error(tmp_path: Path, example_scenario: Path) -> None:
    responder, seen = runaway_then_play(every=2)
    with ChatServer(responder) as server:
        assert run(tmp_path / "run", example_scenario, server) == 0
    assert seen["huge"] >= 1
    record = json.loads((tmp_path / "run" / "episodes.jsonl").read_text(encoding="utf-8").splitlines()[0])
    assert sum(record["format_errors"].values()) >= seen["huge"], record["format_errors"]
    trajectory = read_trajectory(next((tmp_path / "run" / "trajectories").rglob("run-1.json")))
    errors = [e for step in trajectory.steps if step.action.usage for e in step.action.usage.format_errors]
    assert any("characters long" in error and "was cut" in error for error in errors), errors
    raws = [step.action.raw or "" for step in trajectory.steps]
    assert max(len(raw) for raw in raws) <= DEFAULT_MAX_ANSWER_CHARS
    with sqlite3.connect(tmp_path / "run" / "model_calls.sqlite") as cache:
        stored = [json.loads(row[0]) for row in cache.execute("SELECT completion FROM completions")]
    cache.close()
    cut = [answer for answer in stored if answer.get("cut_from")]
    assert len(cut) == seen["huge"] and all(len(answer["text"]) == DEFAULT_MAX_ANSWER_CHARS for answer in cut)
    assert max(len(answer["text"]) for answer in stored) <= DEFAULT_MAX_ANSWER_CHARS
    # Everything the run wrote is bounded by the cap, not by what the model wrote.
    written = sum(path.stat().st_size for path in (tmp_path / "run").rglob("*") if path.is_file())
    assert written < 20 * DEFAULT_MAX_ANSWER_CHARS * seen["huge"], written


def test_the_cap_is_set_per_role(tmp_path: Path, example_scenario: Path) -> None:
    responder, _ = runaway_then_play(every=1_000)  # only the first observe answer is long
    with ChatServer(responder) as server:
        code = run(
            tmp_path / "run", example_scenario, server, "--set", "models.assistant.max_answer_chars=2000000"
        )
    assert code == 0
    record = json.loads((tmp_path / "run" / "episodes.jsonl").read_text(encoding="utf-8").splitlines()[0])
    errors = json.dumps(record)
    assert "characters long" not in errors  # 1 MB was within this role's cap: an ordinary malformed answer
