"""What a run would do, before it does it: roles, API keys, episodes, and an estimate of calls and cost.

``pare run --dry-run`` prints this without calling any provider and without creating the run folder.

The estimate is built from PARE's real prompts, not from a guess at their size. Each planned scenario is
played once by the model-backed actors (:class:`~pare.agents.llm.LLMUser`,
:class:`~pare.agents.llm.LLMAssistant`) whose models answer what the scenario's oracle would do, so every
prompt is the one a model would be sent on that path: the rendered system prompts, the screens, the
observations, the growing conversation. Their characters are counted and turned into tokens at
:data:`CHARS_PER_TOKEN`. Two figures come out per role:

* **typical**: the oracle's path, i.e. a model that does what the scenario needs, turn for turn; each
  answer written as one thought of :data:`THOUGHT_CHARS` characters and one action;
* **upper bound**: every episode runs all ``max_turns`` turns at the oracle path's pace (its calls per
  turn for the user and observe mode), every accepted task (at least one) uses all ``execute_steps``,
  each call's prompt grows by what a call added to that role's conversation on the oracle's path, and
  each answer is ``max_tokens`` long when the role sets it. A model that also uses every step of every
  turn can make more calls: :func:`ceiling_calls` says how many at most.

Neither counts malformed answers sent back to the model (at most ``max_format_retries`` a step) or a
reasoning model's thinking beyond ``max_tokens``. Costs use the configuration's ``prices``, else
litellm's price table when it is installed and knows the model, else they are unknown (never 0).
"""

from __future__ import annotations

import asyncio
import json
import math
import os
from collections.abc import Callable, Coroutine, Iterable, Mapping, Sequence
from dataclasses import asdict, dataclass, field
from typing import Any

from pare.agents.actions import format_action
from pare.agents.judge import JUDGE_PROMPT
from pare.agents.llm import EXECUTE_OPENING, LLMAssistant, LLMUser
from pare.agents.models.config import ModelConfig
from pare.agents.models.pricing import call_cost, price_source
from pare.agents.models.secrets import redact_secrets
from pare.agents.models.types import ChatMessage, Completion, Usage
from pare.agents.policy import DEFAULT_BUDGET, Action, Task, TurnBudget
from pare.bench.episode import arun_episode
from pare.bench.policies import PolicyRole
from pare.bench.runconfig import RunConfig
from pare.env import AssistantObservation, Environment, ToolResult, UserView
from pare.results.run_folder import EPISODES, MANIFEST, latest_records, read_manifest, read_records
from pare.scenarios.model import Scenario
from pare.scenarios.oracle import OracleAssistant, OracleUser

CHARS_PER_TOKEN = 4.0
"""Characters per token of PARE's prompts, measured on what the oracle's path sends (every call's whole
conversation, a sixth of the library): 3.96 with the o200k_base encoding (GPT-4o's) and with cl100k_base
(GPT-4's), 4.1 for the system prompts alone; 3.7 with Anthropic's older published tokenizer. Other
models' tokenizers may differ by a tenth or more."""

THOUGHT = (
    "The user is busy with something else, so I look at what changed on the phone and what it means for "
    "them before I decide on my next step; nothing here needs more than one action."
)
"""The thought written in each estimated answer (THOUGHT_CHARS characters of plain English prose)."""
THOUGHT_CHARS = len(THOUGHT)
"""About twice the prompts' own example thoughts: one or two sentences. Reasoning models think far more
(billed as output tokens): set ``max_tokens`` to bound it."""

JUDGED_TEXT_CHARS = 1_000
"""Length assumed for a text the judge reads (an email or message the assistant wrote)."""

JUDGE_ANSWER_TOKENS = 30
"""The judge answers YES or NO and one sentence saying why."""


# -- roles and keys ----------------------------------------------------------------------------------------
@dataclass(frozen=True)
class RoleLine:
    """One role as the run would play it."""

    role: str
    model: str | None
    """``None``: the scenario's oracle plays it (or, for the judge, the checks' deterministic fallback)."""
    backend: str | None = None
    endpoint: str | None = None
    """Without credentials."""
    sampling: dict[str, Any] = field(default_factory=dict)
    """The parameters sent with every request (empty: none, the server's defaults apply); secret-looking
    values masked, as in the manifest."""
    native_tools: bool = False
    inherited_from: str | None = None
    """The role whose model this one uses because it was not set itself."""
    prices: str | None = None
    """Where its prices come from: ``config``, ``litellm``, or ``None`` (unknown)."""
    policy: str = "model"
    """Who plays the role (:mod:`pare.bench.policies`): ``model``, ``oracle``, ``deterministic`` for the
    judge, another built-in name, or an import path."""


