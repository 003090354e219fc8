"""Model-backed actors: the user simulator and the proactive assistant (observe and execute modes).

Each keeps its conversation with its model: the system prompt of its role, then one message per
observation and one per answer. An answer is parsed into one tool call (the paper's Thought / Action
format, or native tool calling when configured); a malformed answer is sent back to the model with what
was wrong and how to answer, at most ``max_format_retries`` times per step, after which the step fails and
the loop records it. Execute mode starts a fresh conversation for each accepted task, whose first message
hands over the items observe mode read and the ids it saw (:mod:`pare.agents.handover`). A thinking model's
reasoning is recorded with the action it led to, and left out of the conversation.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any, Protocol

from pare.agents.actions import parse_action, parse_tool_arguments
from pare.agents.handover import Handover
from pare.agents.models.ledger import StepUsage
from pare.agents.models.reasoning import join_reasoning, split_reasoning
from pare.agents.models.types import ChatMessage, Completion
from pare.agents.policy import Action, AssistantPolicy, Ending, Task, UserPolicy
from pare.agents.prompts import execute_system_prompt, observe_system_prompt, user_system_prompt
from pare.env import AssistantObservation, Environment, NamedTool, ToolResult, TurnMark, UserView
from pare.errors import ActionFormatError
from pare.sim.budget import DEFAULT_BUDGET, TurnBudget
from pare.sim.log import AssistantMode

EXECUTE_OPENING = "The user accepted your proposal. Carry out the task now."
"""What execute mode is told first, in the fresh conversation that carries out an accepted task."""


class ChatModel(Protocol):
    """What an actor needs from a model: one completion for a conversation (``ModelClient`` has it)."""

    async def complete(
        self, messages: Sequence[ChatMessage], tools: Sequence[dict[str, Any]] | None = None
    ) -> Completion:
        """The model's answer to ``messages`` (with ``tools`` as function schemas, when given)."""
        ...


@dataclass
class Conversation:
    """One role's running conversation with its model, and how answers become actions."""

    model: ChatModel
    native_tools: bool = False
    max_format_retries: int = 2
    messages: list[ChatMessage] = field(default_factory=list)
    _pending_call_id: str | None = None

    def reset(self, system_prompt: str) -> None:
        """Start over with ``system_prompt``."""
        self.messages = [ChatMessage(role="system", content=system_prompt)]
        self._pending_call_id = None

    def tell(self, text: str) -> None:
        """Add what the actor observes; with native tools, a tool result answers the pending call."""
        if self._pending_call_id is not None:
            self.messages.append(ChatMessage(role="tool", content=text, tool_call_id=self._pending_call_id))
            self._pending_call_id = None
        else:
            self.messages.append(ChatMessage(role="user", content=text))

    async def decide(self, tools: Sequence[NamedTool] = ()) -> Action:
        """Ask the model for its next action; malformed answers are returned to it with a hint.

        ``tools`` are the actor's tools now; with native tool calling they go to the model as function
        schemas (built only then: the text format lists them in the prompt instead).
        """
        schemas = [tool.function_schema() for tool in tools] if self.native_tools else None
        usage = {"calls": 0, "prompt_tokens": 0, "completion_tokens": 0, "cached_tokens": 0}
        costs: list[float | None] = []
        errors: list[str] = []
        raw = ""
        reasoning: str | None = None
        for _ in range(self.max_format_retries + 1):
            completion = await self.model.complete(self.messages, schemas)
            usage["calls"] += 1
            usage["prompt_tokens"] += completion.usage.prompt_tokens
            usage["completion_tokens"] += completion.usage.completion_tokens
            usage["cached_tokens"] += completion.usage.cached_tokens
            costs.append(completion.cost_usd)
            # The backends take reasoning out of the text already; answers replayed from a cache recorded
            # before they did still hold their think blocks.
            raw, inline_reasoning = split_reasoning(completion.text or "")
            reasoning = join_reasoning(completion.reasoning, inline_reasoning)
            try:
                if completion.cut_from is not None:
                    raise ActionFormatError(
                        f"Your answer was {completion.cut_from:,} characters long, more than this role may "
                        "write, and was cut. Answer with one short action."
                    )
                tool, args = self._read(completion, raw, reasoning)
            except ActionFormatError as error:
                errors.append(str(error))
                self._reject(raw, str(error))
                continue
            summary = _usage_summary(usage, costs, errors)
            return Action(tool, args, raw=raw, usage=summary, reasoning=reasoning)
        message = f"No valid action after {len(errors)} answers; last problem: {errors[-1]}"
        return Action(
            "", {}, raw=raw, error=message, usage=_usage_summary(usage, costs, errors), reasoning=reasoning
        )

    # The conversation keeps each answer without its reasoning: providers expect only the answer in earlier
    # turns (chat templates such as Qwen3's drop past reasoning, and some APIs refuse a reasoning field in
    # the messages sent), and resending it would cost prompt tokens on every later call.
    def _read(self, completion: Completion, answer: str, reasoning: str | None) -> tuple[str, dict[str, Any]]:
        if self.native_tools and completion.tool_calls:
            if len(completion.tool_calls) > 1:
                raise ActionFormatError("Call exactly one tool per answer; you called several.")
            call = completion.tool_calls[0]
            args = parse_tool_arguments(call.name, call.arguments)
            self.messages.append(ChatMessage(role="assistant", content=answer, tool_calls=(call,)))
            self._pending_call_id = call.id
            return call.name, args
        parsed = parse_action(answer, reasoning=reasoning)
        self.messages.append(ChatMessage(role="assistant", content=answer))
        return parsed.tool, parsed.args

    def _reject(self, answer: str, error: str) -> None:
        self.messages.append(ChatMessage(role="assistant", content=answer))
        self.messages.append(ChatMessage(role="user", content=f"Error: {error}"))


