"""Model-backed benchmark runs through ``pare run``, against local chat servers that play the game.

The user and the assistant each talk to their own :class:`~pare.testing.ChatServer` on 127.0.0.1 that
answers with :func:`~pare.testing.proactive_play` (the user waits, then accepts the one proposal; the
assistant proposes once, then reports), so the whole path runs: the CLI, the runner, the clients, the
cache, the store, resume and the failure handling.
"""

from __future__ import annotations

import json
import socket
import urllib.error
import urllib.request
from collections import Counter
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pytest

import pare.bench.runner as runner
from pare.agents.actions import parse_action
from pare.agents.policy import Task
from pare.agents.prompts import execute_system_prompt, observe_system_prompt, user_system_prompt
from pare.bench.store import CACHE_FILE
from pare.cli import main
from pare.results.run_folder import EPISODES, load_run, read_records
from pare.results.trajectory import read_trajectory
from pare.scenarios import build_environment, get_scenario
from pare.testing import PROPOSAL, ChatServer, Reply, Responder, conversation_role, failure, proactive_play
from tests.agents.conftest import NetworkBlocked

KEY_VARIABLE = "PARE_TEST_API_KEY"
KEY = "sk-pare-test-KEY-7f3a9c41d2e8"  # recognisable, so a leak into any file is easy to find
SCENARIOS = ("dentist_moves_checkup", "five_a_side_kickoff_moved")
RUNS = 2
EPISODE_COUNT = len(SCENARIOS) * RUNS
USER_MODEL = "pare-user-model"
ASSISTANT_MODEL = "pare-assistant-model"
ROLES = {"user", "observe", "execute"}


@dataclass
class Servers:
    user: ChatServer
    assistant: ChatServer

    def set_responder(self, responder: Responder) -> None:
        self.user.responder = responder
        self.assistant.responder = responder

    @property
    def requests(self) -> int:
        return self.user.request_count + self.assistant.request_count