@dataclass(frozen=True)
class KeyStatus:
    """Whether the API key a role needs is in the environment (its value is never read out)."""

    variable: str | None
    """The variable's name; ``None`` when no key is sent (a local server)."""
    roles: tuple[str, ...]
    found: bool | None
    """``None`` when nothing is needed or it cannot be told here."""
    note: str = ""


_PLAYED_AS: dict[str, PolicyRole] = {
    "user": "user",
    "observe": "assistant",
    "execute": "assistant",
    "judge": "judge",
}
"""The policy that plays each model role."""


def role_lines(config: RunConfig) -> list[RoleLine]:
    """The user, observe, execute and judge roles: their models, or who plays them without one."""
    models = config.models
    configured = models.roles()
    lines: list[RoleLine] = []
    for role in ("user", "observe", "execute", "judge"):
        model = configured.get(role)
        policy = config.policy(_PLAYED_AS[role])
        if model is None:
            lines.append(RoleLine(role=role, model=None, policy=policy))
            continue
        lines.append(
            RoleLine(
                role=role,
                model=model.model,
                backend=model.backend,
                endpoint=model.endpoint(),
                sampling=redact_secrets(dict(model.request_params())),
                native_tools=model.native_tools,
                inherited_from=models.inherited_from(role),
                prices=price_source(model),
                policy=policy,
            )
        )
    return lines


def key_statuses(config: RunConfig, environ: Mapping[str, str] | None = None) -> list[KeyStatus]:
    """For each API key variable the roles need, whether it is set (and not blank) in ``environ``.

    A litellm role without a variable of its own is checked by litellm, which reads the provider's usual
    variable from the process's environment itself.
    """
    environ = os.environ if environ is None else environ
    found: dict[tuple[str | None, bool | None, str], list[str]] = {}
    for role, model in config.models.roles().items():
        for variable, present, note in _role_keys(model, environ):
            found.setdefault((variable, present, note), []).append(role)
    return [
        KeyStatus(variable, tuple(roles), present, note) for (variable, present, note), roles in found.items()
    ]


def _role_keys(model: ModelConfig, environ: Mapping[str, str]) -> list[tuple[str | None, bool | None, str]]:
    """The variables one role needs: (name, whether set, a note)."""
    if model.api_key_env is not None:
        return [(model.api_key_env, bool(environ.get(model.api_key_env, "").strip()), "")]
    if model.backend != "litellm" or model.api_base is not None:
        return [(None, None, "no key sent (api_key_env is null: a local server)")]
    from pare.agents.models.backends import import_litellm, litellm_available

    if not litellm_available():
        return [(None, False, "the litellm backend is not installed")]
    missing = import_litellm().validate_environment(model=model.model).get("missing_keys", [])
    if missing:
        return [(str(name), False, "") for name in missing]
    return [(None, True, "litellm finds the provider's key in the environment")]


# -- episodes ----------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class EpisodeCount:
    """The planned episodes, and what an existing run folder already holds."""

    scenarios: int
    runs: int
    planned: int
    finished: int
    folder: str
    folder_exists: bool
    refused: str | None = None
    """Why ``pare run`` would refuse the existing folder, if it would."""

    @property
    def to_run(self) -> int:
        """Episodes the run would play."""
        return 0 if self.refused else self.planned - self.finished


def count_episodes(
    config: RunConfig, scenario_ids: Iterable[str]
) -> tuple[EpisodeCount, set[tuple[str, int]]]:
    """The planned episodes and the keys of those already finished in the run folder (read only)."""
    ids = sorted(scenario_ids)
    folder = config.output_dir()
    planned = {(scenario_id, run) for scenario_id in ids for run in range(1, config.runs + 1)}
    finished: set[tuple[str, int]] = set()
    refused = None
    manifest_file = folder / MANIFEST
    if manifest_file.exists():
        manifest = read_manifest(manifest_file)
        if manifest.get("identity") != config.identity():
            refused = (
                f"{folder} holds a run of a different configuration: pare run would refuse it and list "
                "the differences; pass another --output"
            )
        else:
            records = latest_records(read_records(folder / EPISODES))
            finished = {key for key, record in records.items() if record.complete and key in planned}
    count = EpisodeCount(
        scenarios=len(ids),
        runs=config.runs,
        planned=len(planned),
        finished=len(finished),
        folder=str(folder),
        folder_exists=folder.exists(),
        refused=refused,
    )
    return count, finished


