"""Messaging: one-to-one and group conversations with the people the user chats with."""

from __future__ import annotations

import difflib
import posixpath
from datetime import UTC, datetime
from typing import Any

from pydantic import BaseModel, ConfigDict, Field, model_validator

from pare.apps.base import App, DatedRecord
from pare.apps.done import Done, listed
from pare.apps.files import DirectoryEntry, FilesApp, browse, files_of, normalize_path
from pare.apps.paging import Paged, showing, showing_screen
from pare.apps.screens import Screen, Transition, action, push
from pare.apps.text import PAGE, preview, short_time
from pare.apps.tools import tool
from pare.apps.types import SimTime
from pare.errors import ToolError, did_you_mean

_NEVER = datetime.min.replace(tzinfo=UTC)


class Message(BaseModel):
    """One message in a conversation."""

    model_config = ConfigDict(extra="forbid")

    message_id: str
    sender_id: str
    content: str = ""
    timestamp: SimTime
    attachment: str | None = Field(default=None, description="Path of the attached file in the Files app.")


class Conversation(BaseModel):
    """A one-to-one or group conversation; its messages are kept oldest first."""

    model_config = ConfigDict(extra="forbid")

    conversation_id: str
    participant_ids: list[str]
    title: str | None = None
    messages: list[Message] = Field(default_factory=list)
    last_updated: SimTime | None = None
    is_group: bool = Field(
        default=False, description="Set automatically when there are more than two participants."
    )
    unread: int = Field(
        default=0, ge=0, description="Messages received since the user last opened the conversation."
    )

    @model_validator(mode="after")
    def _check(self) -> Conversation:
        if len(set(self.participant_ids)) != len(self.participant_ids):
            raise ValueError(f"conversation '{self.conversation_id}' lists a participant twice")
        if len(self.participant_ids) > 2:
            self.is_group = True
        self.messages.sort(key=lambda m: m.timestamp)
        if self.messages and (self.last_updated is None or self.last_updated < self.messages[-1].timestamp):
            self.last_updated = self.messages[-1].timestamp
        return self


class MessagingState(BaseModel):
    """The people the user can message (the user included) and every conversation by id."""

    model_config = ConfigDict(extra="forbid")

    current_user_id: str = "user-me"
    current_user_name: str = "Me"
    users: dict[str, str] = Field(default_factory=dict, description="User id -> display name.")
    conversations: dict[str, Conversation] = Field(default_factory=dict)

    @model_validator(mode="after")
    def _check(self) -> MessagingState:
        me = self.current_user_id
        if me in self.users:
            if "current_user_name" in self.model_fields_set and self.users[me] != self.current_user_name:
                raise ValueError(
                    f"current_user_name {self.current_user_name!r} differs from "
                    f"users[{me!r}] {self.users[me]!r}"
                )
            self.current_user_name = self.users[me]
        else:
            self.users[me] = self.current_user_name
        message_ids: set[str] = set()
        one_to_one: dict[str, str] = {}
        for key, conversation in self.conversations.items():
            where = f"conversation '{key}'"
            if conversation.conversation_id != key:
                raise ValueError(f"{where} is stored under a different id '{conversation.conversation_id}'")
            unknown = [p for p in conversation.participant_ids if p not in self.users]
            if unknown:
                raise ValueError(f"{where} has participants that are not users: {unknown}")
            if me not in conversation.participant_ids:
                raise ValueError(f"{where} does not include the current user '{me}'")
            others = [p for p in conversation.participant_ids if p != me]
            if not others:
                raise ValueError(f"{where} has no participant besides the current user")
            if not conversation.is_group:
                if others[0] in one_to_one:
                    raise ValueError(
                        f"{where} and conversation '{one_to_one[others[0]]}' are both one-to-one "
                        f"conversations with '{others[0]}'"
                    )
                one_to_one[others[0]] = key
            for message in conversation.messages:
                if message.sender_id not in self.users:
                    raise ValueError(f"{where}: message '{message.message_id}' is from unknown user")
                if message.message_id in message_ids:
                    raise ValueError(f"{where}: message id '{message.message_id}' is used twice")
                message_ids.add(message.message_id)
        return self


# -- what the tools return ---------------------------------------------------------------------------


