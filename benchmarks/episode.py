"""Episode timings with instant models: PARE's own overhead per turn, and prompt sizes.

    python benchmarks/episode.py [--repeat 5] [--quiet]

Plays every library scenario with the model-backed actors (:class:`~pare.agents.llm.LLMUser`,
:class:`~pare.agents.llm.LLMAssistant`) in two stages:

1. **Recording (untimed).** The actors' models answer what the scenario's oracle would do (the user
   waits or follows the oracle's steps, the assistant proposes and acts as the oracle), formatted as the
   paper's text actions. Every answer is kept, per episode and per model, in order. Unless ``--quiet``,
   the prompt tokens of every call are counted here (litellm's tokenizer when installed, else characters
   / 4): the prompts are the same in every pass.
2. **Timing (``--repeat`` passes).** The same episodes again, each model replaying its recorded answers
   in order: same prompts, same answers, so the episodes are the same. What is timed is PARE's own work
   per model call (rendering prompts and observations, parsing answers, the environment, the turn loop,
   evaluating the goals), with no model work in it. Each episode is compared with its recording (its
   whole result as JSON) as soon as it ends, untimed, and dropped, as a run drops an episode once it is
   stored; a difference is printed, as it means an episode is not deterministic. As in ``pare run``,
   everything alive before the timed passes (the library, the recordings) is frozen out of the cyclic
   collector's sight while they play (:mod:`pare.bench.collector`). Figures printed before these two
   changes counted the collector walking the recordings and the pass's results too, about a third more.

The figure is the timed pass's time over its turns, so it includes what an episode does once whatever
its length (building the environment, the system prompts, evaluating the goals, the state diff); the
library's oracle episodes are short (about five turns), so a second line splits that work from the
turns' own.

**The figure's definition changed** (issue 13). Before, the timed passes ran the model doubles live: at
every call the oracle policy decided, ``format_action`` wrote the answer and parsed it back to check it,
which is the model's work, not PARE's (about a fifth of the old figure, 0.70-0.86 ms per turn). Now only
the replay is timed, so figures printed by this version are lower and not comparable with older ones.

:class:`Bridge`, :class:`ShimUser` and :class:`ShimAssistant` (the recording actors) are also what
``benchmarks/fingerprint.py`` plays in its ``llm`` configuration. Prints numbers only; no assertion.
"""

from __future__ import annotations

import argparse
import asyncio
import functools
import hashlib
import inspect
import json
import os
import statistics
import time
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass, field
from typing import Any, cast

import pare.bench.episode as episode_module
from pare.agents.actions import format_action
from pare.agents.llm import LLMAssistant, LLMUser
from pare.agents.models.types import ChatMessage, Completion, Usage
from pare.agents.policy import Action, AssistantPolicy, Task, UserPolicy
from pare.bench import EpisodeResult, arun_episode
from pare.bench.collector import long_lived_frozen
from pare.env import AssistantObservation, Environment, ToolResult, UserView
from pare.scenarios import OracleAssistant, OracleUser, Scenario, load_scenarios

ROLES = ("user", "observe", "execute")


@functools.cache
def tokenizer() -> Callable[..., int] | None:
    """litellm's token counter, imported on first use (it takes seconds), or ``None`` without litellm."""
    os.environ.setdefault("LITELLM_LOCAL_MODEL_COST_MAP", "True")  # litellm's bundled prices: no download
    try:
        from litellm import token_counter
    except ImportError:  # the litellm extra is optional
        return None
    return cast(Callable[..., int], token_counter)


def count_tokens(messages: Sequence[ChatMessage]) -> int:
    counter = tokenizer()
    if counter is not None:
        return int(counter(model="gpt-4o", messages=[m.to_openai() for m in messages]))
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
        self.answers: list[Completion] = []
        """Every answer given, in order: what a :class:`ReplayModel` gives back."""

    async def complete(
        self, messages: Sequence[ChatMessage], tools: Sequence[dict[str, Any]] | None = None
    ) -> Completion:
        self.calls += 1
        if self.count:
            size = count_tokens(messages)
            self.prompt_tokens += size
            self.sizes.append(size)
        action: Action = await self.decide()
        completion = Completion(
            text=format_action(action.tool, action.args, "Following the plan."),
            usage=Usage(),
            cost_usd=0.0,
            latency_s=0.0,
            model="oracle-driven",
        )
        self.answers.append(completion)
        return completion