# -- measuring the prompts ---------------------------------------------------------------------------------
@dataclass
class _Conversations:
    """Prompt characters of every call of one role, conversation by conversation."""

    prompts: list[list[int]] = field(default_factory=list)
    answers: list[int] = field(default_factory=list)
    _last_length: int = 0

    def add(self, messages: Sequence[ChatMessage], tools: Sequence[dict[str, Any]] | None) -> None:
        if not self.prompts or len(messages) <= self._last_length:  # a reset: a new conversation
            self.prompts.append([])
        self._last_length = len(messages)
        size = sum(_message_chars(message) for message in messages)
        if tools:
            size += len(json.dumps(list(tools)))
        self.prompts[-1].append(size)

    @property
    def calls(self) -> int:
        return sum(len(conversation) for conversation in self.prompts)


def _message_chars(message: ChatMessage) -> int:
    size = len(message.content or "")
    for call in message.tool_calls or ():
        size += len(call.name) + len(call.arguments)
    return size


class _OracleDrivenModel:
    """A chat model that answers what an oracle policy decides, and counts what it is sent."""

    def __init__(self, decide: Callable[[], Coroutine[Any, Any, Action]]) -> None:
        self.decide = decide
        self.measured = _Conversations()

    async def complete(
        self, messages: Sequence[ChatMessage], tools: Sequence[dict[str, Any]] | None = None
    ) -> Completion:
        self.measured.add(messages, tools)
        action = await self.decide()
        text = format_action(action.tool, action.args, THOUGHT)
        self.measured.answers.append(len(text))
        return Completion(text=text, usage=Usage(), cost_usd=None, latency_s=0.0, model="estimate")


@dataclass(frozen=True)
class ScenarioShape:
    """What one scenario's episode costs on the oracle's path, per role (characters)."""

    scenario_id: str
    turns: int
    prompts: dict[str, list[list[int]]]
    """Per actor role, each conversation's prompt sizes, call by call."""
    answers: dict[str, list[int]]
    """Per actor role, each answer's length."""
    judge_criteria: list[int]
    """The length of each judge check's criterion, with its facts."""
    first_prompt: dict[str, int]
    """Per actor role, the first call's prompt (system prompt and first observation)."""


class _Oracles:
    """The oracle policies that decide the oracle-driven models' answers, and what each was last shown."""

    def __init__(self, scenario: Scenario) -> None:
        self.user = OracleUser(scenario)
        self.assistant = OracleAssistant(scenario)
        self.view: UserView | None = None
        self.observation: AssistantObservation | None = None
        self.task: Task | None = None
        self.user_previous: ToolResult | None = None
        self.assistant_previous: ToolResult | None = None

    async def user_step(self) -> Action:
        assert self.view is not None  # set by _MeasuringUser.step before its model is called
        return await self.user.step(self.view, self.user_previous)

    async def observe(self) -> Action:
        return await self.assistant.observe(self.observation, self.assistant_previous)

    async def execute(self) -> Action:
        return await self.assistant.execute(self.task, self.assistant_previous)


class _MeasuringUser(LLMUser):
    """The LLM user, telling the oracle what its model is about to be asked about."""

    def __init__(
        self, oracles: _Oracles, model: _OracleDrivenModel, scenario: Scenario, native: bool
    ) -> None:
        super().__init__(model, persona=scenario.user.persona, goal=scenario.user.goal, native_tools=native)
        self.oracles = oracles

    def start(self, env: Environment, budget: TurnBudget = DEFAULT_BUDGET) -> None:
        self.oracles.user.start(env, budget)
        super().start(env, budget)

    async def step(self, view: UserView, previous: ToolResult | None) -> Action:
        self.oracles.view, self.oracles.user_previous = view, previous
        return await super().step(view, previous)