class Participant(BaseModel):
    """Someone in a conversation."""

    user_id: str
    name: str
    is_current_user: bool = False


class MessageView(BaseModel):
    """A message with its sender's name."""

    message_id: str
    sender_id: str
    sender_name: str
    from_current_user: bool
    content: str
    timestamp: datetime
    attachment: str | None = None


class ConversationSummary(BaseModel):
    """A conversation as listed: who is in it and its last message."""

    conversation_id: str
    is_group: bool
    title: str | None
    participants: list[Participant]
    last_updated: datetime | None
    message_count: int
    unread: int
    last_message: MessageView | None


class ConversationMatch(ConversationSummary):
    """A conversation found by a search, with the messages that contain every searched word."""

    matching_messages: list[MessageView]


class ConversationPage(Paged):
    """One page of conversations, most recently updated first."""

    rows_field = "conversations"

    conversations: list[ConversationSummary]
    total: int
    offset: int


class ConversationMessages(Paged):
    """One page of a conversation's messages, newest first."""

    rows_field = "messages"
    total_field = "total_messages"

    conversation_id: str
    is_group: bool
    title: str | None
    participants: list[Participant]
    messages: list[MessageView]
    total_messages: int
    offset: int


class ReceivedMessage(BaseModel):
    """Where an incoming message landed."""

    conversation_id: str
    message_id: str
    sender_id: str


