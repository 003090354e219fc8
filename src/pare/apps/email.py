"""Email: the user's mailbox, with folders, attachments (files in the Files app), replies and drafts."""

# Screen actions take the app as their second argument; the framework passes it and models never see it,
# so it is not described in their docstrings.

from __future__ import annotations

import posixpath
import re
from datetime import datetime
from enum import StrEnum
from typing import Any

from pydantic import BaseModel, ConfigDict, Field, field_validator, model_validator

from pare.apps.base import App, DatedRecord
from pare.apps.done import Done, SavedFiles, listed
from pare.apps.files import DirectoryEntry, FilesApp, browse, files_of, normalize_path
from pare.apps.paging import Paged, showing_screen
from pare.apps.screens import BACK, Screen, Transition, action, back, push, replace
from pare.apps.text import PAGE, preview, short_time
from pare.apps.tools import tool
from pare.apps.types import SimTime
from pare.errors import ToolError

_FOLDER_ALIASES = {"DRAFTS": "DRAFT", "ARCHIVED": "ARCHIVE", "BIN": "TRASH", "DELETED": "TRASH"}


class Folder(StrEnum):
    """A mailbox folder. Names are accepted in any case ("inbox", "Archive")."""

    INBOX = "INBOX"
    SENT = "SENT"
    DRAFT = "DRAFT"
    TRASH = "TRASH"
    ARCHIVE = "ARCHIVE"

    @classmethod
    def _missing_(cls, value: object) -> Folder | None:
        if isinstance(value, str):
            name = value.strip().upper()
            name = _FOLDER_ALIASES.get(name, name)
            if name in cls.__members__:
                return cls[name]
        return None

    def __repr__(self) -> str:
        return repr(self.value)


FOLDERS = tuple(folder.value for folder in Folder)
"""The mailbox's folders."""

_ADDRESS = re.compile(r"^[^@\s<>()\[\],;:\"]+@[^@\s<>()\[\],;:\"]+\.[^@\s<>()\[\],;:\".]+$")

_FORWARD_RULE = "---------- Forwarded message ----------"


def normalize_folder(folder: str) -> Folder:
    """Return the folder called ``folder`` (any case); :class:`ToolError` listing the folders otherwise."""
    try:
        return Folder(folder)
    except ValueError:
        raise ToolError(f"Unknown folder '{folder}'. Folders are: {', '.join(FOLDERS)}.") from None


def is_address(address: str) -> bool:
    """Whether ``address`` looks like an email address (``name@domain.tld``)."""
    return bool(_ADDRESS.match(address))


def _sent(what: str, email: Email) -> Done:
    """The result of sending ``email``, e.g. ``Sent email-712 to bob@example.com: 'Re: Lunch'.``."""
    copied = f" (cc {listed(email.cc)})" if email.cc else ""
    attached = f", with {len(email.attachments)} attachment(s)" if email.attachments else ""
    done = f"{what} {email.email_id} to {listed(email.recipients)}{copied}: '{email.subject}'{attached}."
    return Done(done=done, id=email.email_id)


def _reply_subject(subject: str) -> str:
    return subject if subject.strip().lower().startswith("re:") else f"Re: {subject}"


def _forward_subject(subject: str) -> str:
    lowered = subject.strip().lower()
    return subject if lowered.startswith(("fwd:", "fw:")) else f"Fwd: {subject}"


class Email(BaseModel):
    """One email, in one folder."""

    model_config = ConfigDict(extra="forbid")

    email_id: str
    sender: str
    recipients: list[str] = Field(default_factory=list)
    cc: list[str] = Field(default_factory=list)
    subject: str = ""
    content: str = ""
    timestamp: SimTime
    is_read: bool = False
    attachments: list[str] = Field(default_factory=list, description="Paths of files in the Files app.")
    folder: Folder = Folder.INBOX
    in_reply_to: str | None = Field(default=None, description="Id of the email this one answers.")