class _MeasuringAssistant(LLMAssistant):
    """The LLM assistant, telling the oracle what its models are about to be asked about."""

    def __init__(
        self, oracles: _Oracles, observe: _OracleDrivenModel, execute: _OracleDrivenModel, native: bool
    ) -> None:
        super().__init__(observe, execute, native_tools=native)
        self.oracles = oracles

    def start(self, env: Environment, budget: TurnBudget = DEFAULT_BUDGET) -> None:
        self.oracles.assistant.start(env, budget)
        super().start(env, budget)

    async def observe(self, observation: AssistantObservation | None, previous: ToolResult | None) -> Action:
        self.oracles.observation, self.oracles.assistant_previous = observation, previous
        return await super().observe(observation, previous)

    async def execute(self, task: Task | None, previous: ToolResult | None) -> Action:
        self.oracles.task, self.oracles.assistant_previous = task, previous
        return await super().execute(task, previous)


async def measure_scenario(scenario: Scenario, config: RunConfig, seed: int) -> ScenarioShape:
    """Play ``scenario`` once with model-backed actors whose models answer as the oracle would."""
    roles = config.models.roles()

    def native(role: str) -> bool:
        model = roles.get(role)
        return model is not None and model.native_tools

    oracles = _Oracles(scenario)
    models = {
        "user": _OracleDrivenModel(oracles.user_step),
        "observe": _OracleDrivenModel(oracles.observe),
        "execute": _OracleDrivenModel(oracles.execute),
    }
    user = _MeasuringUser(oracles, models["user"], scenario, native("user"))
    assistant = _MeasuringAssistant(oracles, models["observe"], models["execute"], native("observe"))
    result = await arun_episode(scenario, user, assistant, config.episode_settings(seed))
    measured = {role: model.measured for role, model in models.items()}
    first_prompt = {role: m.prompts[0][0] for role, m in measured.items() if m.prompts}
    if "execute" not in first_prompt:  # no task on the oracle's path: what starting one would send
        first_prompt["execute"] = _execute_opening(result.env, assistant, config)
    return ScenarioShape(
        scenario_id=scenario.id,
        turns=result.turns,
        prompts={role: m.prompts for role, m in measured.items()},
        answers={role: m.answers for role, m in measured.items()},
        judge_criteria=[
            len(check.judge.criterion) + sum(len(f"- {fact}\n") for fact in check.judge.facts)
            for goal in scenario.goals
            for check in goal.checks
            if check.judge
        ],
        first_prompt=first_prompt,
    )


def _execute_opening(env: Environment, assistant: LLMAssistant, config: RunConfig) -> int:
    """The first execute call's prompt, for a task as long as a thought, on the episode's phone."""
    from pare.agents.prompts import execute_system_prompt

    task = Task(proposal=THOUGHT, answer="Yes, go ahead.", proposal_id="estimate")
    prompt = execute_system_prompt(
        env, task, max_steps=config.protocol.execute_steps, native_tools=assistant.executor.native_tools
    )
    return len(prompt) + len(EXECUTE_OPENING)


def measure_scenarios(config: RunConfig, scenarios: Mapping[str, Scenario]) -> dict[str, ScenarioShape]:
    """:func:`measure_scenario` for each scenario, with the seed of its first run."""

    async def measure_all() -> dict[str, ScenarioShape]:
        return {
            scenario_id: await measure_scenario(scenario, config, config.episode_seed(scenario_id, 1))
            for scenario_id, scenario in sorted(scenarios.items())
        }

    return asyncio.run(measure_all())


# -- the estimate ------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Span:
    """A typical figure and an upper bound."""

    typical: float
    upper: float

    def __add__(self, other: Span) -> Span:
        return Span(self.typical + other.typical, self.upper + other.upper)


ZERO = Span(0.0, 0.0)


@dataclass(frozen=True)
class RoleEstimate:
    """One role's calls, tokens and cost over the episodes still to run."""

    role: str
    model: str
    calls: Span
    prompt_tokens: Span
    completion_tokens: Span
    cost_usd: Span | None
    """``None``: the model's prices are unknown."""


