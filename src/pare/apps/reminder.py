"""Reminders: things to be reminded of at a time, once or repeatedly, announced when they fall due."""

from __future__ import annotations

from calendar import monthrange
from collections.abc import Iterable
from datetime import datetime, timedelta
from enum import StrEnum
from typing import Any

from pydantic import BaseModel, ConfigDict, Field, model_validator

from pare.apps.base import App
from pare.apps.done import Done
from pare.apps.paging import Paged, showing_screen
from pare.apps.screens import Screen, Transition, action, back_to, push, replace
from pare.apps.text import PAGE, preview, short_time
from pare.apps.tools import tool
from pare.apps.types import SimTime
from pare.errors import ToolError
from pare.sim.clock import ensure_utc


class Repetition(StrEnum):
    """How often a reminder repeats. Accepted in any case ("Daily", "WEEKLY")."""

    NONE = "none"
    DAILY = "daily"
    WEEKLY = "weekly"
    MONTHLY = "monthly"
    YEARLY = "yearly"

    @classmethod
    def _missing_(cls, value: object) -> Repetition | None:
        if isinstance(value, str):
            wanted = value.strip().lower()
            for member in cls:
                if member.value == wanted:
                    return member
        return None

    def __repr__(self) -> str:
        return repr(self.value)


class Reminder(BaseModel):
    """A reminder: a title and notes, due at a time, possibly repeating."""

    model_config = ConfigDict(extra="forbid")

    reminder_id: str
    title: str
    description: str = ""
    due_datetime: SimTime = Field(
        description="when it is due next (for a repeating one, its next occurrence)"
    )
    repetition: Repetition = Repetition.NONE
    repeat_until: SimTime | None = Field(
        default=None, description="the last moment an occurrence may fall on; None repeats forever"
    )
    set_for: SimTime = Field(
        json_schema_extra={"optional": True},  # _set_for_the_due_time fills it in: not required in seed data
        description="the due time as it was set (when added, or when someone last moved it): unlike "
        "due_datetime, it stays put as a repeating reminder fires; the due time when left out",
    )
    announced: bool = Field(
        default=False,
        description="whether the current due occurrence has been announced; a seeded reminder already due "
        "that should not be announced again sets it",
    )

    @model_validator(mode="before")
    @classmethod
    def _set_for_the_due_time(cls, data: Any) -> Any:
        if isinstance(data, dict) and data.get("set_for") is None and "due_datetime" in data:
            data = {**data, "set_for": data["due_datetime"]}
        return data

    @model_validator(mode="after")
    def _repeat_until_fits(self) -> Reminder:
        problem = _repeat_problem(self.due_datetime, self.repetition, self.repeat_until)
        if problem:
            raise ValueError(f"reminder '{self.reminder_id}': {problem}")
        return self


class ReminderUpdate(BaseModel):
    """Fields to change on a reminder; fields left out are kept."""

    model_config = ConfigDict(extra="forbid")

    title: str | None = None
    description: str | None = None
    due_datetime: SimTime | None = None
    repetition: Repetition | None = None
    repeat_until: SimTime | None = None


class ReminderState(BaseModel):
    """Every reminder by id."""

    model_config = ConfigDict(extra="forbid")

    reminders: dict[str, Reminder] = Field(default_factory=dict)

    @model_validator(mode="after")
    def _keys_are_ids(self) -> ReminderState:
        for key, reminder in self.reminders.items():
            if key != reminder.reminder_id:
                raise ValueError(f"reminder stored under '{key}' has reminder_id '{reminder.reminder_id}'")
        return self


class UpcomingReminders(Paged):
    """The next reminders to fall due, a page at a time."""

    rows_field = "reminders"

    reminders: list[Reminder]
    total: int = Field(description="how many reminders are due after now in all")
    offset: int = 0


class ReminderDraft(BaseModel):
    """A reminder being created or edited, not saved yet."""

    reminder_id: str | None = Field(description="the reminder being edited; null for a new reminder")
    title: str | None
    description: str
    due_datetime: SimTime
    repetition: Repetition
    repeat_until: SimTime | None


def _repeat_problem(due: datetime, repetition: Repetition, repeat_until: datetime | None) -> str | None:
    """What is wrong with this repetition, or ``None``."""
    if repeat_until is None:
        return None
    if repetition == Repetition.NONE:
        return "repeat_until only applies to a repeating reminder; choose a repetition or leave it out"
    if repeat_until < due:
        return (
            f"repeat_until ({repeat_until:%Y-%m-%d %H:%M}) must not be before the due time "
            f"({due:%Y-%m-%d %H:%M})"
        )
    return None


