"""Episode timings with instant scripted models: simulation overhead per turn, and prompt sizes.

    python benchmarks/episode.py [--repeat 5]

Plays every library scenario with model-backed actors whose models answer instantly from the oracle's
script (the user waits or follows the oracle's steps, the assistant proposes and acts as the oracle), so
the time measured is PARE's own: prompts, parsing, the environment, the loop. Also prints the prompt
tokens per episode the paper's prompts cost (counted with litellm's tokenizer when installed, else
estimated as characters / 4). Prints numbers only; no assertion.
"""

from __future__ import annotations

import argparse
import asyncio
import os
import statistics
import time
from collections.abc import Sequence
from typing import Any

from pare.agents.actions import format_action
from pare.agents.llm import LLMAssistant, LLMUser
from pare.agents.models.types import ChatMessage, Completion, Usage
from pare.agents.policy import Action, AssistantPolicy, Task, UserPolicy
from pare.bench import arun_episode
from pare.env import AssistantObservation, Environment, ToolResult, UserView
from pare.scenarios import OracleAssistant, OracleUser, Scenario, load_scenarios

os.environ.setdefault("LITELLM_LOCAL_MODEL_COST_MAP", "True")  # litellm's bundled prices: no download
try:
    from litellm import token_counter
except ImportError:  # the litellm extra is optional
    token_counter = None


def count_tokens(messages: Sequence[ChatMessage]) -> int:
    if token_counter is not None:
        return int(token_counter(model="gpt-4o", messages=[m.to_openai() for m in messages]))
    return sum(len(m.content or "") for m in messages) // 4


class OracleDrivenModel:
    """A model that answers what an oracle policy would do, formatted as the paper's text actions."""

    def __init__(self, decide: Any, count: bool) -> None:
        self.decide = decide
        self.count = count
        self.prompt_tokens = 0
        self.calls = 0
        self.sizes: list[int] = []
        """The prompt size of each call, in order: how the conversation grows."""

    async def complete(
        self, messages: Sequence[ChatMessage], tools: Sequence[dict[str, Any]] | None = None
    ) -> Completion:
        self.calls += 1
        if self.count:
            size = count_tokens(messages)
            self.prompt_tokens += size
            self.sizes.append(size)
        action: Action = await self.decide()
        return Completion(
            text=format_action(action.tool, action.args, "Following the plan."),
            usage=Usage(),
            cost_usd=0.0,
            latency_s=0.0,
            model="oracle-driven",
        )


class Bridge(UserPolicy, AssistantPolicy):
    """Feeds the LLM actors' models from the oracle policies, one decision per model call."""

    def __init__(self, scenario: Scenario) -> None:
        self.user = OracleUser(scenario)
        self.assistant = OracleAssistant(scenario)
        self.view: UserView | None = None
        self.previous: ToolResult | None = None
        self.task: Task | None = None

    def start(self, env: Environment, *budget: Any) -> None:
        self.user.start(env, *budget)
        self.assistant.start(env, *budget)

    async def step(self, view: UserView, previous: ToolResult | None) -> Action:
        return await self.user.step(view, previous)

    async def observe(self, observation: AssistantObservation | None, previous: ToolResult | None) -> Action:
        return await self.assistant.observe(observation, previous)

    async def execute(self, task: Task | None, previous: ToolResult | None) -> Action:
        return await self.assistant.execute(task, previous)


class ShimUser(LLMUser):
    def __init__(self, bridge: Bridge, count: bool) -> None:
        self.bridge = bridge
        self.model = OracleDrivenModel(lambda: bridge.step(self._view, self._previous), count)
        super().__init__(self.model)

    def start(self, env: Environment, *budget: Any) -> None:
        self.bridge.start(env, *budget)
        super().start(env, *budget)

    async def step(self, view: UserView, previous: ToolResult | None) -> Action:
        self._view, self._previous = view, previous
        return await super().step(view, previous)


