"""PARE as an environment in the verifiers library's shape: ``load_environment(...)``, a dataset of
scenarios, rollouts against an OpenAI-compatible client and a rubric, without that library.

The ``verifiers`` package (0.4) requires ``openai<3``, while PARE's locks pin ``openai`` 3; installing it
would move every user of the extra to another major version of the client PARE calls models with (and bring
in some ninety packages, transformers among them). So this module implements the same contract with PARE's
own pieces, and no dependency:

* :func:`load_environment` returns a :class:`PareEnvironment`;
* ``env.dataset`` has one row per scenario: ``prompt`` (empty: an episode's opening messages exist only once
  its phone is built; the rollout's state holds them), ``answer`` (empty: the verdict is the reference),
  ``task`` and ``info`` (the scenario id and the world's seed);
* ``await env.rollout(client, model, prompt, answer, task, info, sampling_args)`` plays the scenario with
  PARE's own turn loop (:func:`~pare.bench.episode.arun_episode`), the model behind ``client`` playing the
  assistant, and returns ``(completion, state)``: the observe conversation after its opening messages, and a
  state with the opening (``prompt``), every ``conversations`` (each execute conversation too), the verdict
  (``outcome``) and the ``trajectory``;
* ``env.rubric`` scores a rollout from its state: PARE's verdict (``success``, weight 1) and, as metrics with
  weight 0, the ``goal_rate`` and the ``acceptance_rate`` of the assistant's proposals;
* ``await env.evaluate(client, model, num_examples, rollouts_per_example)`` plays rows concurrently and
  returns :class:`GenerateOutputs` (``prompt``, ``completion``, ``state``, ``reward``, ``metrics``, ...).
"""

from __future__ import annotations

import asyncio
import hashlib
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

from openai import AsyncOpenAI

from pare.agents.llm import LLMAssistant
from pare.agents.models.types import ChatMessage, Completion, Usage
from pare.bench.episode import arun_episode
from pare.protocols import ProtocolSettings
from pare.scenarios.checks import Judge
from pare.scenarios.library import get_scenario
from pare.training.setup import (
    ORACLE,
    Counterpart,
    Counterparts,
    episode_settings,
    protocol_settings,
    scenario_pool,
)

Messages = list[dict[str, Any]]
State = dict[str, Any]
RewardFunc = Callable[..., float]
"""A reward function: called with keywords ``prompt``, ``completion``, ``answer``, ``state``, ``task``,
``info``; each takes the ones it needs and ignores the rest."""

TASK = "pare/ProactiveAssistant"


# -- the model behind the client -----------------------------------------------------------------------------
@dataclass
class _ClientModel:
    """PARE's :class:`~pare.agents.llm.ChatModel` over an OpenAI-compatible client, keeping every call: the
    messages sent and the answer (the conversations of the rollout are read from them).
    """

    client: AsyncOpenAI
    model: str
    sampling_args: Mapping[str, Any]
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


# -- the rubric ----------------------------------------------------------------------------------------------
def success(*, state: State, **_: Any) -> float:
    """PARE's verdict: 1.0 when every goal was met (and no side effect), else 0.0."""
    return 1.0 if state["outcome"]["success"] else 0.0


def goal_rate(*, state: State, **_: Any) -> float:
    """The share of the scenario's goals met."""
    return float(state["outcome"]["goal_rate"])


def acceptance_rate(*, state: State, **_: Any) -> float:
    """The share of the assistant's proposals the user accepted (0.0 when it proposed nothing)."""
    answers = [entry["tool"] for entry in state["trajectory"]["log"]]
    accepted, rejected = answers.count("accept_proposal"), answers.count("reject_proposal")
    return accepted / (accepted + rejected) if accepted + rejected else 0.0


@dataclass(frozen=True)
class RolloutScore:
    """One rollout's reward (the weighted sum of the functions) and each function's value."""

    reward: float
    metrics: dict[str, float]


@dataclass
class Rubric:
    """Reward functions and their weights."""

    funcs: list[RewardFunc] = field(default_factory=lambda: [success, goal_rate, acceptance_rate])
    weights: list[float] = field(default_factory=lambda: [1.0, 0.0, 0.0])

    def __post_init__(self) -> None:
        if len(self.funcs) != len(self.weights):
            raise ValueError(f"the rubric has {len(self.funcs)} functions but {len(self.weights)} weights")

    async def score_rollout(
        self,
        prompt: Messages,
        completion: Messages,
        answer: str,
        state: State,
        task: str = TASK,
        info: Mapping[str, Any] | None = None,
    ) -> RolloutScore:
        """Score one rollout."""
        given = {
            "prompt": prompt,
            "completion": completion,
            "answer": answer,
            "state": state,
            "task": task,
            "info": dict(info or {}),
        }
        metrics = {func.__name__: float(func(**given)) for func in self.funcs}
        reward = sum(
            weight * metrics[func.__name__] for func, weight in zip(self.funcs, self.weights, strict=True)
        )
        return RolloutScore(reward, metrics)


# -- the environment -----------------------------------------------------------------------------------------
@dataclass
class GenerateOutputs:
    """The rollouts of an evaluation, column by column, with their rewards and metrics."""

    prompt: list[Messages]
    completion: list[Messages]
    answer: list[str]
    state: list[State]
    info: list[dict[str, Any]]
    task: list[str]
    reward: list[float]
    metrics: dict[str, list[float]]


