"""What each actor is told: tool results, the user's view, the assistant's observation."""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from typing import Any

from pare.apps.tools import ToolSpec
from pare.sim.log import LogEntry


@dataclass(frozen=True, slots=True)
class ToolResult:
    """The outcome of one tool call, as the caller sees it."""

    ok: bool
    value: Any = None
    """The JSON-ready result when ``ok``."""
    error: str | None = None
    entry: LogEntry | None = None
    """The action-log entry the call produced."""

    def observation(self) -> str:
        """The text an actor is shown: the result as JSON, or the error."""
        if not self.ok:
            return f"Error: {self.error}"
        if isinstance(self.value, str):
            return self.value
        return json.dumps(self.value, ensure_ascii=False)


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

    @property
    def tool_names(self) -> list[str]:
        """Names of the tools available now."""
        return [tool.name for tool in self.tools]

    def render(self) -> str:
        """A plain-text rendering for a model's prompt."""
        lines = [f"Current time: {self.time}"]
        if self.app is None:
            lines.append("You are on the home screen.")
        else:
            lines.append(f"Current app: {self.app}; screen: {self.screen}")
        lines.append(f"Apps open in the background: {', '.join(self.background_apps) or 'none'}")
        if self.notifications:
            lines.append("New notifications:")
            lines.extend(f"- {n}" for n in self.notifications)
        if self.pending_proposal:
            lines.append(f"The assistant proposes: {self.pending_proposal}")
        lines.append("Available tools:")
        lines.extend(f"- {tool.spec.signature}: {tool.spec.summary}" for tool in self.tools)
        return "\n".join(lines)


@dataclass(frozen=True, slots=True)
class AssistantObservation:
    """What the assistant learns since it last looked: the user's actions and notifications."""

    time: str
    user_actions: list[LogEntry]
    notifications: list[str]

    def render(self) -> str:
        """A plain-text rendering for a model's prompt."""
        lines = [f"Current time: {self.time}"]
        if self.user_actions:
            lines.append("User actions:")
            lines.extend(f"- {describe_action(entry)}" for entry in self.user_actions)
        if self.notifications:
            lines.append("Notifications:")
            lines.extend(f"- {n}" for n in self.notifications)
        if not self.user_actions and not self.notifications:
            lines.append("Nothing new.")
        return "\n".join(lines)


def describe_action(entry: LogEntry) -> str:
    """One line for a logged call, e.g. ``email.open_email(email_id='e1') -> ok``."""
    args = ", ".join(f"{k}={v!r}" for k, v in entry.args.items())
    outcome = "ok" if entry.ok else f"error: {entry.error}"
    return f"{entry.app}.{entry.tool}({args}) -> {outcome}"