@pytest.fixture(autouse=True)
def api_key(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv(KEY_VARIABLE, KEY)


@pytest.fixture
def servers() -> Iterator[Servers]:
    with ChatServer(proactive_play()) as user, ChatServer(proactive_play()) as assistant:
        yield Servers(user, assistant)


def command(output: Path, servers: Servers, *extra: str, runs: int = RUNS) -> list[str]:
    argv = ["run", "--output", str(output), "--no-progress", "--runs", str(runs)]
    for scenario in SCENARIOS:
        argv += ["-s", scenario]
    argv += ["--user-model", USER_MODEL, "--user-endpoint", servers.user.base_url]
    argv += ["--assistant-model", ASSISTANT_MODEL, "--assistant-endpoint", servers.assistant.base_url]
    for role in ("user", "assistant"):
        for setting in (
            f"api_key_env={KEY_VARIABLE}",
            "retry_initial_s=0.001",
            "retry_max_s=0.01",
            "max_retries=1",
            "prices={input: 1.0, output: 2.0}",
        ):
            argv += ["--set", f"models.{role}.{setting}"]
    return argv + list(extra)


def trajectories(run_dir: Path) -> dict[str, bytes]:
    return {
        str(path.relative_to(run_dir)): path.read_bytes()
        for path in sorted((run_dir / "trajectories").rglob("*.json"))
    }


def test_the_network_is_guarded() -> None:
    with pytest.raises(NetworkBlocked):
        socket.create_connection(("192.0.2.1", 443), timeout=0.1)


def test_proactive_play_tells_the_roles_apart() -> None:
    env = build_environment(get_scenario(SCENARIOS[0]))
    task = Task(proposal=PROPOSAL, answer="", proposal_id="proposal-1")
    prompts = {
        "user": user_system_prompt(env),
        "observe": observe_system_prompt(env),
        "execute": execute_system_prompt(env, task, max_steps=10),
    }
    play = proactive_play()
    for role, prompt in prompts.items():
        assert conversation_role([{"role": "system", "content": prompt}]) == role
    first = {
        "messages": [{"role": "system", "content": prompts["observe"]}, {"role": "user", "content": "x"}]
    }
    answer = play(first).body["choices"][0]["message"]["content"]
    assert parse_action(answer).tool == "agent_ui__send_message_to_user"
    assert play({"messages": [{"role": "system", "content": "You are a pirate."}]}).status == 400


def test_a_responder_that_raises_is_answered_with_400() -> None:
    def broken(body: dict[str, Any]) -> Reply:
        raise KeyError("messages")

    with ChatServer(broken) as server:
        request = urllib.request.Request(
            server.base_url + "/chat/completions", data=b'{"model": "m"}', method="POST"
        )
        with pytest.raises(urllib.error.HTTPError) as refused:
            urllib.request.urlopen(request, timeout=5)
        assert refused.value.code == 400
        assert "responder failed" in json.loads(refused.value.read())["error"]["message"]
        refused.value.close()
        assert server.request_count == 1 and isinstance(server.errors[0], KeyError)


def test_a_model_backed_run_completes(tmp_path: Path, servers: Servers) -> None:
    out = tmp_path / "run"
    assert main(command(out, servers)) == 0

    loaded = load_run(out)
    assert len(loaded.records) == EPISODE_COUNT
    calls: Counter[str] = Counter()
    for record in loaded.records:
        assert record.complete, record.failure
        assert set(record.usage) == ROLES
        for role, usage in record.usage.items():
            assert usage.calls > 0 and usage.failed_calls == 0, role
            assert usage.cost_usd is not None and usage.cost_usd > 0, role
            calls[role] += usage.calls
        assert record.cost_usd() is not None
        assert record.proposals, record.scenario_id
        assert {p.decision for p in record.proposals} == {"accept"}
        assert {p.resolution for p in record.proposals} == {"accepted"}
        assert record.trajectory is not None
        trajectory = read_trajectory(out / record.trajectory)
        assert (trajectory.scenario_id, trajectory.run) == record.key
    # every call the records count reached its role's server, with the key and the model configured
    assert servers.user.request_count == calls["user"]
    assert servers.assistant.request_count == calls["observe"] + calls["execute"]
    assert {h["authorization"] for h in servers.user.headers + servers.assistant.headers} == {f"Bearer {KEY}"}
    assert {body["model"] for body in servers.user.requests} == {USER_MODEL}
    assert {body["model"] for body in servers.assistant.requests} == {ASSISTANT_MODEL}
    assert servers.user.errors == [] and servers.assistant.errors == []


def test_runs_of_a_scenario_are_sampled_independently(tmp_path: Path, servers: Servers) -> None:
    out = tmp_path / "run"
    assert main(command(out, servers)) == 0

    records = load_run(out).records
    assert {record.run for record in records} == {1, 2}
    for record in records:  # the cache is on (read_write), yet no run replayed another run's calls
        assert all(usage.cached_calls == 0 for usage in record.usage.values()), record.key
    assert servers.requests == sum(u.calls for r in records for u in r.usage.values())
    # the runs of one scenario send identical requests (the same first prompt): each reached the server
    bodies = Counter(json.dumps(body, sort_keys=True) for body in servers.user.requests)
    assert max(bodies.values()) == RUNS


def test_rerunning_the_same_command_does_nothing_new(tmp_path: Path, servers: Servers) -> None:
    out = tmp_path / "run"
    argv = command(out, servers)
    assert main(argv) == 0
    requests, lines = servers.requests, (out / EPISODES).read_bytes()

    assert main(argv) == 0
    assert servers.requests == requests
    assert (out / EPISODES).read_bytes() == lines


def test_a_replay_reproduces_the_trajectories_without_calling(tmp_path: Path, servers: Servers) -> None:
    first, second = tmp_path / "first", tmp_path / "replay"
    assert main(command(first, servers)) == 0
    requests = servers.requests

    replay = command(second, servers, "--cache", "replay", "--set", f"cache_path={first / CACHE_FILE}")
    assert main(replay) == 0
    assert servers.requests == requests
    recorded = trajectories(first)
    assert len(recorded) == EPISODE_COUNT
    assert trajectories(second) == recorded
    for record in load_run(second).records:
        assert record.complete
        assert all(usage.cached_calls == usage.calls > 0 for usage in record.usage.values())


def test_the_api_key_is_written_nowhere(tmp_path: Path, servers: Servers) -> None:
    out = tmp_path / "run"
    assert main(command(out, servers)) == 0
    assert main(command(out, servers)) == 0  # a resumed session rewrites the manifest
    assert servers.user.headers[0]["authorization"] == f"Bearer {KEY}"  # it was in use

    files = [path for path in out.rglob("*") if path.is_file()]
    assert any(path.name == CACHE_FILE for path in files)
    leaks = [str(path) for path in files if KEY.encode() in path.read_bytes()]
    assert leaks == []


def test_a_provider_that_is_down_fails_episodes_and_the_run_resumes(
    tmp_path: Path, servers: Servers, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(runner, "RETRY_PAUSE_S", 0.0)

    def down(body: dict[str, Any]) -> Reply:
        return failure(503, "The engine is currently overloaded, please try again later.")

    servers.set_responder(down)
    out = tmp_path / "run"
    argv = command(out, servers, "--set", "episode_retries=1")
    assert main(argv) == 1

    records = load_run(out).records
    assert len(records) == EPISODE_COUNT
    for record in records:
        assert record.status == "failed"
        assert record.failure is not None and record.failure.kind == "provider_unavailable"
        assert record.attempts == 2  # the first attempt and one episode retry
        assert USER_MODEL in record.failure.message
    # each attempt's first call (the user's) was tried max_retries + 1 = 2 times
    assert servers.user.request_count == EPISODE_COUNT * 2 * 2
    assert servers.assistant.request_count == 0

    servers.set_responder(proactive_play())
    assert main(argv) == 0
    loaded = load_run(out)
    assert len(loaded.records) == EPISODE_COUNT and all(r.complete for r in loaded.records)
    lines = read_records(out / EPISODES)
    assert len(lines) == 2 * EPISODE_COUNT
    complete = Counter(record.key for record in lines if record.complete)
    assert complete == dict.fromkeys(loaded.planned, 1)


def test_a_refused_key_stops_the_run_at_once(
    tmp_path: Path, servers: Servers, capsys: pytest.CaptureFixture[str]
) -> None:
    servers.assistant.responder = lambda body: failure(
        401, "Incorrect API key provided: sk-pare***.", code="invalid_api_key"
    )
    out = tmp_path / "run"
    assert main(command(out, servers)) == 2

    error = capsys.readouterr().err
    assert f"observe model '{ASSISTANT_MODEL}'" in error
    assert KEY_VARIABLE in error  # what to fix
    assert servers.assistant.request_count <= EPISODE_COUNT  # no retry: each episode asked once at most
    assert not any(record.complete for record in read_records(out / EPISODES))


def test_each_endpoint_stays_within_its_concurrency(tmp_path: Path, servers: Servers) -> None:
    servers.user.delay_s = servers.assistant.delay_s = 0.02
    out = tmp_path / "run"
    argv = command(out, servers, "--concurrency", "4", "--set", "models.assistant.max_concurrency=2", runs=4)
    assert main(argv) == 0

    assert len(load_run(out).records) == len(SCENARIOS) * 4
    assert 2 <= servers.user.max_in_flight <= 4  # episodes ran side by side, at most 4 at once
    assert servers.assistant.max_in_flight <= 2  # the assistant endpoint's own limit