class EmailState(BaseModel):
    """The owner's address and every email by id."""

    model_config = ConfigDict(extra="forbid")

    user_email: str = "me@pare.example"
    emails: dict[str, Email] = Field(default_factory=dict)

    @field_validator("user_email")
    @classmethod
    def _check_user_email(cls, value: str) -> str:
        if not is_address(value.strip()):
            raise ValueError(f"'{value}' is not an email address")
        return value.strip()

    @model_validator(mode="after")
    def _check_keys(self) -> EmailState:
        for key, email in self.emails.items():
            if key != email.email_id:
                raise ValueError(f"email stored under '{key}' has email_id '{email.email_id}'")
        return self


class EmailPage(Paged):
    """One page of a folder, newest first."""

    rows_field = "emails"

    folder: Folder
    emails: list[Email]
    total: int
    offset: int


class EmailApp(App):
    """The mailbox."""

    name = "email"
    title = "Email"
    description = "The user's email: inbox, sent mail, drafts, archive and trash, with attachments."
    State = EmailState
    # sending cannot be taken back; delete_email deletes for good when the email is already in Trash
    harm = {
        "send_email": "irreversible",
        "reply_to_email": "irreversible",
        "forward_email": "irreversible",
        "move_email": "reversible",
        "delete_email": "irreversible",
        "download_attachments": "reversible",
        "save_draft": "reversible",
    }
    also_writes = ("files",)
    state: EmailState

    # -- helpers used by other apps and screens -----------------------------------------------------
    def attached_paths(self) -> list[tuple[str, str]]:
        """Every (holder, path) of a file an email has attached, e.g. ("email 'email-3'", "/Docs/a.pdf")."""
        return [(f"email '{e.email_id}'", path) for e in self.state.emails.values() for path in e.attachments]

    def records_dated_after(self, now: datetime) -> list[DatedRecord]:
        """See :meth:`App.records_dated_after`."""
        return [
            DatedRecord(
                ("emails", key, "timestamp"),
                f"email '{email.email_id}' sent {email.timestamp:%Y-%m-%d %H:%M}",
            )
            for key, email in self.state.emails.items()
            if email.timestamp > now
        ]

    def require(self, email_id: str) -> Email:
        """Return the email with ``email_id``; :class:`ToolError` naming it otherwise."""
        email = self.state.emails.get(email_id)
        if email is None:
            raise ToolError(
                f"No email with id '{email_id}'. Use list_emails or search_emails to find email ids."
            )
        return email

    def files(self) -> FilesApp:
        """Return the Files app, where attachments live."""
        return files_of(self)

    def in_folder(self, folder: str) -> list[Email]:
        """Return the emails of ``folder`` (any case), newest first; on a tie, the latest stored first."""
        name = normalize_folder(folder)
        emails = [email for email in reversed(self.state.emails.values()) if email.folder == name]
        return sorted(emails, key=lambda e: e.timestamp, reverse=True)

    def check_addresses(self, addresses: list[str], what: str) -> list[str]:
        """``addresses`` stripped and de-duplicated; :class:`ToolError` naming any malformed one."""
        cleaned: list[str] = []
        for address in addresses:
            stripped = address.strip()
            if not is_address(stripped):
                raise ToolError(
                    f"'{address}' in {what} is not an email address (expected name@domain, e.g. "
                    "alice@example.com). Look the address up in Contacts if you only know a name."
                )
            if stripped.lower() not in (a.lower() for a in cleaned):
                cleaned.append(stripped)
        return cleaned

    def check_attachments(self, paths: list[str] | None) -> list[str]:
        """Return the normalised paths of ``paths``, each of which must be a file in the Files app."""
        if not paths:
            return []
        files = self.files()
        normalized: list[str] = []
        for path in paths:
            stored = files.require(path)
            if stored not in normalized:
                normalized.append(stored)
        return normalized

    def reply_recipients(self, original: Email) -> list[str]:
        """Who a reply to ``original`` goes to: its sender, or its recipients if the user sent it."""
        if original.sender.lower() == self.state.user_email.lower():
            return list(original.recipients)
        return [original.sender]

    def mark_read(self, email: Email) -> Email:
        """Mark ``email`` read because the user opened it, as a phone does; return it.

        Not a tool and not counted as a write: the user did not choose to change the mailbox, so the call
        that opened the email stays a navigation in the log and in attribution.
        """
        email.is_read = True
        return email

    def require_sent(self, email_id: str, verb: str) -> Email:
        """Return the email with ``email_id``, which must not be an unsent draft."""
        email = self.require(email_id)
        if email.folder == Folder.DRAFT:
            raise ToolError(f"Email '{email_id}' is an unsent draft; it cannot be {verb}.")
        return email

    def _store(
        self,
        *,
        sender: str,
        recipients: list[str],
        cc: list[str],
        subject: str,
        content: str,
        attachments: list[str],
        folder: Folder,
        is_read: bool,
        in_reply_to: str | None = None,
        email_id: str | None = None,
    ) -> Email:
        email_id = email_id or self.new_id("email", self.state.emails)
        email = Email(
            email_id=email_id,
            sender=sender,
            recipients=recipients,
            cc=cc,
            subject=subject,
            content=content,
            timestamp=self.ctx.now(),
            is_read=is_read,
            attachments=attachments,
            folder=folder,
            in_reply_to=in_reply_to,
        )
        self.state.emails[email_id] = email
        return email

    # -- agent API: reading --------------------------------------------------------------------------
    @tool("read")
    def list_emails(self, folder: Folder = Folder.INBOX, offset: int = 0, limit: int = PAGE) -> EmailPage:
        """List the emails of a folder, newest first, a page at a time.

        Args:
            folder: the folder: INBOX, SENT, DRAFT, TRASH or ARCHIVE.
            offset: how many emails to skip.
            limit: how many emails to return (1-100).

        Returns:
            the page of emails, with the total number of emails in the folder.
        """
        if offset < 0 or not 1 <= limit <= 100:
            raise ToolError("offset must be >= 0 and limit between 1 and 100.")
        name = normalize_folder(folder)
        emails = self.in_folder(name)
        return EmailPage(
            folder=name, emails=emails[offset : offset + limit], total=len(emails), offset=offset
        )

    @tool("read")
    def get_email_by_id(self, email_id: str) -> Email:
        """Get one email, with its full content and attachments.

        Args:
            email_id: the email's id, e.g. "email-3".

        Returns:
            the email.
        """
        return self.require(email_id)

    @tool("read")
    def get_email_by_index(self, index: int, folder: Folder = Folder.INBOX) -> Email:
        """Get the email at a position of a folder's newest-first listing (0 is the newest).

        Args:
            index: the position, starting at 0 for the newest email.
            folder: the folder: INBOX, SENT, DRAFT, TRASH or ARCHIVE.

        Returns:
            the email.
        """
        name = normalize_folder(folder)
        emails = self.in_folder(name)
        if not 0 <= index < len(emails):
            raise ToolError(
                f"No email at index {index} in {name}: it holds {len(emails)} email(s), indexed from 0."
            )
        return emails[index]

    @tool("read")
    def search_emails(self, query: str, folder: Folder | None = None) -> list[Email]:
        """Search emails by sender, recipients (To and Cc), subject and content.

        The search is case-insensitive and every word of the query must appear. It matches parts of words
        too: "Priya" finds "Priyanka".

        Args:
            query: words to look for, e.g. "lease renewal" or "alice@example.com".
            folder: only search this folder (INBOX, SENT, DRAFT, TRASH or ARCHIVE); all folders when omitted.

        Returns:
            the matching emails, newest first.
        """
        words = query.lower().split()
        if not words:
            raise ToolError("The search query is empty.")
        candidates = self.in_folder(folder) if folder is not None else self._all_newest_first()
        found = []
        for email in candidates:
            haystack = " ".join(
                [email.sender, *email.recipients, *email.cc, email.subject, email.content]
            ).lower()
            if all(word in haystack for word in words):
                found.append(email)
        return found

    def _all_newest_first(self) -> list[Email]:
        return sorted(reversed(self.state.emails.values()), key=lambda e: e.timestamp, reverse=True)

    # -- agent API: writing --------------------------------------------------------------------------
    @tool("write")
    def send_email(
        self,
        recipients: list[str],
        subject: str,
        content: str,
        cc: list[str] | None = None,
        attachments: list[str] | None = None,
    ) -> Done:
        """Send a new email from the user's address; it is stored in SENT.

        Args:
            recipients: the addresses to send to, e.g. ["alice@example.com"] (at least one).
            subject: the subject line.
            content: the body of the email.
            cc: addresses to copy.
            attachments: paths of files in the Files app to attach, e.g. ["/Documents/lease.pdf"].

        Returns:
            what was sent to whom, and the sent email's id.
        """
        to = self.check_addresses(recipients, "recipients")
        if not to:
            raise ToolError("An email needs at least one recipient.")
        copied = self.check_addresses(cc or [], "cc")
        files = self.check_attachments(attachments)
        sent = self._store(
            sender=self.state.user_email,
            recipients=to,
            cc=copied,
            subject=subject,
            content=content,
            attachments=files,
            folder=Folder.SENT,
            is_read=True,
        )
        return _sent("Sent", sent)

    @tool("write")
    def reply_to_email(self, email_id: str, content: str, attachments: list[str] | None = None) -> Done:
        """Reply to an email; the reply is stored in SENT.

        The reply goes to the email's sender (or, for an email the user sent, to its recipients) with the
        subject "Re: <subject>".

        Args:
            email_id: the email to reply to.
            content: the body of the reply.
            attachments: paths of files in the Files app to attach.

        Returns:
            whom the reply went to, and the reply's id.
        """
        original = self.require_sent(email_id, "replied to")
        to = self.reply_recipients(original)
        if not to:
            raise ToolError(f"Email '{email_id}' has no one to reply to.")
        files = self.check_attachments(attachments)
        sent = self._store(
            sender=self.state.user_email,
            recipients=to,
            cc=[],
            subject=_reply_subject(original.subject),
            content=content,
            attachments=files,
            folder=Folder.SENT,
            is_read=True,
            in_reply_to=original.email_id,
        )
        return _sent(f"Replied to {email_id}: sent", sent)

    @tool("write")
    def forward_email(self, email_id: str, recipients: list[str]) -> Done:
        """Forward an email, with its attachments, to other people; the forward is stored in SENT.

        Args:
            email_id: the email to forward.
            recipients: the addresses to forward it to (at least one).

        Returns:
            whom it was forwarded to, and the forward's id.
        """
        original = self.require_sent(email_id, "forwarded")
        to = self.check_addresses(recipients, "recipients")
        if not to:
            raise ToolError("Forwarding needs at least one recipient.")
        if original.attachments:
            files = self.files()
            missing = [path for path in original.attachments if not files.exists(path)]
            if missing:
                raise files.missing_attachment(missing[0], f"email '{email_id}'")
        header = (
            f"{_FORWARD_RULE}\nFrom: {original.sender}\nDate: {original.timestamp:%Y-%m-%d %H:%M}\n"
            f"Subject: {original.subject}\nTo: {', '.join(original.recipients)}\n\n"
        )
        sent = self._store(
            sender=self.state.user_email,
            recipients=to,
            cc=[],
            subject=_forward_subject(original.subject),
            content=header + original.content,
            attachments=list(original.attachments),
            folder=Folder.SENT,
            is_read=True,
        )
        return _sent(f"Forwarded {email_id}: sent", sent)

    @tool("write")
    def move_email(self, email_id: str, folder: Folder) -> str:
        """Move an email to another folder (INBOX, ARCHIVE, TRASH; SENT only for emails the user sent).

        Args:
            email_id: the email to move.
            folder: the destination folder.

        Returns:
            confirmation.
        """
        email = self.require(email_id)
        target = normalize_folder(folder)
        if target == email.folder:
            raise ToolError(f"Email '{email_id}' is already in {target}.")
        if target == Folder.DRAFT:
            raise ToolError("Emails cannot be moved into DRAFT; use save_draft to write a draft.")
        if target == Folder.SENT and (
            email.folder == Folder.DRAFT or email.sender.lower() != self.state.user_email.lower()
        ):
            raise ToolError("Only emails the user has sent can be moved into SENT; use send_email to send.")
        email.folder = target
        return f"Moved email {email_id} to {target}."

    @tool("write")
    def delete_email(self, email_id: str) -> str:
        """Delete an email: it is moved to TRASH, and an email already in TRASH is deleted for good.

        Args:
            email_id: the email to delete.

        Returns:
            confirmation.
        """
        email = self.require(email_id)
        if email.folder == Folder.TRASH:
            del self.state.emails[email_id]
            return f"Deleted email {email_id} permanently."
        email.folder = Folder.TRASH
        return f"Moved email {email_id} to TRASH."

    @tool("write")
    def download_attachments(self, email_id: str, path: str = "/Downloads") -> SavedFiles:
        """Save copies of an email's attachments in the Files app, in a folder.

        Args:
            email_id: the email whose attachments to download.
            path: the folder to save them in, e.g. "/Downloads".

        Returns:
            what was saved where, the saved files' paths, and the first one's as the id.
        """
        email = self.require(email_id)
        if not email.attachments:
            raise ToolError(f"Email '{email_id}' has no attachments.")
        files = self.files()
        folder = normalize_path(path)
        missing = [source for source in email.attachments if not files.exists(source)]
        if missing:
            raise files.missing_attachment(missing[0], f"email '{email_id}'")
        sources = list(email.attachments)
        plan: dict[str, str] = {}
        for source in sources:
            content = files.state.files[source].content
            target = self._free_name(files, folder, posixpath.basename(source), content, plan)
            plan[target] = content
        for target in plan:  # all or nothing: a failed call leaves the files as they were
            files.check_can_store(target)
        for target, content in plan.items():
            if not files.exists(target) or files.state.files[target].content != content:
                files.store(target, content)
        paths = list(plan)
        saved = listed([posixpath.basename(target) for target in paths])
        return SavedFiles(
            done=f"Saved {email_id}'s attachments in {folder}: {saved}.", id=paths[0], paths=paths
        )

    @staticmethod
    def _free_name(files: FilesApp, folder: str, filename: str, content: str, planned: dict[str, str]) -> str:
        """``folder/filename``, or ``folder/stem (n).ext`` when a different file already has that name."""
        stem, ext = posixpath.splitext(filename)
        number = 1
        while True:
            name = filename if number == 1 else f"{stem} ({number}){ext}"
            target = posixpath.join(folder, name)
            if files.exists(target):
                free = files.state.files[target].content == content
            else:
                free = not files.is_directory(target)
            if free and target not in planned:
                return target
            number += 1

    @tool("write")
    def save_draft(
        self,
        recipients: list[str],
        subject: str,
        content: str,
        cc: list[str] | None = None,
        attachments: list[str] | None = None,
    ) -> Done:
        """Save an unsent email in DRAFT.

        Args:
            recipients: the addresses it will go to (may be empty for now).
            subject: the subject line.
            content: the body written so far.
            cc: addresses to copy.
            attachments: paths of files in the Files app to attach.

        Returns:
            what was saved, and the draft's id.
        """
        to = self.check_addresses(recipients, "recipients")
        copied = self.check_addresses(cc or [], "cc")
        files = self.check_attachments(attachments)
        draft = self._store(
            sender=self.state.user_email,
            recipients=to,
            cc=copied,
            subject=subject,
            content=content,
            attachments=files,
            folder=Folder.DRAFT,
            is_read=True,
        )
        addressed = f" to {listed(draft.recipients)}" if draft.recipients else " (no recipient yet)"
        done = f"Saved draft {draft.email_id}{addressed} in DRAFT: '{draft.subject}'."
        return Done(done=done, id=draft.email_id)

    # -- the world -----------------------------------------------------------------------------------
    @tool("env", actors=())
    def receive_email(
        self,
        sender: str,
        subject: str,
        content: str,
        recipients: list[str] | None = None,
        cc: list[str] | None = None,
        attachments: list[str] | None = None,
        email_id: str | None = None,
        folder: Folder = Folder.INBOX,
        in_reply_to: str | None = None,
    ) -> str:
        """Deliver an email to the user, unread, and notify both the user and the assistant.

        Args:
            sender: the sender's address.
            subject: the subject line.
            content: the body.
            recipients: the To addresses; the user's own address when omitted.
            cc: addresses copied.
            attachments: paths of files in the Files app that come attached.
            email_id: a chosen id (scenarios refer to it later); a fresh one when omitted.
            folder: where it lands, INBOX unless a filter puts it elsewhere.
            in_reply_to: the id of the email it answers, if any.

        Returns:
            the id of the new email.
        """
        sender = sender.strip()
        if not is_address(sender):
            raise ToolError(f"The sender '{sender}' is not an email address (expected name@domain).")
        to = self.check_addresses(recipients, "recipients") if recipients else [self.state.user_email]
        copied = self.check_addresses(cc or [], "cc")
        files = self.check_attachments(attachments)
        target = normalize_folder(folder)
        if email_id is not None:
            if not email_id.strip():
                raise ToolError("A chosen email_id cannot be empty.")
            if email_id in self.state.emails:
                raise ToolError(f"An email with id '{email_id}' already exists; choose another id.")
        received = self._store(
            sender=sender,
            recipients=to,
            cc=copied,
            subject=subject,
            content=content,
            attachments=files,
            folder=target,
            is_read=False,
            in_reply_to=in_reply_to,
            email_id=email_id,
        )
        self.notify(
            "new_email",
            f"New email from {sender}",
            subject=subject,
            body=content,
            data={"email_id": received.email_id, "attachments": list(files)},
        )
        return received.email_id


