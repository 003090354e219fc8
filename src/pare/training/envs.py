"""Asynchronous training environments: one PARE episode, one agent answer per ``step``.

:class:`AsyncProactiveAssistantEnv` lets the agent play the proactive assistant (observe and execute modes)
against the oracle user or a configured user model; :class:`AsyncUserEnv` lets it play the user against the
oracle assistant or a configured assistant model. Both follow Gymnasium's calling convention with coroutines:
``obs, info = await env.reset(seed=..., options=...)`` and
``obs, reward, terminated, truncated, info = await env.step(text)``, so many environments can be stepped at
once with :func:`asyncio.gather` in one event loop. :mod:`pare.gym` wraps them as ``gymnasium.Env``.

An observation is the text the role's model is given since its last answer (the system prompt too, when a
conversation starts: at the episode's start, and for each accepted task in execute mode); an action is the
text the model would write, in PARE's action format (:mod:`pare.agents.actions`), read by the same actor
code that reads a model's answers. A malformed action gets the error text a model gets; with
``max_format_retries=0`` (the default, as in the paper's protocol) it fails its step, which the trajectory
records; a higher number sends it back within the step first, as PARE's protocol does.

Rewards (``reward=``): ``acceptance``, the paper's per-step reward for the assistant (+1 for each of its
proposals the user accepted, -1 for each rejected, else 0; the user answers before the assistant is asked
again, so the reward comes with the step that proposed); ``success`` (1.0 at the end when the scenario's
verdict is success, else 0.0); ``goal_rate`` (the share of goals met, at the end).
"""

from __future__ import annotations

import asyncio
import random
from abc import ABC, abstractmethod
from collections.abc import Mapping, Sequence
from typing import Any, ClassVar, Literal, TypeGuard, get_args

from pare.agents.llm import LLMAssistant, LLMUser
from pare.agents.policy import DEFAULT_BUDGET, Action, AssistantPolicy, Ending, Task, TurnBudget, UserPolicy
from pare.bench.episode import EpisodeResult, arun_episode
from pare.env import AssistantObservation, Environment, ToolResult, UserView
from pare.errors import UserInputError, did_you_mean
from pare.protocols import ProtocolSettings
from pare.results.trajectory import ActionRecord
from pare.scenarios.checks import Judge
from pare.scenarios.model import Scenario
from pare.training.driver import EpisodeDriver, ExternalModel, Request
from pare.training.setup import (
    ORACLE,
    Counterpart,
    Counterparts,
    choose_scenario,
    episode_settings,
    protocol_settings,
    scenario_pool,
)

RewardKind = Literal["acceptance", "success", "goal_rate"]
REWARD_KINDS: tuple[RewardKind, ...] = get_args(RewardKind)
AgentRole = Literal["assistant", "user"]

StepResult = tuple[str, float, bool, bool, dict[str, Any]]
"""What ``step`` returns: observation, reward, terminated, truncated, info."""


def _is_reward(name: str, kinds: tuple[RewardKind, ...]) -> TypeGuard[RewardKind]:
    return name in kinds


class _Watch:
    """What the agent's actor did: the environment it was started on and each action it returned."""

    def __init__(self) -> None:
        self.env: Environment | None = None
        self.actions: list[Action] = []


class _WatchedAssistant(AssistantPolicy):
    """The agent's assistant: PARE's model-backed one, its actions noted."""

    def __init__(self, inner: LLMAssistant, watch: _Watch) -> None:
        self.inner = inner
        self.watch = watch
        self.name = "gym_assistant"

    def start(self, env: Environment, budget: TurnBudget = DEFAULT_BUDGET) -> None:
        """Start the actor and note the environment."""
        self.watch.env = env
        self.inner.start(env, budget)

    async def observe(self, observation: AssistantObservation | None, previous: ToolResult | None) -> Action:
        """The agent's observe-mode action."""
        action = await self.inner.observe(observation, previous)
        self.watch.actions.append(action)
        return action

    async def execute(self, task: Task | None, previous: ToolResult | None) -> Action:
        """The agent's execute-mode action."""
        action = await self.inner.execute(task, previous)
        self.watch.actions.append(action)
        return action

    def finish(
        self, ending: Ending, observation: AssistantObservation, previous: ToolResult | None
    ) -> str | None:
        """The closing observation."""
        return self.inner.finish(ending, observation, previous)