def _check_repeat(due: datetime, repetition: Repetition, repeat_until: datetime | None) -> None:
    """Raise a :class:`ToolError` if ``repeat_until`` does not fit the due time and repetition."""
    problem = _repeat_problem(due, repetition, repeat_until)
    if problem:
        raise ToolError(problem[0].upper() + problem[1:] + ".")


def _add_months(moment: datetime, months: int) -> datetime:
    """``moment`` moved by ``months`` months, on the same day clamped to the month's end."""
    years, month_index = divmod(moment.month - 1 + months, 12)
    year, month = moment.year + years, month_index + 1
    return moment.replace(year=year, month=month, day=min(moment.day, monthrange(year, month)[1]))


def next_occurrence(due: datetime, repetition: Repetition, after: datetime) -> datetime | None:
    """The first occurrence of a reminder due at ``due`` that falls after ``after`` (and after ``due``).

    Monthly reminders keep their day of the month, clamped to the month's end (31 January, 28 February);
    yearly ones keep their date (29 February becomes 28 February). ``None`` for a reminder that does not
    repeat.
    """
    if repetition == Repetition.NONE:
        return None
    if repetition in (Repetition.DAILY, Repetition.WEEKLY):
        step = timedelta(days=1 if repetition == Repetition.DAILY else 7)
        count = max(1, (after - due) // step + 1)
        return due + count * step
    months = 1 if repetition == Repetition.MONTHLY else 12
    count = max(1, ((after.year - due.year) * 12 + after.month - due.month) // months)
    while True:
        candidate = _add_months(due, count * months)
        if candidate > after:
            return candidate
        count += 1


def _by_due(reminders: Iterable[Reminder]) -> list[Reminder]:
    return sorted(reminders, key=lambda r: (r.due_datetime, r.reminder_id))


class ReminderApp(App):
    """The reminders."""

    name = "reminder"
    title = "Reminders"
    description = "The user's reminders: things to remember at a time, once or repeating; due ones notify."
    State = ReminderState
    harm = {
        "add_reminder": "reversible",
        "update_reminder": "reversible",
        "delete_reminder": "irreversible",
    }
    state: ReminderState
    wakeup_tool = "announce_due_reminders"

    # -- helpers used by screens and the environment ------------------------------------------------
    def require(self, reminder_id: str) -> Reminder:
        """Return the reminder with ``reminder_id``; raise a :class:`ToolError` naming it otherwise."""
        reminder = self.state.reminders.get(reminder_id)
        if reminder is None:
            raise ToolError(
                f"No reminder with id '{reminder_id}'. Use get_all_reminders to find reminder ids."
            )
        return reminder

    def next_wakeup(self) -> datetime | None:
        """The earliest due time among the reminders not announced yet."""
        return min((r.due_datetime for r in self.state.reminders.values() if not r.announced), default=None)

    # -- agent API -----------------------------------------------------------------------------------
    @tool("write")
    def add_reminder(
        self,
        title: str,
        due_datetime: SimTime,
        description: str = "",
        repetition: Repetition = Repetition.NONE,
        repeat_until: SimTime | None = None,
    ) -> Done:
        """Add a reminder. When it falls due, the user and the assistant are notified.

        Args:
            title: what to be reminded of, e.g. "Pay the rent".
            due_datetime: when, ISO 8601 in UTC, e.g. "2025-03-05 09:00". A time already past is announced
                right away.
            description: more details, shown in the notification.
            repetition: how often it repeats: "none" (once), "daily", "weekly", "monthly" (same day of the
                month, or the month's last day) or "yearly".
            repeat_until: for a repeating reminder, the last moment an occurrence may fall on, e.g.
                "2025-03-31 23:59"; leave it out to repeat forever.

        Returns:
            what was added and when it falls due, and the new reminder's id.
        """
        if not title.strip():
            raise ToolError("A reminder needs a title.")
        due = ensure_utc(due_datetime)
        until = None if repeat_until is None else ensure_utc(repeat_until)
        _check_repeat(due, repetition, until)
        reminder_id = self.new_id("reminder", self.state.reminders)
        self.state.reminders[reminder_id] = Reminder(
            reminder_id=reminder_id,
            title=title.strip(),
            description=description.strip(),
            due_datetime=due,
            repetition=repetition,
            repeat_until=until,
            set_for=due,
        )
        repeats = "" if repetition is Repetition.NONE else f", repeating {repetition.value}"
        until_text = "" if until is None else f" until {until:%a %Y-%m-%d %H:%M}"
        when = f"due {due:%a %Y-%m-%d %H:%M}{repeats}{until_text}"
        done = f"Added reminder {reminder_id} '{title.strip()}', {when}."
        return Done(done=done, id=reminder_id)

    @tool("write")
    def update_reminder(self, reminder_id: str, updates: ReminderUpdate) -> Reminder:
        """Change some fields of a reminder; fields not given are kept.

        A new due time makes the reminder announce again when it falls due. Setting the repetition to
        "none" also removes repeat_until.

        Args:
            reminder_id: the reminder to change.
            updates: the fields to change, e.g. {"due_datetime": "2025-03-06 18:00", "repetition": "weekly"}.
                Null removes repeat_until (repeat forever) or the description.

        Returns:
            the reminder as it is now.
        """
        reminder = self.require(reminder_id)
        changes: dict[str, Any] = updates.model_dump(exclude_unset=True)
        if not changes:
            raise ToolError("No field to change was given.")
        for required in ("title", "due_datetime", "repetition"):
            if required in changes and changes[required] is None:
                hint = ' (use "none" to stop repeating)' if required == "repetition" else ""
                raise ToolError(
                    f"A reminder's {required} cannot be removed{hint}; give a new value or leave it out."
                )
        if "title" in changes:
            if not changes["title"].strip():
                raise ToolError("A reminder's title cannot be empty.")
            changes["title"] = changes["title"].strip()
        if "description" in changes:
            changes["description"] = (changes["description"] or "").strip()
        if changes.get("repetition") == Repetition.NONE and "repeat_until" not in changes:
            changes["repeat_until"] = None
        merged = {**reminder.model_dump(), **changes}
        _check_repeat(merged["due_datetime"], merged["repetition"], merged["repeat_until"])
        if merged["due_datetime"] != reminder.due_datetime:
            merged["announced"] = False
            merged["set_for"] = merged["due_datetime"]
        elif merged["announced"] and ("repetition" in changes or "repeat_until" in changes):
            self._rearm(merged)
        updated = Reminder.model_validate(merged)
        self.state.reminders[reminder_id] = updated
        return updated

    @tool("write")
    def delete_reminder(self, reminder_id: str) -> str:
        """Delete a reminder.

        Args:
            reminder_id: the reminder to delete.

        Returns:
            confirmation.
        """
        reminder = self.require(reminder_id)
        del self.state.reminders[reminder_id]
        return f"Deleted reminder {reminder_id} ({reminder.title})."

    @tool("read")
    def get_all_reminders(self) -> list[Reminder]:
        """List every reminder, sorted by due time.

        Returns:
            the reminders.
        """
        return _by_due(self.state.reminders.values())

    @tool("read")
    def get_due_reminders(self) -> list[Reminder]:
        """List the reminders due now or earlier, sorted by due time.

        Returns:
            the due reminders.
        """
        now = self.ctx.now()
        return _by_due(r for r in self.state.reminders.values() if r.due_datetime <= now)

    @tool("read")
    def get_upcoming_reminders(self, offset: int = 0, limit: int = PAGE) -> UpcomingReminders:
        """List the next reminders to fall due (after now), soonest first, a page at a time.

        Args:
            offset: how many of the soonest reminders to skip.
            limit: how many reminders to return (1-100).

        Returns:
            the reminders and how many are upcoming in all.
        """
        if offset < 0 or not 1 <= limit <= 100:
            raise ToolError("offset must be >= 0 and limit between 1 and 100.")
        now = self.ctx.now()
        upcoming = _by_due(r for r in self.state.reminders.values() if r.due_datetime > now)
        return UpcomingReminders(
            reminders=upcoming[offset : offset + limit], total=len(upcoming), offset=offset
        )

    @tool("read")
    def get_reminder(self, reminder_id: str) -> Reminder:
        """Get one reminder's details.

        Args:
            reminder_id: the reminder's id.

        Returns:
            the reminder.
        """
        return self.require(reminder_id)

    # -- the environment -----------------------------------------------------------------------------
    @tool("env", actors=())
    def announce_due_reminders(self) -> list[str]:
        """Announce every reminder that has fallen due and not been announced yet.

        The user and the assistant are notified of each. A repeating reminder then moves to its next
        occurrence after now, unless that passes its repeat_until.

        Returns:
            the ids of the reminders announced, in due order.
        """
        now = self.ctx.now()
        due = _by_due(r for r in self.state.reminders.values() if not r.announced and r.due_datetime <= now)
        for reminder in due:
            self.notify(
                "reminder_due",
                f"Reminder: {reminder.title}",
                body=reminder.description,
                data={"reminder_id": reminder.reminder_id},
            )
            record = {**reminder.model_dump(), "announced": True}
            self._rearm(record)
            self.state.reminders[reminder.reminder_id] = Reminder.model_validate(record)
        return [r.reminder_id for r in due]

    def _rearm(self, record: dict[str, Any]) -> None:
        """Make an announced repeating reminder (as a dict of fields) wait for its next occurrence.

        A reminder due in the future just waits again; one whose next occurrence would pass its
        repeat_until stays announced.
        """
        now = self.ctx.now()
        if record["due_datetime"] > now:
            record["announced"] = False
            return
        following = next_occurrence(record["due_datetime"], record["repetition"], now)
        until = record["repeat_until"]
        if following is not None and (until is None or following <= until):
            record["due_datetime"] = following
            record["announced"] = False


# -- screens -----------------------------------------------------------------------------------------


def _row(reminder: Reminder, now: datetime) -> dict[str, Any]:
    """A reminder as the list shows it: title, when it is due (and whether that has come), repetition."""
    row: dict[str, Any] = {
        "reminder_id": reminder.reminder_id,
        "title": reminder.title,
        "due": short_time(reminder.due_datetime),
    }
    if reminder.due_datetime <= now:
        row["due_now"] = True
    if reminder.repetition != Repetition.NONE:
        row["repeats"] = reminder.repetition.value
    if reminder.description:
        row["preview"] = preview(reminder.description)
    return row


class ReminderList(Screen):
    """Every reminder."""

    name = "List"
    title = "Reminders"

    def display(self, app: ReminderApp) -> dict[str, Any]:
        """The first reminders by due time, as list_all_reminders orders them (so the ones due now or
        overdue come first), with the total and how many are due.
        """
        reminders = app.get_all_reminders()
        now = app.ctx.now()
        return {
            "total": len(reminders),
            "due_now": sum(r.due_datetime <= now for r in reminders),
            "reminders": [_row(reminder, now) for reminder in reminders[:PAGE]],
            **showing_screen(reminders[:PAGE], len(reminders), "list_all_reminders()"),
        }

    @action(kind="read")
    def list_all_reminders(self, app: ReminderApp) -> list[Reminder]:
        """Show every reminder, sorted by due time."""
        return app.get_all_reminders()

    @action(kind="read")
    def list_upcoming_reminders(
        self, app: ReminderApp, offset: int = 0, limit: int = PAGE
    ) -> UpcomingReminders:
        """Show the next reminders to fall due.

        Args:
            offset: how many of the soonest to skip.
            limit: how many to show (1-100).
        """
        return app.get_upcoming_reminders(offset=offset, limit=limit)

    @action(kind="read")
    def list_due_reminders(self, app: ReminderApp) -> list[Reminder]:
        """Show the reminders that are due now or overdue."""
        return app.get_due_reminders()

    @action("Detail")
    def open_reminder(self, app: ReminderApp, reminder_id: str) -> Transition:
        """Open a reminder's page.

        Args:
            reminder_id: the reminder's id.
        """
        return push(ReminderDetail(reminder_id=reminder_id), app.require(reminder_id))

    @action("Edit")
    def create_new(self, app: ReminderApp) -> Transition:
        """Start a new reminder, due at the next full hour."""
        due = app.ctx.now().replace(minute=0, second=0, microsecond=0) + timedelta(hours=1)
        draft = ReminderEdit(due_datetime=due)
        return push(draft, draft.draft())


class ReminderDetail(Screen):
    """One reminder's page."""

    name = "Detail"
    title = "Reminder details"
    reminder_id: str

    def display(self, app: ReminderApp) -> Reminder | str:
        """The reminder in full, as open_reminder shows it (or a line saying it is gone)."""
        reminder = app.state.reminders.get(self.reminder_id)
        return reminder if reminder is not None else f"Reminder {self.reminder_id} no longer exists."

    @action(kind="read")
    def refresh(self, app: ReminderApp) -> Reminder:
        """Show this reminder's details as they are now."""
        return app.require(self.reminder_id)

    @action("Edit")
    def edit(self, app: ReminderApp) -> Transition:
        """Edit this reminder."""
        reminder = app.require(self.reminder_id)
        draft = ReminderEdit(
            reminder_id=reminder.reminder_id,
            reminder_title=reminder.title,
            description=reminder.description,
            due_datetime=reminder.due_datetime,
            repetition=reminder.repetition,
            repeat_until=reminder.repeat_until,
        )
        return push(draft, draft.draft())

    @action("List", kind="write")
    def delete(self, app: ReminderApp) -> Transition:
        """Delete this reminder and return to the list."""
        return back_to("List", app.delete_reminder(self.reminder_id))


class ReminderEdit(Screen):
    """A new reminder or changes to a reminder, not saved yet."""

    name = "Edit"
    title = "Edit reminder"
    reminder_id: str | None = Field(default=None, description="the reminder being edited; None for a new one")
    reminder_title: str | None = Field(
        default=None, description="the title; the class attribute title names the screen"
    )
    description: str = ""
    due_datetime: SimTime
    repetition: Repetition = Repetition.NONE
    repeat_until: SimTime | None = None

    def draft(self) -> ReminderDraft:
        """Return the draft as the user sees it."""
        return ReminderDraft(
            reminder_id=self.reminder_id,
            title=self.reminder_title,
            description=self.description,
            due_datetime=self.due_datetime,
            repetition=self.repetition,
            repeat_until=self.repeat_until,
        )

    def display(self, app: ReminderApp) -> ReminderDraft:
        """The draft as it stands."""
        return self.draft()

    @action()
    def set_title(self, app: ReminderApp, title: str) -> ReminderDraft:
        """Set what to be reminded of.

        Args:
            title: the title, e.g. "Water the plants".
        """
        if not title.strip():
            raise ToolError("The title cannot be empty.")
        self.reminder_title = title.strip()
        return self.draft()

    @action()
    def set_description(self, app: ReminderApp, description: str) -> ReminderDraft:
        """Set the reminder's details.

        Args:
            description: more details, or "" for none.
        """
        self.description = description.strip()
        return self.draft()

    @action()
    def set_due_datetime(self, app: ReminderApp, due_datetime: SimTime) -> ReminderDraft:
        """Set when the reminder is due.

        Args:
            due_datetime: the time, e.g. "2025-03-05 09:00".
        """
        self.due_datetime = ensure_utc(due_datetime)
        return self.draft()

    @action()
    def set_repetition(
        self, app: ReminderApp, repetition: Repetition, repeat_until: SimTime | None = None
    ) -> ReminderDraft:
        """Set how often the reminder repeats, and until when.

        Args:
            repetition: "none", "daily", "weekly", "monthly" or "yearly".
            repeat_until: the last moment an occurrence may fall on, e.g. "2025-03-31 23:59"; leave it out
                to repeat forever.
        """
        until = None if repeat_until is None else ensure_utc(repeat_until)
        _check_repeat(self.due_datetime, repetition, until)
        self.repetition, self.repeat_until = repetition, until
        return self.draft()

    @action("Detail", kind="write")
    def save(self, app: ReminderApp) -> Transition:
        """Save the reminder and show it: creates it if it is new, updates it otherwise."""
        if self.reminder_title is None or not self.reminder_title.strip():
            raise ToolError("The reminder has no title yet; use set_title before saving.")
        _check_repeat(self.due_datetime, self.repetition, self.repeat_until)
        if self.reminder_id is None:
            reminder_id = app.add_reminder(
                title=self.reminder_title,
                due_datetime=self.due_datetime,
                description=self.description,
                repetition=self.repetition,
                repeat_until=self.repeat_until,
            ).id
            return replace(ReminderDetail(reminder_id=reminder_id), app.require(reminder_id))
        reminder = app.require(self.reminder_id)
        draft = self.draft().model_dump(exclude={"reminder_id"})
        changes = {key: value for key, value in draft.items() if getattr(reminder, key) != value}
        if changes:
            reminder = app.update_reminder(self.reminder_id, ReminderUpdate.model_validate(changes))
        return back_to("Detail", reminder, ReminderDetail(reminder_id=self.reminder_id))

    @action(("Detail", "List"))
    def cancel(self, app: ReminderApp) -> Transition:
        """Leave without saving; nothing changes. Returns to the reminder, or to the list for a new one."""
        if self.reminder_id is None:
            return back_to("List", "New reminder discarded.")
        return back_to("Detail", "Changes discarded.", ReminderDetail(reminder_id=self.reminder_id))


ReminderApp.set_screens(ReminderList, ReminderDetail, ReminderEdit)
