"""The agent-user interface: proposals from the assistant and the user's answers."""

from __future__ import annotations

from datetime import datetime
from typing import Any, Literal

from pydantic import BaseModel, ConfigDict, Field

from pare.apps.base import App
from pare.apps.tools import tool
from pare.errors import ToolError
from pare.sim.log import AssistantMode

ProposalStatus = Literal["pending", "accepted", "rejected", "expired"]


class Proposal(BaseModel):
    """A task the assistant offered to do, and what became of it."""

    model_config = ConfigDict(extra="forbid")

    proposal_id: str
    content: str
    time: datetime
    status: ProposalStatus = "pending"
    answered_at: datetime | None = None
    reason: str = ""


class AssistantMessage(BaseModel):
    """A message from the assistant that is not a proposal (a report after executing a task)."""

    model_config = ConfigDict(extra="forbid")

    message_id: str
    content: str
    time: datetime


class AgentUIState(BaseModel):
    """Every proposal and message the assistant sent."""

    model_config = ConfigDict(extra="forbid")

    proposals: list[Proposal] = Field(default_factory=list)
    messages: list[AssistantMessage] = Field(default_factory=list)


_ANSWER_HEADLINES: dict[ProposalStatus, str] = {
    "accepted": "The user accepted your proposal",
    "rejected": "The user rejected your proposal; nothing was done",
    "expired": (
        "The user did not answer your proposal in time: it expired and nothing was done. "
        "You may propose again when it is still useful"
    ),
    "pending": "",
}


def _pending(ui: AgentUIApp) -> bool:
    return ui.pending is not None


class AgentUIApp(App):
    """How the assistant and the user talk. In observe mode, ``send_message_to_user`` is a proposal the
    user must accept or reject; in execute mode it is a report. ``accept_proposal`` and
    ``reject_proposal`` are offered to the user only while a proposal is pending.
    """

    name = "agent_ui"
    title = "Assistant"
    description = "Proposals from the proactive assistant and the user's answers."
    State = AgentUIState
    state: AgentUIState

    def __init__(self, ctx: Any = None) -> None:
        super().__init__(ctx)
        self.assistant_mode: AssistantMode = "observe"
        """Set by the environment before each assistant call: decides what a message to the user is."""

    @property
    def pending(self) -> Proposal | None:
        """The proposal awaiting the user's answer, if any."""
        last = self.state.proposals[-1] if self.state.proposals else None
        return last if last is not None and last.status == "pending" else None

    @tool("control", actors=("assistant",))
    def send_message_to_user(self, content: str) -> dict[str, str]:
        """Send a message to the user. In observe mode this is a proposal: state exactly what you will do
        (who, what, when); the user accepts or rejects it, and your turn ends. In execute mode, use it to
        report that the task is done or cannot be done.

        Args:
            content: the message, in plain language, with every detail the user needs to decide.

        Returns:
            the id of the proposal or message.
        """
        if not content.strip():
            raise ToolError("The message to the user is empty; say what you propose to do.")
        now = self.ctx.now()
        if self.assistant_mode == "execute":
            message_id = f"message-{len(self.state.messages) + 1}"
            self.state.messages.append(AssistantMessage(message_id=message_id, content=content, time=now))
            self.notify(
                "assistant_message",
                "Message from your assistant",
                body=content,
                recipients=("user",),
                always_full=True,
            )
            return {"message_id": message_id}
        if self.pending is not None:
            raise ToolError(
                f"Proposal {self.pending.proposal_id} is still waiting for the user's answer; wait for it."
            )
        proposal_id = f"proposal-{len(self.state.proposals) + 1}"
        self.state.proposals.append(Proposal(proposal_id=proposal_id, content=content, time=now))
        # No notification: the user's view shows the pending proposal itself, with how to answer it.
        return {"proposal_id": proposal_id, "status": "pending"}

    def _answer(self, status: ProposalStatus, reason: str) -> dict[str, str]:
        proposal = self.pending
        if proposal is None:
            raise ToolError("There is no proposal waiting for an answer.")
        proposal.status = status
        proposal.answered_at = self.ctx.now()
        proposal.reason = reason
        self.notify(
            f"proposal_{status}",
            _ANSWER_HEADLINES[status],
            body=reason,
            data={"proposal_id": proposal.proposal_id},
            recipients=("assistant",),
        )
        if status == "expired":  # the user is told it is gone, so that a later proposal is not a surprise
            self.notify(
                "proposal_expired",
                "Your assistant withdrew its proposal: its last turn to answer ended without an answer",
                body=proposal.content,
                recipients=("user",),
                always_full=True,
            )
        return {"proposal_id": proposal.proposal_id, "status": status}

    @tool("control", actors=("user",), available=_pending)
    def accept_proposal(self, reason: str = "") -> dict[str, str]:
        """Accept the assistant's pending proposal; the assistant will then carry it out.

        Args:
            reason: optionally, why you accept or what the assistant should keep in mind.

        Returns:
            the proposal's id and its new status.
        """
        return self._answer("accepted", reason)

    @tool("control", actors=("user",), available=_pending)
    def reject_proposal(self, reason: str = "") -> dict[str, str]:
        """Reject the assistant's pending proposal; nothing will be done.

        Args:
            reason: optionally, why you reject it.

        Returns:
            the proposal's id and its new status.
        """
        return self._answer("rejected", reason)

    def expire_pending(self) -> Proposal | None:
        """Mark the pending proposal as expired (unanswered for too long); called by the turn loop."""
        proposal = self.pending
        if proposal is not None:
            self._answer("expired", "")
        return proposal