class _WatchedUser(UserPolicy):
    """The agent's user: PARE's model-backed user simulator, its actions noted."""

    def __init__(self, inner: LLMUser, watch: _Watch) -> None:
        self.inner = inner
        self.watch = watch
        self.name = "gym_user"

    def start(self, env: Environment, budget: TurnBudget = DEFAULT_BUDGET) -> None:
        """Start the actor and note the environment."""
        self.watch.env = env
        self.inner.start(env, budget)

    async def step(self, view: UserView, previous: ToolResult | None) -> Action:
        """The agent's action as the user."""
        action = await self.inner.step(view, previous)
        self.watch.actions.append(action)
        return action

    def finish(self, ending: Ending, previous: ToolResult | None, notifications: list[str]) -> str | None:
        """The closing observation."""
        return self.inner.finish(ending, previous, notifications)


class _AsyncPareEnv(ABC):
    """The episode bookkeeping both roles share; subclasses say which role the agent plays."""

    role: ClassVar[AgentRole]
    rewards: ClassVar[tuple[RewardKind, ...]] = REWARD_KINDS

    def __init__(
        self,
        *,
        scenarios: Sequence[str] | None = None,
        split: str | None = None,
        reward: str = "acceptance",
        protocol: str | Mapping[str, Any] | ProtocolSettings | None = None,
        max_format_retries: int = 0,
        side_effects: bool = True,
        judge: Judge | None = None,
        counterpart: Counterpart = ORACLE,
    ) -> None:
        if not _is_reward(reward, self.rewards):
            choices = ", ".join(self.rewards)
            raise UserInputError(
                f"reward '{reward}' is not one of {choices}.{did_you_mean(reward, self.rewards)}"
            )
        if max_format_retries < 0:
            raise UserInputError(f"max_format_retries must be 0 or more, not {max_format_retries}")
        self.reward_kind: RewardKind = reward
        self.pool = scenario_pool(scenarios, split)
        self.protocol = protocol_settings(protocol)
        self.max_format_retries = max_format_retries
        self.side_effects = side_effects
        self.judge = judge
        self.counterparts = Counterparts(counterpart, self.protocol.max_format_retries)
        self._rng = random.Random()
        self._driver: EpisodeDriver | None = None
        self._watch = _Watch()
        self._answered: set[str] = set()
        self.scenario: Scenario | None = None
        """The scenario being played (set by :meth:`reset`)."""
        self.seed: int | None = None
        """The world's seed of the episode being played."""

    @abstractmethod
    def _players(
        self, scenario: Scenario, requests: asyncio.Queue[Request], watch: _Watch
    ) -> tuple[UserPolicy, AssistantPolicy]:
        """The episode's user and assistant, the agent's role played over ``requests``, noted in ``watch``."""

    async def reset(
        self, *, seed: int | None = None, options: Mapping[str, Any] | None = None
    ) -> tuple[str, dict[str, Any]]:
        """Start an episode: ``options={"scenario": id}`` plays that scenario, ``{"split": name}`` draws one
        from that split, no option draws one from the environment's scenarios. ``seed`` seeds the draw and
        the world (the same seed, the same episode); without it the draws go on from the last seed.

        Returns:
            The first observation, and info (``scenario_id``, ``seed``, ``role``, ``messages``).
        """
        await self._stop()
        if seed is not None:
            self._rng = random.Random(seed)
        scenario = choose_scenario(self.pool, options, self._rng)
        self.scenario = scenario
        self.seed = self._rng.getrandbits(32)
        self._watch = _Watch()
        self._answered = set()
        requests: asyncio.Queue[Request] = asyncio.Queue()
        user, assistant = self._players(scenario, requests, self._watch)
        episode = arun_episode(
            scenario,
            user,
            assistant,
            episode_settings(self.protocol, self.seed),
            judge=self.judge,
            side_effects=self.side_effects,
        )
        self._driver = EpisodeDriver(requests, episode)
        first = await self._driver.next()
        if not isinstance(first, Request):
            raise RuntimeError(
                f"scenario '{scenario.id}' ended before the {self.role} was asked anything"
            )  # a turn loop always asks both actors in its first turn
        return first.observation(), self._info(first)

    async def step(self, action: str) -> StepResult:
        """Give ``action`` (the text the role's model would write) and play on until the agent is asked
        again or the episode ends.

        Returns:
            The next observation (the closing text at the end), the reward, whether the episode ended
            (``terminated``: nothing more could happen; ``truncated``: the turn limit), and info: the
            ``action`` the text was read as (``None`` when it was sent back as malformed), its
            ``action_error`` when it failed its step, the ``conversation``; at the end also the verdict
            (``outcome``), ``success``, ``goal_rate``, ``side_effects`` and the ``trajectory``.

        Raises:
            RuntimeError: no episode is under way (call :meth:`reset` first).
        """
        if not isinstance(action, str):
            raise TypeError(f"an action is the text a model would write, not {type(action).__name__}")
        if self._driver is None or self._driver.pending is None:
            raise RuntimeError("no episode is under way: call reset() first (and again after it ended)")
        before = len(self._watch.actions)
        after = await self._driver.answer(action)
        done = [*self._watch.actions[before:]]
        reward = self._answers_reward() if self.reward_kind == "acceptance" else 0.0
        info: dict[str, Any] = {
            "action": ActionRecord.model_validate(done[0], from_attributes=True).model_dump(mode="json")
            if done
            else None,
            "action_error": done[0].error if done else None,
            "format_retry": not done,
        }
        if isinstance(after, Request):
            info.update(self._info(after))
            return after.observation(), reward, False, False, info
        self._driver = None
        info.update(self._final_info(after))
        if self.reward_kind == "success":
            reward = 1.0 if after.outcome.success else 0.0
        elif self.reward_kind == "goal_rate":
            reward = after.outcome.goal_rate
        truncated = after.ended == "max_turns"
        return after.closing.get(self.role, ""), reward, not truncated, truncated, info

    def _answers_reward(self) -> float:
        """+1 for each proposal the user accepted since the last step, -1 for each rejected."""
        env = self._watch.env
        if env is None:
            return 0.0
        reward = 0.0
        for proposal in env.agent_ui.state.proposals:
            if proposal.status in ("accepted", "rejected") and proposal.proposal_id not in self._answered:
                self._answered.add(proposal.proposal_id)
                reward += 1.0 if proposal.status == "accepted" else -1.0
        return reward

    def _info(self, request: Request) -> dict[str, Any]:
        assert self.scenario is not None
        return {
            "scenario_id": self.scenario.id,
            "seed": self.seed,
            "role": self.role,
            "conversation": request.role,
            "messages": request.chat(),
        }

    def _final_info(self, result: EpisodeResult) -> dict[str, Any]:
        outcome = result.outcome
        return {
            "scenario_id": result.scenario_id,
            "seed": self.seed,
            "role": self.role,
            "ended": result.ended,
            "outcome": outcome.to_dict(),
            "success": outcome.success,
            "goal_rate": outcome.goal_rate,
            "side_effects": [change.to_dict() for change in outcome.side_effects],
            "trajectory": {"seed": self.seed, **result.to_dict()},
        }

    async def _stop(self) -> None:
        if self._driver is not None:
            await self._driver.aclose()
            self._driver = None

    async def aclose(self) -> None:
        """Stop the episode under way and close the counterpart's model clients."""
        await self._stop()
        await self.counterparts.aclose()


