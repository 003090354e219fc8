"""One PARE episode with the assistant played by a model behind an OpenAI-compatible client.

What a training framework's rollout needs from PARE, without that framework: the scenario played by PARE's
own turn loop (:func:`~pare.bench.episode.arun_episode`), the assistant's model reached through the client
the framework hands over (so every call goes where the framework records it), and what came of it: the
assistant's conversations in the chat-completions format, the verdict and the trajectory.
:mod:`pare.training.verifiers` builds the verifiers environment on it.
"""

from __future__ import annotations

import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

from openai import AsyncOpenAI

from pare.agents.llm import LLMAssistant
from pare.agents.models.types import ChatMessage, Completion, Usage
from pare.bench.episode import arun_episode
from pare.protocols import ProtocolSettings
from pare.scenarios.checks import Judge
from pare.scenarios.library import get_scenario
from pare.training.setup import ORACLE, Counterpart, Counterparts, episode_settings

Messages = list[dict[str, Any]]


@dataclass
class ClientModel:
    """PARE's :class:`~pare.agents.llm.ChatModel` over an OpenAI-compatible client, keeping every call: the
    messages sent and the answer (the conversations of the rollout are read from them).
    """

    client: AsyncOpenAI
    model: str
    sampling_args: Mapping[str, Any] = field(default_factory=dict)
    calls: list[tuple[tuple[ChatMessage, ...], str]] = field(default_factory=list)

    async def complete(
        self, messages: Sequence[ChatMessage], tools: Sequence[dict[str, Any]] | None = None
    ) -> Completion:
        """One chat completion."""
        started = time.perf_counter()
        response = await self.client.chat.completions.create(
            model=self.model,
            messages=[message.to_openai() for message in messages],  # type: ignore[misc]
            **dict(self.sampling_args),
        )
        text = (response.choices[0].message.content or "") if response.choices else ""
        self.calls.append((tuple(messages), text))
        usage = response.usage
        return Completion(
            text=text,
            usage=Usage(
                prompt_tokens=usage.prompt_tokens if usage else 0,
                completion_tokens=usage.completion_tokens if usage else 0,
            ),
            cost_usd=None,
            latency_s=time.perf_counter() - started,
            model=response.model or self.model,
            finish_reason=response.choices[0].finish_reason if response.choices else None,
        )

    def conversations(self) -> list[Messages]:
        """Each conversation the actor held, whole, in the order they started (observe mode's first): a
        call continues the conversation whose messages its own begin with (the answers the actor kept
        are not compared: it keeps them without a thinking model's reasoning), else it starts one.
        """
        found: list[Messages] = []
        sent: list[tuple[ChatMessage, ...]] = []
        """The messages of each conversation's last call."""
        for messages, answer in self.calls:
            index = next(
                (
                    i
                    for i, last in enumerate(sent)
                    if messages[: len(last)] == last and len(messages) > len(last)
                ),
                None,
            )
            if index is None:
                found.append([])
                sent.append(())
                index = len(found) - 1
            known = len(sent[index]) + 1 if sent[index] else 0  # the last call's messages and its answer
            found[index].extend(message.to_openai() for message in messages[known:])
            found[index].append({"role": "assistant", "content": answer})
            sent[index] = messages
        return found


@dataclass(frozen=True)
class AssistantRollout:
    """What one episode played by the assistant's model left."""

    prompt: Messages
    """The opening of the assistant's observe conversation: its system prompt and first observation."""
    completion: Messages
    """The rest of the observe conversation, with the closing observation."""
    conversations: list[Messages]
    """Every conversation of the assistant: observe mode's, then one per accepted task (execute mode)."""
    outcome: dict[str, Any]
    """PARE's verdict: ``success``, ``goal_rate``, every goal's checks, the side effects."""
    trajectory: dict[str, Any]
    """The episode as a run's trajectory file holds it, with the world's ``seed``."""

    def acceptance_rate(self) -> float:
        """The share of the assistant's proposals the user accepted (0.0 when it proposed nothing)."""
        answers = [entry["tool"] for entry in self.trajectory["log"]]
        accepted, rejected = answers.count("accept_proposal"), answers.count("reject_proposal")
        return accepted / (accepted + rejected) if accepted + rejected else 0.0


async def play_assistant(
    client: AsyncOpenAI,
    model: str,
    scenario_id: str,
    *,
    seed: int = 0,
    protocol: ProtocolSettings,
    user: Counterpart = ORACLE,
    side_effects: bool = True,
    judge: Judge | None = None,
    sampling_args: Mapping[str, Any] | None = None,
) -> AssistantRollout:
    """Play ``scenario_id`` (world seed ``seed``) with ``model`` behind ``client`` as the assistant and
    ``user`` (the oracle, a model or a model configuration) as the user, under ``protocol``.

    Raises:
        UserInputError: an unknown scenario or a bad user configuration.
    """
    scenario = get_scenario(scenario_id)
    assistant_model = ClientModel(client, model, dict(sampling_args or {}))
    counterparts = Counterparts(user, protocol.max_format_retries)
    try:
        result = await arun_episode(
            scenario,
            counterparts.user(scenario),
            LLMAssistant(assistant_model, max_format_retries=protocol.max_format_retries),
            episode_settings(protocol, seed),
            judge=judge,
            side_effects=side_effects,
        )
    finally:
        await counterparts.aclose()
    conversations = assistant_model.conversations()
    observe = conversations[0] if conversations else []
    if "assistant" in result.closing and observe:
        observe.append({"role": "user", "content": result.closing["assistant"]})
    opening = [message for message in observe[:2] if message["role"] != "assistant"]
    return AssistantRollout(
        prompt=opening,
        completion=observe[len(opening) :],
        conversations=conversations,
        outcome=result.outcome.to_dict(),
        trajectory={**result.to_dict(), "seed": seed},
    )
