"""The Gymnasium environments: Gymnasium's checker passes, the oracle's actions replayed through them reach
success, a seed fixes the episode, malformed actions fail their step with the model's error text."""

from __future__ import annotations

import asyncio
import importlib
import sys
from collections.abc import Iterator
from typing import Any

import pytest

gymnasium = pytest.importorskip("gymnasium")

from gymnasium.utils.env_checker import check_env  # noqa: E402

import pare.gym  # noqa: E402
from pare.agents.actions import FORMAT_HINT  # noqa: E402
from pare.agents.models.config import ModelConfig  # noqa: E402
from pare.errors import UserInputError  # noqa: E402
from pare.testing import PROPOSAL, REPORT, ChatServer, proactive_play  # noqa: E402
from pare.training.envs import AsyncProactiveAssistantEnv, AsyncUserEnv  # noqa: E402
from tests.training.oracle_replay import oracle_texts  # noqa: E402

SCENARIO = "dentist_moves_checkup"


@pytest.fixture
def made() -> Iterator[list[Any]]:
    """Environments made by a test, closed after it."""
    envs: list[Any] = []
    yield envs
    for env in envs:
        env.close()


def _make(made: list[Any], env_id: str, **kwargs: Any) -> Any:
    env = gymnasium.make(env_id, **kwargs)
    made.append(env)
    return env


@pytest.mark.parametrize("env_id", [pare.gym.ASSISTANT_ENV_ID, pare.gym.USER_ENV_ID])
def test_gymnasium_s_checker_passes(made: list[Any], env_id: str) -> None:
    check_env(_make(made, env_id).unwrapped)


def _replay(env: Any, texts: list[str]) -> tuple[float, dict[str, Any], int]:
    """Step ``texts`` until the episode ends: the summed reward, the last info, the steps taken."""
    total = 0.0
    for count, text in enumerate(texts, start=1):
        _, reward, terminated, truncated, info = env.step(text)
        total += reward
        if terminated or truncated:
            return total, info, count
    raise AssertionError("the episode did not end with the oracle's actions")


def test_the_oracle_s_assistant_actions_replayed_reach_success(made: list[Any]) -> None:
    env = _make(made, pare.gym.ASSISTANT_ENV_ID)
    observation, info = env.reset(seed=7, options={"scenario": SCENARIO})
    assert info["scenario_id"] == SCENARIO
    assert info["conversation"] == "observe"
    assert "Action:" in observation and info["messages"][0]["role"] == "system"  # the prompt comes first
    texts = asyncio.run(oracle_texts(env.unwrapped.core.scenario, env.unwrapped.core.seed, "assistant"))
    total, info, steps = _replay(env, texts)
    assert steps == len(texts)
    assert info["success"] and info["goal_rate"] == 1.0 and info["side_effects"] == []
    assert info["outcome"]["success"]
    accepted = [p for p in info["trajectory"]["log"] if p["tool"] == "accept_proposal"]
    assert total == len(accepted) >= 1  # the per-step reward: +1 for each accepted proposal
    assert info["trajectory"]["scenario_id"] == SCENARIO


def test_the_success_reward_comes_at_the_end(made: list[Any]) -> None:
    env = _make(made, pare.gym.ASSISTANT_ENV_ID, reward="success")
    env.reset(seed=7, options={"scenario": SCENARIO})
    texts = asyncio.run(oracle_texts(env.unwrapped.core.scenario, env.unwrapped.core.seed, "assistant"))
    rewards = [env.step(text)[1] for text in texts]
    assert rewards[:-1] == [0.0] * (len(texts) - 1) and rewards[-1] == 1.0


def test_the_oracle_s_user_actions_replayed_reach_success(made: list[Any]) -> None:
    env = _make(made, pare.gym.USER_ENV_ID)
    observation, info = env.reset(seed=11, options={"scenario": SCENARIO})
    assert info["conversation"] == "user" and observation
    texts = asyncio.run(oracle_texts(env.unwrapped.core.scenario, env.unwrapped.core.seed, "user"))
    total, info, _ = _replay(env, texts)
    assert total == 1.0 and info["success"]


def test_a_seed_fixes_the_scenario_and_the_world(made: list[Any]) -> None:
    env = _make(made, pare.gym.ASSISTANT_ENV_ID)
    draws = {seed: env.reset(seed=seed) for seed in (1, 2, 3, 4, 5, 1)}
    first, again = env.reset(seed=1), draws[1]
    assert first[0] == again[0] and first[1]["seed"] == again[1]["seed"]
    assert len({info["scenario_id"] for _, info in draws.values()}) > 1  # the seed draws from the split