class AsyncProactiveAssistantEnv(_AsyncPareEnv):
    """The agent plays the proactive assistant; ``user`` is the oracle (default) or a model.

    Keyword arguments: ``scenarios`` (ids) or ``split`` (default ``smoke``) to sample from; ``reward``
    (``acceptance``, the default, ``success`` or ``goal_rate``); ``protocol`` (a preset's name or settings:
    turn limits and the rest); ``max_format_retries`` (default 0); ``side_effects`` (default on: a change of
    the assistant's that no solution makes fails the episode); ``judge`` for free-text checks; ``user``.
    """

    role: ClassVar[AgentRole] = "assistant"

    def __init__(self, *, user: Counterpart = ORACLE, **kwargs: Any) -> None:
        super().__init__(counterpart=user, **kwargs)

    def _players(
        self, scenario: Scenario, requests: asyncio.Queue[Request], watch: _Watch
    ) -> tuple[UserPolicy, AssistantPolicy]:
        agent = LLMAssistant(
            ExternalModel(requests, "observe"),
            ExternalModel(requests, "execute"),
            max_format_retries=self.max_format_retries,
        )
        return self.counterparts.user(scenario), _WatchedAssistant(agent, watch)


class AsyncUserEnv(_AsyncPareEnv):
    """The agent plays the user (with the scenario's persona and goal in its prompt); ``assistant`` is the
    oracle (default) or a model. Rewards: ``success`` (the default) or ``goal_rate``; the acceptance reward
    is the assistant's. Other keyword arguments as :class:`AsyncProactiveAssistantEnv`.
    """

    role: ClassVar[AgentRole] = "user"
    rewards: ClassVar[tuple[RewardKind, ...]] = ("success", "goal_rate")

    def __init__(self, *, assistant: Counterpart = ORACLE, reward: str = "success", **kwargs: Any) -> None:
        super().__init__(counterpart=assistant, reward=reward, **kwargs)

    def _players(
        self, scenario: Scenario, requests: asyncio.Queue[Request], watch: _Watch
    ) -> tuple[UserPolicy, AssistantPolicy]:
        agent = LLMUser(
            ExternalModel(requests, "user"),
            persona=scenario.user.persona,
            goal=scenario.user.goal,
            max_format_retries=self.max_format_retries,
        )
        return _WatchedUser(agent, watch), self.counterparts.assistant(scenario)