class MessagingApp(App):
    """The phone's messaging app."""

    name = "messaging"
    title = "Messages"
    description = "Text conversations with other people, one-to-one and in groups, with attachments."
    State = MessagingState
    # a group's members see who was added or removed and that a group was made: undoing it is noticed
    harm = {
        "send_message": "irreversible",
        "send_message_to_group_conversation": "irreversible",
        "create_group_conversation": "costly",
        "add_participant_to_conversation": "costly",
        "remove_participant_from_conversation": "costly",
        "change_conversation_title": "reversible",
        "download_attachment": "reversible",
    }
    also_writes = ("files",)
    state: MessagingState

    # -- helpers used by screens -----------------------------------------------------------------------
    def attached_paths(self) -> list[tuple[str, str]]:
        """Every (holder, path) of a file a message has attached."""
        return [
            (f"message '{m.message_id}'", m.attachment)
            for c in self.state.conversations.values()
            for m in c.messages
            if m.attachment is not None
        ]

    def records_dated_after(self, now: datetime) -> list[DatedRecord]:
        """See :meth:`App.records_dated_after`."""
        return [
            DatedRecord(
                ("conversations", key, "messages", index, "timestamp"),
                f"message '{message.message_id}' of conversation '{conversation.conversation_id}' sent "
                f"{message.timestamp:%Y-%m-%d %H:%M}",
            )
            for key, conversation in self.state.conversations.items()
            for index, message in enumerate(conversation.messages)
            if message.timestamp > now
        ]

    @property
    def me(self) -> str:
        """The phone owner's user id."""
        return self.state.current_user_id

    def require(self, conversation_id: str) -> Conversation:
        """Return the conversation ``conversation_id``; raise :class:`ToolError` naming it otherwise."""
        conversation = self.state.conversations.get(conversation_id)
        if conversation is None:
            raise ToolError(
                f"No conversation with id '{conversation_id}'."
                f"{did_you_mean(conversation_id, self.state.conversations)} "
                "Use list_recent_conversations or search to find conversation ids."
            )
        return conversation

    def require_user(self, user_id: str) -> str:
        """Return the display name of user ``user_id``; raise :class:`ToolError` naming it otherwise."""
        name = self.state.users.get(user_id)
        if name is None:
            raise ToolError(
                f"No user with id '{user_id}'.{did_you_mean(user_id, self.state.users)} "
                "Use get_user_id to look up a user's id from their name."
            )
        return name

    def one_to_one_with(self, user_id: str) -> Conversation | None:
        """Return the one-to-one conversation between the phone owner and ``user_id``, if any."""
        wanted = {self.me, user_id}
        return next(
            (
                c
                for c in self.state.conversations.values()
                if not c.is_group and set(c.participant_ids) == wanted
            ),
            None,
        )

    def other_participant(self, conversation: Conversation) -> str:
        """Return the other person in a one-to-one conversation."""
        return next(p for p in conversation.participant_ids if p != self.me)

    def display_title(self, conversation: Conversation) -> str:
        """Return the conversation's title, or the other participants' names when it has none."""
        if conversation.title:
            return conversation.title
        return ", ".join(self.state.users[p] for p in conversation.participant_ids if p != self.me)

    def message_view(self, message: Message) -> MessageView:
        """``message`` with its sender's name, as tools show it."""
        return MessageView(
            message_id=message.message_id,
            sender_id=message.sender_id,
            sender_name=self.state.users.get(message.sender_id, message.sender_id),
            from_current_user=message.sender_id == self.me,
            content=message.content,
            timestamp=message.timestamp,
            attachment=message.attachment,
        )

    def _called(self, conversation: Conversation) -> str:
        """How a result names a conversation: its id, with its title when it has one."""
        title = f" ('{conversation.title}')" if conversation.title else ""
        return f"conversation {conversation.conversation_id}{title}"

    def _others(self, conversation: Conversation) -> str:
        """The participants besides the user, by name, as a sentence lists them."""
        return listed([self.state.users[p] for p in conversation.participant_ids if p != self.me])

    def _participants(self, conversation: Conversation) -> list[Participant]:
        return [
            Participant(user_id=p, name=self.state.users[p], is_current_user=p == self.me)
            for p in conversation.participant_ids
        ]

    def mark_read(self, conversation_id: str) -> None:
        """The user has seen this conversation's messages (it opened or read it), as a phone marks them.

        Not a tool and not counted as a write: the user did not choose to change anything, so the call
        stays a navigation or a read in the log and in attribution.
        """
        self.require(conversation_id).unread = 0

    def _summary(self, conversation: Conversation) -> ConversationSummary:
        last = conversation.messages[-1] if conversation.messages else None
        return ConversationSummary(
            conversation_id=conversation.conversation_id,
            is_group=conversation.is_group,
            title=conversation.title,
            participants=self._participants(conversation),
            last_updated=conversation.last_updated,
            message_count=len(conversation.messages),
            unread=conversation.unread,
            last_message=None if last is None else self.message_view(last),
        )

    @staticmethod
    def _recent_first(conversations: list[Conversation]) -> list[Conversation]:
        """Most recently updated first (never-updated ones last), ties by id."""
        by_id = sorted(conversations, key=lambda c: c.conversation_id)
        return sorted(by_id, key=lambda c: c.last_updated or _NEVER, reverse=True)

    def _page(self, conversations: list[Conversation], offset: int, limit: int) -> ConversationPage:
        _check_page(offset, limit)
        ordered = self._recent_first(conversations)
        return ConversationPage(
            conversations=[self._summary(c) for c in ordered[offset : offset + limit]],
            total=len(ordered),
            offset=offset,
        )

    def _files(self) -> FilesApp:
        return files_of(self)

    def _check_message(self, content: str, attachment: str | None) -> tuple[str, str | None]:
        """Return the stripped content and the attachment's normalised path.

        Raises :class:`ToolError` when the message is empty or the attachment is not a stored file.
        """
        text = content.strip()
        path = None if attachment is None or not attachment.strip() else self._files().require(attachment)
        if not text and path is None:
            raise ToolError("The message is empty: give some content or an attachment.")
        return text, path

    def _all_message_ids(self) -> set[str]:
        return {m.message_id for c in self.state.conversations.values() for m in c.messages}

    def _post(
        self,
        conversation: Conversation,
        sender_id: str,
        content: str,
        attachment: str | None,
        message_id: str | None = None,
    ) -> Message:
        """Append a message (already checked) and move the conversation to the top."""
        now = self.ctx.now()
        message = Message(
            message_id=message_id or self.new_id("msg", self._all_message_ids()),
            sender_id=sender_id,
            content=content,
            timestamp=now,
            attachment=attachment,
        )
        conversation.messages.append(message)
        conversation.last_updated = now
        return message

    def _new_conversation(
        self, participant_ids: list[str], *, title: str | None, is_group: bool
    ) -> Conversation:
        conversation_id = self.new_id("conv", self.state.conversations)
        conversation = Conversation(
            conversation_id=conversation_id,
            participant_ids=participant_ids,
            title=title,
            is_group=is_group,
            last_updated=self.ctx.now(),
        )
        self.state.conversations[conversation_id] = conversation
        return conversation

    def _users_named(self, name: str) -> list[str]:
        wanted = " ".join(name.split()).lower()
        return [uid for uid, n in self.state.users.items() if " ".join(n.split()).lower() == wanted]

    # -- agent API: reading ----------------------------------------------------------------------------
    @tool("read")
    def list_recent_conversations(self, offset: int = 0, limit: int = PAGE) -> ConversationPage:
        """List conversations, most recently updated first, with their participants and last message.

        Args:
            offset: how many conversations to skip (0 starts from the most recent).
            limit: how many conversations to return (1-100).

        Returns:
            the page of conversations (id, whether it is a group, title, participants with ids and names,
            last message) and the total number of conversations.
        """
        return self._page(list(self.state.conversations.values()), offset, limit)

    @tool("read")
    def list_conversations_by_participant(
        self, user_id: str, offset: int = 0, limit: int = PAGE
    ) -> ConversationPage:
        """List the conversations (one-to-one and group) a given person takes part in, latest first.

        Args:
            user_id: the person's user id (use get_user_id to find it from their name).
            offset: how many conversations to skip.
            limit: how many conversations to return (1-100).

        Returns:
            the page of conversations with their participants and last message, and the total.
        """
        self.require_user(user_id)
        found = [c for c in self.state.conversations.values() if user_id in c.participant_ids]
        return self._page(found, offset, limit)

    @tool("read")
    def read_conversation(
        self, conversation_id: str, offset: int = 0, limit: int = 10
    ) -> ConversationMessages:
        """Read a conversation's messages, NEWEST FIRST.

        Offset 0 starts at the latest message; larger offsets go back in time.

        Args:
            conversation_id: the conversation to read.
            offset: how many of the most recent messages to skip (to page back through older ones).
            limit: how many messages to return (1-100).

        Returns:
            the conversation's participants and a page of its messages (newest first), each with the
            sender's id and name, time, content and attachment path, plus the total number of messages.
        """
        conversation = self.require(conversation_id)
        _check_page(offset, limit)
        newest_first = list(reversed(conversation.messages))
        return ConversationMessages(
            conversation_id=conversation.conversation_id,
            is_group=conversation.is_group,
            title=conversation.title,
            participants=self._participants(conversation),
            messages=[self.message_view(m) for m in newest_first[offset : offset + limit]],
            total_messages=len(conversation.messages),
            offset=offset,
        )

    @tool("read")
    def search(self, query: str) -> list[ConversationMatch]:
        """Search conversations by group title, participant names and message contents.

        The search is case-insensitive, and every word of the query must appear somewhere in the
        conversation. It matches parts of words too: "Priya" finds "Priyanka".

        Args:
            query: words to look for, e.g. "dinner friday" or "alice".

        Returns:
            the matching conversations, most recently updated first, each with the messages (newest first)
            whose content contains every word.
        """
        words = query.lower().split()
        if not words:
            raise ToolError("The search query is empty.")
        found: list[Conversation] = []
        for conversation in self.state.conversations.values():
            parts = [conversation.title or ""]
            parts += [self.state.users[p] for p in conversation.participant_ids if p != self.me]
            parts += [m.content for m in conversation.messages]
            parts += [posixpath.basename(m.attachment) for m in conversation.messages if m.attachment]
            haystack = " ".join(parts).lower()
            if all(word in haystack for word in words):
                found.append(conversation)
        results = []
        for conversation in self._recent_first(found):
            matches = [
                m for m in reversed(conversation.messages) if all(w in m.content.lower() for w in words)
            ]
            summary = self._summary(conversation).model_dump()
            summary["matching_messages"] = [self.message_view(m).model_dump() for m in matches]
            results.append(ConversationMatch.model_validate(summary))
        return results

    @tool("read")
    def get_user_id(self, user_name: str) -> str:
        """Find a person's user id from their display name (case-insensitive exact match).

        Args:
            user_name: the person's full display name, e.g. "Alice Chen".

        Returns:
            the user id.
        """
        if not user_name.strip():
            raise ToolError("The user name is empty.")
        matches = self._users_named(user_name)
        if len(matches) == 1:
            return matches[0]
        if matches:
            raise ToolError(
                f"Several users are called '{user_name}': {', '.join(matches)}. "
                "Use list_conversations_by_participant to tell them apart."
            )
        raise ToolError(f"No user is called '{user_name}'.{self._close_names(user_name)}")

    def _close_names(self, name: str) -> str:
        wanted = name.strip().lower()
        names = {n.lower(): n for n in self.state.users.values()}
        words = set(wanted.split())
        close = [names[n] for n in names if wanted in n or words & set(n.split())]
        close += [names[n] for n in difflib.get_close_matches(wanted, list(names), n=5, cutoff=0.6)]
        unique = list(dict.fromkeys(close))[:5]
        if not unique:
            return " Check the spelling, or look the person up in recent conversations."
        return " Close names: " + ", ".join(f"'{n}'" for n in unique) + "."

    @tool("read")
    def get_user_name_from_id(self, user_id: str) -> str:
        """Get a person's display name from their user id.

        Args:
            user_id: the user id, e.g. from a conversation's participants.

        Returns:
            the display name.
        """
        return self.require_user(user_id)

    # -- agent API: writing ----------------------------------------------------------------------------
    @tool("write")
    def send_message(self, user_id: str, content: str, attachment: str | None = None) -> Done:
        """Send a message to one person, in the one-to-one conversation with them.

        The conversation is started if there is none yet. For a group conversation use
        send_message_to_group_conversation.

        Args:
            user_id: the recipient's user id (use get_user_id to find it from their name).
            content: the text of the message; may be empty only when there is an attachment.
            attachment: path of a file in the Files app to attach, e.g. "/Documents/lease.pdf".

        Returns:
            whom the message went to, and the id of the conversation it was sent in.
        """
        name = self.require_user(user_id)
        if user_id == self.me:
            raise ToolError(f"'{user_id}' is the phone's owner ({name}); you cannot message yourself.")
        text, path = self._check_message(content, attachment)
        conversation = self.one_to_one_with(user_id)
        if conversation is None:
            conversation = self._new_conversation([self.me, user_id], title=None, is_group=False)
        message = self._post(conversation, self.me, text, path)
        done = f"Sent {message.message_id} to {name} ({user_id}) in {self._called(conversation)}."
        return Done(done=done, id=conversation.conversation_id)

    @tool("write")
    def send_message_to_group_conversation(
        self, conversation_id: str, content: str, attachment: str | None = None
    ) -> Done:
        """Send a message in an existing conversation, by its id.

        Meant for group conversations; a one-to-one conversation's id works too.

        Args:
            conversation_id: the conversation to post in.
            content: the text of the message; may be empty only when there is an attachment.
            attachment: path of a file in the Files app to attach, e.g. "/Photos/team.jpg".

        Returns:
            whom the message went to, and the new message's id.
        """
        conversation = self.require(conversation_id)
        text, path = self._check_message(content, attachment)
        message = self._post(conversation, self.me, text, path)
        done = f"Sent {message.message_id} in {self._called(conversation)} to {self._others(conversation)}."
        return Done(done=done, id=message.message_id)

    @tool("write")
    def create_group_conversation(self, user_ids: list[str], title: str | None = None) -> Done:
        """Start a group conversation between the user and at least two other people.

        Args:
            user_ids: the other participants' user ids (at least two; the user is added automatically).
            title: the group's name, e.g. "Hiking crew".

        Returns:
            who is in the new conversation, and its id.
        """
        others = list(dict.fromkeys(u for u in user_ids if u != self.me))
        for user_id in others:
            self.require_user(user_id)
        if len(others) < 2:
            raise ToolError(
                "A group conversation needs at least two other people; "
                "to message one person use send_message."
            )
        name = title.strip() if title is not None and title.strip() else None
        conversation = self._new_conversation([self.me, *others], title=name, is_group=True)
        return Done(
            done=f"Started {self._called(conversation)} with {self._others(conversation)}.",
            id=conversation.conversation_id,
        )

    @tool("write")
    def add_participant_to_conversation(self, conversation_id: str, user_id: str) -> str:
        """Add a person to a conversation.

        A one-to-one conversation that gets a third participant becomes a group conversation.

        Args:
            conversation_id: the conversation.
            user_id: the person to add.

        Returns:
            confirmation.
        """
        conversation = self.require(conversation_id)
        name = self.require_user(user_id)
        if user_id in conversation.participant_ids:
            raise ToolError(f"{name} ({user_id}) is already in conversation {conversation_id}.")
        was_group = conversation.is_group
        conversation.participant_ids.append(user_id)
        conversation.is_group = True
        note = "" if was_group else " It is now a group conversation."
        shown = self.display_title(conversation)
        return f"Added {name} ({user_id}) to conversation {conversation_id} ({shown}).{note}"

    @tool("write")
    def remove_participant_from_conversation(self, conversation_id: str, user_id: str) -> str:
        """Remove a person from a group conversation.

        Args:
            conversation_id: the group conversation.
            user_id: the person to remove (not the user themself).

        Returns:
            confirmation.
        """
        conversation = self.require(conversation_id)
        name = self.require_user(user_id)
        if user_id not in conversation.participant_ids:
            raise ToolError(f"{name} ({user_id}) is not in conversation {conversation_id}.")
        if user_id == self.me:
            raise ToolError("The phone's owner cannot be removed from their own conversations.")
        if not conversation.is_group:
            raise ToolError(
                f"Conversation {conversation_id} is one-to-one; only group participants can be removed."
            )
        if len(conversation.participant_ids) <= 2:
            raise ToolError(
                f"{name} is the last other participant of {conversation_id}; a conversation needs one."
            )
        conversation.participant_ids.remove(user_id)
        return f"Removed {name} ({user_id}) from conversation {conversation_id}."

    @tool("write")
    def change_conversation_title(self, conversation_id: str, title: str) -> str:
        """Rename a group conversation.

        Args:
            conversation_id: the group conversation.
            title: the new title.

        Returns:
            confirmation.
        """
        conversation = self.require(conversation_id)
        if not conversation.is_group:
            raise ToolError(
                f"Conversation {conversation_id} is one-to-one and is shown under the other person's name; "
                "only group conversations have titles."
            )
        if not title.strip():
            raise ToolError("The title is empty.")
        conversation.title = title.strip()
        return f"Conversation {conversation_id} is now titled '{conversation.title}'."

    @tool("write")
    def download_attachment(self, conversation_id: str, message_id: str, path: str = "/Downloads") -> Done:
        """Save a message's attachment into a folder of the Files app.

        Args:
            conversation_id: the conversation the message is in.
            message_id: the message with the attachment.
            path: the folder to save into, e.g. "/Downloads" or "/Documents".

        Returns:
            what was saved where, and the saved file's path as its id (a number is added to the name if a
            different file already has it).
        """
        conversation = self.require(conversation_id)
        message = next((m for m in conversation.messages if m.message_id == message_id), None)
        if message is None:
            raise ToolError(
                f"No message with id '{message_id}' in conversation {conversation_id}. "
                "Use read_conversation to see message ids."
            )
        if message.attachment is None:
            raise ToolError(f"Message {message_id} has no attachment.")
        files = self._files()
        source = files.require(message.attachment)
        content = files.state.files[source].content
        folder = normalize_path(path)
        stem, ext = posixpath.splitext(posixpath.basename(source))
        target = posixpath.join(folder, stem + ext)
        number = 1
        while files.exists(target) and files.state.files[target].content != content:
            target = posixpath.join(folder, f"{stem} ({number}){ext}")
            number += 1
        if not files.exists(target):
            files.store(target, content)
        return Done(
            done=f"Saved {message_id}'s attachment {posixpath.basename(source)} as {target}.", id=target
        )

    # -- the world ---------------------------------------------------------------------------------------
    @tool("env", actors=())
    def receive_message(
        self,
        sender: str,
        content: str,
        conversation_id: str | None = None,
        group_title: str | None = None,
        message_id: str | None = None,
        attachment: str | None = None,
    ) -> ReceivedMessage:
        """Deliver a message someone sends the user, and notify the user and the assistant.

        It goes to the conversation ``conversation_id`` if given (the sender joins it if needed); else to
        the group conversation titled ``group_title`` (created with the sender and the user if there is
        none); else to the one-to-one conversation with the sender (created if there is none).

        Args:
            sender: the sender's display name (a new user is created for an unknown name) or user id.
            content: the message text.
            conversation_id: an existing conversation to post in.
            group_title: the title of the group conversation to post in.
            message_id: the id to give the message (generated when omitted; must be unused).
            attachment: path of a file in the Files app attached to the message.

        Returns:
            the conversation and message ids, and the sender's user id.
        """
        text, path = self._check_message(content, attachment)
        if message_id is not None and not message_id.strip():
            raise ToolError("The message id is empty.")
        if message_id is not None and message_id in self._all_message_ids():
            raise ToolError(f"A message with id '{message_id}' already exists.")
        sender_id = self._resolve_sender(sender)
        if sender_id == self.me:
            raise ToolError(f"'{sender}' is the phone's owner; an incoming message needs another sender.")
        title = group_title.strip() if group_title is not None and group_title.strip() else None
        conversation: Conversation | None = None
        if conversation_id is not None:
            conversation = self.require(conversation_id)
        elif title is not None:
            conversation = self._group_titled(title)
        else:
            conversation = self.one_to_one_with(sender_id) if sender_id is not None else None
        # everything is checked; now change things
        if sender_id is None:
            sender_id = self.new_id("user", self.state.users)
            self.state.users[sender_id] = " ".join(sender.split())
        if conversation is None:
            if title is not None:
                conversation = self._new_conversation([self.me, sender_id], title=title, is_group=True)
            else:
                conversation = self._new_conversation([self.me, sender_id], title=None, is_group=False)
        elif sender_id not in conversation.participant_ids:
            conversation.participant_ids.append(sender_id)
            conversation.is_group = True
        message = self._post(conversation, sender_id, text, path, message_id)
        conversation.unread += 1
        name = self.state.users[sender_id]
        headline = f"New message from {name}"
        if conversation.is_group:
            headline += f" in {self.display_title(conversation)}"
        body = text or f"[attachment: {posixpath.basename(path or '')}]"
        data: dict[str, Any] = {
            "conversation_id": conversation.conversation_id,
            "message_id": message.message_id,
        }
        if path is not None:
            data["attachment"] = path
        self.notify("new_message", headline, body=body, data=data)
        return ReceivedMessage(
            conversation_id=conversation.conversation_id, message_id=message.message_id, sender_id=sender_id
        )

    def _resolve_sender(self, sender: str) -> str | None:
        """Return the id of the user ``sender`` names (an id or a display name); ``None`` if unknown."""
        if not sender.strip():
            raise ToolError("The sender is empty.")
        if sender in self.state.users:
            return sender
        matches = self._users_named(sender)
        return matches[0] if matches else None

    def _group_titled(self, title: str) -> Conversation | None:
        """Return the latest updated group conversation titled ``title`` (case-insensitive), if any."""
        wanted = title.lower()
        groups = [
            c
            for c in self.state.conversations.values()
            if c.is_group and c.title is not None and c.title.strip().lower() == wanted
        ]
        ordered = self._recent_first(groups)
        return ordered[0] if ordered else None