def _usage_summary(usage: dict[str, int], costs: list[float | None], errors: list[str]) -> StepUsage:
    known = [cost for cost in costs if cost is not None]
    return StepUsage(
        **usage,
        cost_usd=None if len(known) != len(costs) else round(sum(known), 10),
        format_errors=tuple(errors),
    )


def _observation_text(previous: ToolResult | None, body: str = "") -> str:
    parts = []
    if previous is not None:
        parts.append(f"Observation: {previous.observation()}")
    if body:
        parts.append(body)
    return "\n\n".join(parts) or "Nothing new."


class LLMUser(UserPolicy):
    """The user simulator: one model call per user action, from the user's view of the phone."""

    name = "llm_user"

    def __init__(
        self,
        model: ChatModel,
        *,
        persona: str | None = None,
        goal: str | None = None,
        native_tools: bool = False,
        max_format_retries: int = 2,
    ) -> None:
        self.persona = persona
        self.goal = goal
        self.conversation = Conversation(model, native_tools, max_format_retries)
        self.described: set[str] = set()
        """Tool lines already shown in full: later observations list those tools by signature only."""

    def start(self, env: Environment, budget: TurnBudget = DEFAULT_BUDGET) -> None:
        """Write the system prompt for this episode's phone."""
        prompt = user_system_prompt(
            env,
            persona=self.persona,
            goal=self.goal,
            native_tools=self.conversation.native_tools,
            budget=budget,
        )
        self.conversation.reset(prompt)
        self.described = set()

    async def step(self, view: UserView, previous: ToolResult | None) -> Action:
        """Show the model the result of its last action and the current screen; take its next action."""
        self.conversation.tell(_observation_text(previous, view.render(self.described)))
        return await self.conversation.decide(view.tools)

    def finish(self, ending: Ending, previous: ToolResult | None, notifications: list[str]) -> str | None:
        """End the conversation with the last action's result, what arrived since and the end itself."""
        lines = []
        if notifications:
            lines.append("New notifications:")
            lines.extend(f"- {notification}" for notification in notifications)
        lines.append(ending.text())
        text = _observation_text(previous, "\n".join(lines))
        self.conversation.tell(text)
        return text


