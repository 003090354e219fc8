"""Who a call told something, through which channel, with what text and files.

One notion of "a person was told", shared by the checks, the world's reactive events and the side
effects (:mod:`pare.scenarios.side_effects`): an email reaches everyone in its To, CC and BCC, whether new,
a reply or a forward (whose text is the forwarded email); a message reaches the other person of a
one-to-one conversation, or every other member of a group (:func:`email_addressees`,
:func:`conversation_members`). What a call delivered is read from the app data right after it (for the
world's reactions) or at the end (for the checks): the email the call stored, the conversation the message
went to.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any, Literal

from pare.sim.log import LogEntry

Channel = Literal["email", "messaging", "reply", "forward", "chat", "group"]
CHANNELS: dict[str, str] = {
    "email": "any email: new, reply or forward, in To or CC",
    "messaging": "any message: one-to-one or group",
    "reply": "a reply to an email",
    "forward": "a forwarded email",
    "chat": "a message in a one-to-one conversation",
    "group": "a message in a group conversation",
}
"""The channels a pattern's ``via`` may name, with what each means."""

_EMAIL_SENDS = frozenset({"send_email", "reply_to_email", "forward_email", "send", "reply", "forward"})
"""Email calls that send (the agent's tools and the user's screen actions)."""
_FORWARDS = frozenset({"forward_email", "forward"})
_MESSAGE_SENDS = frozenset({"send_message", "send_message_to_group_conversation"})

SENDING_TOOLS = frozenset(
    [*(f"email__{tool}" for tool in _EMAIL_SENDS), *(f"messaging__{tool}" for tool in _MESSAGE_SENDS)]
)
"""Every call that can tell someone something, as ``app__tool`` (agent tools and user screen actions)."""

AppState = Callable[[str], Mapping[str, Any] | None]
"""An app's data as JSON-ready values, by app name (``None`` when the phone has no such app)."""


@dataclass(frozen=True, slots=True)
class Delivery:
    """What one call delivered: to whom (email addresses and messaging user ids, lowercase), through
    which channels, the text as the recipients got it, and the files attached (paths).
    """

    people: frozenset[str]
    channels: frozenset[str]
    content: str
    attachments: tuple[str, ...]

    def reaches(self, people: frozenset[str], via: frozenset[str] | None) -> bool:
        """Whether one of ``people`` got it, through one of the channels ``via`` (any, when ``None``)."""
        if self.people.isdisjoint(people):
            return False
        return via is None or not self.channels.isdisjoint(via)

    def as_args(self, args: Mapping[str, Any]) -> dict[str, Any]:
        """The call's arguments with its text and files as delivered: ``content`` (a forward's is the
        forwarded email) and ``attachments`` (a list, for email and messaging alike; left out when nothing
        was attached, as a call without attachments has none, so ``present: true`` means files were sent).
        """
        delivered = {key: value for key, value in args.items() if key != "attachments"}
        delivered["content"] = self.content
        if self.attachments:
            delivered["attachments"] = list(self.attachments)
        return delivered


def delivery(entry: LogEntry, state: AppState) -> Delivery | None:
    """What the successful sending call ``entry`` delivered, read from ``state``; ``None`` for any other
    call, or when the app data no longer holds what it sent.
    """
    if not entry.ok or entry.actor not in ("assistant", "user", "oracle"):
        return None
    if entry.app == "email" and entry.tool in _EMAIL_SENDS:
        return _email(entry, state("email"))
    if entry.app == "messaging" and entry.tool in _MESSAGE_SENDS:
        return _message(entry, state("messaging"))
    return None


def _email(entry: LogEntry, data: Mapping[str, Any] | None) -> Delivery | None:
    emails = (data or {}).get("emails") or {}
    sent = emails.get(_made(entry.result))
    if not isinstance(sent, Mapping):
        return None
    people = frozenset(address.lower() for address in email_addressees(sent))
    channels = {"email"}
    if sent.get("in_reply_to"):
        channels.add("reply")
    if entry.tool in _FORWARDS:
        channels.add("forward")
    return Delivery(people, frozenset(channels), sent.get("content", ""), tuple(sent.get("attachments", [])))


def _message(entry: LogEntry, data: Mapping[str, Any] | None) -> Delivery | None:
    if data is None:
        return None
    conversations: Mapping[str, Any] = data.get("conversations") or {}
    me = data.get("current_user_id", "")
    result = entry.result
    message_id = result.get("message_id") if isinstance(result, Mapping) and "message_id" in result else None
    conversation = _holding(conversations, message_id or _made(result))
    if conversation is None:  # the agent's one-to-one send returns the conversation's id
        for key in (_made(result), entry.args.get("conversation_id")):
            if isinstance(key, str) and isinstance(conversations.get(key), Mapping):
                conversation = conversations[key]
                break
    if conversation is None:
        return None
    people = frozenset(user.lower() for user in conversation_members(conversation, me))
    channels = frozenset({"messaging", "group" if conversation.get("is_group") else "chat"})
    attachment = entry.args.get("attachment")
    content = entry.args.get("content")
    return Delivery(
        people, channels, content if isinstance(content, str) else "", (attachment,) if attachment else ()
    )


def email_addressees(email: Mapping[str, Any]) -> list[str]:
    """Everyone a sent email reaches, as written: its To, CC and BCC addresses."""
    found: list[str] = []
    for field in ("recipients", "cc", "bcc"):
        value = email.get(field)
        for address in [value] if isinstance(value, str) else value if isinstance(value, list) else []:
            if isinstance(address, str) and address.strip():
                found.append(address.strip())
    return found


def conversation_members(conversation: Mapping[str, Any], me: str) -> list[str]:
    """Everyone a message in ``conversation`` reaches, as written: its participants but the sender ``me``
    (the other person of a one-to-one conversation, every other member of a group).
    """
    members = conversation.get("participant_ids") or []
    return [str(user) for user in members if user != me and str(user).strip()]


def _made(result: Any) -> str | None:
    """The id a sending call's result names: a write's ``Done`` carries it as ``id``; older logs hold
    the bare id.
    """
    if isinstance(result, Mapping):
        made = result.get("id")
        return made if isinstance(made, str) else None
    return result if isinstance(result, str) else None


def _holding(conversations: Mapping[str, Any], message_id: Any) -> Mapping[str, Any] | None:
    """The conversation holding the message ``message_id``, if any."""
    if not isinstance(message_id, str):
        return None
    for conversation in conversations.values():
        if any(message.get("message_id") == message_id for message in conversation.get("messages", [])):
            return conversation  # type: ignore[no-any-return]
    return None
