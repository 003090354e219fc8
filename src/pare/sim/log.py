"""The action log: one entry per tool call by any actor, the single source of truth.

Checks, metrics, notifications to the assistant and the trajectory viewer all read this log; nothing is
counted from agent-side records.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass, field
from datetime import datetime
from typing import Any, Literal

Actor = Literal["user", "assistant", "env", "oracle"]
"""Who made a call: the simulated user, the proactive assistant, the world (scheduled events and
noise), or the scenario's oracle."""

ToolKind = Literal["read", "write", "env", "ui", "control"]
"""What a call does.

* ``read`` — looks at app data without changing it;
* ``write`` — changes app data;
* ``env`` — what only scenarios and the world may do (an email arriving);
* ``ui`` — changes only what the user is looking at (navigation, a draft being typed);
* ``control`` — the turn protocol: ``wait``, proposals, accepting and rejecting them.
"""

AssistantMode = Literal["observe", "execute"]


@dataclass(frozen=True, slots=True)
class LogEntry:
    """One tool call and what came of it."""

    index: int
    turn: int
    time: datetime
    actor: Actor
    app: str
    tool: str
    args: dict[str, Any]
    kind: ToolKind | None
    """The tool's kind; ``None`` when the call named no known tool."""
    ok: bool
    result: Any = None
    """The JSON-ready result of a successful call."""
    error: str | None = None
    mode: AssistantMode | None = None
    """For the assistant: the mode it was in."""
    injected_failure: bool = False
    """True when the failure was injected by the robustness setting, not caused by the call."""
    event_id: str | None = None
    """For calls made by scheduled events and noise: the event's id."""
    screen: str | None = None
    """For the user: the screen the action was taken on."""

    @property
    def app_screen(self) -> tuple[str, str] | None:
        """For a user call made inside an app: the app and the screen's FSM name, e.g. ``("email",
        "Detail")``; ``None`` for other actors and on the home screen.
        """
        if self.screen is None or " > " not in self.screen:
            return None
        app, _, label = self.screen.partition(" > ")
        return app, label.split("(", 1)[0]

    def to_dict(self) -> dict[str, Any]:
        """A JSON-ready dict; the key order is fixed so serialised logs compare byte for byte."""
        return {
            "index": self.index,
            "turn": self.turn,
            "time": self.time.isoformat(),
            "actor": self.actor,
            "app": self.app,
            "tool": self.tool,
            "args": self.args,
            "kind": self.kind,
            "ok": self.ok,
            "result": self.result,
            "error": self.error,
            "mode": self.mode,
            "injected_failure": self.injected_failure,
            "event_id": self.event_id,
            "screen": self.screen,
        }


@dataclass
class ActionLog:
    """Append-only list of :class:`LogEntry`, with the few queries everything else needs."""

    entries: list[LogEntry] = field(default_factory=list)

    def append(self, entry: LogEntry) -> None:
        """Add ``entry``; its index must be the next position."""
        self.entries.append(entry)

    def __len__(self) -> int:
        return len(self.entries)

    def __iter__(self) -> Iterator[LogEntry]:
        return iter(self.entries)

    def __getitem__(self, index: int) -> LogEntry:
        return self.entries[index]

    def since(self, index: int) -> list[LogEntry]:
        """Entries from position ``index`` on."""
        return self.entries[index:]

    def by_actor(self, actor: Actor) -> list[LogEntry]:
        """Every entry made by ``actor``, in order."""
        return [entry for entry in self.entries if entry.actor == actor]

    def to_list(self) -> list[dict[str, Any]]:
        """The whole log as JSON-ready dicts."""
        return [entry.to_dict() for entry in self.entries]