class LLMAssistant(AssistantPolicy):
    """The proactive assistant: an observe conversation that lasts the episode, and a fresh execute
    conversation for each accepted task (observe and execute may use different models).
    """

    name = "llm_assistant"

    def __init__(
        self,
        observe_model: ChatModel,
        execute_model: ChatModel | None = None,
        *,
        native_tools: bool = False,
        max_format_retries: int = 2,
    ) -> None:
        self.observer = Conversation(observe_model, native_tools, max_format_retries)
        self.executor = Conversation(execute_model or observe_model, native_tools, max_format_retries)
        self.execute_steps = DEFAULT_BUDGET.execute_steps
        """What execute mode's prompt says it may take: the turn loop's limit, given to :meth:`start`."""
        self.env: Environment | None = None
        self.observe_budget = DEFAULT_BUDGET.observe_steps
        self._turn: TurnMark | None = None
        """The turn observe mode is in, from the turn's first observation."""
        self._steps_taken = 0
        """Actions taken so far in the current observe turn, or for the current task in execute mode."""
        self.handover = Handover()
        """What observe mode read and saw this episode: execute mode's first message holds it."""

    def start(self, env: Environment, budget: TurnBudget = DEFAULT_BUDGET) -> None:
        """Write the observe-mode system prompt for this episode's phone."""
        self.env = env
        self.execute_steps = budget.execute_steps
        self.observe_budget = budget.observe_steps
        self.handover.clear()
        self.observer.reset(
            observe_system_prompt(env, native_tools=self.observer.native_tools, budget=budget)
        )

    async def observe(self, observation: AssistantObservation | None, previous: ToolResult | None) -> Action:
        """Show the model what happened (and its last action's result); take its next action."""
        self._env()  # fails clearly when start() was not called
        if previous is not None and previous.entry is not None:
            self.handover.read(previous.entry)
        if observation is not None:
            for entry in [*observation.user_actions, *observation.executed]:
                self.handover.saw(entry)
            self._turn = observation.turn
            self._steps_taken = 0
            body = observation.render()
        else:  # a later action of the same turn: where it stands in the turn
            turn = f"Turn {self._turn.turn} of {self._turn.of}; " if self._turn is not None else ""
            body = f"{turn}action {self._steps_taken + 1} of {self.observe_budget} this turn."
        self._steps_taken += 1
        self.observer.tell(_observation_text(previous, body))
        return await self.observer.decide(self._tools(self.observer, "observe"))

    def finish(
        self, ending: Ending, observation: AssistantObservation, previous: ToolResult | None
    ) -> str | None:
        """End the observe conversation with its last action's result, what happened since it last
        looked, and the end itself.
        """
        text = _observation_text(previous, f"{observation.render()}\n{ending.text()}")
        self.observer.tell(text)
        return text

    async def execute(self, task: Task | None, previous: ToolResult | None) -> Action:
        """Carry out the accepted task in a fresh conversation."""
        env = self._env()
        if task is not None:
            prompt = execute_system_prompt(
                env, task, max_steps=self.execute_steps, native_tools=self.executor.native_tools
            )
            self.executor.reset(prompt)
            self._steps_taken = 0
        self._steps_taken += 1
        count = f"Action {self._steps_taken} of {self.execute_steps}."
        if task is not None:
            handover = self.handover.render()
            opening = f"{EXECUTE_OPENING}\n\n{handover}" if handover else EXECUTE_OPENING
            self.executor.tell(f"{opening}\n\n{count}")
        else:
            self.executor.tell(_observation_text(previous, count))
        return await self.executor.decide(self._tools(self.executor, "execute"))

    def _tools(self, conversation: Conversation, mode: AssistantMode) -> Sequence[NamedTool]:
        """The tools to send with a call: only native tool calling sends them (the text format's prompt
        lists them), so they are not gathered otherwise.
        """
        return self._env().assistant_tools(mode) if conversation.native_tools else ()

    def _env(self) -> Environment:
        if self.env is None:
            raise RuntimeError("LLMAssistant.start() was not called")
        return self.env
