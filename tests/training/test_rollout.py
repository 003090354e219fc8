"""One episode played by a model behind an OpenAI-compatible client: what a training framework's rollout
gets from PARE (no extra needed)."""

from __future__ import annotations

import asyncio

from openai import AsyncOpenAI

from pare.protocols import ProtocolSettings
from pare.testing import PROPOSAL, ChatServer, proactive_play
from pare.training.rollout import AssistantRollout, play_assistant

SCENARIO = "dentist_moves_checkup"


def _play(seed: int) -> AssistantRollout:
    async def play() -> AssistantRollout:
        with ChatServer(proactive_play()) as server:
            async with AsyncOpenAI(base_url=server.base_url, api_key="not-needed", max_retries=0) as client:
                return await play_assistant(
                    client, "pare-test-model", SCENARIO, seed=seed, protocol=ProtocolSettings()
                )

    return asyncio.run(play())


def test_the_rollout_keeps_the_assistant_s_conversations_and_the_verdict() -> None:
    played = _play(seed=7)
    assert [message["role"] for message in played.prompt] == ["system", "user"]
    assert PROPOSAL in played.completion[0]["content"]  # the model's first answer proposes
    assert played.completion[-1]["role"] == "user"  # the closing observation ends the observe conversation
    assert len(played.conversations) == 2  # observe mode's, then execute mode's for the accepted proposal
    assert played.conversations[1][0]["role"] == "system"
    # proactive_play only reports: the scenario's goals are not met
    assert not played.outcome["success"] and played.outcome["goal_rate"] < 1.0
    assert played.acceptance_rate() == 1.0  # the oracle user accepted the one proposal
    assert played.trajectory["seed"] == 7 and played.trajectory["scenario_id"] == SCENARIO