def _check_page(offset: int, limit: int) -> None:
    if offset < 0 or not 1 <= limit <= 100:
        raise ToolError("offset must be >= 0 and limit between 1 and 100.")


# -- screens -----------------------------------------------------------------------------------------


def _row(app: MessagingApp, conversation: Conversation) -> dict[str, Any]:
    """A conversation as the list shows it: its name, the last message (who, a preview) and when."""
    row: dict[str, Any] = {
        "conversation_id": conversation.conversation_id,
        "title": app.display_title(conversation),
    }
    if conversation.is_group:
        row["group"] = True
    if conversation.messages:
        last = conversation.messages[-1]
        who = "You" if last.sender_id == app.me else app.state.users.get(last.sender_id, last.sender_id)
        text = last.content or f"[attachment: {posixpath.basename(last.attachment or '')}]"
        row["last_message"] = f"{who}: {preview(text)}"
    row["time"] = short_time(conversation.last_updated)
    row["messages"] = len(conversation.messages)
    if conversation.unread:
        row["unread"] = conversation.unread
    return row


def _on_screen(
    app: MessagingApp, conversation_id: str, offset: int = 0, limit: int = 10
) -> ConversationMessages:
    """A page of a conversation as its screen shows it, whose ``showing`` names the screen's own way back
    to older messages (read_messages), since a model reading the latest ten takes them for the whole talk.
    """
    page = app.read_conversation(conversation_id, offset=offset, limit=limit)
    page.showing = showing(offset, len(page.messages), page.total_messages, "read_messages(offset={offset})")
    return page


