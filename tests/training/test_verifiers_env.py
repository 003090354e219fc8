"""The verifiers environment: the library's own Env, whose rollouts play PARE's turn loop against a chat
server and whose rewards are PARE's verdict."""

from __future__ import annotations

import asyncio
import threading
from typing import Any

import pytest

vf = pytest.importorskip(
    "verifiers.v1", reason="the verifiers extra is not installed (pip install -e '.[verifiers]')"
)

from pare.errors import UserInputError  # noqa: E402
from pare.scenarios.library import get_scenario, splits  # noqa: E402
from pare.testing import PROPOSAL, ChatServer, Reply, completion, proactive_play  # noqa: E402
from pare.training.verifiers import ENV_ID, PareEnv, load_environment  # noqa: E402
from tests.training.oracle_replay import oracle_texts  # noqa: E402

SCENARIO = "dentist_moves_checkup"
KEY_VARIABLE = "PARE_TEST_VERIFIERS_KEY"


def _rollout(env: PareEnv, server: ChatServer, monkeypatch: pytest.MonkeyPatch) -> Any:
    """One episode of the taskset's first task, the assistant's seat answered by ``server``."""
    monkeypatch.setenv(KEY_VARIABLE, "not-needed")
    task = next(iter(env.taskset))
    context = vf.ModelContext(
        model="pare-test-model",
        client=vf.EvalClientConfig(base_url=server.base_url, api_key_var=KEY_VARIABLE),
    )

    async def play() -> Any:
        async with env.serving():
            return await env.run_episode(task, context)

    episode = asyncio.run(play())
    assert episode.ok, episode.errors or [error.message for trace in episode.traces for error in trace.errors]
    (trace,) = episode.traces
    return trace


def test_load_environment_is_the_library_s_env_over_the_split() -> None:
    env = load_environment(split="smoke")
    assert isinstance(env, vf.Env)
    assert sorted(task.data.scenario_id for task in env.taskset) == sorted(splits()["smoke"])
    # the library finds the same classes by the id a user gives its command line
    assert vf.environment_class(ENV_ID) is PareEnv
    assert vf.default_harness_id(ENV_ID) == ENV_ID


def test_a_rollout_plays_the_scenario_through_the_interception_and_is_rewarded_by_its_verdict(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    env = load_environment(scenarios=[SCENARIO])
    with ChatServer(proactive_play()) as server:
        trace = _rollout(env, server, monkeypatch)
    played = trace.info["pare"]
    assert played["scenario_id"] == SCENARIO
    # the model's calls went through the library's interception: the trace holds them
    answers = [m.content for branch in trace.branches for m in branch.messages if m.role == "assistant"]
    assert any(PROPOSAL in (answer or "") for answer in answers)
    # proactive_play only reports: the scenario's goals are not met, and the rewards say so
    assert not played["outcome"]["success"]
    assert trace.rewards["success"].score == 0.0 and trace.rewards["success"].weight == 1.0
    assert trace.rewards["goal_rate"].score == played["outcome"]["goal_rate"] < 1.0
    assert trace.metrics["acceptance_rate"] == 1.0  # the oracle user accepted the one proposal


def _oracle_replay(task: Any) -> Any:
    """A chat server's handler answering with the oracle assistant's actions for ``task``, in order."""
    texts = asyncio.run(oracle_texts(get_scenario(SCENARIO), task.data.seed, "assistant"))
    answers = iter(texts)
    lock = threading.Lock()

    def replay(body: dict[str, Any]) -> Reply:
        with lock:
            return completion(next(answers))

    return replay


def test_the_oracle_s_answers_through_the_client_are_rewarded_one(monkeypatch: pytest.MonkeyPatch) -> None:
    env = load_environment(scenarios=[SCENARIO], seed=5)
    task = next(iter(env.taskset))
    with ChatServer(_oracle_replay(task)) as server:
        trace = _rollout(env, server, monkeypatch)
    assert trace.info["pare"]["seed"] == task.data.seed == trace.info["pare"]["trajectory"]["seed"]
    assert trace.rewards["success"].score == 1.0
    assert trace.rewards["goal_rate"].score == 1.0


def test_free_text_checks_go_to_the_configured_judge(monkeypatch: pytest.MonkeyPatch) -> None:
    with ChatServer(lambda body: completion("NO. The text does not say so.")) as judge:
        env = load_environment(
            scenarios=[SCENARIO],
            seed=5,
            judge={"model": "test-judge", "api_base": judge.base_url, "api_key_env": None},
        )
        task = next(iter(env.taskset))
        with ChatServer(_oracle_replay(task)) as server:
            trace = _rollout(env, server, monkeypatch)
        assert judge.requests  # the judge was asked
    # the oracle's episode meets every goal by the fallbacks; the judge refusing its text fails it
    outcome = trace.info["pare"]["outcome"]
    judged = [check for goal in outcome["goals"] for check in goal["checks"] if check["form"] == "judge"]
    assert judged and not any(check["passed"] for check in judged)
    assert trace.rewards["success"].score == 0.0


def test_bad_selections_are_refused_by_name() -> None:
    with pytest.raises(UserInputError, match="no_such_scenario"):
        load_environment(scenarios=["no_such_scenario"])
    with pytest.raises(UserInputError, match="no split 'nope'"):
        load_environment(split="nope")
    with pytest.raises(UserInputError, match="protocol"):
        load_environment(protocol="no-such-preset")
    with pytest.raises(UserInputError, match="user"):
        load_environment(user={"modle": "gpt-4o"})