@dataclass(frozen=True)
class Estimate:
    """Calls, tokens and cost of the episodes still to run, per role and in total."""

    episodes: int
    roles: list[RoleEstimate]
    ceiling_calls_per_episode: int
    """The most calls an episode can make (:func:`ceiling_calls`)."""
    mean_turns: float
    """Turns of the oracle's path, averaged over the episodes to run (the typical length)."""
    max_turns: int
    """The protocol's turn limit (the upper bound's length)."""
    chars_per_token: float = CHARS_PER_TOKEN

    @property
    def cost_usd(self) -> Span | None:
        """The total cost, or ``None`` when any role's prices are unknown."""
        total = ZERO
        for role in self.roles:
            if role.cost_usd is None:
                return None
            total += role.cost_usd
        return total

    @property
    def known_cost_usd(self) -> Span | None:
        """The cost of the roles whose prices are known, or ``None`` when none is."""
        known = [role.cost_usd for role in self.roles if role.cost_usd is not None]
        total = ZERO
        for cost in known:
            total += cost
        return total if known else None

    @property
    def calls(self) -> Span:
        """Model calls of every role."""
        total = ZERO
        for role in self.roles:
            total += role.calls
        return total


@dataclass
class _Tally:
    calls: Span = ZERO
    prompt_chars: Span = ZERO
    completion_tokens: Span = ZERO


def estimate(config: RunConfig, shapes: Mapping[str, ScenarioShape], episodes: Mapping[str, int]) -> Estimate:
    """The calls, tokens and cost of ``episodes`` (episodes still to run per scenario id).

    See the module docstring for what *typical* and *upper bound* mean.
    """
    roles = config.models.roles()
    growth = _growth(shapes.values())
    tallies: dict[str, _Tally] = {role: _Tally() for role in roles}
    for scenario_id, count in episodes.items():
        if count <= 0:
            continue
        shape = shapes[scenario_id]
        for role, tally in tallies.items():
            calls, prompt, completion = _episode(role, shape, config, roles[role], growth)
            tally.calls += _times(calls, count)
            tally.prompt_chars += _times(prompt, count)
            tally.completion_tokens += _times(completion, count)
    results = []
    for role, tally in tallies.items():
        prompt_tokens = Span(
            tally.prompt_chars.typical / CHARS_PER_TOKEN, tally.prompt_chars.upper / CHARS_PER_TOKEN
        )
        results.append(
            RoleEstimate(
                role=role,
                model=roles[role].model,
                calls=tally.calls,
                prompt_tokens=prompt_tokens,
                completion_tokens=tally.completion_tokens,
                cost_usd=_cost(roles[role], prompt_tokens, tally.completion_tokens),
            )
        )
    counts = {scenario_id: count for scenario_id, count in episodes.items() if count > 0}
    total = sum(counts.values())
    return Estimate(
        episodes=total,
        roles=results,
        ceiling_calls_per_episode=ceiling_calls(config),
        mean_turns=sum(shapes[s].turns * count for s, count in counts.items()) / total if total else 0.0,
        max_turns=config.protocol.max_turns,
    )


def _times(span: Span, count: int) -> Span:
    return Span(span.typical * count, span.upper * count)


def _episode(
    role: str, shape: ScenarioShape, config: RunConfig, model: ModelConfig, growth: Mapping[str, float]
) -> tuple[Span, Span, Span]:
    """One episode's calls, prompt characters and completion tokens for ``role``."""
    if role == "judge":
        calls = float(len(shape.judge_criteria))
        prompt = float(sum(_judge_prompt_chars(criterion) for criterion in shape.judge_criteria))
        completion = calls * JUDGE_ANSWER_TOKENS
        return Span(calls, calls), Span(prompt, prompt), Span(completion, completion)
    conversations = shape.prompts[role]
    answers = shape.answers[role]
    typical_calls = sum(len(conversation) for conversation in conversations)
    per_call = _conversation_growth(conversations)
    if per_call is None:
        per_call = growth.get(role, growth.get("any", 0.0))
    first = shape.first_prompt[role]
    if role == "execute":  # each accepted task (at least one) uses every step of its budget
        upper_conversations = [config.protocol.execute_steps] * max(len(conversations), 1)
    else:  # one conversation for the episode, at the oracle path's calls per turn, for max_turns turns
        upper_conversations = [math.ceil(typical_calls * config.protocol.max_turns / max(shape.turns, 1))]
    upper_calls = sum(upper_conversations)
    upper_prompt = sum(calls * first + per_call * calls * (calls - 1) / 2 for calls in upper_conversations)
    answer_tokens = (
        float(model.max_tokens)
        if model.max_tokens is not None
        else (sum(answers) / len(answers) if answers else THOUGHT_CHARS) / CHARS_PER_TOKEN
    )
    return (
        Span(float(typical_calls), float(upper_calls)),
        Span(float(sum(sum(conversation) for conversation in conversations)), upper_prompt),
        Span(sum(answers) / CHARS_PER_TOKEN, upper_calls * answer_tokens),
    )