# -- screens -----------------------------------------------------------------------------------------


def _row(email: Email, outgoing: bool) -> dict[str, Any]:
    """An email as a mailbox row shows it: who it is from (to, in SENT and DRAFT), subject, time, a
    preview; enough to choose which one to open.
    """
    row: dict[str, Any] = {"email_id": email.email_id}
    if outgoing:
        row["to"] = ", ".join(email.recipients)
    else:
        row["from"] = email.sender
    row.update(
        subject=email.subject,
        time=short_time(email.timestamp),
        read=email.is_read,
        preview=preview(email.content),
    )
    if email.attachments:
        row["attachments"] = len(email.attachments)
    return row


class Mailbox(Screen):
    """A folder of the mailbox."""

    name = "Mailbox"
    title = "Mailbox"
    folder: Folder = Folder.INBOX

    def display(self, app: EmailApp) -> dict[str, Any]:
        """The folder's newest emails as a phone lists them (who, subject, time, read, a preview), with
        the total and the number unread; the email ids are those open_email takes.
        """
        emails = app.in_folder(self.folder)
        outgoing = self.folder in (Folder.SENT, Folder.DRAFT)
        return {
            "folder": self.folder.value,
            "total": len(emails),
            "unread": sum(not email.is_read for email in emails),
            "emails": [_row(email, outgoing) for email in emails[:PAGE]],
            **showing_screen(emails[:PAGE], len(emails), "list_emails(offset={offset})"),
        }

    @action(kind="read")
    def list_emails(self, app: EmailApp, offset: int = 0, limit: int = PAGE) -> EmailPage:
        """Show a page of this folder's emails, newest first.

        Args:
            offset: how many emails to skip.
            limit: how many to show.
        """
        return app.list_emails(folder=self.folder, offset=offset, limit=limit)

    @action(kind="read")
    def search_emails(self, app: EmailApp, query: str) -> list[Email]:
        """Search this folder's emails by sender, recipients, subject or text. It matches parts of words
        too: "Priya" finds "Priyanka".

        Args:
            query: what to look for.
        """
        return app.search_emails(query, folder=self.folder)

    @action("Detail")
    def open_email(self, app: EmailApp, email_id: str) -> Transition:
        """Open an email; opening it marks it read.

        Args:
            email_id: the email's id.
        """
        email = app.mark_read(app.require(email_id))
        return push(EmailDetail(email_id=email_id), email)

    @action("Detail")
    def open_email_by_index(self, app: EmailApp, index: int) -> Transition:
        """Open the email at a position of this folder's list (0 is the newest); opening it marks it read.

        Args:
            index: the position in the list, starting at 0.
        """
        email = app.mark_read(app.get_email_by_index(index, folder=self.folder))
        return push(EmailDetail(email_id=email.email_id), email)

    @action("Mailbox")
    def switch_folder(self, app: EmailApp, folder: Folder) -> Transition:
        """Show another folder: INBOX, SENT, DRAFT, TRASH or ARCHIVE.

        Args:
            folder: the folder to show.
        """
        screen = Mailbox(folder=normalize_folder(folder))
        return replace(screen, screen.display(app))  # the folder's first page, as the screen shows it

    @action("Compose")
    def start_compose(self, app: EmailApp) -> Transition:
        """Write a new email."""
        screen = Compose()
        return push(screen, screen.draft())


