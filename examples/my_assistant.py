"""Your own assistant in ``pare run``: a policy and the factory that makes one per episode.

    PYTHONPATH=examples pare run --assistant-policy my_assistant:make --split smoke --runs 1

(or run it from this folder: ``pare`` also looks for the module in the current folder). This assistant
asks once whether to look at today's calendar, reads it when the user accepts, and says what it found:
it solves nothing, it shows the interface. Replace ``observe`` and ``execute`` with your scaffold; a
model it should call is in ``context.models`` when the run configures one (``--assistant-model``), with the
run's cache, limits and cost accounting.
"""

from __future__ import annotations

from pare.agents import ASSISTANT_WAIT, SEND_MESSAGE, Action, AssistantPolicy, Task
from pare.bench import PolicyContext
from pare.env import AssistantObservation, ToolResult


class CalendarGlance(AssistantPolicy):
    """Proposes one look at today's calendar, then reports what the look returned."""

    name = "calendar_glance"

    def __init__(self) -> None:
        self.proposed = False

    async def observe(self, observation: AssistantObservation | None, previous: ToolResult | None) -> Action:
        """Propose once, on the first turn; then wait."""
        if self.proposed:
            return Action(ASSISTANT_WAIT)
        self.proposed = True
        return Action(SEND_MESSAGE, {"content": "Shall I look at today's calendar for you?"})

    async def execute(self, task: Task | None, previous: ToolResult | None) -> Action:
        """Read today's events (the first step), then report the observation it got."""
        if task is not None:
            return Action("calendar__read_today_calendar_events")
        seen = previous.observation() if previous is not None else "nothing"
        return Action(SEND_MESSAGE, {"content": f"Today's calendar: {seen[:300]}"})


def make(context: PolicyContext) -> CalendarGlance:
    """A new assistant for one episode (``context`` has the scenario, run, seed and any models)."""
    return CalendarGlance()