class ConversationList(Screen):
    """The list of conversations."""

    name = "List"
    title = "Conversations"

    def display(self, app: MessagingApp) -> dict[str, Any]:
        """The most recent conversations as a phone lists them: who, the last message and when, with the
        total; the conversation ids are those open_conversation takes.
        """
        ordered = app._recent_first(list(app.state.conversations.values()))
        return {
            "total": len(ordered),
            "conversations": [_row(app, c) for c in ordered[:PAGE]],
            **showing_screen(ordered[:PAGE], len(ordered), "list_recent_conversations(offset={offset})"),
        }

    @action(kind="read")
    def list_recent_conversations(
        self, app: MessagingApp, offset: int = 0, limit: int = PAGE
    ) -> ConversationPage:
        """Show conversations, most recent first.

        Args:
            app: the messaging app.
            offset: how many conversations to skip.
            limit: how many to show.
        """
        return app.list_recent_conversations(offset=offset, limit=limit)

    @action(kind="read")
    def search_conversations(self, app: MessagingApp, query: str) -> list[ConversationMatch]:
        """Search conversations by name, group title or message text. It matches parts of words too:
        "Priya" finds "Priyanka".

        Args:
            app: the messaging app.
            query: what to look for.
        """
        return app.search(query)

    @action("Opened")
    def open_conversation(self, app: MessagingApp, conversation_id: str) -> Transition:
        """Open a conversation and show its latest messages.

        Args:
            app: the messaging app.
            conversation_id: the conversation's id.
        """
        shown = _on_screen(app, conversation_id)
        app.mark_read(conversation_id)
        return push(ConversationOpened(conversation_id=conversation_id), shown)