class EmailDetail(Screen):
    """One email."""

    name = "Detail"
    title = "Email"
    email_id: str

    def display(self, app: EmailApp) -> Email | str:
        """The email in full, as open_email shows it (or a line saying it is gone)."""
        email = app.state.emails.get(self.email_id)
        return email if email is not None else f"Email {self.email_id} no longer exists."

    @action(kind="read")
    def refresh(self, app: EmailApp) -> Email:
        """Show this email again."""
        return app.require(self.email_id)

    @action(kind="write")
    def reply(self, app: EmailApp, content: str, attachments: list[str] | None = None) -> Done:
        """Send a quick reply to this email.

        Args:
            content: the reply's text.
            attachments: paths of files to attach, e.g. ["/Documents/notes.pdf"].
        """
        return app.reply_to_email(self.email_id, content, attachments)

    @action(kind="write")
    def forward(self, app: EmailApp, recipients: list[str]) -> Done:
        """Forward this email and its attachments.

        Args:
            recipients: the addresses to forward it to.
        """
        return app.forward_email(self.email_id, recipients)

    @action(BACK, kind="write")
    def move(self, app: EmailApp, folder: Folder) -> Transition:
        """Move this email to another folder (INBOX, ARCHIVE or TRASH) and go back to the list.

        Args:
            folder: the destination folder.
        """
        return back(app.move_email(self.email_id, folder))

    @action(BACK, kind="write")
    def delete(self, app: EmailApp) -> Transition:
        """Delete this email (to TRASH, or for good if it is in TRASH) and go back to the list."""
        return back(app.delete_email(self.email_id))

    @action(kind="write")
    def download_attachments(self, app: EmailApp, path: str = "/Downloads") -> SavedFiles:
        """Save this email's attachments to your files.

        Args:
            path: the folder to save them in.
        """
        return app.download_attachments(self.email_id, path)

    @action("Compose")
    def start_compose_reply(self, app: EmailApp) -> Transition:
        """Write a reply to this email."""
        original = app.require_sent(self.email_id, "replied to")
        screen = Compose(
            recipients=app.reply_recipients(original),
            subject=_reply_subject(original.subject),
            reply_to=original.email_id,
        )
        return push(screen, screen.draft())


