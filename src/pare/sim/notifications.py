"""Notifications and the per-recipient inboxes they are delivered to.

The user's copy is truncated like a phone notification (sender, subject, first words); the assistant's is
the full serialised content. Each recipient has its own inbox with its own read position.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass, field
from datetime import datetime
from typing import Any, Literal

from pydantic import BaseModel, ConfigDict, Field

Recipient = Literal["user", "assistant"]
DetailLevel = Literal["minimal", "preview", "full"]
"""How much of a notification a recipient sees.

* ``minimal`` — the app and who it is from ("Email: new email from Alice Chen");
* ``preview`` — also the subject and the first words of the body, like a phone's lock screen;
* ``full`` — everything, including structured data such as ids.
"""


class NotificationPolicy(BaseModel):
    """How much detail each recipient gets."""

    model_config = ConfigDict(extra="forbid", frozen=True)

    user: DetailLevel = "preview"
    assistant: DetailLevel = "full"
    preview_words: int = Field(default=12, ge=1, description="Words of the body shown in a preview.")

    def level_for(self, recipient: Recipient) -> DetailLevel:
        """The detail level for ``recipient``."""
        return self.user if recipient == "user" else self.assistant


@dataclass(frozen=True, slots=True)
class Notification:
    """Something an app announces: an email arrived, a proposal was made, a reminder is due."""

    index: int
    time: datetime
    app: str
    kind: str
    """A short machine name, e.g. ``new_email`` or ``proposal``."""
    headline: str
    """One line naming the event and who it is from, e.g. "New email from Alice Chen"."""
    subject: str = ""
    body: str = ""
    data: dict[str, Any] = field(default_factory=dict)
    """Structured details (ids and so on), shown only at full detail."""
    always_full: bool = False
    """Shown in full to every recipient (the assistant's proposals to the user)."""

    def render(self, level: DetailLevel, preview_words: int = 12) -> str:
        """The text a recipient at ``level`` sees."""
        if self.always_full:
            level = "full"
        stamp = self.time.strftime("%Y-%m-%d %H:%M")
        text = f"[{stamp}] {self.app}: {self.headline}"
        if level == "minimal":
            return text
        if self.subject:
            text += f" — {self.subject}"
        if not self.body:
            return text if level != "full" or not self.data else f"{text}\n{_format_data(self.data)}"
        if level == "preview":
            return f"{text}: {truncate_words(self.body, preview_words)}"
        text += f"\n{self.body}"
        if self.data:
            text += f"\n{_format_data(self.data)}"
        return text

    def to_dict(self) -> dict[str, Any]:
        """A JSON-ready dict of every field."""
        return {
            "index": self.index,
            "time": self.time.isoformat(),
            "app": self.app,
            "kind": self.kind,
            "headline": self.headline,
            "subject": self.subject,
            "body": self.body,
            "data": self.data,
            "always_full": self.always_full,
        }


def truncate_words(text: str, words: int) -> str:
    """The first ``words`` words of ``text``, with an ellipsis when something was cut."""
    parts = text.split()
    if len(parts) <= words:
        return " ".join(parts)
    return " ".join(parts[:words]) + " …"


def _format_data(data: dict[str, Any]) -> str:
    return "(" + ", ".join(f"{key}={value}" for key, value in data.items()) + ")"


@dataclass
class Inbox:
    """One recipient's notifications and how far it has read."""

    items: list[Notification] = field(default_factory=list)
    read_position: int = 0

    def unread(self) -> list[Notification]:
        """The notifications not yet read, without marking them read."""
        return self.items[self.read_position :]

    def take_unread(self) -> list[Notification]:
        """The notifications not yet read, marking them read."""
        new = self.items[self.read_position :]
        self.read_position = len(self.items)
        return new


class NotificationCenter:
    """Routes notifications to the recipients' inboxes and renders them at each one's detail level."""

    def __init__(self, policy: NotificationPolicy | None = None) -> None:
        self.policy = policy or NotificationPolicy()
        self.inboxes: dict[Recipient, Inbox] = {"user": Inbox(), "assistant": Inbox()}
        self._count = 0

    def post(
        self,
        *,
        time: datetime,
        app: str,
        kind: str,
        headline: str,
        subject: str = "",
        body: str = "",
        data: dict[str, Any] | None = None,
        recipients: Iterable[Recipient] = ("user", "assistant"),
        always_full: bool = False,
    ) -> Notification:
        """Create a notification and deliver it to each of ``recipients``."""
        notification = Notification(
            index=self._count,
            time=time,
            app=app,
            kind=kind,
            headline=headline,
            subject=subject,
            body=body,
            data=dict(data or {}),
            always_full=always_full,
        )
        self._count += 1
        for recipient in recipients:
            self.inboxes[recipient].items.append(notification)
        return notification

    def render(self, notification: Notification, recipient: Recipient) -> str:
        """``notification`` as ``recipient`` sees it."""
        return notification.render(self.policy.level_for(recipient), self.policy.preview_words)

    def take_unread(self, recipient: Recipient) -> list[str]:
        """Rendered unread notifications of ``recipient``, marking them read."""
        return [self.render(n, recipient) for n in self.inboxes[recipient].take_unread()]