class ReplayModel:
    """A model that gives back recorded answers in order, whatever it is asked: no work of its own."""

    def __init__(self, answers: Sequence[Completion]) -> None:
        self._answers: Iterator[Completion] = iter(answers)

    async def complete(
        self, messages: Sequence[ChatMessage], tools: Sequence[dict[str, Any]] | None = None
    ) -> Completion:
        answer = next(self._answers, None)
        if answer is None:
            raise RuntimeError("the episode asked for more answers than were recorded: not deterministic")
        return answer


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


@dataclass
class Recording:
    """One episode as the oracle-driven models played it: their answers, and what came of it."""

    scenario: Scenario
    answers: dict[str, list[Completion]]
    """Per role (user, observe, execute), every answer in order."""
    turns: int
    steps: int
    success: bool
    digest: str
    """The SHA-256 of the episode's whole result as JSON: a replay must give the same."""
    tokens: dict[str, int] = field(default_factory=dict)
    """Per role, the prompt tokens summed over its calls (when counted)."""
    sizes: dict[str, list[int]] = field(default_factory=dict)
    """Per role, the prompt tokens of each call, in order (when counted)."""


def digest(result: EpisodeResult) -> str:
    text = json.dumps(result.to_dict(), sort_keys=True, ensure_ascii=False)
    return hashlib.sha256(text.encode()).hexdigest()


async def record(scenario: Scenario, count: bool) -> Recording:
    """Play one episode with oracle-driven models, keeping their answers (and prompt sizes if ``count``)."""
    bridge = Bridge(scenario)
    user, assistant = ShimUser(bridge, count), ShimAssistant(bridge, count)
    result = await arun_episode(scenario, user, assistant)
    models = {"user": user.model, "observe": assistant.observe_model, "execute": assistant.execute_model}
    return Recording(
        scenario=scenario,
        answers={role: model.answers for role, model in models.items()},
        turns=result.turns,
        steps=len(result.steps),
        success=result.success,
        digest=digest(result),
        tokens={role: model.prompt_tokens for role, model in models.items()} if count else {},
        sizes={role: model.sizes for role, model in models.items()} if count else {},
    )


async def replay(recording: Recording) -> EpisodeResult:
    """Play a recorded episode again, the actors' models giving back the recorded answers."""
    answers = recording.answers
    user = LLMUser(ReplayModel(answers["user"]))
    assistant = LLMAssistant(ReplayModel(answers["observe"]), ReplayModel(answers["execute"]))
    return await arun_episode(recording.scenario, user, assistant)


@dataclass
class Pass:
    """One timed pass: its time without the checking, and the scenarios whose replay differed."""

    seconds: float = 0.0
    differing: list[str] = field(default_factory=list)


async def replay_pass(recordings: list[Recording]) -> Pass:
    """Replay every recording, each compared with its recording as soon as it ends and then dropped, as
    a run drops an episode once it is stored (kept, the pass's results would make the collector walk
    them all again and again: a twelfth of the pass). The comparison is not timed: it is not PARE's work.
    """
    timed = Pass()
    for recording in recordings:
        began = time.perf_counter()
        result = await replay(recording)
        timed.seconds += time.perf_counter() - began
        if digest(result) != recording.digest:
            timed.differing.append(recording.scenario.id)
        del result
    return timed


def growth_per_call(sizes: list[int]) -> float | None:
    """How much a conversation's prompt grows per call, from its first call to its last."""
    return (sizes[-1] - sizes[0]) / (len(sizes) - 1) if len(sizes) > 1 else None


def print_tokens(recordings: list[Recording]) -> None:
    counter = "litellm's tokenizer (gpt-4o)" if tokenizer() is not None else "characters / 4"
    print(f"prompt tokens per episode ({counter}, summed over every model call):")
    for role in ROLES:
        values = [r.tokens[role] for r in recordings]
        print(f"  {role:8s} mean {statistics.mean(values):9.0f}   max {max(values):9.0f}")
    totals = [sum(r.tokens.values()) for r in recordings]
    print(f"  {'total':8s} mean {statistics.mean(totals):9.0f}   max {max(totals):9.0f}")
    print("prompt tokens per turn (per episode: a role's prompt tokens / the episode's turns), and growth:")
    for role in ROLES:
        per_turn_values = [r.tokens[role] / r.turns for r in recordings if r.turns]
        first = [r.sizes[role][0] for r in recordings if r.sizes[role]]
        growth = [g for r in recordings if (g := growth_per_call(r.sizes[role])) is not None]
        print(
            f"  {role:8s} {statistics.mean(per_turn_values):7.0f} per turn;"
            f" first prompt {statistics.mean(first):6.0f};"
            f" grows {statistics.mean(growth) if growth else 0:5.0f} per call"
        )


