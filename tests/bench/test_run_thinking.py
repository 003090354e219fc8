"""``pare run`` with thinking models: local chat servers that play the game as :func:`proactive_play` does,
each answer preceded by reasoning that drafts an ``Action:`` of its own (:func:`pare.testing.thinking`).

The run must go as it goes without thinking, the trajectories must hold the reasoning, and a replay from
the cache must reproduce them.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest

from pare.bench.store import CACHE_FILE
from pare.cli import main
from pare.results.run_folder import load_run
from pare.results.trajectory import Trajectory, parse_trajectory
from pare.testing import ChatServer, proactive_play, thinking
from pare.testing.chat_server import THINKING
from tests.bench.test_run_models import KEY, KEY_VARIABLE, Servers, command, trajectories


def steps_without_usage(trajectory: Trajectory) -> list[dict[str, Any]]:
    """Each step's actor, action and result, without the model's text and usage."""
    kept = {"turn", "actor", "mode", "ok", "observation", "log_index"}
    return [
        {**step.model_dump(include=kept), "tool": step.action.tool, "args": step.action.args}
        for step in trajectory.steps
    ]


@pytest.mark.parametrize("style", ["inline", "field"])
def test_a_run_with_thinking_models_goes_as_without_and_keeps_the_reasoning(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, style: str
) -> None:
    monkeypatch.setenv(KEY_VARIABLE, KEY)
    plain, thought, replayed = tmp_path / "plain", tmp_path / "thinking", tmp_path / "replay"
    with ChatServer(proactive_play()) as user, ChatServer(proactive_play()) as assistant:
        assert main(command(plain, Servers(user, assistant), runs=1)) == 0
    responder = thinking(proactive_play(), style=style)  # type: ignore[arg-type]
    with ChatServer(responder) as user, ChatServer(responder) as assistant:
        servers = Servers(user, assistant)
        assert main(command(thought, servers, runs=1)) == 0
        replay = ["--cache", "replay", "--set", f"cache_path={thought / CACHE_FILE}"]
        requests = servers.requests
        assert main(command(replayed, servers, *replay, runs=1)) == 0
        assert servers.requests == requests  # the replay called no model
        sent = [m for body in user.requests + assistant.requests for m in body["messages"]]
    assert not [m for m in sent if m["role"] == "assistant" and "draft_from_thinking" in m["content"]]

    recorded, without = trajectories(thought), trajectories(plain)
    assert recorded.keys() == without.keys() and recorded
    assert trajectories(replayed) == recorded
    for name, data in recorded.items():
        trajectory, baseline = parse_trajectory(data, name), parse_trajectory(without[name], name)
        assert steps_without_usage(trajectory) == steps_without_usage(baseline)
        assert trajectory.outcome == baseline.outcome
        model_actions = [s.action for s in trajectory.steps if s.action.usage is not None]
        assert model_actions
        for action in model_actions:
            assert action.reasoning == THINKING
            assert action.usage is not None and not action.usage.format_errors
    for record in load_run(thought).records:
        assert record.complete and record.proposals
        assert {p.decision for p in record.proposals} == {"accept"}
