"""The judge in a model-backed run: it calls through the run's shared client, so its calls wait for the same
per-endpoint limit as the user's and the assistant's, and what it answered is kept in the trajectory.

One :class:`~pare.testing.ChatServer` on 127.0.0.1 serves every role: :func:`~pare.testing.proactive_play`
for the user and the assistant, a fixed answer for the judge (told apart by its system prompt).
"""

from __future__ import annotations

import json
import threading
from pathlib import Path
from typing import Any

import pytest

from pare.agents.judge import JUDGE_PROMPT
from pare.bench.runconfig import build_config
from pare.bench.runner import EpisodeOutput, plan_episodes, play_apart, select_scenarios
from pare.bench.store import CACHE_FILE
from pare.cli import main
from pare.results.run_folder import load_run
from pare.testing import ChatServer, Reply, completion, proactive_play
from tests.scenarios.helpers import base, to_yaml

KEY_VARIABLE = "PARE_TEST_API_KEY"
LIMIT = 2
CHECK_ANSWER = "NO\nIt does not name Ann's day."
EVENT_ANSWER = "YES\nIt offers to take care of it."
EVENT_CRITERION = "offers to take care of what came in"


@pytest.fixture(autouse=True)
def api_key(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv(KEY_VARIABLE, "sk-pare-test")


def judged_scenario() -> dict[str, Any]:
    """The small scenario with three judge checks on the assistant's messages (its proposal and its
    report, each judged alone: a refused text makes the judge read the next) and a reactive event whose
    trigger the judge reads.
    """
    data = base()
    message = {"actor": "assistant", "tool": "agent_ui__send_message_to_user"}
    data["goals"][0]["checks"] = [
        {
            "judge": {
                "criterion": criterion,
                "action": message,
                "field": "content",
                "fallback": {"contains": "thursday"},
            }
        }
        for criterion in ("says Thursday works", "names Ann", "is polite to Ann")
    ]
    data["events"].append(
        {
            "id": "ann_thanks",
            "when": message,
            "if_args": {"content": {"contains": "no rule text matches this"}},
            "judge": {"criterion": EVENT_CRITERION},
            "tool": "email__receive_email",
            "args": {
                "email_id": "e_thanks",
                "sender": "ann@x.example",
                "subject": "Thanks",
                "content": "Thanks!",
            },
        }
    )
    return data


class Responder:
    """Plays the user and the assistant, answers the judge, and notes how many requests were in flight at
    the server when each judge request arrived.
    """

    def __init__(self, server: ChatServer | None = None) -> None:
        self.server = server
        self.play = proactive_play()
        self.lock = threading.Lock()
        self.judged_in_flight: list[int] = []

    def __call__(self, body: dict[str, Any]) -> Reply:
        if body["messages"][0]["content"] != JUDGE_PROMPT:
            return self.play(body)
        with self.lock:
            self.judged_in_flight.append(self.server.in_flight if self.server is not None else 0)
        question = body["messages"][-1]["content"]
        return completion(EVENT_ANSWER if EVENT_CRITERION in question else CHECK_ANSWER)


def command(output: Path, scenarios: Path, server: ChatServer, *extra: str) -> list[str]:
    """``pare run`` of the scenarios in ``scenarios`` with every role at ``server``."""
    path = scenarios / "tiny_reply.yaml"
    path.write_text(to_yaml(judged_scenario()))
    argv = ["run", "--output", str(output), "--no-progress", "--scenario-path", str(path)]
    for role in ("user", "assistant", "judge"):
        argv += [f"--{role}-model", f"pare-{role}", f"--{role}-endpoint", server.base_url]
        argv += ["--set", f"models.{role}.api_key_env={KEY_VARIABLE}"]
    return argv + list(extra)


def test_judge_calls_share_the_endpoint_limit_and_their_answers_are_kept(tmp_path: Path) -> None:
    responder = Responder()
    with ChatServer(responder, delay_s=0.03) as server:
        responder.server = server
        # the strictest role's limit holds for every role at the endpoint
        limit = ["--set", f"models.judge.max_concurrency={LIMIT}"]
        argv = command(tmp_path / "run", tmp_path, server, "--runs", "4", "--concurrency", "4", *limit)
        assert main(argv) == 0
        most_in_flight = server.max_in_flight

    # per episode: the event's reading of the proposal, then each check's two texts, both refused
    assert len(responder.judged_in_flight) == 4 * (1 + 3 * 2)
    assert most_in_flight <= LIMIT
    assert max(responder.judged_in_flight) == LIMIT  # judge calls overlapped with others, and were counted

    run = load_run(tmp_path / "run")
    assert [record.status for record in run.records] == ["complete"] * 4
    for record in run.records:
        assert record.trajectory is not None
        trajectory = json.loads((tmp_path / "run" / record.trajectory).read_text())
        fired = [entry["event_id"] for entry in trajectory["log"] if entry["actor"] == "env"]
        assert "ann_thanks" in fired  # the judge read the proposal as an offer, though the rule would not
        messages = [entry["index"] for entry in trajectory["log"] if entry["tool"] == "send_message_to_user"]
        assert len(messages) == 2  # the proposal and the report
        checks = trajectory["outcome"]["goals"][0]["checks"]
        assert len(checks) == 3
        for check in checks:
            assert check["detail"].endswith(" | the judge: It does not name Ann's day.")
            judged = check["judged"]
            verdicts = [text["verdict"] for text in judged]
            assert [verdict["answer"] for verdict in verdicts] == [CHECK_ANSWER, CHECK_ANSWER]
            assert {(verdict["passed"], verdict["reason"], verdict["model"]) for verdict in verdicts} == {
                (False, "It does not name Ann's day.", "pare-judge")
            }
            assert [text["entries"] for text in judged] == [[index] for index in messages]


def test_a_replay_gives_the_judges_answers_without_calling(tmp_path: Path) -> None:
    with ChatServer(Responder()) as server:
        first, second = tmp_path / "first", tmp_path / "replay"
        assert main(command(first, tmp_path, server, "--runs", "2")) == 0
        calls = server.request_count
        cache = ["--cache", "replay", "--set", f"cache_path={first / CACHE_FILE}"]
        assert main(command(second, tmp_path, server, "--runs", "2", *cache)) == 0
        assert server.request_count == calls
    recorded = sorted((first / "trajectories").rglob("*.json"))
    assert len(recorded) == 2
    for path in recorded:
        assert (second / path.relative_to(first)).read_bytes() == path.read_bytes()
    for record in load_run(second).records:
        assert record.usage["judge"].cached_calls == record.usage["judge"].calls == 1 + 3 * 2


def test_an_episode_played_apart_asks_its_judge_and_keeps_the_answers(tmp_path: Path) -> None:
    """What a Ray task runs (:func:`~pare.bench.runner.play_apart`): its own clients, the judge's too."""
    path = tmp_path / "tiny_reply.yaml"
    path.write_text(to_yaml(judged_scenario()))
    responder = Responder()
    with ChatServer(responder) as server:
        models = {
            role: {"model": f"pare-{role}", "api_base": server.base_url, "api_key_env": None}
            for role in ("user", "observe", "execute", "judge")
        }
        data = {"scenarios": {"paths": [str(path)]}, "runs": 1, "models": models, "output": str(tmp_path)}
        config = build_config(data)
        (plan,) = plan_episodes(config, select_scenarios(config))
        status, output = play_apart(plan, config, tmp_path / "run")
    assert status == "ok" and isinstance(output, EpisodeOutput) and output.trajectory is not None
    assert len(responder.judged_in_flight) == 1 + 3 * 2
    checks = json.loads(output.trajectory)["outcome"]["goals"][0]["checks"]
    assert [[text["verdict"]["answer"] for text in check["judged"]] for check in checks] == [
        [CHECK_ANSWER, CHECK_ANSWER]
    ] * 3