class Compose(Screen):
    """Writing an email; the draft lives on the screen until it is sent, saved or discarded."""

    name = "Compose"
    title = "New email"
    recipients: list[str] = Field(default_factory=list)
    cc: list[str] = Field(default_factory=list)
    subject: str = ""
    body: str = ""
    attachments: list[str] = Field(default_factory=list)
    reply_to: str | None = None

    def draft(self) -> dict[str, Any]:
        """Return the draft as shown on screen."""
        return self.model_dump()

    def display(self, app: EmailApp) -> dict[str, Any]:
        """The draft as it stands."""
        return self.draft()

    def _not_in_reply(self, what: str) -> None:
        if self.reply_to is not None:
            raise ToolError(
                f"This is a reply to email {self.reply_to}: its {what} cannot be changed. Discard it and use "
                "start_compose from the mailbox to write to other people."
            )

    @action()
    def set_recipients(self, app: EmailApp, recipients: list[str]) -> dict[str, Any]:
        """Replace the recipients.

        Args:
            recipients: the addresses to send to.
        """
        self._not_in_reply("recipients")
        self.recipients = app.check_addresses(recipients, "recipients")
        return self.draft()

    @action()
    def add_recipient(self, app: EmailApp, recipient: str) -> dict[str, Any]:
        """Add one recipient.

        Args:
            recipient: an email address.
        """
        self._not_in_reply("recipients")
        self.recipients = app.check_addresses([*self.recipients, recipient], "recipients")
        return self.draft()

    @action()
    def set_cc(self, app: EmailApp, cc: list[str]) -> dict[str, Any]:
        """Replace the addresses copied.

        Args:
            cc: the addresses to copy.
        """
        self._not_in_reply("cc")
        self.cc = app.check_addresses(cc, "cc")
        return self.draft()

    @action()
    def set_subject(self, app: EmailApp, subject: str) -> dict[str, Any]:
        """Set the subject.

        Args:
            subject: the subject line.
        """
        self._not_in_reply("subject")
        self.subject = subject
        return self.draft()

    @action()
    def set_body(self, app: EmailApp, body: str) -> dict[str, Any]:
        """Set the text of the email.

        Args:
            body: the whole text.
        """
        self.body = body
        return self.draft()

    @action(kind="read")
    def browse_files(self, app: EmailApp, directory: str = "/") -> list[DirectoryEntry]:
        """Look through the files on your phone to find one to attach.

        Args:
            directory: the folder to look in, e.g. "/Documents"; "/" is the top.
        """
        return browse(app, directory)

    @action()
    def attach_file(self, app: EmailApp, path: str) -> dict[str, Any]:
        """Attach a file from your files.

        Args:
            path: the file's path, e.g. "/Documents/lease.pdf".
        """
        self.attachments = app.check_attachments([*self.attachments, path])
        return self.draft()

    @action(BACK, kind="write")
    def send(self, app: EmailApp) -> Transition:
        """Send the email and go back."""
        if self.reply_to is not None:
            return back(app.reply_to_email(self.reply_to, self.body, self.attachments or None))
        sent = app.send_email(
            recipients=self.recipients,
            subject=self.subject,
            content=self.body,
            cc=self.cc or None,
            attachments=self.attachments or None,
        )
        return back(sent)

    @action(BACK, kind="write")
    def save_draft(self, app: EmailApp) -> Transition:
        """Save the email in DRAFT without sending it, and go back."""
        return back(
            app.save_draft(
                recipients=self.recipients,
                subject=self.subject,
                content=self.body,
                cc=self.cc or None,
                attachments=self.attachments or None,
            )
        )

    @action(BACK)
    def discard(self, app: EmailApp) -> Transition:
        """Throw the draft away and go back."""
        return back("Draft discarded.")


EmailApp.set_screens(Mailbox, EmailDetail, Compose)