class ShimAssistant(LLMAssistant):
    def __init__(self, bridge: Bridge, count: bool) -> None:
        self.observe_model = OracleDrivenModel(
            lambda: bridge.observe(self._observation, self._previous), count
        )
        self.execute_model = OracleDrivenModel(lambda: bridge.execute(self._task, self._previous), count)
        super().__init__(self.observe_model, self.execute_model)

    async def observe(self, observation: AssistantObservation | None, previous: ToolResult | None) -> Action:
        self._observation, self._previous = observation, previous
        return await super().observe(observation, previous)

    async def execute(self, task: Task | None, previous: ToolResult | None) -> Action:
        self._task, self._previous = task, previous
        return await super().execute(task, previous)


Outcome = tuple[int, int, dict[str, int], bool, dict[str, list[int]]]


async def play(scenario: Scenario, count: bool) -> Outcome:
    """One episode; with ``count``, prompt tokens are counted (slow, so not while timing)."""
    bridge = Bridge(scenario)
    user, assistant = ShimUser(bridge, count), ShimAssistant(bridge, count)
    result = await arun_episode(scenario, user, assistant)
    models = {"user": user.model, "observe": assistant.observe_model, "execute": assistant.execute_model}
    tokens = {role: model.prompt_tokens for role, model in models.items()}
    sizes = {role: model.sizes for role, model in models.items()}
    return result.turns, len(result.steps), tokens, result.success, sizes


def growth_per_call(sizes: list[int]) -> float | None:
    """How much a conversation's prompt grows per call, from its first call to its last."""
    return (sizes[-1] - sizes[0]) / (len(sizes) - 1) if len(sizes) > 1 else None


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5)
    options = parser.parse_args()
    scenarios = load_scenarios()

    async def all_episodes(count: bool = False) -> list[Outcome]:
        return [await play(scenario, count) for scenario in scenarios]

    samples = []
    for _ in range(options.repeat):
        began = time.perf_counter()
        outcomes = asyncio.run(all_episodes())
        samples.append(time.perf_counter() - began)
    elapsed = statistics.median(samples)
    turns = sum(o[0] for o in outcomes)
    steps = sum(o[1] for o in outcomes)
    print(f"episodes: {len(scenarios)}, oracle-driven successes: {sum(o[3] for o in outcomes)}")
    per_turn, per_step = elapsed / turns * 1000, elapsed / steps * 1000
    print(f"simulation overhead: {per_turn:.2f} ms per turn, {per_step:.2f} ms per step")
    print(f"  ({turns} turns, {steps} steps, {elapsed * 1000:.0f} ms in all, median of {options.repeat})")

    outcomes = asyncio.run(all_episodes(count=True))
    counter = "litellm's tokenizer (gpt-4o)" if token_counter is not None else "characters / 4"
    print(f"prompt tokens per episode ({counter}, summed over every model call):")
    for role in ("user", "observe", "execute"):
        values = [o[2][role] for o in outcomes]
        print(f"  {role:8s} mean {statistics.mean(values):9.0f}   max {max(values):9.0f}")
    totals = [sum(o[2].values()) for o in outcomes]
    print(f"  {'total':8s} mean {statistics.mean(totals):9.0f}   max {max(totals):9.0f}")
    print("prompt tokens per turn (per episode: a role's prompt tokens / the episode's turns), and growth:")
    for role in ("user", "observe", "execute"):
        per_turn_values = [o[2][role] / o[0] for o in outcomes if o[0]]
        first = [o[4][role][0] for o in outcomes if o[4][role]]
        growth = [g for o in outcomes if (g := growth_per_call(o[4][role])) is not None]
        print(
            f"  {role:8s} {statistics.mean(per_turn_values):7.0f} per turn;"
            f" first prompt {statistics.mean(first):6.0f};"
            f" grows {statistics.mean(growth) if growth else 0:5.0f} per call"
        )


if __name__ == "__main__":
    main()