def ceiling_calls(config: RunConfig) -> int:
    """The most model calls an episode can make without a malformed answer: every turn, the user uses
    all its steps and the assistant all of its observe or execute steps (judge calls aside).
    """
    protocol = config.protocol
    roles = config.models.roles()
    per_turn = protocol.user_steps if "user" in roles else 0
    if "observe" in roles:
        per_turn += max(protocol.observe_steps, protocol.execute_steps)
    return protocol.max_turns * per_turn


def _judge_prompt_chars(criterion: int) -> int:
    return len(JUDGE_PROMPT) + len("Criterion: \n\nText:\n") + criterion + JUDGED_TEXT_CHARS


def _conversation_growth(conversations: Sequence[Sequence[int]]) -> float | None:
    """How much a prompt grows per call, on average over the conversations' calls after the first."""
    grown = sum(conversation[-1] - conversation[0] for conversation in conversations if len(conversation) > 1)
    steps = sum(len(conversation) - 1 for conversation in conversations if len(conversation) > 1)
    return grown / steps if steps else None


def _growth(shapes: Iterable[ScenarioShape]) -> dict[str, float]:
    """Growth per call per role over every measured scenario (``any``: over every role), for a scenario
    whose own episode has too few calls of a role to measure it.
    """
    pooled: dict[str, list[Sequence[int]]] = {}
    for shape in shapes:
        for role, conversations in shape.prompts.items():
            pooled.setdefault(role, []).extend(conversations)
            pooled.setdefault("any", []).extend(conversations)
    growth = {role: _conversation_growth(conversations) for role, conversations in pooled.items()}
    return {role: value for role, value in growth.items() if value is not None}


def _cost(model: ModelConfig, prompt_tokens: Span, completion_tokens: Span) -> Span | None:
    typical = call_cost(
        model,
        Usage(prompt_tokens=round(prompt_tokens.typical), completion_tokens=round(completion_tokens.typical)),
    )
    upper = call_cost(
        model,
        Usage(prompt_tokens=round(prompt_tokens.upper), completion_tokens=round(completion_tokens.upper)),
    )
    if typical is None or upper is None:
        return None
    return Span(typical, upper)


# -- the whole plan ----------------------------------------------------------------------------------------
@dataclass(frozen=True)
class RunPlan:
    """Everything ``pare run --dry-run`` shows."""

    label: str
    cache: str
    roles: list[RoleLine]
    keys: list[KeyStatus]
    episodes: EpisodeCount
    estimate: Estimate | None
    """``None`` for a run without models (the oracle plays): it calls nothing."""

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready form."""
        data = asdict(self)
        data["episodes"]["to_run"] = self.episodes.to_run
        if self.estimate is not None:
            cost = self.estimate.cost_usd
            data["estimate"]["calls"] = asdict(self.estimate.calls)
            data["estimate"]["cost_usd"] = asdict(cost) if cost is not None else None
            data["estimate"]["basis"] = ESTIMATE_BASIS
        return data


ESTIMATE_BASIS = (
    "typical: each scenario's oracle path (its turns), every prompt as PARE renders it; upper bound: "
    "every episode runs max_turns turns at that pace and every accepted task uses all execute_steps, "
    "answers max_tokens long when set; tokens = characters / chars_per_token; malformed answers sent "
    "back and a reasoning model's thinking beyond max_tokens are not counted"
)


def plan_run(
    config: RunConfig, scenarios: Mapping[str, Scenario], environ: Mapping[str, str] | None = None
) -> RunPlan:
    """What ``config`` would do over ``scenarios``: nothing is called and no folder is made."""
    episodes, finished = count_episodes(config, scenarios)
    result_estimate = None
    if not config.oracle_only:
        to_run = {
            scenario_id: sum(1 for run in range(1, config.runs + 1) if (scenario_id, run) not in finished)
            for scenario_id in scenarios
        }
        if episodes.refused:
            to_run = dict.fromkeys(scenarios, 0)
        pending = {scenario_id: scenarios[scenario_id] for scenario_id, count in to_run.items() if count}
        result_estimate = estimate(config, measure_scenarios(config, pending), to_run)
    return RunPlan(
        label=config.label(),
        cache=config.cache,
        roles=role_lines(config),
        keys=key_statuses(config, environ),
        episodes=episodes,
        estimate=result_estimate,
    )
