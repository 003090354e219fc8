"""The verifiers-shaped environment: rollouts play PARE's turn loop against a chat server, the rubric is
PARE's verdict."""

from __future__ import annotations

import asyncio
import threading
from typing import Any

from openai import AsyncOpenAI

from pare.scenarios.library import get_scenario
from pare.testing import PROPOSAL, ChatServer, Reply, completion, proactive_play
from pare.training.verifiers import load_environment
from tests.training.oracle_replay import oracle_texts

SCENARIO = "dentist_moves_checkup"


def _client(server: ChatServer) -> AsyncOpenAI:
    return AsyncOpenAI(base_url=server.base_url, api_key="not-needed", max_retries=0)


def test_a_rollout_plays_the_scenario_and_is_scored_by_its_verdict() -> None:
    env = load_environment(scenarios=[SCENARIO])
    row = env.dataset[0]
    assert row["info"]["scenario_id"] == SCENARIO

    async def roll() -> Any:
        with ChatServer(proactive_play()) as server:
            async with _client(server) as client:
                completion, state = await env.rollout(client, "pare-test-model", **row)
            score = await env.rubric.score_rollout(state["prompt"], completion, "", state, info=row["info"])
            return completion, state, score

    completion, state, score = asyncio.run(roll())
    assert [message["role"] for message in state["prompt"]] == ["system", "user"]
    assert PROPOSAL in completion[0]["content"]  # the model's first answer proposes
    assert len(state["conversations"]) == 2  # observe mode's, then execute mode's for the accepted proposal
    assert state["conversations"][1][0]["role"] == "system"
    # proactive_play only reports: the scenario's goals are not met, and the rubric says so
    assert not state["outcome"]["success"]
    assert score.reward == 0.0 and score.metrics["success"] == 0.0
    assert score.metrics["acceptance_rate"] == 1.0  # the oracle user accepted the one proposal
    assert score.metrics["goal_rate"] == state["outcome"]["goal_rate"] < 1.0


def test_the_oracle_s_answers_through_the_client_score_one() -> None:
    env = load_environment(scenarios=[SCENARIO], seed=5)
    row = env.dataset[0]
    texts = asyncio.run(oracle_texts(get_scenario(SCENARIO), row["info"]["seed"], "assistant"))
    answers = iter(texts)
    lock = threading.Lock()

    def replay(body: dict[str, Any]) -> Reply:
        with lock:
            return completion(next(answers))

    async def roll() -> Any:
        with ChatServer(replay) as server:
            async with _client(server) as client:
                completion_, state = await env.rollout(client, "pare-test-model", **row)
            return await env.rubric.score_rollout(state["prompt"], completion_, "", state)

    score = asyncio.run(roll())
    assert score.reward == 1.0 and score.metrics["goal_rate"] == 1.0


def test_evaluate_rolls_out_every_row_the_times_asked() -> None:
    env = load_environment(split="smoke")

    async def evaluate() -> Any:
        with ChatServer(proactive_play()) as server:
            async with _client(server) as client:
                return await env.evaluate(client, "pare-test-model", num_examples=2, rollouts_per_example=2)

    outputs = asyncio.run(evaluate())
    ids = [info["scenario_id"] for info in outputs.info]
    assert ids == [env.dataset[0]["info"]["scenario_id"]] * 2 + [env.dataset[1]["info"]["scenario_id"]] * 2
    assert len(outputs.reward) == 4 and set(outputs.metrics) == {"success", "goal_rate", "acceptance_rate"}
    assert outputs.reward == [1.0 if state["outcome"]["success"] else 0.0 for state in outputs.state]
