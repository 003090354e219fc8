"""What each actor is told: tool results, the user's view, the assistant's observation."""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from datetime import datetime
from typing import Any

from pare.apps.tools import ToolSpec
from pare.sim.log import LogEntry

ON_SCREEN = "\nOn screen: "
"""What separates a user action's result from the screen it arrived on, in the text the user is shown."""


def split_observation(text: str) -> tuple[str, Any]:
    """An observation (:meth:`ToolResult.observation`) as (the result's text, what the screen arrived on
    displays, or ``None`` when the action arrived on no new screen).
    """
    head, marker, tail = text.partition(ON_SCREEN)
    if not marker:
        return text, None
    try:
        return head, json.loads(tail)
    except json.JSONDecodeError:
        return head, tail


@dataclass(frozen=True, slots=True)
class ToolResult:
    """The outcome of one tool call, as the caller sees it."""

    ok: bool
    value: Any = None
    """The JSON-ready result when ``ok``."""
    error: str | None = None
    entry: LogEntry | None = None
    """The action-log entry the call produced."""
    screen_display: Any = None
    """For a user action that brought the user to a screen without showing it (opening or switching
    apps, going back): what that screen displays. Shown to the user, not logged as the call's result."""
    _observation: str | None = field(default=None, init=False, repr=False, compare=False)
    """:meth:`observation`, kept once written: the turn loop records it and the actor is shown it."""

    def observation(self) -> str:
        """The text an actor is shown: the result as JSON, or the error, then the screen arrived on."""
        text = self._observation
        if text is None:
            text = self._write_observation()
            # the result is not changed after the call (the log holds it too), so the text cannot go stale
            object.__setattr__(self, "_observation", text)
        return text

    def _write_observation(self) -> str:
        if not self.ok:
            return f"Error: {self.error}"
        text = self.value if isinstance(self.value, str) else json.dumps(self.value, ensure_ascii=False)
        if self.screen_display is not None:
            text += ON_SCREEN + json.dumps(self.screen_display, ensure_ascii=False)
        return text


@dataclass(frozen=True, slots=True)
class NamedTool:
    """A tool under the name an actor calls it by."""

    name: str
    spec: ToolSpec

    def function_schema(self) -> dict[str, Any]:
        """OpenAI function-calling schema under this name."""
        return self.spec.function_schema(self.name)


@dataclass(frozen=True, slots=True)
class UserView:
    """What the user sees now: where they are, what they can do, what is new."""

    time: str
    app: str | None
    """The app on screen, or ``None`` on the home screen."""
    screen: str | None
    """The screen with its parameters, e.g. ``Detail(email_id='email-3')``."""
    background_apps: list[str]
    tools: list[NamedTool]
    notifications: list[str] = field(default_factory=list)
    pending_proposal: str | None = None
    screen_update: Any = None
    """What the screen on view displays now, when its app's data changed since the user last saw it
    (a message arriving in the open conversation)."""
    turn: TurnMark | None = None
    """Which turn this is, and why the clock jumped to it if it did: set by the turn loop."""
    proposal_turns_left: int | None = None
    """Turns the pending proposal may still be answered in, this one included: set by the turn loop."""

    @property
    def tool_names(self) -> list[str]:
        """Names of the tools available now."""
        return [tool.name for tool in self.tools]

    def render(self, described: set[str] | None = None) -> str:
        """A plain-text rendering for a model's prompt.

        ``described`` holds the tool lines (signature and description) this reader has already been
        shown: those are listed by signature only, so that a long episode does not repeat every screen's
        descriptions each turn. New lines are added to it. ``None`` describes every tool.
        """
        lines = [time_line(self.time, self.turn)]
        if self.app is None:
            lines.append("You are on the home screen.")
        else:
            lines.append(f"Current app: {self.app}; screen: {self.screen}")
        lines.append(f"Apps open in the background: {', '.join(self.background_apps) or 'none'}")
        if self.screen_update is not None:
            shown = json.dumps(self.screen_update, ensure_ascii=False)
            lines.append(f"The screen has changed; it now shows: {shown}")
        if self.notifications:
            lines.append("New notifications:")
            lines.extend(f"- {n}" for n in self.notifications)
        if self.pending_proposal:
            answer = "accept_proposal or reject_proposal"
            lines.append(f"The assistant proposes ({answer}): {self.pending_proposal}")
            if self.proposal_turns_left is not None:
                lines.append(_proposal_clock(self.proposal_turns_left))
        lines.append("Available tools:")
        abridged = False
        for tool in self.tools:
            line = f"{tool.spec.signature}: {tool.spec.summary}"
            if described is None:
                lines.append(f"- {line}")
            elif line in described:
                lines.append(f"- {tool.spec.signature}")
                abridged = True
            else:
                described.add(line)
                lines.append(f"- {line}")
        if abridged:
            lines.append("(Tools listed without a description were described earlier.)")
        return "\n".join(lines)


