"""Policies written outside PARE, named by import path in the tests (``tests.bench.custom_policies:...``)."""

from __future__ import annotations

from typing import Any

from pare.agents import ASSISTANT_WAIT, SEND_MESSAGE, Action, AssistantPolicy, Task, UserPolicy
from pare.agents.models.types import ChatMessage
from pare.bench import PolicyContext
from pare.env import AssistantObservation, ToolResult, UserView
from pare.scenarios.checks import JudgeVerdict

CREATED: list[PolicyContext] = []
"""Every context a factory of this module was given, in this process."""

PROPOSAL = "Shall I move your dentist check-up to Thursday 07:45 and tell the practice?"


class DentistAssistant(AssistantPolicy):
    """Proposes a fixed task at once; once accepted, makes two fixed tool calls and reports.

    On ``dentist_moves_checkup`` it solves the scenario; on any other it fails.
    """

    name = "dentist_assistant"

    def __init__(self) -> None:
        self.proposed = False
        self.calls = [
            Action(
                "calendar__edit_calendar_event",
                {
                    "event_id": "ev-checkup-sam",
                    "updates": {"start_datetime": "2025-03-06 07:45", "end_datetime": "2025-03-06 08:30"},
                },
            ),
            Action(
                "email__reply_to_email",
                {"email_id": "email-checkup-moves", "content": "Thursday at 07:45 works for me. Sam"},
            ),
        ]

    async def observe(self, observation: AssistantObservation | None, previous: ToolResult | None) -> Action:
        if self.proposed:
            return Action(ASSISTANT_WAIT)
        self.proposed = True
        return Action(SEND_MESSAGE, {"content": PROPOSAL})

    async def execute(self, task: Task | None, previous: ToolResult | None) -> Action:
        if self.calls:
            return self.calls.pop(0)
        return Action(SEND_MESSAGE, {"content": "Moved it to Thursday 07:45 and told the practice."})


def dentist_assistant(context: PolicyContext) -> DentistAssistant:
    CREATED.append(context)
    return DentistAssistant()


class WaitingUser(UserPolicy):
    name = "waiting_user"

    async def step(self, view: UserView, previous: ToolResult | None) -> Action:
        return Action("wait")


def waiting_user(context: PolicyContext) -> WaitingUser:
    CREATED.append(context)
    return WaitingUser()


def always_yes(context: PolicyContext) -> Any:
    async def judge(criterion: str, text: str, facts: Any = ()) -> JudgeVerdict:
        return JudgeVerdict(True, "always yes")

    return judge


def not_a_policy(context: PolicyContext) -> Any:
    return "an assistant"


NOT_CALLABLE = 42


class VagueDentistAssistant(DentistAssistant):
    """As :class:`DentistAssistant`, but its reply names no day or time: only a judge can pass it."""

    def __init__(self) -> None:
        super().__init__()
        self.calls[1] = Action(
            "email__reply_to_email", {"email_id": "email-checkup-moves", "content": "That slot works. Sam"}
        )


def vague_dentist_assistant(context: PolicyContext) -> VagueDentistAssistant:
    return VagueDentistAssistant()


class ModelProposer(AssistantPolicy):
    """Proposes what its observe model says, once; reports at once when accepted."""

    name = "model_proposer"

    def __init__(self, context: PolicyContext) -> None:
        self.model = context.model()
        self.proposed = False

    async def observe(self, observation: AssistantObservation | None, previous: ToolResult | None) -> Action:
        if self.proposed:
            return Action(ASSISTANT_WAIT)
        self.proposed = True
        answer = await self.model.complete([ChatMessage(role="user", content="What should I offer?")])
        return Action(SEND_MESSAGE, {"content": answer.text or ""})

    async def execute(self, task: Task | None, previous: ToolResult | None) -> Action:
        return Action(SEND_MESSAGE, {"content": "Done."})


class Crashing(DentistAssistant):
    async def execute(self, task: Task | None, previous: ToolResult | None) -> Action:
        raise RuntimeError("my scaffold broke")


def crashing(context: PolicyContext) -> Crashing:
    return Crashing()