def test_a_malformed_action_fails_its_step_with_the_model_s_error_text(made: list[Any]) -> None:
    env = _make(made, pare.gym.ASSISTANT_ENV_ID)
    env.reset(seed=7, options={"scenario": SCENARIO})
    observation, reward, terminated, _, info = env.step("I think I should wait.")
    assert reward == 0.0 and not terminated
    assert info["action_error"] and FORMAT_HINT in observation
    # with retries, the same answer is sent back within the step instead
    env = _make(made, pare.gym.ASSISTANT_ENV_ID, max_format_retries=1)
    env.reset(seed=7, options={"scenario": SCENARIO})
    observation, _, _, _, info = env.step("I think I should wait.")
    assert info["format_retry"] and info["action"] is None and FORMAT_HINT in observation


def test_bad_settings_are_named() -> None:
    with pytest.raises(UserInputError, match="reward 'win'"):
        AsyncProactiveAssistantEnv(reward="win")
    with pytest.raises(UserInputError, match="acceptance"):
        AsyncUserEnv(reward="acceptance")  # the assistant's signal, not the user's
    with pytest.raises(UserInputError, match="no split 'smoky'"):
        AsyncProactiveAssistantEnv(split="smoky")


def test_an_unknown_reset_option_is_named(made: list[Any]) -> None:
    env = _make(made, pare.gym.ASSISTANT_ENV_ID)
    with pytest.raises(UserInputError, match="scenario_id"):
        env.reset(options={"scenario_id": SCENARIO})


def test_many_async_environments_step_at_once() -> None:
    async def play(seed: int) -> bool:
        env = AsyncProactiveAssistantEnv(scenarios=[SCENARIO])
        try:
            await env.reset(seed=seed)
            assert env.scenario is not None and env.seed is not None
            texts = await oracle_texts(env.scenario, env.seed, "assistant")
            for text in texts:
                _, _, terminated, truncated, info = await env.step(text)
                if terminated or truncated:
                    return bool(info["success"])
            return False
        finally:
            await env.aclose()

    async def all_of_them() -> list[bool]:
        return await asyncio.gather(*(play(seed) for seed in range(4)))

    assert asyncio.run(all_of_them()) == [True] * 4


def test_a_configured_user_model_answers_the_agent_s_proposal(made: list[Any]) -> None:
    with ChatServer(proactive_play()) as server:
        user = ModelConfig(model="pare-test-model", api_base=server.base_url, api_key_env=None, max_retries=0)
        env = _make(made, pare.gym.ASSISTANT_ENV_ID, user=user)
        env.reset(seed=3, options={"scenario": SCENARIO})
        proposal = '{"action": "agent_ui__send_message_to_user", "action_input": {"content": "Shall I?"}}'
        observation, reward, _, _, info = env.step(f"Thought: propose.\nAction:\n{proposal}<end_action>")
        assert reward == 1.0  # the user model accepted
        assert info["conversation"] == "execute" and "accepted" in observation
        assert server.request_count >= 1
        env.close()


def test_a_configured_assistant_model_proposes_to_the_agent_as_user(made: list[Any]) -> None:
    with ChatServer(proactive_play()) as server:
        assistant = {"model": "pare-test-model", "api_base": server.base_url, "api_key_env": None}
        env = _make(made, pare.gym.USER_ENV_ID, assistant=assistant)
        env.reset(seed=3, options={"scenario": SCENARIO})
        wait = 'Thought: Nothing yet.\nAction:\n{"action": "wait", "action_input": {}}<end_action>'
        observation, *_ = env.step(wait)
        assert PROPOSAL in observation  # the assistant model proposed in the first turn
        accept = '{"action": "accept_proposal", "action_input": {"reason": "Yes."}}'
        observation, *_ = env.step(f"Thought: Fine.\nAction:\n{accept}<end_action>")
        assert REPORT in observation  # it carried the task out and reported
        env.close()


def test_without_gymnasium_the_import_names_the_extra(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setitem(sys.modules, "gymnasium", None)  # as if not installed
    monkeypatch.delitem(sys.modules, "pare.gym")
    with pytest.raises(ImportError, match=r"\[gym\]"):
        importlib.import_module("pare.gym")
