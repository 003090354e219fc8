"""The oracle's own actions, as texts in PARE's action format, for replaying them through an environment."""

from __future__ import annotations

from pare.agents.actions import format_action
from pare.agents.policy import AssistantPolicy, UserPolicy
from pare.bench.episode import StepActor, arun_episode
from pare.protocols import ProtocolSettings
from pare.scenarios.model import Scenario
from pare.scenarios.oracle import OracleAssistant, OracleUser
from pare.training.setup import episode_settings


async def oracle_texts(scenario: Scenario, seed: int, actor: StepActor) -> list[str]:
    """What ``actor`` does when the oracle plays both roles of ``scenario`` with world seed ``seed``."""
    user: UserPolicy = OracleUser(scenario)
    assistant: AssistantPolicy = OracleAssistant(scenario)
    result = await arun_episode(scenario, user, assistant, episode_settings(ProtocolSettings(), seed))
    assert result.success
    return [
        format_action(step.action.tool, step.action.args, "As the solution does.")
        for step in result.steps
        if step.actor == actor
    ]