class ConversationOpened(Screen):
    """One conversation."""

    name = "Opened"
    title = "Conversation"
    conversation_id: str

    def display(self, app: MessagingApp) -> ConversationMessages | str:
        """The conversation's latest messages in full, newest first, as read_messages shows them; a
        message arriving while it is open appears here whole.
        """
        if self.conversation_id not in app.state.conversations:
            return f"Conversation {self.conversation_id} no longer exists."
        return _on_screen(app, self.conversation_id)

    @action(kind="write")
    def send_message(self, app: MessagingApp, content: str, attachment: str | None = None) -> MessageView:
        """Send a message in this conversation.

        Args:
            app: the messaging app.
            content: the text to send.
            attachment: path of a file to attach, e.g. "/Photos/beach.jpg".
        """
        conversation = app.require(self.conversation_id)
        if conversation.is_group:
            app.send_message_to_group_conversation(self.conversation_id, content, attachment)
        else:
            app.send_message(app.other_participant(conversation), content, attachment)
        return app.message_view(conversation.messages[-1])

    @action(kind="read")
    def browse_files(self, app: MessagingApp, directory: str = "/") -> list[DirectoryEntry]:
        """Look through the files on your phone to find one to send as an attachment.

        Args:
            directory: the folder to look in, e.g. "/Photos"; "/" is the top.
        """
        return browse(app, directory)

    @action(kind="read")
    def read_messages(self, app: MessagingApp, offset: int = 0, limit: int = 10) -> ConversationMessages:
        """Show this conversation's messages, newest first; an offset goes back to older ones.

        Args:
            app: the messaging app.
            offset: how many of the newest messages to skip, e.g. 10 for the ten before the latest ten.
            limit: how many to show.
        """
        shown = _on_screen(app, self.conversation_id, offset=offset, limit=limit)
        app.mark_read(self.conversation_id)
        return shown


MessagingApp.set_screens(ConversationList, ConversationOpened)
