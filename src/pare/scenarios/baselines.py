"""Assistants that need no model: the floor a model's results are read against.

A benchmark's numbers mean little without a floor. These four assistants play through the same turn loop
as any other and stand for the ways of scoring without understanding anything:

* ``silent`` never proposes. It can succeed only where staying quiet is right (the no-proposal
  scenarios), so its success rate is at most the library's no-proposal share; above it, some scenario
  passes an assistant that did nothing.
* ``generic_offer`` proposes the same vague help whenever nothing is waiting for an answer and, if
  accepted, does nothing. It measures how far a user accepts an offer that names no task.
* ``propose_only`` proposes exactly what the scenario's oracle proposes, when the oracle does, and after
  the acceptance reports the oracle's summary without making a single call. It measures whether the
  checks read the world rather than the assistant's account of it: it should succeed nowhere a task was
  needed.
* ``random`` waits, reads or proposes at random and, once accepted, makes random calls with plausible
  arguments before reporting: an assistant that acts without reasons (seeded per episode).

Each is built from the episode's scenario and seed by :data:`BASELINES`.
"""

from __future__ import annotations

import random
from collections.abc import Callable
from dataclasses import dataclass

from pare.agents.policy import (
    ASSISTANT_WAIT,
    DEFAULT_BUDGET,
    SEND_MESSAGE,
    Action,
    AssistantPolicy,
    SilentAssistant,
    Task,
    TurnBudget,
)
from pare.env import AssistantObservation, Environment, ToolResult
from pare.env.random_walk import RandomAssistant
from pare.scenarios.model import Scenario
from pare.scenarios.oracle import OracleAssistant

GENERIC_OFFER = "I noticed new activity on your phone. Would you like me to take care of it for you?"
"""The offer ``generic_offer`` and ``random`` make: it names no task."""
DONE = "Done."


class GenericOfferAssistant(AssistantPolicy):
    """Offers vague help at the first step of every turn in which no proposal awaits an answer."""

    name = "generic_offer"

    def __init__(self) -> None:
        self.env: Environment | None = None

    def start(self, env: Environment, budget: TurnBudget = DEFAULT_BUDGET) -> None:
        """Remember the environment, to see whether a proposal still awaits an answer."""
        self.env = env

    async def observe(self, observation: AssistantObservation | None, previous: ToolResult | None) -> Action:
        """Propose on a turn's first step when nothing is pending; otherwise wait."""
        if observation is not None and self.env is not None and self.env.agent_ui.pending is None:
            return Action(SEND_MESSAGE, {"content": GENERIC_OFFER})
        return Action(ASSISTANT_WAIT)

    async def execute(self, task: Task | None, previous: ToolResult | None) -> Action:
        """Do nothing and say it is done."""
        return Action(SEND_MESSAGE, {"content": DONE})


class ProposeOnlyAssistant(AssistantPolicy):
    """Proposes what the oracle proposes, when it does; once accepted, reports without doing anything."""

    name = "propose_only"

    def __init__(self, scenario: Scenario) -> None:
        self.oracle = OracleAssistant(scenario)

    def start(self, env: Environment, budget: TurnBudget = DEFAULT_BUDGET) -> None:
        """Start the oracle whose proposals it copies."""
        self.oracle.start(env, budget)

    async def observe(self, observation: AssistantObservation | None, previous: ToolResult | None) -> Action:
        """The oracle's next proposal when its moment has come; otherwise wait."""
        return await self.oracle.observe(observation, previous)

    async def execute(self, task: Task | None, previous: ToolResult | None) -> Action:
        """Report the oracle's summary of the task, having done none of it."""
        proposal = task.proposal if task is not None else None
        intervention = next((i for i in self.oracle.solution.interventions if i.proposal == proposal), None)
        return Action(SEND_MESSAGE, {"content": intervention.report if intervention is not None else DONE})


class RandomBaselineAssistant(AssistantPolicy):
    """Waits, reads or offers help at random; when accepted, makes random app calls, then reports."""

    name = "random"

    READ_SHARE = 0.4
    OFFER_SHARE = 0.1
    EXECUTE_CALLS = 3

    def __init__(self, seed: int) -> None:
        self.rng = random.Random(f"baseline-random:{seed}")
        self.env: Environment | None = None
        self.calls_left = 0

    def start(self, env: Environment, budget: TurnBudget = DEFAULT_BUDGET) -> None:
        """Remember the environment: the random calls are drawn from its tools."""
        self.env = env

    async def observe(self, observation: AssistantObservation | None, previous: ToolResult | None) -> Action:
        """A random read (40%), a vague offer (10%, when nothing is pending) or a wait."""
        env = self._env()
        draw = self.rng.random()
        if draw < self.READ_SHARE:
            tool, args = RandomAssistant(self.rng, mode="observe").choose(env)
            return Action(tool.name, args)
        if draw < self.READ_SHARE + self.OFFER_SHARE and env.agent_ui.pending is None:
            return Action(SEND_MESSAGE, {"content": GENERIC_OFFER})
        return Action(ASSISTANT_WAIT)

    async def execute(self, task: Task | None, previous: ToolResult | None) -> Action:
        """A few random app calls with plausible arguments, then a report."""
        if task is not None:
            self.calls_left = self.EXECUTE_CALLS
        if self.calls_left > 0:
            self.calls_left -= 1
            tool, args = RandomAssistant(self.rng, mode="execute").choose(self._env())
            return Action(tool.name, args)
        return Action(SEND_MESSAGE, {"content": DONE})

    def _env(self) -> Environment:
        if self.env is None:
            raise RuntimeError("RandomBaselineAssistant.start() was not called")
        return self.env


@dataclass(frozen=True)
class Baseline:
    """One model-free assistant: its name, what it stands for, and how an episode builds it."""

    name: str
    description: str
    build: Callable[[Scenario, int], AssistantPolicy]


BASELINES: dict[str, Baseline] = {
    baseline.name: baseline
    for baseline in (
        Baseline("silent", "never proposes", lambda scenario, seed: SilentAssistant()),
        Baseline(
            "generic_offer",
            "offers vague help whenever nothing is pending; does nothing when accepted",
            lambda scenario, seed: GenericOfferAssistant(),
        ),
        Baseline(
            "propose_only",
            "proposes the right task at the right time; reports it done without doing anything",
            lambda scenario, seed: ProposeOnlyAssistant(scenario),
        ),
        Baseline(
            "random",
            "reads, waits and offers help at random; makes random calls when accepted",
            lambda scenario, seed: RandomBaselineAssistant(seed),
        ),
    )
}
"""The model-free assistants by name, in the order reports show them."""