@dataclass(frozen=True, slots=True)
class AssistantObservation:
    """What the assistant learns since it last looked: the user's actions and notifications."""

    time: str
    user_actions: list[LogEntry]
    notifications: list[str]
    executed: list[LogEntry] = field(default_factory=list)
    """The assistant's own execute-mode calls since it last observed: the changes it made for an
    accepted task, and its report. Observe mode remembers what execute mode did."""
    turn: TurnMark | None = None
    """Which turn this is, and why the clock jumped to it if it did: set by the turn loop."""

    def render(self) -> str:
        """A plain-text rendering for a model's prompt.

        The user's actions and what execute mode did are told in the order they happened: the actions
        up to the acceptance, the task carried out, then what the user did after it.
        """
        lines = [time_line(self.time, self.turn)]
        started = self.executed[0].index if self.executed else None
        before = [entry for entry in self.user_actions if started is None or entry.index < started]
        after = [entry for entry in self.user_actions if started is not None and entry.index > started]
        if before:
            lines.append("User actions:")
            lines.extend(f"- {describe_action(entry)}" for entry in before)
        if self.executed:
            lines.extend(_execution_lines(self.executed))
        if after:
            lines.append("User actions since:")
            lines.extend(f"- {describe_action(entry)}" for entry in after)
        if self.notifications:
            lines.append("Notifications:")
            lines.extend(f"- {n}" for n in self.notifications)
        if not self.user_actions and not self.notifications and not self.executed:
            lines.append("Nothing new.")
        return "\n".join(lines)


@dataclass(frozen=True, slots=True)
class TurnMark:
    """Where an observation stands in the episode: turn ``turn`` of ``of``, and, when the clock jumped
    further than a turn takes to get here, by how much and why (``clock_jump``).
    """

    turn: int
    of: int
    clock_jump: str | None = None


def time_line(time: str, turn: TurnMark | None) -> str:
    """The first line of an observation: the turn, then the current time and why it jumped if it did.

    The time is written as the tools take it (``YYYY-MM-DD HH:MM``) after its weekday: a model reading
    "on Thursday" in a message needs the day of the week, and copies times into calls in their format.
    """
    line = f"Current time: {readable_time(time)}"
    if turn is None:
        return line
    if turn.clock_jump:
        line += f" ({turn.clock_jump})"
    return f"Turn {turn.turn} of {turn.of}. {line}"


def readable_time(time: str) -> str:
    """``2025-03-03T09:05:00+00:00`` as ``Monday 2025-03-03 09:05`` (seconds only when there are some)."""
    try:
        moment = datetime.fromisoformat(time)
    except ValueError:  # not a time this module wrote: shown as it is
        return time
    clock = "%H:%M:%S" if moment.second else "%H:%M"
    return moment.strftime(f"%A %Y-%m-%d {clock}")


def _proposal_clock(turns_left: int) -> str:
    if turns_left <= 1:
        return "This is the last turn to answer it: unanswered, it is withdrawn at the end of this turn."
    return f"It can be answered this turn and {turns_left - 1} more; then, unanswered, it is withdrawn."


_CALL_LABELS = {"read": "read", "write": "change"}


def _execution_lines(entries: list[LogEntry]) -> list[str]:
    """What the assistant did for its accepted task: every call in order, the reads named as such, then
    its report.
    """
    reports = [entry for entry in entries if entry.app == "agent_ui" and entry.tool == "send_message_to_user"]
    calls = [entry for entry in entries if entry not in reports]
    lines = ["You carried out the task the user accepted (execute mode), in this order:"]
    for entry in calls:
        label = _CALL_LABELS.get(entry.kind or "", "call")
        lines.append(f"- {label}: {describe_action(entry)}")
    if not any(entry.kind == "write" for entry in calls):
        lines.append("- no change was made")
    for report in reports:
        lines.append(f"Your report to the user: {report.args.get('content', '')}")
    if not reports:
        lines.append("You sent no report: the task ran out of actions before you finished it.")
    return lines


def describe_action(entry: LogEntry) -> str:
    """One line for a logged call, e.g. ``email.open_email(email_id='e1') -> ok``."""
    args = ", ".join(f"{k}={v!r}" for k, v in entry.args.items())
    outcome = "ok" if entry.ok else f"error: {entry.error}"
    return f"{entry.app}.{entry.tool}({args}) -> {outcome}"