def _row_seed(seed: int, scenario_id: str) -> int:
    digest = hashlib.sha256(f"{seed}:{scenario_id}".encode()).digest()
    return int.from_bytes(digest[:4], "big")


class PareEnvironment:
    """Scenarios to roll out, PARE's turn loop to play them, PARE's verdict to score them."""

    def __init__(
        self,
        scenario_ids: Sequence[str],
        *,
        user: Counterpart = ORACLE,
        protocol: ProtocolSettings,
        seed: int = 0,
        side_effects: bool = True,
        judge: Judge | None = None,
        rubric: Rubric | None = None,
    ) -> None:
        self.protocol = protocol
        self.user = user
        self.side_effects = side_effects
        self.judge = judge
        self.rubric = rubric or Rubric()
        self.dataset: list[dict[str, Any]] = [
            {
                "prompt": [],
                "answer": "",
                "task": TASK,
                "info": {"scenario_id": scenario_id, "seed": _row_seed(seed, scenario_id)},
            }
            for scenario_id in scenario_ids
        ]

    async def rollout(
        self,
        client: AsyncOpenAI,
        model: str,
        prompt: Messages | None = None,
        answer: str = "",
        task: str = TASK,
        info: Mapping[str, Any] | None = None,
        sampling_args: Mapping[str, Any] | None = None,
    ) -> tuple[Messages, State]:
        """Play the scenario ``info["scenario_id"]`` (world seed ``info["seed"]``, default 0) with ``model``
        behind ``client`` as the assistant; return the completion and the state (see the module's text).
        """
        info = dict(info or {})
        if "scenario_id" not in info:
            raise ValueError("a rollout's info names its scenario: info={'scenario_id': ..., 'seed': ...}")
        scenario = get_scenario(str(info["scenario_id"]))
        assistant_model = _ClientModel(client, model, sampling_args or {})
        counterparts = Counterparts(self.user, self.protocol.max_format_retries)
        try:
            result = await arun_episode(
                scenario,
                counterparts.user(scenario),
                LLMAssistant(assistant_model, max_format_retries=self.protocol.max_format_retries),
                episode_settings(self.protocol, int(info.get("seed", 0))),
                judge=self.judge,
                side_effects=self.side_effects,
            )
        finally:
            await counterparts.aclose()
        conversations = assistant_model.conversations()
        observe = conversations[0] if conversations else []
        if "assistant" in result.closing and observe:
            observe.append({"role": "user", "content": result.closing["assistant"]})
        opening = [message for message in observe[:2] if message["role"] != "assistant"]
        completion = observe[len(opening) :]
        state: State = {
            "prompt": opening,
            "completion": completion,
            "answer": answer,
            "task": task,
            "info": info,
            "conversations": conversations,
            "outcome": result.outcome.to_dict(),
            "trajectory": {"seed": info.get("seed", 0), **result.to_dict()},
        }
        return completion, state

    async def evaluate(
        self,
        client: AsyncOpenAI,
        model: str,
        num_examples: int = -1,
        rollouts_per_example: int = 1,
        sampling_args: Mapping[str, Any] | None = None,
        max_concurrent: int = 8,
    ) -> GenerateOutputs:
        """Roll out the first ``num_examples`` rows (all: -1), each ``rollouts_per_example`` times, at most
        ``max_concurrent`` at once, and score them.
        """
        rows = self.dataset if num_examples < 0 else self.dataset[:num_examples]
        rows = [row for row in rows for _ in range(rollouts_per_example)]
        limit = asyncio.Semaphore(max_concurrent)

        async def one(row: dict[str, Any]) -> tuple[Messages, State, RolloutScore]:
            async with limit:
                completion, state = await self.rollout(
                    client, model, row["prompt"], row["answer"], row["task"], row["info"], sampling_args
                )
            score = await self.rubric.score_rollout(
                state["prompt"], completion, row["answer"], state, row["task"], row["info"]
            )
            return completion, state, score

        played = await asyncio.gather(*(one(row) for row in rows))
        names = [func.__name__ for func in self.rubric.funcs]
        return GenerateOutputs(
            prompt=[state["prompt"] for _, state, _ in played],
            completion=[completion for completion, _, _ in played],
            answer=[row["answer"] for row in rows],
            state=[state for _, state, _ in played],
            info=[row["info"] for row in rows],
            task=[row["task"] for row in rows],
            reward=[score.reward for _, _, score in played],
            metrics={name: [score.metrics[name] for _, _, score in played] for name in names},
        )


def load_environment(
    *,
    scenarios: Sequence[str] | None = None,
    split: str | None = None,
    user: Counterpart = ORACLE,
    protocol: str | Mapping[str, Any] | ProtocolSettings | None = None,
    seed: int = 0,
    side_effects: bool = True,
    judge: Judge | None = None,
    rubric: Rubric | None = None,
) -> PareEnvironment:
    """PARE's assistant task as an environment: the given ``scenarios`` (ids) or ``split`` (default
    ``smoke``), the user played by the oracle or a model (as in :mod:`pare.training.envs`), the turn
    ``protocol`` (a preset's name or settings), each scenario's world seeded from ``seed``.
    """
    return PareEnvironment(
        scenario_pool(scenarios, split),
        user=user,
        protocol=protocol_settings(protocol),
        seed=seed,
        side_effects=side_effects,
        judge=judge,
        rubric=rubric,
    )