class EpisodeWork:
    """Times the work each episode does once, whatever its length, during the timed passes: building
    the environment, the actors' system prompts at the start, grading the episode (its goals and side
    effects) and the state diff at the end. The rest of an episode's time is its turns.
    """

    PLACES: tuple[tuple[Any, str], ...] = (
        (episode_module, "build_environment"),
        (LLMUser, "start"),
        (LLMAssistant, "start"),
        (episode_module, "grade"),
        (episode_module, "state_changes"),
    )

    def __init__(self) -> None:
        self.seconds = 0.0
        self.counting = False
        for owner, name in self.PLACES:
            setattr(owner, name, self._timed(getattr(owner, name)))

    def _timed(self, function: Callable[..., Any]) -> Callable[..., Any]:
        if inspect.iscoroutinefunction(function):  # grading awaits the judge: time the awaited call

            @functools.wraps(function)
            async def timed_async(*args: Any, **kwargs: Any) -> Any:
                if not self.counting:
                    return await function(*args, **kwargs)
                began = time.perf_counter()
                try:
                    return await function(*args, **kwargs)
                finally:
                    self.seconds += time.perf_counter() - began

            return timed_async

        @functools.wraps(function)
        def timed(*args: Any, **kwargs: Any) -> Any:
            if not self.counting:
                return function(*args, **kwargs)
            began = time.perf_counter()
            try:
                return function(*args, **kwargs)
            finally:
                self.seconds += time.perf_counter() - began

        return timed


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5, help="Timed replay passes (the median is shown).")
    parser.add_argument(
        "--quiet", action="store_true", help="Do not count prompt tokens (litellm is slow to import and run)."
    )
    options = parser.parse_args()
    scenarios = load_scenarios()

    async def record_all() -> list[Recording]:
        return [await record(scenario, count=not options.quiet) for scenario in scenarios]

    recordings = asyncio.run(record_all())
    once = EpisodeWork()
    samples = []
    fixed = []
    differing: set[str] = set()
    # As in `pare run`: the library and everything alive before the episodes (here the recordings too)
    # are out of the cyclic collector's sight while the episodes play (pare.bench.collector).
    with long_lived_frozen():
        for _ in range(options.repeat):
            once.seconds, once.counting = 0.0, True
            timed = asyncio.run(replay_pass(recordings))
            samples.append(timed.seconds)
            once.counting = False
            fixed.append(once.seconds)
            differing.update(timed.differing)
    elapsed = statistics.median(samples)
    turns = sum(r.turns for r in recordings)
    steps = sum(r.steps for r in recordings)
    print(f"episodes: {len(recordings)}, oracle-driven successes: {sum(r.success for r in recordings)}")
    if differing:
        print(f"WARNING: {len(differing)} replayed episodes differ from their recording: {sorted(differing)}")
    else:
        print("every replayed episode is identical to its recording")
    per_turn, per_step = elapsed / turns * 1000, elapsed / steps * 1000
    print(f"PARE overhead (replayed answers): {per_turn:.2f} ms per turn, {per_step:.2f} ms per step")
    fastest = min(samples) / turns * 1000  # on a busy machine, the least disturbed pass
    print(
        f"  ({turns} turns, {steps} steps, {elapsed * 1000:.0f} ms in all, median of {options.repeat};"
        f" fastest pass {fastest:.2f} ms per turn)"
    )
    # the pass whose total is the median, split into what an episode does once and what its turns do
    middle = sorted(range(len(samples)), key=samples.__getitem__)[len(samples) // 2]
    once_ms = fixed[middle] / len(recordings) * 1000
    turn_ms = (samples[middle] - fixed[middle]) / turns * 1000
    print(
        f"  of which once per episode (environment, system prompts, goals, state diff): {once_ms:.2f} ms;"
        f" the turns alone: {turn_ms:.2f} ms per turn"
    )
    if not options.quiet:
        print_tokens(recordings)


if __name__ == "__main__":
    main()
