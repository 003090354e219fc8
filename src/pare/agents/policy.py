"""What an actor is to the episode loop: given what it observes, its next action.

The loop owns the environment and the turn order; an actor only decides. A user policy is asked for one
action at a time and sees the user's view; an assistant policy is asked in observe mode (it sees the
user's actions and notifications) and, after the user accepts a proposal, in execute mode (it sees the
accepted task). Each is told the result of its previous action. Model-backed actors and deterministic
ones (silent, oracle, scripted) share these interfaces.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from dataclasses import dataclass, field
from typing import Any, Literal

from pare.agents.models.ledger import StepUsage
from pare.env import AssistantObservation, Environment, ToolResult, UserView
from pare.sim.budget import DEFAULT_BUDGET as DEFAULT_BUDGET  # re-exported: the actors are told it
from pare.sim.budget import TurnBudget as TurnBudget

WAIT = "wait"
"""The user's name for waiting."""
ASSISTANT_WAIT = "system__wait"
"""The assistant's name for waiting (observe mode only)."""
SEND_MESSAGE = "agent_ui__send_message_to_user"
"""The assistant's proposal (observe mode) or report (execute mode)."""


@dataclass(frozen=True, slots=True)
class Action:
    """One tool call an actor chose: the tool's name as that actor calls it, and the arguments."""

    tool: str
    args: dict[str, Any] = field(default_factory=dict)
    raw: str | None = None
    """What a model wrote to produce this action, when a model did."""
    error: str | None = None
    """Set when the actor could not produce a valid action (a model's answers stayed malformed); the
    loop records the step as failed without calling the environment."""
    usage: StepUsage | None = None
    """For model-backed actors: calls, prompt / completion / cached tokens, cost and format errors of the
    model calls behind this action."""
    reasoning: str | None = None
    """A thinking model's reasoning behind ``raw`` (which holds its answer only), when it gave any."""


@dataclass(frozen=True, slots=True)
class Task:
    """What execute mode starts from: the accepted proposal and the user's answer."""

    proposal: str
    answer: str
    proposal_id: str


EndReason = Literal["max_turns", "idle", "context_limit"]
"""Why an episode ended: its turn limit, nothing left to happen, or a prompt beyond a model's context."""

_ENDINGS: dict[EndReason, str] = {
    "max_turns": "that was its last turn",
    "idle": "nothing more was going to happen",
    "context_limit": "a conversation grew longer than its model can read",
}


@dataclass(frozen=True, slots=True)
class Ending:
    """How an episode ended, as the closing observation tells each actor."""

    turn: int
    """The last turn played."""
    max_turns: int
    reason: EndReason

    def text(self) -> str:
        """The closing sentence: the session is over, after which turn, and why."""
        return (
            f"The session is over after turn {self.turn} of {self.max_turns}: {_ENDINGS[self.reason]}. "
            "Nothing more will happen and no answer is expected."
        )


class UserPolicy(ABC):
    """Plays the user: one action per call, from the user's view of the phone."""

    name: str = "user"

    def start(self, env: Environment, budget: TurnBudget = DEFAULT_BUDGET) -> None:  # noqa: B027 - optional hook
        """Called once before the episode's first turn, with the limits of the episode's turn protocol."""

    @abstractmethod
    async def step(self, view: UserView, previous: ToolResult | None) -> Action:
        """The next action, given what the user sees and the result of the previous action."""

    def finish(self, ending: Ending, previous: ToolResult | None, notifications: list[str]) -> str | None:
        """Called once after the last turn, with the result of the user's last action and the
        notifications that came after it; a model-backed user ends its conversation with them (no model
        call) and returns the text it added. Others return ``None``.
        """
        return None


class AssistantPolicy(ABC):
    """Plays the proactive assistant in its two modes."""

    name: str = "assistant"

    def start(self, env: Environment, budget: TurnBudget = DEFAULT_BUDGET) -> None:  # noqa: B027 - optional hook
        """Called once before the episode's first turn, with the limits of the episode's turn protocol."""

    @abstractmethod
    async def observe(self, observation: AssistantObservation | None, previous: ToolResult | None) -> Action:
        """Observe mode: ``observation`` is given on the turn's first step (then ``None``); read tools,
        ``system__wait`` or a proposal through ``agent_ui__send_message_to_user``.
        """

    @abstractmethod
    async def execute(self, task: Task | None, previous: ToolResult | None) -> Action:
        """Execute mode: ``task`` is given on the first step (then ``None``); any app tool, ending with
        a report through ``agent_ui__send_message_to_user``.
        """

    def finish(
        self, ending: Ending, observation: AssistantObservation, previous: ToolResult | None
    ) -> str | None:
        """Called once after the last turn, with what happened since observe mode last looked and the
        result of its last action; a model-backed assistant ends its observe conversation with them (no
        model call) and returns the text it added. Others return ``None``.
        """
        return None


class SilentUser(UserPolicy):
    """A user who never does anything."""

    name = "silent_user"

    async def step(self, view: UserView, previous: ToolResult | None) -> Action:
        """Always wait."""
        return Action(WAIT)


class SilentAssistant(AssistantPolicy):
    """An assistant that only ever waits."""

    name = "silent_assistant"

    async def observe(self, observation: AssistantObservation | None, previous: ToolResult | None) -> Action:
        """Always wait."""
        return Action(ASSISTANT_WAIT)

    async def execute(self, task: Task | None, previous: ToolResult | None) -> Action:
        """Never reached (it never proposes); reports at once if it is."""
        return Action(SEND_MESSAGE, {"content": "I did nothing."})
